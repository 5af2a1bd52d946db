"""Chapter 2, §2.1-§2.2 and C2.1-C2.6: positioner dynamics from Lagrange's equations, with and without constraints."""
