"""The claims of Leppik (1960) on the parabolas: y = x^2/p with the table (13) three ways
and the dependence (15) on beta, the non-identical channels (17)-(18), the horizontal
parabola x = y^2/p (19) of Fig. 4b, the transient (24) of the corrected program, and the
parabolas of degree 3 and 4; each computed from the exact model and compared with the
article's numbers.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import ClaimResult, at_most
from analyzer_lab.lessons.servo.formulas import (
    cubic_curve,
    curve_17,
    curve_19,
    deviation_24,
    locus_18,
    parabola_vertex_17,
    parabola_vertex_19,
    quartic_curve,
    quartic_y1,
)
from analyzer_lab.lessons.servo.geometry import power_distance
from analyzer_lab.lessons.servo.model import Channel, TwoAxisServo, settled
from analyzer_lab.lessons.servo.paths import horizontal_parabola_program, power_program
from analyzer_lab.lessons.servo.table import parabola_table, table_ratio_interval


def claim_table_13() -> ClaimResult:
    rows = parabola_table()
    worst = max(abs(r.simulated_over_formula - 1.0) for r in rows)
    return at_most(0.01, worst, "max |simulation/(13) - 1| ")


def claim_table_08() -> ClaimResult:
    rows = parabola_table()
    lo, hi = table_ratio_interval()
    ok = all(r.within_print_rounding for r in rows) and lo <= 0.8 <= hi and not (lo <= 1.0 <= hi)
    return ClaimResult(
        expected="every printed cell = 0.8 x (13) to its printed digits; 0.8 in the interval, 1 "
        "not",
        got=f"{sum(r.within_print_rounding for r in rows)}/16 cells; interval [{lo:.4f}, {hi:.4f}]",
        passed=ok,
    )


def claim_beta() -> ClaimResult:
    b = sp.symbols("beta", positive=True)
    f = 1 / b**2 - 2 / b
    crit = sp.solve(sp.diff(f, b), b)
    zero = sp.solve(f, b)
    ok = (
        crit == [1]
        and f.subs(b, 1) == -1
        and sp.diff(f, b, 2).subs(b, 1) > 0
        and zero == [sp.Rational(1, 2)]
        and sp.diff(f, b).subs(b, sp.Rational(1, 2)) == -8
    )
    return ClaimResult(
        "stationary point beta = 1 (minimum, f = -1); zero 1/2, slope -8",
        f"stationary {crit}, f'' {sp.diff(f, b, 2).subs(b, 1)}; zero {zero}, slope "
        f"{sp.diff(f, b).subs(b, sp.Rational(1, 2))}",
        ok,
    )


def claim_parabola_17_18() -> ClaimResult:
    T1, T2sq, omega, p = 0.01, 0.001, 5.0, 20.0
    ch = Channel(T1, T2sq)
    worst, worst18 = 0.0, 0.0
    for g in (0.5, 0.8, 1.5, 2.0):
        _, out = settled(
            power_program(2, -300.0, 0.0, 0.0, p, omega), ch, ch.scaled(g), window=2.0, n=401
        )
        x, y = out["x1"], out["y1"]
        worst = max(worst, float(np.max(np.abs(y - curve_17(x, omega, p, T1, T2sq, g)))))
        xv, yv = parabola_vertex_17(omega, p, T1, T2sq, g)
        worst18 = max(worst18, abs(yv - locus_18(xv, omega, p, T1, T2sq)))
    return ClaimResult(
        "|y1 - (17)| < 1e-7 mm, vertices on corrected (18) to 1e-12",
        f"{worst:.1e} mm, {worst18:.1e}",
        worst < 1e-7 and worst18 < 1e-12,
    )


#: the Fig. 4b case (2 T2^2 > T1^2): T1 = 0.01 s, T2^2 = 0.001 s^2, omega = 5, p = 20 mm
FIG4B = (5.0, 20.0, 0.01, 0.001)


def _fig4b_output(gamma: float) -> dict[str, np.ndarray]:
    """Settled output of the horizontal parabola (y from -50 to 50 mm), y channel x gamma."""
    omega, p, T1, T2sq = FIG4B
    ch = Channel(T1, T2sq)
    program = horizontal_parabola_program(-300.0, 0.0, 0.0, p, omega)
    return settled(program, ch, ch.scaled(gamma), window=2.0, n=4001)[1]


def claim_parabola_19() -> ClaimResult:
    worst, worst_v, got = 0.0, 0.0, []
    for g in (0.5, 0.8, 1.0, 1.25, 2.0):
        out = _fig4b_output(g)
        x, y = out["x1"], out["y1"]
        worst = max(worst, float(np.max(np.abs(x - curve_19(y, *FIG4B, g)))))
        near = np.abs(y) <= 8.0
        c = np.polyfit(y[near], x[near], 2)
        yv = -c[1] / (2 * c[0])
        xv = float(np.polyval(c, yv))
        xf, yf = parabola_vertex_19(*FIG4B, g)
        worst_v = max(worst_v, abs(xv - xf), abs(yv - yf), abs(xv + 0.2375))
        got.append(f"({xv:.6f}, {yv:.6f})")
    return ClaimResult(
        "|x1 - (19)| < 1e-7 mm; vertices (-0.2375, 0.25 ... -0.5) mm to 1e-7",
        f"{worst:.1e} mm; vertices " + ", ".join(got),
        worst < 1e-7 and worst_v < 1e-7,
    )


def claim_parabola_19_error() -> ClaimResult:
    expected = {(1.0, 1): 0.2375, (0.5, 1): 0.3448, (2.0, -1): 0.5533, (2.0, 1): 0.3445}
    y = np.linspace(-20.0, 20.0, 40001)
    worst, worst_sim, got = 0.0, 0.0, []
    for (g, side), value in expected.items():
        d = power_distance(y, curve_19(y, *FIG4B, g), 2, 0.0, 0.0, FIG4B[1])[0]
        largest = float(np.max(np.abs(d[side * y > 0])))
        worst = max(worst, abs(largest - value))
        got.append(f"{largest:.5f}")
        out = _fig4b_output(g)
        ys = out["y1"][np.abs(out["y1"]) <= 20.0]
        xs = out["x1"][np.abs(out["y1"]) <= 20.0]
        d_sim = power_distance(ys, xs, 2, 0.0, 0.0, FIG4B[1])[0]
        d_19 = power_distance(ys, curve_19(ys, *FIG4B, g), 2, 0.0, 0.0, FIG4B[1])[0]
        worst_sim = max(worst_sim, float(np.max(np.abs(d_sim - d_19))))
    return ClaimResult(
        "0.2375, 0.3448, 0.5533, 0.3445 mm (atol 1e-4); simulation = (19) to 1e-7 mm",
        ", ".join(got) + f" mm; simulation - (19) {worst_sim:.1e} mm",
        worst <= 1e-4 and worst_sim < 1e-7,
    )


def claim_parabola_24() -> ClaimResult:
    ch = Channel.from_open_loop(100.0, 0.1)
    sysm = TwoAxisServo(power_program(2, 0.0, 0.0, 0.0, 20.0, 5.0), ch, ch, "on")
    t = np.linspace(0.0, 3.0, 3001)
    out = sysm.outputs(sysm.states(t, sysm.initial_state()))
    dev = out["y1"] - out["x1"] ** 2 / 20.0
    d24 = deviation_24(t, 5.0, 20.0, ch)
    i = int(np.argmax(d24))
    ok = (
        float(np.max(np.abs(dev - d24))) < 1e-8
        and abs(d24[i] - 0.56243) < 1e-4
        and abs(t[i] - 0.25) < 0.005
        and abs(dev[-1]) < 1e-5
    )
    return ClaimResult(
        "|sim - (24)| < 1e-8; peak 0.56243 mm at 0.25 s; -> 0",
        f"{np.max(np.abs(dev - d24)):.1e}; peak {d24[i]:.5f} at {t[i]:.3f} s; end {dev[-1]:.1e}",
        ok,
    )


def claim_cubic_quartic() -> ClaimResult:
    T1, T2 = 0.01, 0.0005
    ch = Channel(T1, T2)
    w, p = 0.125, 400.0
    _, out = settled(power_program(3, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    e3 = float(np.max(np.abs(y - cubic_curve(x, w, p, T1, T2))))
    w, p = 0.00625, 8000.0
    _, out = settled(power_program(4, -100.0, 0.0, 0.0, p, w), ch, ch, window=2.0, n=401)
    x, y = out["x1"], out["y1"]
    e4 = float(np.max(np.abs(y - quartic_curve(x, w, p, T1, T2))))
    tau = out["x"] / (w * p)  # PU time measured from the vertex
    e_fix = float(np.max(np.abs(y - quartic_y1(tau, w, p, T1, T2))))
    e_pr = float(np.max(np.abs(y - quartic_y1(tau, w, p, T1, T2, printed=True))))
    scale = float(np.max(np.abs(y)))
    tol = 1e-9 * max(scale, 1.0)
    ok = e3 < 1e-6 and e4 < tol + 1e-7 and e_fix < tol + 1e-7 and e_pr > 1e-3
    return ClaimResult(
        "cubic curve, quartic curve and corrected quartic y1(t) match; printed y1(t) does not",
        f"cubic {e3:.1e}, quartic {e4:.1e}, corrected y1 {e_fix:.1e}, printed y1 {e_pr:.2g} mm",
        ok,
    )


def claim_quartic_beta() -> ClaimResult:
    b = sp.symbols("beta_1", positive=True)
    T2 = sp.symbols("T_2", positive=True)
    T1 = sp.sqrt(b) * T2
    lead = sp.simplify((T1**2 - 2 * T2**2) / T2**2)  # sign of the x^2 coefficient of y'
    const = sp.expand((3 * T1**4 + 8 * T2**4 - 12 * T1**2 * T2**2) / T2**4)
    slope = sp.simplify((3 * T2**2 * T1 - T1**3) / T2**3)
    roots = sorted(float(r) for r in sp.solve(const, b))
    ok = (
        sp.solve(lead, b) == [2]
        and abs(roots[0] - 0.8453) < 1e-4
        and abs(roots[1] - 3.1547) < 1e-4
        and sp.solve(slope, b) == [3]
        and lead.subs(b, 1) < 0
        and slope.subs(b, 1) > 0
        and const.subs(b, 2) < 0
    )
    return ClaimResult(
        "opens down for beta1 < 2; constant term roots 0.8453, 3.1547; slope zero at 3",
        f"x^2 coefficient zero at {sp.solve(lead, b)}; roots {roots[0]:.4f}, {roots[1]:.4f}; "
        f"slope zero at {sp.solve(slope, b)}",
        ok,
    )
