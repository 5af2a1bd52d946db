"""The common page of the positioners of Problems 2.1-2.5: forward and inverse runs."""
