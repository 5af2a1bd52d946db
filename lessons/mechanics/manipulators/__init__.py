"""Self-study C2.1-C2.6: the simple manipulators' models, numbers, derivation pages, scene and page."""
