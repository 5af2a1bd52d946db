"""Derivation steps as HTML with MathML (viser's markdown has no math).

The textbook's printer (:mod:`analyzer_lab.view.mathml_printer`, for expressions) and
latex2mathml (for LaTeX strings) produce MathML; neither escapes the text it copies
from ``\\text{}``, so every MathML string is rebuilt by :func:`sanitize_mathml` from a
whitelist of MathML elements and attributes with all text re-escaped.  Prose (titles,
text) is escaped and then shows Greek names and one-letter subscripts as the textbook
prints them (:func:`prose_html`).  Formulas keep the text's size (scripts not below
:data:`MIN_FORMULA_PX`); a sum wraps at its terms only where the panel is too narrow,
and what is still too wide scrolls inside its own line.
"""

from __future__ import annotations

import html
import logging
import re
from collections.abc import Callable, Iterable, Sequence
from html.parser import HTMLParser

import sympy as sp
from analyzer_lab.i18n import N_
from analyzer_lab.lesson_texts import figure_caption, remark_parts
from analyzer_lab.lessons.kit.contract import DerivationStep
from analyzer_lab.view.mathml_printer import TextbookMathML, tex_free, textbook_mathml

MATHML_TAGS = frozenset(
    """math mrow mi mn mo ms mtext mspace msup msub msubsup mfrac msqrt mroot mtable mtr mtd
    mlabeledtr mstyle mover munder munderover mpadded mphantom menclose merror semantics mfenced""".split()
)
MATHML_ATTRS = frozenset(
    """display mathvariant stretchy fence separator lspace rspace columnalign rowalign accent
    accentunder linethickness displaystyle scriptlevel width height depth open close separators
    columnspacing rowspacing notation form largeop movablelimits symmetric minsize maxsize""".split()
)
#: Elements whose content is dropped with them (never shown as text).
DROP_CONTENT = frozenset(
    {"script", "style", "annotation", "annotation-xml", "iframe", "object", "svg"}
)
_SAFE_VALUE = re.compile(r"^[\w .,:%#+\-]*$")

log = logging.getLogger(__name__)


#: SVG figures (block diagrams) are rebuilt from this whitelist: shapes and text only.
SVG_TAGS = frozenset(
    "svg g defs marker rect line polyline polygon path circle ellipse text tspan title".split()
)
SVG_ATTRS = frozenset(
    """width height viewbox x y x1 y1 x2 y2 cx cy r rx ry d points fill stroke stroke-width
    stroke-dasharray font-family font-size font-weight text-anchor dominant-baseline transform
    marker-end marker-start id refx refy markerwidth markerheight orient opacity role aria-label
    preserveaspectratio""".split()
)
_SAFE_SVG_VALUE = re.compile(
    r"^(?!.*(?:javascript|data:|expression))[\w .,:%#+\-()]*$", re.IGNORECASE
)
_SVG_NAMES = {
    "viewbox": "viewBox",
    "refx": "refX",
    "refy": "refY",
    "markerwidth": "markerWidth",
    "markerheight": "markerHeight",
    "preserveaspectratio": "preserveAspectRatio",
}


class _Sanitizer(HTMLParser):
    def __init__(
        self,
        tags: frozenset[str] = MATHML_TAGS,
        attrs: frozenset[str] = MATHML_ATTRS,
        drop: frozenset[str] = DROP_CONTENT,
        safe: re.Pattern[str] = _SAFE_VALUE,
        root: tuple[str, str] = ("math", 'xmlns="http://www.w3.org/1998/Math/MathML"'),
        names: dict[str, str] | None = None,
    ) -> None:
        super().__init__(convert_charrefs=True)
        self.out: list[str] = []
        self.open: list[str] = []
        self.drop_depth = 0
        self.tags, self.attrs, self.drop, self.safe, self.root = tags, attrs, drop, safe, root
        self.names = names or {}

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag in self.drop:
            self.drop_depth += 1
            return
        if self.drop_depth or tag not in self.tags:
            return
        parts = [tag]
        if tag == self.root[0]:
            parts.append(self.root[1])
        for name, value in attrs:
            if name in self.attrs and value is not None and self.safe.match(value):
                parts.append(f'{self.names.get(name, name)}="{html.escape(value, quote=True)}"')
        self.out.append("<" + " ".join(parts) + ">")
        self.open.append(tag)

    def handle_startendtag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag in self.drop:
            return
        self.handle_starttag(tag, attrs)
        if not self.drop_depth and tag in self.tags:
            self.handle_endtag(tag)

    def handle_endtag(self, tag: str) -> None:
        if tag in self.drop:
            self.drop_depth = max(0, self.drop_depth - 1)
            return
        if self.drop_depth or tag not in self.tags or tag not in self.open:
            return
        while self.open:
            top = self.open.pop()
            self.out.append(f"</{top}>")
            if top == tag:
                break

    def handle_data(self, data: str) -> None:
        if not self.drop_depth:
            self.out.append(html.escape(data, quote=False))

    def result(self) -> str:
        self.close()
        while self.open:
            self.out.append(f"</{self.open.pop()}>")
        return "".join(self.out)


def sanitize_mathml(markup: str) -> str:
    """Rebuild MathML from the whitelist: unknown elements vanish (script/style with
    their content), attributes are filtered, text is escaped."""
    s = _Sanitizer()
    s.feed(markup)
    return s.result()


def sanitize_svg(markup: str) -> str:
    """Rebuild an SVG figure from the whitelist (shapes and text; no scripts, links,
    styles, foreign objects or event attributes); text is escaped."""
    s = _Sanitizer(
        SVG_TAGS,
        SVG_ATTRS,
        frozenset({"script", "style", "foreignobject", "a", "image", "use", "iframe", "object"}),
        _SAFE_SVG_VALUE,
        ("svg", 'xmlns="http://www.w3.org/2000/svg"'),
        _SVG_NAMES,
    )
    s.feed(markup)
    return s.result()


def plain_name(name: str) -> str:
    """A symbol name as plain text: TeX commands and braces removed (``z_{z\\,pr}`` ->
    ``z_z pr``, ``\\varphi`` -> ``φ``), markup characters escaped."""
    return html.escape(tex_free(name), quote=True)


#: Greek letters spelled out in prose, as the textbook prints them.
GREEK_WORDS = {
    "alpha": "α",
    "beta": "β",
    "gamma": "γ",
    "delta": "δ",
    "epsilon": "ε",
    "zeta": "ζ",
    "theta": "θ",
    "kappa": "κ",
    "lambda": "λ",
    "mu": "μ",
    "nu": "ν",
    "xi": "ξ",
    "pi": "π",
    "rho": "ρ",
    "sigma": "σ",
    "tau": "τ",
    "phi": "φ",
    "chi": "χ",
    "psi": "ψ",
    "omega": "ω",
    "varpi": "ϖ",
    "Gamma": "Γ",
    "Delta": "Δ",
    "Theta": "Θ",
    "Lambda": "Λ",
    "Sigma": "Σ",
    "Phi": "Φ",
    "Psi": "Ψ",
    "Omega": "Ω",
}
_GREEK_WORD = re.compile(r"(?<![A-Za-z])(" + "|".join(GREEK_WORDS) + r")(?![A-Za-z])")
#: A Greek letter opening a subscript, with an index of its own: ``A_phiy`` is A_φy.
_GREEK_INDEX = re.compile(r"(?<=_)(" + "|".join(GREEK_WORDS) + r")(?=[A-Za-z0-9]{1,2}(?!\w))")
#: A one-letter name with a short subscript in prose: ``x_A``, ``M_φ``, ``t_end``.
_SUBSCRIPT = re.compile(r"(?<![\w'])([A-Za-zα-ωΑ-Ωϖ])_([A-Za-z0-9α-ωΑ-Ωϖ]{1,4})(?![\w])")
#: A one-digit power after a name or a closing bracket in prose: ``varpi^2`` is ϖ².
_POWER = re.compile(r"(?<=[\w)])\^([0-9])(?![\w.])")


def prose_text(text: str) -> str:
    """Prose as plain text with the Greek letters spelled out written as letters
    (``varpi`` is ϖ, ``A_phiy`` is A_φy): a tooltip's text."""
    out = _GREEK_INDEX.sub(lambda m: GREEK_WORDS[m.group(1)], text)
    return _GREEK_WORD.sub(lambda m: GREEK_WORDS[m.group(1)], out)


def prose_html(text: str, words: Callable[[str], str] | None = None) -> str:
    """Prose as HTML, escaped, with names written as in the textbook: ``phi`` is φ,
    ``varpi`` is ϖ, ``x_A`` is x with subscript A, ``A_phiy`` is A with subscript φy,
    ``varpi^2`` is ϖ with the power 2 raised; a word as a subscript (``R_sopr``) in the
    page's language through ``words`` (:meth:`~analyzer_lab.i18n.Language.quantity`)."""

    def sub(m: re.Match[str]) -> str:
        index = m.group(2)
        if words is not None and len(index) >= 3 and index.isascii() and index.isalpha():
            index = html.escape(words(index))
        return f"{m.group(1)}<sub>{index}</sub>"

    out = _SUBSCRIPT.sub(sub, html.escape(prose_text(text)))
    return _POWER.sub(r"<sup>\1</sup>", out)


def _math(inner: str, display: str) -> str:
    return sanitize_mathml(f'<math display="{display}">{inner}</math>')


def _latex_inner(text: str) -> str:
    import latex2mathml.converter

    raw = latex2mathml.converter.convert(text)
    return re.sub(r"<math[^>]*>", "", raw, count=1).replace("</math>", "")


def expr_to_mathml(expr: sp.Basic | str, display: str = "block") -> str:
    """One sympy expression/equation (or a LaTeX string) as a sanitized ``<math>`` element."""
    display = "inline" if display == "inline" else "block"
    if isinstance(expr, str):
        try:
            return _math(_latex_inner(expr), display)
        except Exception:  # an unparsable LaTeX string is shown as escaped text
            log.warning("LaTeX not converted to MathML: %.80s", expr, exc_info=True)
            return f'<math display="{display}"><mtext>{html.escape(expr)}</mtext></math>'
    try:
        return _math(textbook_mathml(sp.sympify(expr)), display)
    except Exception:
        log.warning("expression not printed as MathML: %.80s", expr, exc_info=True)
        return f'<math display="{display}"><mtext>{html.escape(str(expr))}</mtext></math>'


def _signed_terms(side: sp.Basic, printer: TextbookMathML) -> list[str]:
    """The terms of a sum as MathML rows, each after the first with its own sign."""
    if not isinstance(side, sp.Add):
        return [printer.doprint(side)]
    rows = []
    for k, term in enumerate(printer._as_ordered_terms(side)):
        if k == 0:
            rows.append(printer.doprint(term))
        elif term.could_extract_minus_sign():
            rows.append(f'<mo form="infix">\u2212</mo>{printer.doprint(-term)}')
        else:
            rows.append(f'<mo form="infix">+</mo>{printer.doprint(term)}')
    return rows


def _pieces(item: sp.Basic | str) -> list[str] | None:
    """A statement cut where a line may break: a sum at its terms (``lhs =`` stays with
    the line before), a LaTeX string at its top-level ``\\quad``.  ``None`` when it is
    one piece."""
    if isinstance(item, str):
        parts = [p.strip() for p in re.split(r"\\quad(?![A-Za-z])", item) if p.strip()]
        if len(parts) < 2 or any(p.count("{") != p.count("}") for p in parts):
            return None
        return [_latex_inner(p) for p in parts]
    expr = sp.sympify(item)
    printer = TextbookMathML({})
    if isinstance(expr, sp.Equality):
        left = _signed_terms(expr.lhs, printer)
        right = _signed_terms(expr.rhs, printer)
        if len(left) + len(right) < 3:
            return None
        return [*left[:-1], f'{left[-1]}<mo form="infix">=</mo>', *right]
    if isinstance(expr, sp.Add):
        return _signed_terms(expr, printer)
    return None


def formula_html(item: sp.Basic | str) -> str:
    """One statement as a line of the step: one formula in display style, or a sum whose
    terms wrap onto further (indented) lines only where the panel is too narrow.  A
    piece wider than the panel scrolls inside its line; nothing is shrunk."""
    try:
        pieces = _pieces(item) or [
            _latex_inner(item) if isinstance(item, str) else textbook_mathml(sp.sympify(item))
        ]
    except Exception:  # shown as escaped text by expr_to_mathml, which logs why
        log.warning("statement not printed: %.80s", item, exc_info=True)
        return f'<div class="al-eq">{expr_to_mathml(item)}</div>'
    maths = "".join(
        _math(f'<mstyle displaystyle="true"><mrow>{p}</mrow></mstyle>', "inline") for p in pieces
    )
    if len(pieces) == 1:
        return f'<div class="al-eq">{maths}</div>'
    kind = "al-wrap al-wrap-text" if isinstance(item, str) else "al-wrap"
    return f'<div class="al-eq"><div class="{kind}">{maths}</div></div>'


def _as_list(math: sp.Basic | Sequence[sp.Basic] | str | None) -> list[sp.Basic | str]:
    if math is None:
        return []
    if isinstance(math, (str, sp.Basic)):
        return [math]
    if isinstance(math, (list, tuple)):
        return list(math)
    return [math]


RECON_STYLE = (
    "background:#fff3cd;color:#7a5600;border:1px solid #e0c060;border-radius:4px;"
    "padding:0 4px;font-size:max(11px,0.8em)"
)
SOURCE_STYLE = "color:#555;font-size:max(11px,0.85em);margin-left:6px"
#: The smallest text a formula shows (px): sub- and superscripts shrink to 75 % of their
#: base but not below this; a formula never shrinks to fit, it scrolls inside its line.
MIN_FORMULA_PX = 12
#: The derivation's style sheet: formulas at the text's size, scripts not below
#: MIN_FORMULA_PX, a long line scrolling inside itself, a sum wrapping with a hanging indent.
DERIVATION_CSS = (
    ".al-derivation .al-eq{margin:4px 0;line-height:normal;overflow-x:auto;overflow-y:hidden;"
    "padding:0.35em 0}"
    ".al-derivation math{font-size:1.05em}"
    ".al-derivation :is(msub,msup,msubsup,munder,mover,munderover,mroot)>:not(:first-child)"
    f"{{font-size:max({MIN_FORMULA_PX}px,0.75em)}}"
    ".al-derivation mfrac>*{font-size:1em}"
    ".al-derivation .al-wrap{display:flex;flex-wrap:wrap;align-items:baseline;"
    "column-gap:0;row-gap:0.35em;padding:0.35em 0 0.35em 2em;overflow-x:auto;overflow-y:hidden}"
    ".al-derivation .al-wrap>:first-child{margin-left:-2em}"
    ".al-derivation .al-wrap-text{column-gap:1.2em}"
)


#: A figure is never scaled so far down that its smallest text is below this (CSS px): on a
#: narrow panel it keeps this size and scrolls sideways inside its step.
FIGURE_TEXT_PX = 11.5


def _fit_svg(svg: str) -> str:
    """A figure scaled to the panel's width (its drawing size kept as the viewBox), but
    not below the width at which its smallest text is :data:`FIGURE_TEXT_PX`."""
    clean = sanitize_svg(svg)
    m = re.match(r"<svg([^>]*)>", clean)
    if not m:
        return clean
    attrs = m.group(1)
    w = re.search(r'\swidth="([\d.]+)"', attrs)
    h = re.search(r'\sheight="([\d.]+)"', attrs)
    if "viewBox" not in attrs and w and h:
        attrs += f' viewBox="0 0 {w.group(1)} {h.group(1)}"'
    attrs = re.sub(r'\s(width|height)="[^"]*"', "", attrs)
    style = ""
    box = re.search(r'viewBox="[-\d.]+[\s,]+[-\d.]+[\s,]+([\d.]+)', attrs)
    sizes = [float(v) for v in re.findall(r'font-size(?:="|:\s*)([\d.]+)', clean)]
    if box and sizes and min(sizes) > 0:
        style = f' style="min-width:{float(box.group(1)) * FIGURE_TEXT_PX / min(sizes):.0f}px"'
    return (
        f'<svg{attrs} width="100%"{style} preserveAspectRatio="xMidYMid meet">' + clean[m.end() :]
    )


#: The tag word of a step's remark, by its kind (:func:`remark_parts`), in the chrome's domain.
TAG_WORDS: dict[str, str] = {"corrected": N_("corrected"), "reconstructed": N_("reconstructed")}


def _as_written(text: str) -> str:
    return text


def _captioned(svg: str, text: Callable[[str], str]) -> str:
    """``svg`` with its caption (:func:`figure_caption`, its ``aria-label`` and the line
    that draws it) through ``text``; sanitized afterwards like any figure."""
    caption = figure_caption(svg)
    shown = text(caption) if caption else caption
    if shown == caption:
        return svg
    return svg.replace(f"{html.escape(caption)}<", f"{html.escape(shown)}<").replace(
        f'aria-label="{html.escape(caption)}"', f'aria-label="{html.escape(shown)}"', 1
    )


def step_to_html(
    step: DerivationStep,
    index: int | None = None,
    text: Callable[[str], str] = _as_written,
    tr: Callable[[str], str] = _as_written,
) -> str:
    """One derivation step: heading (title, source equation number, "reconstructed" tag),
    prose, then each statement as a display ``<math>``; ``text`` puts the title, the
    prose, the source, the remark and the figure's caption into the page's language (e.g.
    :meth:`analyzer_lab.i18n.Language.lesson_text`), ``tr`` the tag word (e.g.
    :meth:`analyzer_lab.i18n.Language.gettext`)."""
    esc = html.escape
    head = f"{index}. " if index is not None else ""
    parts = ['<div class="al-step" style="margin:0 0 12px 0">']
    parts.append(f"<div><b>{esc(head)}{prose_html(text(step.title))}</b>")
    if step.source:
        parts.append(
            f'<span class="al-source" style="{SOURCE_STYLE}">{esc(text(step.source))}</span>'
        )
    tag, why = remark_parts(step.reconstructed)
    word, why = (tr(TAG_WORDS[tag]), text(why)) if tag else ("", "")
    if tag:
        parts.append(
            f' <span class="al-{tag}" style="{RECON_STYLE}" title="{esc(prose_text(why))}">'
            f"{esc(word)}</span>"
        )
    parts.append("</div>")
    if step.text:
        parts.append(
            f'<div style="font-size:0.9em;margin:2px 0">{prose_html(text(step.text))}</div>'
        )
    for item in _as_list(step.math):
        parts.append(formula_html(item))
    if step.svg:
        svg = _captioned(step.svg, text)
        parts.append(
            f'<div class="al-figure" style="width:100%;overflow-x:auto">{_fit_svg(svg)}</div>'
        )
    if tag:
        parts.append(
            f'<div style="font-size:max(11px,0.8em);color:#7a5600">{esc(word)}: '
            f"{prose_html(why)}</div>"
        )
    parts.append("</div>")
    return "".join(parts)


def derivation_to_html(
    steps: Iterable[DerivationStep],
    header: str = "",
    text: Callable[[str], str] = _as_written,
    tr: Callable[[str], str] = _as_written,
) -> str:
    """The whole derivation as one HTML block (numbered steps), its titles, prose, sources
    and remarks through ``text`` and its tag words through ``tr`` (the page's language; as
    written by default)."""
    body = "".join(step_to_html(s, i, text, tr) for i, s in enumerate(steps, 1))
    top = f'<div style="margin-bottom:8px">{html.escape(header)}</div>' if header else ""
    return (
        f'<div class="al-derivation" style="font-size:0.95em;line-height:1.35">'
        f"<style>{DERIVATION_CSS}</style>{top}{body}</div>"
    )


__all__ = [
    "derivation_to_html",
    "expr_to_mathml",
    "formula_html",
    "sanitize_mathml",
    "sanitize_svg",
    "step_to_html",
]
