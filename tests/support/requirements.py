"""What a test needs that a machine may lack: skipped with the reason where it is missing,
failed under ``CI=true`` (where `.ci/run` installed everything and every test must run)."""

from __future__ import annotations

import os
from importlib.util import find_spec

import pytest


def skip_or_fail(why: str) -> None:
    """Skip saying ``why``; under ``CI=true`` fail saying it."""
    if os.environ.get("CI", "").lower() == "true":
        pytest.fail(why + " (CI=true: these tests must run)")
    pytest.skip(why)


def require_modules(*modules: str) -> None:
    """Skip (fail under CI) unless every one of ``modules`` of the ``test`` extra imports."""
    missing = [m for m in modules if find_spec(m) is None]
    if missing:
        skip_or_fail(f"{', '.join(missing)} not installed: pip install -e '.[test]'")
