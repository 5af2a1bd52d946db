"""The parabola table of Leppik (1960) three ways: formula (13), simulation, the print.

The article tabulates the largest contour error of the parabola y = x^2/p for
v = 50 mm/s, p = 20 mm, omega = 5 and a servo loop W = k/((Ts+1)s).  The printed header
is transposed (rows are k [1/s], columns T [s]); every printed cell is 0.8 x (13) to its
printed digits, while the exact simulation agrees with (13).  This module holds the
printed values, simulates every cell and gives the interval of the factor that every
printed cell allows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from analyzer_lab.lessons.servo.formulas import delta_parabola_13
from analyzer_lab.lessons.servo.geometry import power_distance
from analyzer_lab.lessons.servo.model import Channel, Correction, TwoAxisServo
from analyzer_lab.lessons.servo.paths import power_program

#: the table [mm] as printed (rows k [1/s], columns T [s]; the header is transposed in print)
PARABOLA_TABLE_PRINTED: dict[tuple[float, float], str] = {
    (100.0, 0.01): "-0.01",
    (100.0, 0.1): "-0.19",
    (100.0, 0.5): "-1.0",
    (100.0, 1.0): "-2",
    (200.0, 0.01): "-0.0075",
    (200.0, 0.1): "-0.1",
    (200.0, 0.5): "-0.5",
    (200.0, 1.0): "-1",
    (500.0, 0.01): "-0.0036",
    (500.0, 0.1): "-0.04",
    (500.0, 0.5): "-0.2",
    (500.0, 1.0): "-0.4",
    (1000.0, 0.01): "-0.002",
    (1000.0, 0.1): "-0.02",
    (1000.0, 0.5): "-0.1",
    (1000.0, 1.0): "-0.2",
}


def printed_half_unit(text: str) -> float:
    """Half a unit in the last printed digit (the rounding interval of a printed value)."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10.0 ** (-decimals)


@dataclass(frozen=True)
class TableRow:
    """One cell of the parabola table: formula (13), simulation and the printed value [mm]."""

    k: float
    T: float
    T1: float
    T2sq: float
    formula_13: float
    simulated: float
    printed: float
    printed_text: str
    printed_over_formula: float
    simulated_over_formula: float
    point_eight_formula: float
    within_print_rounding: bool


def simulate_parabola_vertex_error(
    ch: Channel, omega: float, p: float, correction: Correction = "off", settle: float = 20.0
) -> float:
    """Signed contour error of largest magnitude near the vertex after the transient.

    The PU starts far before the vertex (reached after ``settle`` slowest time
    constants), the servo at rest on the start point; the exact state is taken around the
    vertex and the exact normal distance to y = x^2/p is maximised there.
    """
    t_v = max(settle / ch.decay_rate(), 1.0)
    program = power_program(2, -omega * p / 2.0 * t_v, 0.0, 0.0, p, omega)
    system = TwoAxisServo(program, ch, ch, correction)
    t = t_v + np.linspace(-0.5, 0.5, 1001)
    out = system.outputs(system.states(t, system.initial_state()))
    d, _, _ = power_distance(out["x1"], out["y1"], 2, 0.0, 0.0, p, guess=out["x"])
    return float(d[int(np.argmax(np.abs(d)))])


@lru_cache(maxsize=4)
def parabola_table(p: float = 20.0, omega: float = 5.0) -> tuple[TableRow, ...]:
    """The article's table three ways: formula (13), simulation, the printed values.

    v = 50 mm/s is the vertex speed omega p/2 of the stated omega = 5, p = 20.
    """
    rows: list[TableRow] = []
    for (k, T), text in PARABOLA_TABLE_PRINTED.items():
        ch = Channel.from_open_loop(k, T)
        f13 = delta_parabola_13(omega, p, ch.T1, ch.T2sq)
        sim = simulate_parabola_vertex_error(ch, omega, p)
        printed = float(text)
        rows.append(
            TableRow(
                k=k,
                T=T,
                T1=ch.T1,
                T2sq=ch.T2sq,
                formula_13=f13,
                simulated=sim,
                printed=printed,
                printed_text=text,
                printed_over_formula=printed / f13,
                simulated_over_formula=sim / f13,
                point_eight_formula=0.8 * f13,
                within_print_rounding=abs(printed - 0.8 * f13) <= printed_half_unit(text) + 1e-12,
            )
        )
    return tuple(rows)


def table_row(k: float, T: float) -> TableRow | None:
    """The cell (k, T) of the article's table (omega = 5, p = 20), if it is one."""
    return next((r for r in parabola_table() if (r.k, r.T) == (k, T)), None)


def table_ratio_interval() -> tuple[float, float]:
    """The interval of c/(omega^2 p/4) for which table = c (T1^2 - 2T2^2) rounds to every
    printed cell."""
    lo, hi = -math.inf, math.inf
    for (k, T), text in PARABOLA_TABLE_PRINTED.items():
        g = (1.0 / k) ** 2 - 2.0 * T / k  # negative in every cell
        val, h = float(text), printed_half_unit(text)
        c1, c2 = (val - h) / g, (val + h) / g
        lo, hi = max(lo, min(c1, c2)), min(hi, max(c1, c2))
    return lo / 125.0, hi / 125.0


def format_table(rows: tuple[TableRow, ...]) -> str:
    """Markdown table: (13) | simulation | printed | printed/(13)."""
    lines = [
        "| k [1/s] | T [s] | (13) [mm] | simulation [mm] | printed [mm] | 0.8 x (13) |"
        " printed / (13) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.k:g} | {r.T:g} | {r.formula_13:.6g} | {r.simulated:.6g} | {r.printed_text} | "
            f"{r.point_eight_formula:.4g} | {r.printed_over_formula:.3f} |"
        )
    return "\n".join(lines)
