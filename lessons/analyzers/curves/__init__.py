"""Space curves and motion laws of §1.1: arc length, the curve typed as formulas, speed
profiles, the linear analyzer.
"""
