"""Second-order surfaces (1.42): the quadric, its type, the nearest point on it, its mesh."""
