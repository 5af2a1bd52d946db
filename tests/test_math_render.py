"""MathML rendering of derivation steps: math appears, nothing executable gets through."""

from __future__ import annotations

import pytest
import sympy as sp
from analyzer_lab.lessons.kit.contract import DerivationStep
from analyzer_lab.view.math import derivation_to_html, expr_to_mathml, sanitize_mathml, step_to_html


def test_sympy_equation_becomes_math_element() -> None:
    x, t = sp.symbols("x t")
    out = expr_to_mathml(sp.Eq(sp.Symbol("dx/dt"), 5 * x + sp.sin(10 * t)))
    assert out.startswith('<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">')
    assert out.endswith("</math>")
    assert "<mi>sin</mi>" in out and "<mn>10</mn>" in out and "dx/dt" in out


def test_latex_string_becomes_math_element() -> None:
    out = expr_to_mathml(r"\omega = \frac{V}{|\nabla F|}")
    assert out.startswith("<math") and "<mfrac>" in out


def test_symbol_names_with_markup_are_escaped() -> None:
    out = expr_to_mathml(sp.Symbol("<img src=x onerror=alert(1)>") + 1)
    assert "<img" not in out and "onerror=alert(1)&gt;" in out


def test_latex_text_cannot_inject_script() -> None:
    out = expr_to_mathml(r"\text{<script>alert(1)</script>} + x")
    assert "<script" not in out.lower() and "alert" not in out


def test_sanitizer_drops_foreign_elements_and_attributes() -> None:
    dirty = (
        '<math><mi onclick="evil()" mathvariant="bold">a</mi><iframe src="x"></iframe>'
        "<b>bold</b><mo>&lt;</mo></math>"
    )
    clean = sanitize_mathml(dirty)
    assert "onclick" not in clean and "iframe" not in clean and "<b>" not in clean
    assert 'mathvariant="bold"' in clean and "bold" in clean and "<mo>&lt;</mo>" in clean


def test_step_html_escapes_prose_and_shows_tags() -> None:
    step = DerivationStep(
        "Title <b>",
        "a & b < c",
        [sp.Symbol("x"), sp.Symbol("y")],
        "(1.54)",
        reconstructed="lost <here>",
    )
    out = step_to_html(step, 3)
    assert "3. Title &lt;b&gt;" in out and "a &amp; b &lt; c" in out
    assert "(1.54)" in out and 'class="al-reconstructed"' in out and "lost &lt;here&gt;" in out
    assert out.count("<math") == 2


def test_a_steps_source_remark_and_tag_word_go_through_the_pages_language() -> None:
    """``text`` translates the title, the source and the remark (the part after
    ``corrected:``), ``tr`` the tag word; the tag's class stays the kind."""
    step = DerivationStep("T", source="Fig. 1.15", reconstructed="corrected: sign <lost>")
    out = step_to_html(step, 1, text=lambda t: f"<{t}>", tr=str.upper)
    assert "&lt;Fig. 1.15&gt;" in out and "&lt;sign &lt;lost&gt;&gt;" in out
    assert 'class="al-corrected"' in out and ">CORRECTED<" in out
    assert "CORRECTED: &lt;sign" in out and "corrected:" not in out
    plain = step_to_html(DerivationStep("T", reconstructed="lost here"))
    assert ">reconstructed<" in plain and "reconstructed: lost here" in plain


def test_a_figures_caption_goes_through_the_pages_language() -> None:
    """The caption (``aria-label`` and the line drawing it) is translated, escaped, the
    rest of the figure is kept."""
    svg = (
        '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 40" aria-label="Fig &amp; A">'
        '<text x="10" y="20" font-weight="bold">Fig &amp; A</text><text>x0</text></svg>'
    )
    out = step_to_html(
        DerivationStep("T", svg=svg), text=lambda t: "Рис <&>" if t == "Fig & A" else t
    )
    assert ">Рис &lt;&amp;&gt;</text>" in out  # the root's aria-label is not kept
    assert "Fig" not in out and ">x0</text>" in out
    assert "Fig &amp; A</text>" in step_to_html(DerivationStep("T", svg=svg))


def test_step_without_reconstruction_has_no_tag() -> None:
    out = step_to_html(DerivationStep("Plain", math=sp.Integer(1), source="(1.42)"))
    assert "reconstructed" not in out


def test_sphere_derivation_renders() -> None:
    from analyzer_lab.lessons.analyzers.sphere import LESSON

    params = LESSON.resolve(preset="example-1.2")
    out = derivation_to_html(LESSON.derivation(params))
    assert out.count("<math") >= 8
    assert "(1.54)" in out and "al-reconstructed" in out
    assert "<script" not in out


def test_block_diagram_svg_is_rendered_and_sanitized():
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.view.math import sanitize_svg, step_to_html

    lesson = get_lesson("sphere")
    step = lesson.block_diagram_step(lesson.resolve(), lesson.prepare(lesson.resolve()))
    out = step_to_html(step)
    assert (
        out.count("<svg") == 1
        and "viewBox=" in out
        and out.count("<rect") >= 6
        and out.count("<circle") >= 6
    )
    hostile = (
        '<svg onload="alert(1)"><script>alert(2)</script><a href="javascript:x"><text>t</text></a>'
        '<rect fill="url(javascript:alert(3))" width="5"/><text x="1">&lt;b&gt;</text>'
        '<foreignObject><div>x</div></foreignObject><image href="data:x"/></svg>'
    )
    clean = sanitize_svg(hostile)
    for bad in (
        "onload",
        "script",
        "javascript",
        "<a",
        "foreignobject",
        "<image",
        "<div",
        "alert(2)",
    ):
        assert bad not in clean.lower(), bad
    assert "&lt;b&gt;" in clean and '<rect width="5">' in clean


def test_symbol_names_never_show_tex() -> None:
    from analyzer_lab.view.math import plain_name

    assert plain_name(r"z_{z\,pr}") == "z_z pr"
    assert plain_name("varphi") == "φ"
    assert plain_name(r"\varphi_1") == "φ_1"
    html_out = expr_to_mathml(sp.Symbol("varphi") + sp.Symbol(r"z_{z\,pr}"))
    assert "varphi" not in html_out and "{" not in html_out and "\\" not in html_out


def test_time_derivative_uses_an_ordinary_d() -> None:
    t = sp.Symbol("t")
    out = expr_to_mathml(sp.Derivative(sp.Function("x")(t), t))
    assert "\u2146" not in out and "&dd;" not in out
    assert '<mi mathvariant="normal">d</mi>' in out


def test_derivatives_read_as_in_the_textbook() -> None:
    """d²φ/dt² (the power on d above, on t below), the function by its name alone; a
    partial derivative of a function of several variables with ∂."""
    t, s = sp.symbols("t s")
    out = expr_to_mathml(sp.Derivative(sp.Function("phi")(t), (t, 2)))
    d2 = '<msup><mi mathvariant="normal">d</mi><mn>2</mn></msup>'
    assert (
        f"<mfrac><mrow>{d2}<mi>&#966;</mi></mrow>" in out
        or f"<mfrac><mrow>{d2}<mi>φ</mi></mrow>" in out
    )
    assert (
        '<mrow><mi mathvariant="normal">d</mi><msup><mi>t</mi><mn>2</mn></msup></mrow></mfrac>'
        in out
    )
    assert "phi" not in out and "(" not in out
    part = expr_to_mathml(sp.Derivative(sp.Function("f")(t, s), t, s))
    assert part.count("∂") + part.count("&#8706;") == 3 and "<mo>(</mo>" in part


def test_a_derivative_is_one_factor_and_a_squared_one_keeps_parentheses() -> None:
    t, m = sp.Symbol("t"), sp.Symbol("m")
    phi = sp.Function("phi")(t)
    square = expr_to_mathml(m * phi.diff(t) ** 2 - m)
    assert (
        "<msup><mrow><mo>(</mo><mfrac>" in square and "<mo>)</mo></mrow><mn>2</mn></msup>" in square
    )
    assert "\u2212" in square and "<mo>-</mo>" not in square
    factor = expr_to_mathml(m * phi.diff(t, 2))
    assert "<mo>&InvisibleTimes;</mo><mfrac>" in factor or "<mo>\u2062</mo><mfrac>" in factor
    assert "<mo>(</mo>" not in factor


def test_names_are_written_as_in_the_textbook() -> None:
    """x_A(t) is x with subscript A (not sympy's lower-cased ``x_a(t)``), \\psi is ψ, an
    equation with a matrix side stays an equation."""
    t = sp.Symbol("t")
    out = expr_to_mathml(sp.Function("x_A")(t) + sp.Symbol(r"\psi"))
    assert "<msub><mi>x</mi><mi>A</mi></msub>" in out and "x_a" not in out
    assert "ψ" in out or "&#968;" in out
    eq = expr_to_mathml(sp.Eq(sp.Symbol(r"\psi"), sp.Matrix([[0]]), evaluate=False))
    assert "False" not in eq and "<mtable>" in eq and "<mo>=</mo>" in eq
    dot = expr_to_mathml(sp.Symbol(r"\dot\varphi_0"))
    assert '<msub><mover accent="true">' in dot and "dot" not in dot


def test_a_long_sum_wraps_at_its_terms_only_where_needed() -> None:
    """A long sum is one formula per term, in a wrapping row (the browser breaks the line
    only when the panel is too narrow); a short one is a single formula."""
    from analyzer_lab.view.math import formula_html

    xs = sp.symbols("x1:13")
    eq = sp.Eq(sp.Symbol("y"), sum(sp.Symbol(f"a{k}") * x**2 for k, x in enumerate(xs)))
    out = formula_html(eq)
    assert 'class="al-wrap"' in out and out.count("<math") == 13  # "y =" and 12 terms
    assert out.count(">=</mo>") == 1 and out.count(">+</mo>") == 11
    short = formula_html(sp.Eq(sp.Symbol("y"), xs[0]))
    assert "al-wrap" not in short and short.count("<math") == 1
    minus = formula_html(sp.Eq(sp.Symbol("y"), xs[0] - xs[1] + xs[2]))
    assert minus.count("<math") == 4 and "\u2212" in minus
    tex = formula_html(r"a=1,\quad b=2,\quad c=3")
    assert 'class="al-wrap al-wrap-text"' in tex and tex.count("<math") == 3


def test_formulas_never_shrink_below_a_readable_size() -> None:
    from analyzer_lab.view.math import MIN_FORMULA_PX, derivation_to_html

    out = derivation_to_html([DerivationStep("s", math=sp.Symbol("x") ** 2)])
    assert "cqi" not in out and "clamp(" not in out and MIN_FORMULA_PX >= 12
    assert f"max({MIN_FORMULA_PX}px" in out and "overflow-x:auto" in out


def test_figures_scale_to_the_panel_width() -> None:
    from analyzer_lab.view.math import step_to_html

    svg = '<svg width="660" height="300"><rect x="0" y="0" width="660" height="300"/></svg>'
    out = step_to_html(DerivationStep("diagram", svg=svg))
    head = out[out.index("<svg") : out.index(">", out.index("<svg"))]
    assert 'width="100%"' in head and 'viewBox="0 0 660 300"' in head
    assert 'width="660"' not in head


def test_no_lesson_shows_raw_tex() -> None:
    """Every preset's derivation, rendered: no backslash or TeX name in the shown text,
    and no brace outside a formula (inside one a brace is a set or a case split)."""
    import html as html_lib
    import re

    from analyzer_lab.lessons.catalog import all_lessons

    for lesson in all_lessons():
        seen: set[str] = set()
        for preset in lesson.presets:
            out = derivation_to_html(lesson.derivation(lesson.resolve(preset=preset.name)))
            if out in seen:
                continue
            seen.add(out)
            out = re.sub(r"<style>.*?</style>", " ", out, flags=re.S)  # not shown
            maths = re.findall(r"<math.*?</math>", out, flags=re.S)
            prose = re.sub(r"<math.*?</math>", " ", out, flags=re.S)
            prose_text = html_lib.unescape(re.sub(r"<[^>]+>", " ", prose))
            math_text = html_lib.unescape(re.sub(r"<[^>]+>", " ", " ".join(maths)))
            where = f"{lesson.id}:{preset.name}"
            for tex in ("\\", "varphi", "{", "}"):
                assert tex not in prose_text, (where, tex, prose_text[:200])
            for tex in ("\\", "varphi"):
                assert tex not in math_text, (where, tex)


def test_a_corrected_misprint_is_tagged_corrected() -> None:
    from analyzer_lab.view.math import step_to_html

    out = step_to_html(DerivationStep("(2.19)", reconstructed="corrected: (2.18) names g_i"))
    assert ">corrected</span>" in out and "corrected: (2.18) names g<sub>i</sub>" in out
    out = step_to_html(DerivationStep("(1.53)", reconstructed="lost in the source"))
    assert ">reconstructed</span>" in out and "reconstructed: lost in the source" in out


@pytest.mark.parametrize(
    "text, html_",
    [
        ("m varpi^2 (e + z)", "m ϖ<sup>2</sup> (e + z)"),
        ("A_phiy/A_x", "A<sub>φy</sub>/A<sub>x</sub>"),
        ("varpi_c, varpi_K", "ϖ<sub>c</sub>, ϖ<sub>K</sub>"),
        ("phi_y = A_phiy sin(varpi t)", "φ<sub>y</sub> = A<sub>φy</sub> sin(ϖ t)"),
        ("e^(-t/tau) and x^2.5", "e^(-t/τ) and x^2.5"),  # only a one-digit power is raised
        ("pi r^2 < 10^4", "π r<sup>2</sup> &lt; 10<sup>4</sup>"),
    ],
)
def test_prose_writes_names_as_the_textbook(text: str, html_: str) -> None:
    from analyzer_lab.view.math import prose_html

    assert prose_html(text) == html_
