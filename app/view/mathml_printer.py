"""sympy's presentation MathML, written the way the textbook writes formulas.

Three changes to sympy's printer, for every lesson at once:

- a derivative reads d²φ/dt² (sympy 1.14 prints d²/d²t φ(t)), partial ones ∂²f/∂x∂y;
- an unknown function of time is its name alone, printed like a symbol: ``phi(t)`` is
  φ, ``x_A(t)`` is x with subscript A (sympy prints the lower-cased class name ``x_a(t)``);
- symbol names lose their TeX spelling (``\\psi`` is ψ, ``\\varphi`` is φ) before the
  printer splits off sub- and superscripts.

Names are taken as they are spelled (no substitution into the expression), so an
unevaluated equation stays an equation.
"""

from __future__ import annotations

import html
import re
from typing import Any

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.printing.conventions import requires_partial
from sympy.printing.mathml import MathMLPresentationPrinter
from sympy.printing.precedence import PRECEDENCE

#: TeX spellings of letters that have no plain name sympy knows, and what they show as.
TEX_NAMES = {
    "varphi": "φ",
    "vartheta": "ϑ",
    "varepsilon": "ε",
    "varpi": "ϖ",
    "varrho": "ϱ",
    "varsigma": "ς",
}
_TEX_COMMAND = re.compile(r"\\([A-Za-z]+)")
#: TeX accents a name may start with (``\\dot\\varphi_0`` is φ with a dot, subscript 0).
ACCENTS = {"ddot": "¨", "dot": "˙", "hat": "^", "bar": "¯", "tilde": "~"}
_ACCENT = re.compile(r"^\\(ddot|dot|hat|bar|tilde)(?![A-Za-z])\s*")
#: The name of the time variable whose argument is left out: φ, not φ(t).
TIME = "t"


def tex_free(name: str) -> str:
    """A symbol name without TeX: commands and braces removed (``z_{z\\,pr}`` ->
    ``z_z pr``, ``\\varphi`` -> ``φ``); not escaped."""
    text = name.replace("\\,", " ").replace("\\;", " ").replace("\\ ", " ")
    text = _TEX_COMMAND.sub(lambda m: TEX_NAMES.get(m.group(1), m.group(1)), text)
    for tex, shown in TEX_NAMES.items():
        text = re.sub(rf"(?<![A-Za-z]){tex}(?![A-Za-z])", shown, text)
    return text.replace("{", "").replace("}", "")


def _of_time(expr: Any) -> bool:
    """An unknown function of t alone (a coordinate, a program): shown by its name."""
    return (
        isinstance(expr, AppliedUndef)
        and len(expr.args) == 1
        and isinstance(expr.args[0], sp.Symbol)
        and expr.args[0].name == TIME
    )


class TextbookMathML(MathMLPresentationPrinter):
    """Presentation MathML with the textbook's derivatives and names."""

    def _element(self, tag: str, text: str | None = None, **attrs: str) -> Any:
        el = self.dom.createElement(tag)
        for key, value in attrs.items():
            el.setAttribute(key, value)
        if text is not None:
            el.appendChild(self.dom.createTextNode(text))
        return el

    def doprint(self, expr: Any) -> str:
        """The MathML of ``expr``, minus signs as the minus character (not a hyphen)."""
        return super().doprint(expr).replace("<mo>-</mo>", "<mo>\u2212</mo>")

    def _print_Symbol(self, sym: Any, style: str = "plain") -> Any:
        accent = _ACCENT.match(sym.name)
        name = sym.name[accent.end() :] if accent else sym.name
        shown = html.escape(tex_free(name), quote=False)  # sympy's writer does not escape
        out = super()._print_Symbol(sp.Symbol(shown) if shown != sym.name else sym, style)
        if accent:  # the dot sits on the letter, under its superscript, over its subscript
            letter = out if out.tagName == "mi" else out.firstChild
            over = self._element("mover", accent="true")
            if letter is out:
                over.appendChild(out)
                out = over
            else:
                out.replaceChild(over, letter)
                over.appendChild(letter)
            over.appendChild(self._element("mo", ACCENTS[accent.group(1)]))
        return out

    def _print_Function(self, e: Any) -> Any:
        if not isinstance(e, AppliedUndef):
            return super()._print_Function(e)
        name = self._print_Symbol(sp.Symbol(e.func.__name__))
        if _of_time(e):
            return name
        mrow = self.dom.createElement("mrow")
        mrow.appendChild(name)
        mrow.appendChild(self._paren_comma_separated(*e.args))
        return mrow

    def parenthesize(self, item: Any, level: int, strict: bool = False) -> Any:
        """d²z/dt² of a coordinate is a single factor: m d²z/dt², not m (d²z/dt²); as the
        base of a power it keeps its parentheses, (dφ/dt)²."""
        if (
            level <= PRECEDENCE["Mul"]
            and isinstance(item, sp.Derivative)
            and isinstance(item.expr, (sp.Symbol, AppliedUndef))
        ):
            return self._print(item)
        return super().parenthesize(item, level, strict)

    def _power(self, base: Any, n: int) -> Any:
        if n < 2:
            return base
        sup = self.dom.createElement("msup")
        sup.appendChild(base)
        sup.appendChild(self._print(sp.Integer(n)))
        return sup

    def _print_Derivative(self, e: Any) -> Any:
        in_time = all(getattr(v, "name", "") == TIME for v, _ in e.variable_count)
        d = "d" if in_time or not requires_partial(e.expr) else "∂"
        order = sum(int(n) for _, n in e.variable_count)
        top = self.dom.createElement("mrow")
        top.appendChild(self._power(self._element("mi", d, mathvariant="normal"), order))
        simple = isinstance(e.expr, (sp.Symbol, AppliedUndef))
        if simple:
            top.appendChild(self._print(e.expr))
        bottom = self.dom.createElement("mrow")
        for var, n in e.variable_count:
            bottom.appendChild(self._element("mi", d, mathvariant="normal"))
            bottom.appendChild(self._power(self._print(var), int(n)))
        frac = self.dom.createElement("mfrac")
        frac.appendChild(top)
        frac.appendChild(bottom)
        if simple:
            return frac
        mrow = self.dom.createElement("mrow")
        mrow.appendChild(frac)
        inner = self.dom.createElement("mrow")
        inner.appendChild(self._element("mo", "("))
        inner.appendChild(self._print(e.expr))
        inner.appendChild(self._element("mo", ")"))
        mrow.appendChild(inner)
        return mrow


def textbook_mathml(expr: Any) -> str:
    """``expr`` as presentation MathML (the inside of a ``<math>`` element)."""
    return TextbookMathML({}).doprint(expr)


__all__ = ["TEX_NAMES", "TextbookMathML", "tex_free", "textbook_mathml"]
