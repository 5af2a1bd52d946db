"""Block diagrams of analyzers in the notation of Fig. 1.5, generated from their equations.

Fig. 1.5 has four block types: the scale block (a square with K: y -> Ky), the summing
block Σ (inputs with signs), the integrating block ∫ (integrand, differential input,
initial value z0) and the multiplication block (x, y -> xy).  From a system
dx_i/dt = rhs_i this module builds the analyzer the textbook draws in Figs. 1.6, 1.11,
1.13-1.15, 1.25, 1.27 and 1.30:

* one integrator per state, with its initial value (x0, y0, ...);
* every right-hand side is split into terms (after pulling out a common factor: a
  constant common factor becomes a scale block after the summer, as ω² in Fig. 1.6, a
  common signal a multiplier after it, as ω in Fig. 1.27);
* in a term, the product of signals and states is a chain of multipliers, a numeric or
  parameter coefficient a scale block (±1 only sets the sign at the summer); a term
  without states or signals is a constant input;
* a summer collects the terms of a row when there are two or more.

Signals (sources) are the symbols declared time-varying (controls u1, u2, u3, ω) and
any sub-expression of t; the other free symbols are constant parameters (a_ij, λ, ω²).

:func:`block_diagram` returns plain data (:class:`BlockDiagram`: blocks, wires) with a
self-contained SVG rendering (no scripts, no external references, every text escaped).
Wires that run back from an integrator to the blocks that use its output are drawn as
labelled net stubs (the output's name at both ends), as the textbook's figures label
their feedback lines.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import sympy as sp
from analyzer_lab.lessons.kit.formula import t_symbol

if TYPE_CHECKING:
    from analyzer_lab.lessons.kit.contract import DerivationStep

BlockKind = str  # "integrator" | "multiplier" | "summer" | "scale" | "source" | "constant"


@dataclass
class Block:
    id: str
    kind: BlockKind
    label: str
    initial: str = ""
    row: int = 0
    col: int = 0
    slot: int = 0
    x: float = 0.0
    y: float = 0.0


@dataclass
class Wire:
    src: str
    dst: str
    sign: int = 1  # the sign at a summer input
    label: str = ""  # the signal's name (feedback wires are drawn as labelled stubs)


@dataclass
class BlockDiagram:
    """Plain-data analyzer diagram: blocks, wires and the states they integrate."""

    title: str
    states: tuple[str, ...]
    argument: str
    blocks: list[Block] = field(default_factory=list)
    wires: list[Wire] = field(default_factory=list)

    def count(self, kind: BlockKind) -> int:
        return sum(1 for b in self.blocks if b.kind == kind)

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for b in self.blocks:
            out[b.kind] = out.get(b.kind, 0) + 1
        return out

    def block(self, bid: str) -> Block:
        for b in self.blocks:
            if b.id == bid:
                return b
        raise KeyError(bid)

    def to_dict(self) -> dict:
        return {
            "title": self.title,
            "states": list(self.states),
            "argument": self.argument,
            "blocks": [
                {"id": b.id, "kind": b.kind, "label": b.label, "initial": b.initial}
                for b in self.blocks
            ],
            "wires": [
                {"src": w.src, "dst": w.dst, "sign": w.sign, "label": w.label} for w in self.wires
            ],
        }

    @property
    def svg(self) -> str:
        return render_svg(self)


def label_of(expr: sp.Expr) -> str:
    """A compact plain-text label: ``**`` as ``^``, ``*`` as ``·``."""
    num, den = (
        sp.fraction(sp.together(expr))
        if isinstance(expr, sp.Expr) and not expr.is_Atom
        else (expr, sp.Integer(1))
    )
    if den != 1:
        d = _plain_text(den)
        return f"{_plain_text(num)}/{d if den.is_Atom or den.is_Pow else '(' + d + ')'}"
    return _plain_text(expr)


def _plain_text(expr: sp.Expr) -> str:
    return sp.sstr(expr).replace("**", "^").replace("*", "·")


def _state_name(lhs: sp.Expr) -> str:
    if isinstance(lhs, sp.Derivative):
        f = lhs.expr
        return f.func.__name__ if isinstance(f, sp.core.function.AppliedUndef) else str(f)
    text = str(lhs)
    if text.startswith("d") and "/" in text:
        return text[1:].split("/", 1)[0]
    return text


def _plain(expr: sp.Expr) -> sp.Expr:
    """Applied functions x(t) -> symbols x (so that states look the same everywhere)."""
    reps = {
        f: sp.Symbol(f.func.__name__, real=True) for f in expr.atoms(sp.core.function.AppliedUndef)
    }
    return expr.xreplace(reps) if reps else expr


class _Builder:
    def __init__(
        self,
        states: Sequence[sp.Symbol],
        signals: set[sp.Symbol],
        argument: str,
        initial: Mapping[str, str],
    ) -> None:
        self.states = list(states)
        self.state_names = {s: str(s) for s in states}
        self.signals = signals
        self.argument = argument
        self.blocks: list[Block] = []
        self.wires: list[Wire] = []
        self.sources: dict[str, str] = {}
        self.n = 0
        for i, s in enumerate(states):
            self.blocks.append(
                Block(
                    f"int_{s}",
                    "integrator",
                    f"∫ d{argument}",
                    initial.get(str(s), f"{s}0"),
                    row=i,
                    col=6,
                )
            )

    def _id(self, kind: str) -> str:
        self.n += 1
        return f"{kind}_{self.n}"

    def is_signal(self, e: sp.Expr) -> bool:
        return (
            bool(e.free_symbols & self.signals)
            or (t_symbol in e.free_symbols)
            or sp.Symbol("t") in e.free_symbols
        )

    def source(self, e: sp.Expr) -> str:
        """Block id giving signal ``e`` (a state's integrator, or a source block, shared)."""
        if e in self.state_names:
            return f"int_{e}"
        key = label_of(e)
        if key not in self.sources:
            bid = self._id("src")
            self.blocks.append(Block(bid, "source", key, row=-1, col=0))
            self.sources[key] = bid
        return self.sources[key]

    def add(self, block: Block) -> str:
        self.blocks.append(block)
        return block.id

    def wire(self, src: str, dst: str, sign: int = 1) -> None:
        label = src[4:] if src.startswith("int_") else self.block(src).label
        self.wires.append(Wire(src, dst, sign, label))

    def block(self, bid: str) -> Block:
        for b in self.blocks:
            if b.id == bid:
                return b
        raise KeyError(bid)

    def factors(self, term: sp.Expr) -> tuple[sp.Expr, list[sp.Expr]]:
        """(constant coefficient, signal/state factors with multiplicity)."""
        coeff = sp.Integer(1)
        sig: list[sp.Expr] = []
        for f in sp.Mul.make_args(term):
            base, exp = f.as_base_exp()
            if base in self.state_names or self.is_signal(base):
                if exp.is_Integer and exp > 0:
                    sig.extend([base] * int(exp))
                else:
                    sig.append(f)
            else:
                coeff *= f
        return coeff, sig

    def chain(self, factors: list[sp.Expr], row: int, slot: int) -> str | None:
        """Multipliers for a product of signals; returns the id of the product's output."""
        if not factors:
            return None
        out = self.source(factors[0])
        for f in factors[1:]:
            m = self.add(Block(self._id("mul"), "multiplier", "×", row=row, col=1, slot=slot))
            self.wire(out, m)
            self.wire(self.source(f), m)
            out = m
        return out

    def scaled(self, src: str, K: sp.Expr, row: int, col: int, slot: int) -> tuple[str, int]:
        """Apply coefficient K: ±1 -> sign only; else a scale block |K| (sign to the summer)."""
        sign = 1
        if K.could_extract_minus_sign():
            sign, K = -1, -K
        if K == 1:
            return src, sign
        b = self.add(Block(self._id("scale"), "scale", label_of(K), row=row, col=col, slot=slot))
        self.wire(src, b)
        return b, sign

    def row(self, i: int, state: sp.Symbol, rhs: sp.Expr) -> None:
        integ = f"int_{state}"
        rhs = sp.factor_terms(sp.expand(rhs))
        common_c, common_s = sp.Integer(1), []
        inner = rhs
        if isinstance(rhs, sp.Mul):
            parts = [f for f in rhs.args if isinstance(f, sp.Add)]
            if len(parts) == 1:
                inner = parts[0]
                rest = sp.Mul(*[f for f in rhs.args if f is not parts[0]])
                common_c, common_s = self.factors(rest)
        terms = sp.Add.make_args(sp.expand(inner)) if inner != 0 else ()
        if not terms:
            return
        outs: list[tuple[str, int]] = []
        for k, term in enumerate(terms):
            coeff, sig = self.factors(term)
            prod = self.chain(sig, i, k)
            if prod is None:  # a constant input
                sign = 1
                if coeff.could_extract_minus_sign():
                    sign, coeff = -1, -coeff
                outs.append(
                    (
                        self.add(
                            Block(
                                self._id("const"), "constant", label_of(coeff), row=i, col=0, slot=k
                            )
                        ),
                        sign,
                    )
                )
            else:
                outs.append(self.scaled(prod, coeff, i, 2, k))
        if len(outs) > 1:
            s = self.add(Block(self._id("sum"), "summer", "Σ", row=i, col=3))
            for src, sign in outs:
                self.wire(src, s, sign)
            out, sign = s, 1
        else:
            out, sign = outs[0]
        if common_s:
            m = self.chain(common_s, i, len(terms))
            mul = self.add(Block(self._id("mul"), "multiplier", "×", row=i, col=4, slot=-1))
            self.wire(out, mul)
            self.wire(m, mul)  # type: ignore[arg-type]
            out = mul
        K = common_c * sign
        if (
            K != 1
        ):  # one gain block after the summer, sign included (ω², -ω² of Fig. 1.6; -1 of Fig. 1.13)
            b = self.add(Block(self._id("scale"), "scale", label_of(K), row=i, col=5, slot=-1))
            self.wire(out, b)
            out = b
        self.wire(out, integ)


def block_diagram(
    equations: Sequence[sp.Eq],
    signals: Iterable[sp.Symbol | str] = ("u1", "u2", "u3", "u", "ω", "omega"),
    initial: Mapping[str, str] | None = None,
    argument: str = "t",
    title: str = "",
) -> BlockDiagram:
    """The analyzer diagram of ``equations`` (``d x_i / d t = rhs_i``; lhs a Derivative of
    ``x_i(t)`` or a symbol named ``dx_i/d...``)."""
    names = [_state_name(eq.lhs) for eq in equations]
    states = [sp.Symbol(n, real=True) for n in names]
    sig_names = {str(s) for s in signals}
    rhs_list = [_plain(eq.rhs) for eq in equations]
    # unify same-named symbols (real=True or not) with the states
    by_name = {str(s): s for s in states}
    rhs_list = [
        r.xreplace({s: by_name[str(s)] for s in r.free_symbols if str(s) in by_name})
        for r in rhs_list
    ]
    sig_syms = {s for r in rhs_list for s in r.free_symbols if str(s) in sig_names}
    b = _Builder(states, sig_syms, argument, dict(initial or {}))
    for i, (s, r) in enumerate(zip(states, rhs_list)):
        b.row(i, s, r)
    diagram = BlockDiagram(title, tuple(names), argument, b.blocks, b.wires)
    _layout(diagram)
    return diagram


# ------------------------------------------------------------------------------ layout & SVG

COL_X = (20.0, 130.0, 200.0, 290.0, 350.0, 410.0, 500.0)
ROW_GAP = 26.0
SLOT_H = 44.0


def _layout(d: BlockDiagram) -> None:
    rows = len(d.states)
    slots = [1] * rows
    for bl in d.blocks:
        if bl.row >= 0:
            slots[bl.row] = max(slots[bl.row], bl.slot + 1)
    tops = []
    y = 40.0
    for r in range(rows):
        tops.append(y)
        y += slots[r] * SLOT_H + ROW_GAP
    src_y = y
    k = 0
    for bl in d.blocks:
        bl.x = COL_X[min(bl.col, 6)]
        if bl.row < 0:  # sources: a strip below the rows
            bl.x = COL_X[0] + (k % 6) * 95.0
            bl.y = src_y + (k // 6) * SLOT_H
            k += 1
        elif bl.slot < 0 or bl.kind in ("integrator", "summer"):
            bl.y = tops[bl.row] + (slots[bl.row] * SLOT_H) / 2 - SIZE[bl.kind][1] / 2 - 6
        else:
            bl.y = tops[bl.row] + bl.slot * SLOT_H


SIZE = {
    "integrator": (70.0, 32.0),
    "multiplier": (32.0, 32.0),
    "summer": (40.0, 40.0),
    "scale": (52.0, 28.0),
    "source": (86.0, 26.0),
    "constant": (70.0, 26.0),
}


def _e(text: str) -> str:
    return html.escape(str(text), quote=True)


def _port(b: Block, side: str, k: int = 0, n: int = 1) -> tuple[float, float]:
    w, h = SIZE[b.kind]
    return (b.x + (w if side == "out" else 0.0), b.y + h * (k + 1) / (n + 1))


def render_svg(d: BlockDiagram) -> str:
    """A self-contained SVG (inline styles, escaped text, no scripts or links)."""
    width = 660.0
    height = max((b.y + SIZE[b.kind][1] for b in d.blocks), default=60.0) + 30.0
    out: list[str] = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
        f'viewBox="0 0 {width:.0f} {height:.0f}" '
        f'font-family="sans-serif" font-size="12" role="img" aria-label="{_e(d.title or "analyzer block diagram")}">',
        '<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" '
        'markerWidth="7" markerHeight="7" orient="auto-start-reverse">'
        '<path d="M 0 0 L 10 5 L 0 10 z" fill="#333"/></marker></defs>',
    ]
    if d.title:
        out.append(f'<text x="10" y="20" font-weight="bold">{_e(d.title)}</text>')
    for bl in d.blocks:
        w, h = SIZE[bl.kind]
        cx, cy = bl.x + w / 2, bl.y + h / 2
        if bl.kind in ("multiplier", "summer"):
            out.append(
                f'<circle cx="{cx:.1f}" cy="{cy:.1f}" r="{w / 2:.1f}" fill="#fff" stroke="#333"/>'
            )
        elif bl.kind == "integrator":
            out.append(
                f'<rect x="{bl.x:.1f}" y="{bl.y:.1f}" width="{w:.0f}" height="{h:.0f}" fill="#eef3fb" stroke="#333"/>'
            )
            out.append(
                f'<text x="{cx:.1f}" y="{bl.y - 4:.1f}" text-anchor="middle" font-size="11">{_e(bl.initial)}</text>'
            )
        elif bl.kind in ("source", "constant"):
            out.append(
                f'<rect x="{bl.x:.1f}" y="{bl.y:.1f}" width="{w:.0f}" height="{h:.0f}" '
                'rx="8" fill="#f7f7f7" stroke="#777"/>'
            )
        else:
            out.append(
                f'<rect x="{bl.x:.1f}" y="{bl.y:.1f}" width="{w:.0f}" height="{h:.0f}" fill="#fff" stroke="#333"/>'
            )
        text = bl.label if len(bl.label) <= 14 else bl.label[:13] + "…"
        tx = cx + (5 if bl.kind == "summer" else 0)
        out.append(f'<text x="{tx:.1f}" y="{cy + 4:.1f}" text-anchor="middle">{_e(text)}</text>')
        if bl.kind == "integrator":
            sx, sy = _port(bl, "out")
            out.append(
                f'<line x1="{sx:.1f}" y1="{sy:.1f}" x2="{sx + 40:.1f}" y2="{sy:.1f}" '
                'stroke="#333" marker-end="url(#arrow)"/>'
            )
            out.append(f'<text x="{sx + 44:.1f}" y="{sy + 4:.1f}">{_e(bl.id[4:])}</text>')
    n_in: dict[str, int] = {}
    for w in d.wires:
        n_in[w.dst] = n_in.get(w.dst, 0) + 1
    seen: dict[str, int] = {}
    for w in d.wires:
        src, dst = d.block(w.src), d.block(w.dst)
        k = seen.get(w.dst, 0)
        seen[w.dst] = k + 1
        x1, y1 = _port(src, "out")
        x2, y2 = _port(dst, "in", k, n_in[w.dst])
        if src.kind == "integrator" or src.row < 0 or x2 <= x1:
            # a net stub: the signal's name at the input
            out.append(
                f'<line x1="{x2 - 26:.1f}" y1="{y2:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" '
                'stroke="#333" marker-end="url(#arrow)"/>'
            )
            out.append(
                f'<text x="{x2 - 28:.1f}" y="{y2 - 3:.1f}" text-anchor="end" font-size="11">'
                f"{_e(w.label if len(w.label) <= 12 else w.label[:11] + '…')}</text>"
            )
        else:
            xm = (x1 + x2) / 2
            out.append(
                f'<polyline points="{x1:.1f},{y1:.1f} {xm:.1f},{y1:.1f} {xm:.1f},{y2:.1f} {x2:.1f},{y2:.1f}" '
                'fill="none" stroke="#333" marker-end="url(#arrow)"/>'
            )
        if dst.kind == "summer":
            out.append(
                f'<text x="{x2 + 4:.1f}" y="{y2 + 4:.1f}" font-size="10" font-weight="bold">'
                f"{'+' if w.sign > 0 else '−'}</text>"
            )
    out.append("</svg>")
    return "".join(out)


__all__ = ["Block", "BlockDiagram", "Wire", "block_diagram", "render_svg", "label_of"]


def diagram_step(d: BlockDiagram, figure: str, reconstructed: str) -> DerivationStep:
    """A block diagram as a derivation step (its counts in the title, the SVG as the figure)."""
    from analyzer_lab.lessons.kit.contract import DerivationStep

    c = d.counts()
    title = (
        f"Block diagram: {c.get('integrator', 0)} integrators, {c.get('multiplier', 0)} multipliers, "
        f"{c.get('summer', 0)} summers, {c.get('scale', 0)} scale blocks"
    )
    text = "Integrators (with their initial values), multipliers, summers and scale blocks, wired as the equations say."
    return DerivationStep(title, text, None, figure, reconstructed=reconstructed, svg=d.svg)
