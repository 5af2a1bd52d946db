"""Plane-curve analyzers (1.21)-(1.41): the conic analyzer, solved exactly, and the shared page
of Problems 1.1, 1.2, C1.1-C1.4.
"""
