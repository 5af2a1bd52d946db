"""Start-up: the catalog's index equals what discovery finds, and a command imports only
what it needs (one lesson's page for ``run LESSON``, nothing heavy for a refused
argument; ``import analyzer_lab`` imports no view code, no viser, no sympy)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

import pytest
from analyzer_lab.lessons.catalog import INDEX, all_lessons, lesson_ids, page_modules

from tests.support.servers import free_port, stop_process
from tests.support.waiting import wait_until

#: Packages whose import is the start-up's cost.
HEAVY = ("numpy", "scipy", "sympy", "viser", "trimesh", "matplotlib", "pandas")


def test_the_index_equals_what_discovery_finds() -> None:
    found: dict[str, str] = {}
    for module in page_modules():
        items = [*getattr(module, "LESSONS", ()), getattr(module, "LESSON", None)]
        for lesson in items:
            if lesson is not None:
                found[lesson.id] = module.__name__.removeprefix("analyzer_lab.lessons.")
    assert dict(INDEX) == found
    assert lesson_ids() == tuple(l.id for l in all_lessons())  # the catalog's order


def imported_after(code: str) -> tuple[list[str], str]:
    """Run ``code`` in a fresh interpreter: the modules it had imported then, and what it
    wrote on stderr."""
    probe = f"{code}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))\n"
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1]), out.stderr


def heavy(modules: list[str]) -> list[str]:
    return sorted({m.split(".")[0] for m in modules} & set(HEAVY))


def pages(modules: list[str]) -> list[str]:
    wanted = {f"analyzer_lab.lessons.{where}" for _, where in INDEX}
    return sorted(m for m in modules if m in wanted)


@pytest.mark.parametrize(
    "argv, says",
    [
        (["run", "nosuch"], "unknown lesson 'nosuch'"),
        (["check", "nosuch"], "unknown lesson 'nosuch'"),
        (["run"], "the following arguments are required: lesson"),
        (["serve", "--workers", "0"], "--workers must be in 1..64"),
        (["run", "sphere", "--t-end", "x"], "invalid float value"),
    ],
)
def test_a_refused_argument_imports_nothing_heavy(argv: list[str], says: str) -> None:
    modules, stderr = imported_after(
        f"from analyzer_lab.serve.cli import main\nassert main({argv!r}) == 2"
    )
    assert says in stderr
    assert heavy(modules) == []


def test_run_of_one_lesson_imports_that_page_only() -> None:
    modules, _ = imported_after(
        "from analyzer_lab.serve.cli import main\n"
        "assert main(['run', 'sphere', '--t-end', '0.1', '--out', '/dev/null']) == 0"
    )
    assert pages(modules) == ["analyzer_lab.lessons.analyzers.sphere"]
    assert not {"viser", "matplotlib", "pandas"} & set(heavy(modules))


def test_a_refused_formula_imports_its_lesson_only() -> None:
    modules, stderr = imported_after(
        "from analyzer_lab.serve.cli import main\n"
        "assert main(['run', 'linear-positioner', '--set', 'x_t=__import__(1)']) == 2"
    )
    assert "is not allowed" in stderr
    assert pages(modules) == ["analyzer_lab.lessons.mechanics.linear_positioner"]


@pytest.mark.parametrize(
    "code",
    [
        "import analyzer_lab",
        "import analyzer_lab as al\nal.AnalyzerLabError\nal.Run",
        "import analyzer_lab.lessons.catalog",
        "import analyzer_lab.api",
    ],
)
def test_the_face_imports_no_view_and_nothing_heavy(code: str) -> None:
    modules, _ = imported_after(code)
    view = [
        m
        for m in modules
        if m.startswith("analyzer_lab.")
        and m.split(".")[1] in ("view", "session", "viser_boundary", "classroom")
    ]
    assert view == []
    assert set(heavy(modules)) <= {"numpy"}
    assert pages(modules) == []


def test_serve_answers_the_browser_before_its_lessons_are_loaded(tmp_path: Path) -> None:
    """The page is served as soon as the command starts listening; the lessons, the
    course record and the classroom load after it (a browser opened at once waits on
    the page instead of on a refused connection)."""
    port = free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", str(port)]
        + ["--data", str(tmp_path)],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    lines: list[tuple[float, str]] = []
    reader = threading.Thread(
        target=lambda: [lines.append((time.monotonic(), line)) for line in proc.stdout or ()],
        daemon=True,
    )
    reader.start()
    try:
        answered = None
        deadline = time.monotonic() + 60
        while answered is None and time.monotonic() < deadline:
            try:
                page = urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1).read()
                answered = time.monotonic()
            except OSError:
                assert proc.poll() is None, "the server exited"
                time.sleep(0.02)
        assert answered is not None, "no HTTP answer within 60 s"
        assert b"<title>Analyzer Lab</title>" in page
        ready = wait_until(
            lambda: (
                next((at, text) for at, text in lines if "Analyzer Lab: http://" in text)
                if any("Analyzer Lab: http://" in text for _, text in lines)
                else None
            ),
            60,
            "the ready line",
        )
        assert answered < ready[0]  # the page came before the lab was ready
        found = re.search(r"page served after ([\d.]+) s, ready in ([\d.]+) s", ready[1])
        assert found, ready[1]
        assert float(found[1]) < float(found[2])
    finally:
        stop_process(proc)
