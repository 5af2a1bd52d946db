"""Derivation steps as HTML with MathML (viser's markdown has no math).

sympy's presentation printer (for expressions) and latex2mathml (for LaTeX strings)
produce MathML; neither escapes the text it copies from symbol names or ``\\text{}``,
so every MathML string is rebuilt by :func:`sanitize_mathml` from a whitelist of
MathML elements and attributes with all text re-escaped.  Prose (titles, text,
equation numbers, the "reconstructed" note) goes through :func:`html.escape`.
"""

from __future__ import annotations

import html
import logging
import re
from collections.abc import Iterable, Sequence
from html.parser import HTMLParser
from typing import Any

import sympy as sp
from analyzer_lab.lessons.kit.contract import DerivationStep
from sympy.core.function import AppliedUndef

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


#: TeX spellings that must never reach a student as text, and what they show as.
TEX_NAMES = {
    "varphi": "φ",
    "vartheta": "ϑ",
    "varepsilon": "ε",
    "varpi": "ϖ",
    "varrho": "ϱ",
    "varsigma": "ς",
}
_TEX_COMMAND = re.compile(r"\\([A-Za-z]+)")


def plain_name(name: str) -> str:
    """A symbol name as plain text: TeX commands and braces removed (``z_{z\\,pr}`` ->
    ``z_z pr``, ``\\varphi`` -> ``φ``), markup characters escaped."""
    text = name.replace("\\,", " ").replace("\\;", " ").replace("\\ ", " ")
    text = _TEX_COMMAND.sub(lambda m: TEX_NAMES.get(m.group(1), m.group(1)), text)
    for tex, shown in TEX_NAMES.items():
        text = re.sub(rf"(?<![A-Za-z]){tex}(?![A-Za-z])", shown, text)
    text = text.replace("{", "").replace("}", "")
    return html.escape(text, quote=True)


def _escape_names(expr: sp.Basic) -> sp.Basic:
    """Symbols/undefined functions get plain, escaped names, so sympy's printer (which
    copies names verbatim) yields displayable, inert text with no TeX in it."""
    subs: dict[Any, Any] = {}
    for s in expr.atoms(sp.Symbol):
        shown = plain_name(s.name)
        if shown != s.name:
            subs[s] = sp.Symbol(shown, **s.assumptions0)
    for f in expr.atoms(AppliedUndef):
        name = f.func.__name__
        shown = plain_name(name)
        if shown != name:
            subs[f] = sp.Function(shown)(*f.args)
    return expr.xreplace(subs) if subs else expr


def expr_to_mathml(expr: sp.Basic | str, display: str = "block") -> str:
    """One sympy expression/equation (or a LaTeX string) as a sanitized ``<math>`` element."""
    display = "inline" if display == "inline" else "block"
    if isinstance(expr, str):
        import latex2mathml.converter

        try:
            raw = latex2mathml.converter.convert(expr)
        except Exception:  # an unparsable LaTeX string is shown as escaped text
            log.warning("LaTeX not converted to MathML: %.80s", expr, exc_info=True)
            return f'<math display="{display}"><mtext>{html.escape(expr)}</mtext></math>'
        raw = re.sub(r"<math[^>]*>", "", raw, count=1).replace("</math>", "")
    else:
        from sympy.printing.mathml import mathml

        try:
            raw = mathml(_escape_names(sp.sympify(expr)), printer="presentation")
        except Exception:
            log.warning("expression not printed as MathML: %.80s", expr, exc_info=True)
            return f'<math display="{display}"><mtext>{html.escape(str(expr))}</mtext></math>'
    # sympy prints d/dt with the double-struck differential d (U+2146): ordinary d
    raw = raw.replace("&dd;", "d").replace("\u2146", "d")
    out = sanitize_mathml(f'<math display="{display}">{raw}</math>')
    if not isinstance(expr, str) and math_width(out) > MAX_LINE_GLYPHS:
        return _broken_lines(expr, display) or out
    return out


#: Longer formulas are broken into lines at their top-level + and - (see _broken_lines).
MAX_LINE_GLYPHS = 80
LINE_GLYPHS = 48


def _row(expr: sp.Basic) -> str:
    from sympy.printing.mathml import mathml

    raw = mathml(_escape_names(expr), printer="presentation")
    return raw.replace("&dd;", "d").replace("\u2146", "d")


def _broken_lines(expr: Any, display: str) -> str | None:
    """An equation ``lhs = a + b + ...`` (or a long sum) as aligned lines of a table, a
    few terms per line, so that it reads in a narrow panel without scrolling."""
    expr = sp.sympify(expr)
    lhs, rhs = (expr.lhs, expr.rhs) if isinstance(expr, sp.Equality) else (None, expr)
    if not isinstance(rhs, sp.Add):
        return None
    lines: list[list[sp.Basic]] = [[]]
    used = 0.0
    for term in sp.Add.make_args(rhs):
        w = math_width(f"<math>{_row(term)}</math>")
        if lines[-1] and used + w > LINE_GLYPHS:
            lines.append([])
            used = 0.0
        lines[-1].append(term)
        used += w + 1.0
    rows = []
    for k, terms in enumerate(lines):
        part = _row(sp.Add(*terms, evaluate=False))
        if k == 0:
            head = f"{_row(lhs)}<mo>=</mo>" if lhs is not None else ""
        else:  # a continued line starts with its sign
            head = "" if terms[0].could_extract_minus_sign() else "<mo>+</mo>"
        rows.append(f'<mtr><mtd columnalign="left"><mrow>{head}{part}</mrow></mtd></mtr>')
    table = f'<mtable columnalign="left">{"".join(rows)}</mtable>'
    return sanitize_mathml(f'<math display="{display}">{table}</math>')


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


#: Average width of a rendered math glyph in em (a deliberate over-estimate: fit first).
GLYPH_EM = 0.72


def math_width(mathml: str) -> float:
    """The width of a MathML formula in glyphs, estimated from its structure: a fraction
    is as wide as its wider part, scripts count at 70 %, rows add up."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(mathml)
    except ET.ParseError:
        return float(len(re.sub(r"<[^>]+>", "", mathml)))

    def width(el: ET.Element) -> float:
        tag = el.tag.rsplit("}", 1)[-1]
        kids = list(el)
        if tag in ("mi", "mn", "mtext", "ms"):
            return float(len((el.text or "").strip()) or 1)
        if tag == "mo":
            text = (el.text or "").strip()
            return len(text) + (0.6 if text in "=+-−<>≤≥±" else 0.2)
        if tag == "mfrac":
            return max((width(k) for k in kids), default=0.0) + 0.4
        if tag in ("msup", "msub", "munder", "mover"):
            return width(kids[0]) + 0.7 * sum(width(k) for k in kids[1:]) if kids else 0.0
        if tag in ("msubsup", "munderover"):
            return width(kids[0]) + 0.7 * max((width(k) for k in kids[1:]), default=0.0)
        if tag in ("msqrt", "mroot"):
            return sum(width(k) for k in kids) + 1.0
        if tag == "mtable":
            return max((width(k) for k in kids), default=0.0)
        return sum(width(k) for k in kids)

    return max(width(root), 1.0)


def _fit_font(mathml: str) -> str:
    """A font size that fits the formula into its container's width (CSS container
    units), never above the surrounding size and never below 45 % of it."""
    em = math_width(mathml) * GLYPH_EM
    return f"clamp(0.4em, {96.0 / em:.2f}cqi, 1em)"


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


def _tag_of(note: str | None) -> tuple[str, str]:
    """("corrected", why) for a misprint put right, ("reconstructed", why) for a formula
    rebuilt from the text; ("", "") for a formula as printed."""
    if not note:
        return "", ""
    if note.lower().startswith("corrected"):
        return "corrected", note.split(":", 1)[1].strip() if ":" in note else note
    return "reconstructed", note


def step_to_html(step: DerivationStep, index: int | None = None) -> str:
    """One derivation step: heading (title, source equation number, "reconstructed" tag),
    prose, then each statement as a display ``<math>``."""
    esc = html.escape
    head = f"{index}. " if index is not None else ""
    parts = ['<div class="al-step" style="margin:0 0 12px 0">']
    parts.append(f"<div><b>{esc(head + step.title)}</b>")
    if step.source:
        parts.append(f'<span class="al-source" style="{SOURCE_STYLE}">{esc(step.source)}</span>')
    tag, why = _tag_of(step.reconstructed)
    if tag:
        parts.append(
            f' <span class="al-{tag}" style="{RECON_STYLE}" title="{esc(why)}">{tag}</span>'
        )
    parts.append("</div>")
    if step.text:
        parts.append(f'<div style="font-size:0.9em;margin:2px 0">{esc(step.text)}</div>')
    for item in _as_list(step.math):
        mathml = expr_to_mathml(item)
        parts.append(
            '<div style="container-type:inline-size;width:100%">'
            f'<div class="al-eq" style="font-size:{_fit_font(mathml)};line-height:normal;'
            f'margin:4px 0;overflow-x:auto;overflow-y:hidden">{mathml}</div></div>'
        )
    if step.svg:
        parts.append(
            f'<div class="al-figure" style="width:100%;overflow-x:auto">{_fit_svg(step.svg)}</div>'
        )
    if tag:
        parts.append(
            f'<div style="font-size:max(11px,0.8em);color:#7a5600">{tag}: {esc(why)}</div>'
        )
    parts.append("</div>")
    return "".join(parts)


def derivation_to_html(steps: Iterable[DerivationStep], header: str = "") -> str:
    """The whole derivation as one HTML block (numbered steps)."""
    body = "".join(step_to_html(s, i) for i, s in enumerate(steps, 1))
    top = f'<div style="margin-bottom:8px">{html.escape(header)}</div>' if header else ""
    return f'<div class="al-derivation" style="font-size:0.95em;line-height:1.35">{top}{body}</div>'


__all__ = [
    "derivation_to_html",
    "expr_to_mathml",
    "sanitize_mathml",
    "sanitize_svg",
    "step_to_html",
]
