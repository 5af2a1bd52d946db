"""Serving the lab: the viser server, the front door of several workers, the command line and its limits."""
