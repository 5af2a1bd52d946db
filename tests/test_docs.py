"""The documentation (``docs/``) builds with warnings as errors, every notebook runs (nbclient,
the ``python3`` ipykernel) and every code example runs (Sphinx's doctest builder over the
pages and the API's docstrings). The two builds run once per session, side by side."""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.support.requirements import require_modules

pytestmark = [pytest.mark.slow, pytest.mark.timeout(900)]

DOCS = Path(__file__).resolve().parent.parent / "docs"
NOTEBOOKS = sorted(DOCS.glob("notebooks/*.ipynb"))


def sphinx(builder: str, out: Path, *options: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-b", builder, "-q"]
        + ["-d", str(out / "doctrees"), *options, str(DOCS), str(out / builder)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )


@pytest.fixture(scope="session")
def builds(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, tuple[int, str, Path]]]:
    """The HTML build (notebooks executed) and the doctest build, each: (exit code, what it
    printed, its output folder)."""
    require_modules("sphinx", "myst_nb", "ipykernel", "pandas", "matplotlib")
    html_dir = tmp_path_factory.mktemp("docs-html")
    doctest_dir = tmp_path_factory.mktemp("docs-doctest")
    jobs = {
        "html": (sphinx("html", html_dir), html_dir),
        # the notebooks ran in the HTML build: the doctest build reads them unexecuted
        "doctest": (sphinx("doctest", doctest_dir, "-D", "nb_execution_mode=off"), doctest_dir),
    }
    try:
        done = {}
        for name, (job, out) in jobs.items():
            printed, _ = job.communicate(timeout=800)
            done[name] = (job.returncode, printed, out / name)
        yield done
    finally:
        for job, _ in jobs.values():
            job.kill()


def sphinx_warnings(printed: str) -> list[str]:
    return [line for line in printed.splitlines() if "WARNING" in line or "ERROR" in line]


def test_the_docs_build_with_warnings_as_errors(builds: dict[str, tuple[int, str, Path]]) -> None:
    code, printed, out = builds["html"]
    assert code == 0, printed[-4000:]
    warnings = [w for w in sphinx_warnings(printed) if "[IPKernelApp]" not in w]
    assert warnings == []
    for page in ("index", "getting-started", "api", "assignments", "classroom", "deployment"):
        assert (out / f"{page}.html").exists(), page
    api = (out / "api.html").read_text(encoding="utf-8")
    for name in ("lessons", "run", "runs", "check", "grade", "serve", "Run", "Runs", "Scene"):
        assert f'id="analyzer_lab.api.{name}"' in api, name


@pytest.mark.parametrize("notebook", [p.stem for p in NOTEBOOKS])
def test_every_notebook_runs(builds: dict[str, tuple[int, str, Path]], notebook: str) -> None:
    code, printed, out = builds["html"]
    assert code == 0, printed[-4000:]
    page = (out / "notebooks" / f"{notebook}.html").read_text(encoding="utf-8")
    cells = page.count('class="cell docutils container"')
    outputs = page.count('class="cell_output docutils container"')
    assert cells >= 2 and outputs >= cells - 2, (cells, outputs)  # executed, with outputs
    assert "Traceback" not in page


def test_the_notebooks_are_one_per_chapter_and_article() -> None:
    assert [p.stem for p in NOTEBOOKS] == [
        "chapter1-sphere",
        "chapter2-positioner",
        "laser-interpolation",
        "servo-offset",
    ]


def test_every_code_example_runs(builds: dict[str, tuple[int, str, Path]]) -> None:
    code, printed, out = builds["doctest"]
    summary = (out / "output.txt").read_text(encoding="utf-8")
    assert code == 0, summary[-4000:] + printed[-2000:]
    totals = summary.rsplit("Doctest summary", 1)[-1]
    tests = int(re.findall(r"(\d+) tests", totals)[-1])
    assert tests >= 50 and "\n    0 failures in tests" in totals
