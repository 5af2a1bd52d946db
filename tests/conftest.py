"""Test selection, and the fixtures the test modules share.

Tests that start a live server (real websockets, real browser) are marked ``live``
by file; one browser smoke test is also marked ``quick``.  The quick command

    python -m pytest -m "quick or not (live or slow)"

runs the model, the CLI and that smoke test.

Fixtures: ``lab`` (an in-process server for the module; a module that needs other
options overrides it with ``make_lab``), ``serve`` (``python -m analyzer_lab serve``
subprocesses for the module), ``browser`` (Debian's Chromium through Playwright), ``tab``
(a fresh page) and ``shared_tab`` (a page reused through the module), ``redis_server``
(a redis-server for one test), ``postgres`` (a PostgreSQL cluster for the module).
The helpers behind them are in :mod:`tests.support`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.browser import ARTIFACTS, CHROMIUM, LAUNCH_ARGS, Page, require_browser
from tests.support.busy import BusyProcesses, busy_count
from tests.support.postgres import PostgresCluster
from tests.support.redis_server import RedisServer
from tests.support.servers import ServeProcess

LIVE_FILES = {
    "test_attacks_stepping.py",
    "test_browser.py",
    "test_browser_lessons.py",
    "test_browser_plots.py",
    "test_assignments_browser.py",
    "test_classroom_browser.py",
    "test_classroom.py",
    "test_classlink.py",
    "test_classlink_browser.py",
    "test_frontdoor.py",
    "test_server.py",
    "test_attacks_transport.py",
    "test_attacks_pages.py",
    "test_attacks_grading.py",
    "test_loadtest.py",
    "test_course_record_live.py",
}


@pytest.fixture(scope="session", autouse=True)
def course_record_data(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """Servers started by the tests keep their course record in a temporary data folder
    (never the user's own)."""
    import os

    from analyzer_lab.classroom.store.location import ENV_DATA

    folder = tmp_path_factory.mktemp("analyzer-lab-data")
    before = os.environ.get(ENV_DATA)
    os.environ[ENV_DATA] = str(folder)
    yield folder
    if before is None:
        os.environ.pop(ENV_DATA, None)
    else:
        os.environ[ENV_DATA] = before


@pytest.fixture(scope="module")
def postgres() -> Iterator[PostgresCluster]:
    """A PostgreSQL cluster made for this module on a free loopback port (skipped without
    Debian's postgresql; failing under CI=true), removed at its end."""
    cluster = PostgresCluster().create()
    yield cluster
    cluster.remove()


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    for item in items:
        if item.path.name in LIVE_FILES or item.get_closest_marker("browser") is not None:
            item.add_marker(pytest.mark.live)


def _in_quick_subset(item: pytest.Item) -> bool:
    """Whether ``item`` is selected by ``-m "quick or not (live or slow)"``."""
    if item.get_closest_marker("quick") is not None:
        return True
    return item.get_closest_marker("live") is None and item.get_closest_marker("slow") is None


@pytest.fixture(scope="session")
def busy_processes() -> Iterator[BusyProcesses]:
    """The busy processes ``ANALYZER_LAB_BUSY`` asks for (none by default)."""
    busy = BusyProcesses(busy_count())
    try:
        yield busy
    finally:
        busy.stop()


@pytest.fixture(autouse=True)
def busy_machine(request: pytest.FixtureRequest, busy_processes: BusyProcesses) -> None:
    """The quick subset's tests run beside the busy processes; the live servers' measured
    tests (attacks, loads, browsers) run without them."""
    if _in_quick_subset(request.node):
        busy_processes.start()
    else:
        busy_processes.stop()


@pytest.fixture(scope="module")
def make_lab(request: pytest.FixtureRequest) -> Iterator[Callable[..., Any]]:
    """Start in-process servers for this module: ``make_lab(**options)`` is
    ``LabServer(host="127.0.0.1", port=0, **options)``; all stop at the module's end.  In a
    module marked ``browser``, a missing browser skips before a server starts."""
    started: list[Any] = []

    def make(**options: Any) -> Any:
        if request.node.get_closest_marker("browser") is not None:
            require_browser()
        from analyzer_lab.serve.server import LabServer

        server = LabServer(host="127.0.0.1", port=0, **options)
        started.append(server)
        return server

    yield make
    for server in reversed(started):
        server.stop()


@pytest.fixture(scope="module")
def labs(make_lab: Callable[..., Any]) -> dict[str, Any]:
    """Two in-process servers on the sphere alone (no warm-up, nothing restored): ``"ru"``
    opens its pages in Russian, ``"en"`` in English."""
    from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE

    options = {"lessons": [SPHERE], "lesson": "sphere", "warm_up": False, "restore": False}
    return {"ru": make_lab(language="ru", **options), "en": make_lab(**options)}


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    """The module's in-process server on the sphere (every lesson, warmed up)."""
    return make_lab(lesson="sphere")


@pytest.fixture(scope="module")
def serve(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Callable[..., ServeProcess]]:
    """Start ``python -m analyzer_lab serve`` subprocesses for this module:
    ``serve(lesson, *flags)`` returns once the server answers; its stderr goes to
    ``log_path``; all stop at the module's end."""
    started: list[ServeProcess] = []

    def start(lesson: str = "sphere", *flags: str) -> ServeProcess:
        log_path: Path = tmp_path_factory.mktemp("serve") / "server.log"
        server = ServeProcess.start(lesson, flags, log_path)
        started.append(server)
        return server

    yield start
    for server in reversed(started):
        server.stop()


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    """Debian's Chromium, launched by Playwright for this module (skipped without it;
    failing under CI=true)."""
    require_browser()
    from playwright.sync_api import sync_playwright

    ARTIFACTS.mkdir(exist_ok=True)
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=LAUNCH_ARGS)
        yield b
        b.close()


@pytest.fixture()
def tab(lab: Any, browser: Any) -> Iterator[Page]:
    """A fresh page of ``lab`` (closed after the test)."""
    p = Page(lab, browser)
    yield p
    p.close()


@pytest.fixture(scope="module")
def shared_tab(lab: Any, browser: Any) -> Iterator[Page]:
    """One page of ``lab`` (900 x 640) reused by the module's tests."""
    context = browser.new_context(viewport={"width": 900, "height": 640})
    p = Page(lab, browser, context)
    yield p
    p.close()


@pytest.fixture()
def redis_server() -> Iterator[RedisServer]:
    """A redis-server on a free loopback port for one test (skipped without it; failing
    under CI=true); the test may stop and start it again."""
    server = RedisServer().start()
    yield server
    server.stop()
