"""Chapter 2, §2.3: vibrations of the air-bearing carriage (Problems 2.6-2.7)."""
