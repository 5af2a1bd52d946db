"""Lagrange equations of the 2nd kind (§2.1), the constrained algorithm of §2.2 and its examples."""
