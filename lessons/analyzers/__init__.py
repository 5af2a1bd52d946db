"""Chapter 1: differential analyzers that keep a point on a curve or a surface (§1.1-§1.3, C1.1-C1.5)."""
