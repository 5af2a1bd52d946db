"""Space curves and motion laws of §1.1: arc length, the curve typed as formulas, speed
profiles, the linear analyzer, and the source's helix with the claims checked on it.
"""
