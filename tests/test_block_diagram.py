"""Block diagrams (Fig. 1.5 notation) generated from analyzer equations."""

import re
import xml.etree.ElementTree as ET

import sympy as sp
from analyzer_lab.lessons.analyzers.field.block_diagram import block_diagram, label_of

x, y, z, u, u1, u2, u3, w = sp.symbols("x y z u u1 u2 u3 ω", real=True)
a11, a12, a22, a13, a23 = sp.symbols("a11 a12 a22 a13 a23")
D = lambda n: sp.Symbol(f"d{n}/dt")  # noqa: E731
SPHERE = [
    sp.Eq(D("x"), u1 * y - u2 * z),
    sp.Eq(D("y"), -u1 * x + u3 * z),
    sp.Eq(D("z"), u2 * x - u3 * y),
]


def test_sphere_154_counts():
    d = block_diagram(SPHERE)
    assert d.counts() == {"integrator": 3, "multiplier": 6, "summer": 3, "source": 3}
    assert [b.initial for b in d.blocks if b.kind == "integrator"] == ["x0", "y0", "z0"]
    signs = sorted(w.sign for w in d.wires if d.block(w.dst).kind == "summer")
    assert signs == [-1, -1, -1, 1, 1, 1]


def test_fig_1_6_conic():
    eqs = [
        sp.Eq(D("x"), w**2 * (a12 * x + a22 * y + a23)),
        sp.Eq(D("y"), -(w**2) * (a11 * x + a12 * y + a13)),
    ]
    d = block_diagram(eqs, signals=("u",))
    assert (
        d.count("integrator") == 2
        and d.count("summer") == 2
        and d.count("scale") == 6
        and d.count("multiplier") == 0
    )
    assert sorted(b.label for b in d.blocks if b.kind == "scale") == sorted(
        ["a12", "a22", "a11", "a12", "ω^2", "-ω^2"]
    )
    assert sorted(b.label for b in d.blocks if b.kind == "constant") == ["a13", "a23"]


def test_fig_1_11_and_1_13_circle():
    d = block_diagram([sp.Eq(D("x"), u * y), sp.Eq(D("y"), -u * x)])
    assert d.counts() == {"integrator": 2, "source": 1, "multiplier": 2, "scale": 1}
    d = block_diagram([sp.Eq(D("x"), y), sp.Eq(D("y"), -x)])
    assert d.counts() == {"integrator": 2, "scale": 1}
    assert [b.label for b in d.blocks if b.kind == "scale"] == ["-1"]


def test_fig_1_27_and_1_30():
    d = block_diagram([sp.Eq(e.lhs, w * e.rhs) for e in SPHERE])
    assert d.count("multiplier") == 9 and d.count("summer") == 3 and d.count("source") == 4
    a, b, c = sp.symbols("a b c", positive=True)
    ell = [
        sp.Eq(D("x"), u1 * y / b**2 - u2 * z / c**2),
        sp.Eq(D("y"), -u1 * x / a**2 + u3 * z / c**2),
        sp.Eq(D("z"), u2 * x / a**2 - u3 * y / b**2),
    ]
    d = block_diagram(ell)
    assert d.count("multiplier") == 6 and d.count("scale") == 6
    assert sorted(b.label for b in d.blocks if b.kind == "scale") == [
        "1/a^2",
        "1/a^2",
        "1/b^2",
        "1/b^2",
        "1/c^2",
        "1/c^2",
    ]


def test_derivative_lhs_and_time_functions():
    t = sp.Symbol("t", real=True)
    X, Y = sp.Function("x")(t), sp.Function("y")(t)
    d = block_diagram(
        [sp.Eq(sp.Derivative(X, t), sp.sin(10 * t) * Y), sp.Eq(sp.Derivative(Y, t), -t * X)]
    )
    assert d.states == ("x", "y")
    assert sorted(b.label for b in d.blocks if b.kind == "source") == ["sin(10·t)", "t"]
    assert d.count("multiplier") == 2


def test_svg_is_self_contained_and_escaped():
    evil = sp.Symbol("<script>alert(1)</script>")
    d = block_diagram([sp.Eq(D("x"), evil * y), sp.Eq(D("y"), -x)], title="a < b & c")
    svg = d.svg
    ET.fromstring(svg)  # well-formed XML
    assert "<script" not in svg and "&lt;script&gt;" in svg
    assert not re.search(r"(href|src)\s*=", svg.replace('xmlns="http://www.w3.org/2000/svg"', ""))
    assert "a &lt; b &amp; c" in svg


def test_lessons_expose_the_diagram():
    from analyzer_lab.lessons.analyzers.ellipsoid import LESSON as E
    from analyzer_lab.lessons.analyzers.parabola import LESSON as P

    p = E.resolve(preset="example")
    assert E.block_diagram(p).counts()["integrator"] == 3
    step = [s for s in E.derivation(p) if s.title.startswith("Block diagram")][0]
    assert step.math is None and step.svg.startswith("<svg") and step.source == "Fig. 1.30"
    pp = P.resolve(preset="lambda-0.05")
    assert P.block_diagram(pp).count("scale") == 6


def test_label_of():
    assert label_of(sp.Symbol("a") ** 2) == "a^2"
    assert label_of(1 / sp.Symbol("b") ** 2) == "1/b^2"
    assert label_of(sp.Rational(1, 25)) == "1/25"
