"""Analyzer Lab: programmed motion of mechatronic systems, in the browser and headless.

The model is :mod:`analyzer_lab.lessons` (numpy, scipy, sympy; it never imports the view);
the view and the command line are the other subpackages: :mod:`analyzer_lab.serve` (the
server, the front door, the command line), :mod:`analyzer_lab.session` (one page's state
and clock), :mod:`analyzer_lab.view` (what a page shows), :mod:`analyzer_lab.classroom`
(the instructor, the class and its bus) and :mod:`analyzer_lab.viser_boundary` (the one
place that reaches into viser's internals).
"""
