"""The analyzer (1.49)-(1.50) of any quadric and its constant-speed variant (1.58)-(1.59): the
field, its runs and the shared page.
"""
