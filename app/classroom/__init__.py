"""The classroom: the instructor's code and panel, follow-me, pushes, assignments, and the bus between workers."""
