"""Test selection: the full suite (what CI runs) and a quick subset for daily work.

Tests that start a live server (real websockets, real browser) are marked ``live``
by file; one browser smoke test is also marked ``quick``.  The quick command

    python -m pytest -m "quick or not (live or slow)"

runs the model, the CLI and that smoke test.
"""

from __future__ import annotations

import pytest

LIVE_FILES = {
    "test_attacks_stepping.py",
    "test_browser.py",
    "test_browser_lessons.py",
    "test_assignments_browser.py",
    "test_classroom_browser.py",
    "test_classroom.py",
    "test_classlink.py",
    "test_classlink_browser.py",
    "test_frontdoor.py",
    "test_server.py",
    "test_attacks_transport.py",
    "test_loadtest.py",
}


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        if item.path.name in LIVE_FILES:
            item.add_marker(pytest.mark.live)
