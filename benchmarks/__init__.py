"""Measurements of Analyzer Lab (not shipped with the package).

``python -m benchmarks.loadtest``: pages per server and their update rates;
``python -m benchmarks.classroom_load``: an instructor and a class of followers;
``python -m benchmarks.soak``: students joining and leaving for a long time;
``python -m benchmarks.integrators``: the analyzer's integrators against scipy's.
They use real websocket clients (the ``websockets`` package) and psutil, both in the
``bench`` extra, never imported by ``app`` or ``lessons``.
"""
