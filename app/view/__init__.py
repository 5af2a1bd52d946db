"""What one page shows: controls, scene, plots, readout, derivation, export and replay."""
