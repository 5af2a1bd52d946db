"""The viser version whose internals the boundary was written against, and the lock
every patch of viser's classes or modules takes."""

from __future__ import annotations

import threading

#: The viser version whose internals this module was written and tested against.
VISER_VERSION = "1.1.1"
PATCH_LOCK = threading.Lock()


def check_viser_version() -> None:
    """Refuse to run on a viser whose private internals were not checked."""
    import viser

    found = getattr(viser, "__version__", "unknown")
    if found != VISER_VERSION:
        raise RuntimeError(
            f"Analyzer Lab needs viser {VISER_VERSION} (found {found}):"
            " analyzer_lab.viser_boundary patches its internals"
        )
