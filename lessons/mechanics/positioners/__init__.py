"""The positioners of chapter 2 (Problems 2.1-2.5): the page solved once per parameter set,
the common page of the Lagrange positioners, and the mechanism of Problem 2.4."""
