"""One thread per math-library call in a server process.

A server steps many sessions, each with small matrices (3x3 solves, a 7x7 ``expm``).  The
linear-algebra library that numpy and scipy ship (OpenBLAS) starts a thread per core for a
call; on a busy machine those threads wait for each other and one 7x7 ``expm`` then takes
70-950 us of CPU instead of 13 us (measured on a 2-core machine running other work).  A
worker is meant to use one core (``serve --workers N`` for more), so its calls run on the
calling thread.  The setting must be made before numpy is first imported.
"""

from __future__ import annotations

import os
import sys

#: The variables OpenBLAS, OpenMP and MKL read when they load.
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def one_math_thread() -> bool:
    """Ask the math libraries for one thread each, unless the environment already says how
    many; False if numpy was already imported (the libraries have then read the setting)."""
    for name in THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
    return "numpy" not in sys.modules
