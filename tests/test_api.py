"""The Python API (``import analyzer_lab as al``): response objects, tables, figures, scenes,
and bad input refused with the command line's own one-line messages."""

from __future__ import annotations

import html
import json
import re
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import analyzer_lab as al
import numpy as np
import pytest
from analyzer_lab.lessons.analyzers.sphere import V2_TABLE

from tests.support.requirements import require_modules

#: A formula that would create a file if it were evaluated as code.
PWNED = "/tmp/analyzer-lab-evaluated"
ATTACK = f"__import__('os').system('touch {PWNED}')"


@pytest.fixture(scope="module")
def example_1_1() -> al.Run:
    return al.run("sphere", preset="example-1.1")


def test_a_run_is_a_response_object(example_1_1: al.Run) -> None:
    run = example_1_1
    assert run.lesson == "sphere" and run.preset == "example-1.1" and run.label == "example-1.1"
    assert run.t[0] == 0.0 and run.t[-1] == pytest.approx(10.0) and run.t_end == 10.0
    assert {"x", "y", "z", "vx", "vy", "vz", "v2"} <= set(run.series)
    assert all(v.shape == run.t.shape for v in run.series.values())
    assert run.units["v2"] == "units²/s²" and run.units["drift"] == ""
    assert run.values["u1"] == "5" and run.values["R"] == 1.0  # every value used
    assert run.metrics["v2_max"] == pytest.approx(50.0)
    assert run["t"] is run.t and np.array_equal(run["v2"], run.series["v2"])
    assert "samples=1001" in repr(run)


def test_values_over_a_preset_are_named_in_the_label() -> None:
    run = al.run("sphere", "example-1.2", 2, u1="t", family=2)
    assert run.given == {"u1": "t", "family": 2} and run.values["u1"] == "t"
    assert run.label == "example-1.2, u1=t, family=2" and run.t[-1] == pytest.approx(2.0)
    assert "x_2" in run.series  # the family's second curve
    keyword = al.run("parabola", **{"lambda": 0.05})  # a parameter named as a keyword
    assert keyword.values["lambda"] == 0.05


def test_the_textbook_tables_of_examples_1_1_to_1_3() -> None:
    require_modules("pandas")
    for preset, table in V2_TABLE.items():
        run = al.run("sphere", preset=preset)
        frame = run.to_pandas()
        at = frame.loc[[float(t) for t in range(len(table))], "v2"]
        assert np.allclose(at.to_numpy(), table, atol=5e-4), preset


def test_to_csv_is_the_command_lines_csv(tmp_path: Path, example_1_1: al.Run) -> None:
    text = example_1_1.to_csv(tmp_path / "run.csv")
    assert (tmp_path / "run.csv").read_text() == text
    assert text.splitlines()[0] == "t," + ",".join(example_1_1.series)
    assert len(text.splitlines()) == len(example_1_1.t) + 1


def test_to_pandas(example_1_1: al.Run) -> None:
    require_modules("pandas")
    frame = example_1_1.to_pandas()
    assert frame.index.name == "t" and list(frame.columns) == list(example_1_1.series)
    assert frame.attrs["units"]["vx"] == "units/s"
    family = al.runs([example_1_1, {"lesson": "sphere", "preset": "example-1.2", "t_end": 1}])
    table = family.to_pandas()
    assert table.index.names == ["run", "t"] and len(table) == len(example_1_1.t) + 101


@pytest.mark.parametrize(
    "module, extra, call",
    [
        ("pandas", "pandas", lambda run: run.to_pandas()),
        ("matplotlib.pyplot", "plot", lambda run: run.plot()),
    ],
)
def test_a_missing_extra_says_which_to_install(
    monkeypatch: pytest.MonkeyPatch, example_1_1: al.Run, module: str, extra: str, call: object
) -> None:
    monkeypatch.setitem(sys.modules, module, None)  # as if not installed
    with pytest.raises(al.AnalyzerLabError) as err:
        call(example_1_1)  # type: ignore[operator]
    assert f"pip install 'analyzer-lab[{extra}]'" in str(err.value)
    assert module.split(".")[0] in str(err.value)


def test_plot_returns_titled_unit_labelled_axes(example_1_1: al.Run) -> None:
    require_modules("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.axes import Axes

    ax = example_1_1.plot()  # the lesson's first live plot
    assert isinstance(ax, Axes)
    assert ax.get_title() == "sphere (example-1.1): velocity components"
    assert ax.get_xlabel() == "t [s]" and ax.get_ylabel() == "vx, vy, vz [units/s]"
    assert len(ax.get_lines()) == 3
    ax = example_1_1.plot("x", "v2")
    assert ax.get_ylabel() == "x [units], v2 [units²/s²]"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["x [units]", "v2 [units²/s²]"]
    family = al.runs({"lesson": "sphere", "preset": p} for p in ("example-1.1", "example-1.3"))
    ax = family.plot("v2")
    assert ax.get_title() == "sphere: v2" and ax.get_ylabel() == "v2 [units²/s²]"
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["example-1.1: v2 [units²/s²]", "example-1.3: v2 [units²/s²]"]
    with pytest.raises(al.AnalyzerLabError, match="no series 'nope'; known: x, y"):
        example_1_1.plot("nope")


#: Where a page would reach the network (an address in an attribute, a CSS import).
NETWORK = re.compile(
    r"""(?:src|href|action)\s*=\s*["']?\s*(?:https?:)?//|@import|url\(\s*["']?https?:"""
)


@pytest.mark.parametrize(
    "lesson, preset, title",
    [
        ("sphere", "example-1.1", "Problem 1.4 Curve on a sphere"),
        ("linear-positioner", None, "Problem 2.1 Single-coordinate linear positioner"),
        ("laser-5axis", "final-test", "LSP-2000 article LSP-2000 five-axis laser"),
    ],
)
def test_show_is_a_self_contained_html_scene(
    tmp_path: Path, lesson: str, preset: str | None, title: str
) -> None:
    run = al.run(lesson, preset=preset)
    scene = run.show(height=300)
    page = scene.html
    assert page.startswith("<!doctype html>") and f"<title>Analyzer Lab replay: {title}" in page
    assert "window.__VISER_EMBED_DATA__=" in page and 'id="al-caption"' in page
    assert NETWORK.search(page) is None  # nothing fetched to view it
    inline = scene._repr_html_()
    assert inline.startswith('<div style="border:1px solid #ddd"><iframe srcdoc="&lt;!doctype')
    srcdoc = re.search(r'srcdoc="([^"]*)"', inline)
    assert srcdoc is not None and html.unescape(srcdoc[1]) == page  # the page, isolated
    assert 'height="300"' in inline and "<script" not in inline
    assert scene.save(tmp_path / "scene.html").read_text(encoding="utf-8") == page


def test_lessons_lists_the_catalog() -> None:
    items = al.lessons()
    assert [i.id for i in items][:2] == ["motion-program", "parabola"] and len(items) == 19
    sphere = next(i for i in items if i.id == "sphere")
    assert sphere.problem == "Problem 1.4" and "u1" in sphere.params
    assert sphere.presets[0] == "example-1.1" and sphere.series["vx"] == "units/s"
    assert sphere.declaration["presets"][0]["values"]["u1"] == "5"
    assert al.lessons("servo-errors")[0].chapter == al.lessons()[-2].chapter
    import analyzer_lab.lessons.catalog as catalog
    import analyzer_lab.serve.cli as cli

    assert al.lessons.catalog is catalog  # al.lessons is the model package too
    assert al.serve.cli is cli and callable(al.serve)  # and al.serve the serving package


def test_check_and_grade() -> None:
    checks = al.check("sphere")
    assert len(checks) == 8 and all(c.passed for c in checks)
    assert checks[0].lesson == "sphere" and checks[0].expected and checks[0].got
    ok = al.grade("sphere-circle-plane", {"u1": "2", "u2": "2", "u3": "1"})
    assert ok.passed and ok.to_json_dict()["assignment"] == "sphere-circle-plane"
    wrong = al.grade("sphere-circle-plane", {"u1": "5"})
    assert not wrong.passed and {c.id for c in wrong.failed} == {"plane", "circle"}


def test_grade_takes_files(tmp_path: Path) -> None:
    from analyzer_lab.lessons.assignments import READY_DIR

    answer = tmp_path / "answer.json"
    answer.write_text(json.dumps({"u1": "2", "u2": "2", "u3": "1"}))
    assert al.grade(READY_DIR / "sphere-circle-plane.json", answer).passed
    assert al.grade("sphere-circle-plane", str(answer), folder=READY_DIR).passed


#: Bad input, each given to the command line and to the API (``answer``: an answer file
#: that sets a locked parameter): (argv, call).
BAD: list[tuple[list[str], Callable[[Path], object]]] = [
    (["run", "nosuch"], lambda answer: al.run("nosuch")),
    (["run", "sphere", "--preset", "nope"], lambda answer: al.run("sphere", preset="nope")),
    (["run", "sphere", "--set", "nope=1"], lambda answer: al.run("sphere", nope=1)),
    (["run", "sphere", "--set", "R=-1"], lambda answer: al.run("sphere", R=-1)),
    (["run", "sphere", "--set", "R=1e300"], lambda answer: al.run("sphere", R="1e300")),
    (["run", "sphere", "--set", "h=9e-6"], lambda answer: al.run("sphere", h=9e-6)),
    (
        ["run", "sphere", "--set", f"u1={ATTACK}"],
        lambda answer: al.run("sphere", u1=ATTACK),
    ),
    (["run", "sphere", "--set", "u1=t**999"], lambda answer: al.run("sphere", u1="t**999")),
    (["run", "sphere", "--set", "u1=nan"], lambda answer: al.run("sphere", u1="nan")),
    (["run", "sphere", "--t-end", "0"], lambda answer: al.run("sphere", t_end=0)),
    (["run", "sphere", "--t-end", "2e5"], lambda answer: al.run("sphere", t_end=2e5)),
    (["run", "sphere", "--t-end", "soon"], lambda answer: al.run("sphere", t_end="soon")),
    (
        ["run", "sphere", "--set", "h=1.1e-5", "--t-end", "100000"],
        lambda answer: al.run("sphere", h=1.1e-5, t_end=100000),
    ),
    (
        ["run", "sphere", "--set", "u1=sqrt(101 - t)", "--t-end", "120"],
        lambda answer: al.run("sphere", u1="sqrt(101 - t)", t_end=120),
    ),
    (["check", "nosuch"], lambda answer: al.check("nosuch")),
    (["grade", "nosuch", "{answer}"], lambda answer: al.grade("nosuch", answer)),
    (
        ["grade", "sphere-circle-plane", "{answer}"],
        lambda answer: al.grade("sphere-circle-plane", answer),
    ),
]
#: What the command line puts before its one line (its own, or argparse's).
PREFIX = re.compile(r"^analyzer-lab(?: \w+)?: error: ")


def test_bad_input_is_refused_with_the_command_lines_messages(tmp_path: Path) -> None:
    answer = tmp_path / "answer.json"
    answer.write_text(json.dumps({"x0": 5}))
    argvs = [[a.replace("{answer}", str(answer)) for a in argv] for argv, _ in BAD]
    probe = (
        "import contextlib, io, json\n"
        "from analyzer_lab.serve.cli import main\n"
        "out = []\n"
        f"for argv in {argvs!r}:\n"
        "    err = io.StringIO()\n"
        "    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):\n"
        "        code = main(argv)\n"
        "    out.append([code, err.getvalue()])\n"
        "print(json.dumps(out))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, timeout=300, check=True
    )
    printed = json.loads(done.stdout.splitlines()[-1])
    for (argv, call), (code, stderr) in zip(BAD, printed):
        assert code == 2, argv
        with pytest.raises(al.AnalyzerLabError) as err:
            call(answer)
        line = stderr.strip().splitlines()[-1]
        assert PREFIX.match(line), line
        assert PREFIX.sub("", line) == str(err.value), argv
    assert not Path(PWNED).exists()  # nothing was evaluated as code


def test_the_error_names_the_parameter_and_the_limit() -> None:
    with pytest.raises(al.AnalyzerLabError, match=r"^h: 9e-06 is below the minimum 1e-05 s$"):
        al.run("sphere", h=9e-6)
    with pytest.raises(al.AnalyzerLabError, match=r"the limit is 10,000,000"):
        al.run("sphere", h=1.1e-5, t_end=100000)
    with pytest.raises(
        al.AnalyzerLabError, match=r"^x is not finite \(NaN or infinite\) from t = 101.05 s on"
    ):
        al.run("sphere", u1="sqrt(101 - t)", t_end=120)
    with pytest.raises(al.AnalyzerLabError, match=r"expected a formula of t, got list"):
        al.run("sphere", u1=[1, 2])
    with pytest.raises(al.AnalyzerLabError, match="each item is a Run or a mapping"):
        al.runs(["sphere"])
    assert al.AnalyzerLabError.__module__ == "analyzer_lab"


@pytest.mark.live
def test_serve_starts_a_live_page_shown_inline_and_stops() -> None:
    import urllib.request

    lab = al.serve("circle", height=500)
    try:
        assert lab.running and lab.url.startswith("http://127.0.0.1:")
        assert len(lab.instructor_code) >= 12
        with urllib.request.urlopen(lab.url, timeout=10) as page:
            assert page.status == 200
        inline = lab._repr_html_()
        assert inline.startswith(f'<iframe src="{lab.url}" width="100%" height="500"')
    finally:
        lab.stop()
    assert not lab.running and "analyzer-lab: stopping" in lab.output
    with pytest.raises(al.AnalyzerLabError, match="^port must be in 0..65535, got 70000$"):
        al.serve(port=70000)
