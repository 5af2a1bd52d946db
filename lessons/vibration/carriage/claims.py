"""The checks behind the claims of textbook §2.3: Problem 2.6 (free vibration of the
carriage, (2.38)-(2.77)) and Problem 2.7 (forced vibration of one axis, (2.78)-(2.92)).

Each ``check_*`` computes one statement of the source from the models of
:mod:`analyzer_lab.lessons.vibration.carriage.model` (symbolically with sympy where the source derives, or
numerically against ``scipy.linalg.eigh`` and ``solve_ivp``) and compares it; the lessons
state the claims and hand in what depends on their presets (the preset carriages, a
start state).
"""

from __future__ import annotations

import math

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import ClaimResult, at_most, close
from analyzer_lab.lessons.vibration.carriage.model import (
    Carriage,
    ForcedOscillator,
    box_inertia,
    box_inertia_printed,
    carriage_lagrange,
    carriage_source_equations,
    closed_form_frequencies,
    coupled_frequency,
    coupled_frequency_as_printed,
    eigen_frequencies,
    forced_lagrange,
    frequency_response,
    jeffcott_deflection,
    modal_propagate,
    mode_character,
    mode_shape,
)
from scipy.integrate import solve_ivp

# ---------------------------------------------------------------- Problem 2.6


def random_carriages(n: int, seed: int = 7) -> list[Carriage]:
    """``n`` random stable carriages (K_x > C_y h^2, K_y > C_x h^2: K is the total
    rotational stiffness about O of (2.40))."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        m = rng.uniform(1, 50)
        Ix, Iy, Iz = box_inertia(m, *rng.uniform(0.05, 1.0, 3))
        C = 10 ** rng.uniform(4, 8, 3)
        h = rng.uniform(0, 0.2)
        K = 10 ** rng.uniform(2, 7, 3) + np.array([C[1], C[0], 0.0]) * h**2
        out.append(Carriage(m, Ix, Iy, Iz, *C, *K, h=h))
    return out


def check_lagrange_6dof() -> ClaimResult:
    s = carriage_lagrange()
    diffs = [sp.simplify(a - b) for a, b in zip(s.equations, carriage_source_equations())]
    ok = len(s.equations) == 6 and all(d == 0 for d in diffs)
    return ClaimResult(
        "6 equations, each equal to (2.42)-(2.44)",
        f"{len(s.equations)} equations, differences {diffs}",
        ok,
    )


def check_gradients() -> ClaimResult:
    s = carriage_lagrange()
    x, y, z, px, py, pz = s.q
    (Cx, Cy, Cz), (Kx, Ky, Kz), h = s.C, s.K, s.h
    printed = [
        Cx * x + Cx * h * py,
        Cy * y + Cy * h * px,
        Cz * z,
        Kx * px + Cy * h * y,
        Ky * py + Cx * h * x,
        Kz * pz,
    ]
    diffs = [sp.simplify(sp.diff(s.W, c) - e) for c, e in zip(s.q, printed)]
    return ClaimResult("all differences 0", str(diffs), all(d == 0 for d in diffs))


def check_determinant() -> ClaimResult:
    m, Iy, Cx, Ky, h, w2 = sp.symbols("m I_y C_x K_y h varpi2", positive=True)
    det = sp.Matrix([[Cx - m * w2, Cx * h], [Cx * h, Ky - Iy * w2]]).det()
    f1 = (Cx - m * w2) * (Ky - Iy * w2) - Cx**2 * h**2
    f2 = m * Iy * w2**2 - (Cx * Iy + m * Ky) * w2 + Cx * Ky - Cx**2 * h**2
    f3 = w2**2 - (Cx / m + Ky / Iy) * w2 + (Cx * Ky - Cx**2 * h**2) / (m * Iy)
    a, b = Cx / m, Ky / Iy
    rad = sp.simplify(
        (a + b) ** 2 / 4
        - (Cx * Ky - Cx**2 * h**2) / (m * Iy)
        - ((a - b) ** 2 / 4 + Cx**2 * h**2 / (m * Iy))
    )
    d = [sp.expand(det - f1), sp.expand(det - f2), sp.simplify(det / (m * Iy) - f3), rad]
    return ClaimResult("all differences 0", str(d), all(x == 0 for x in d))


def check_closed_vs_eig(carriages: list[Carriage]) -> ClaimResult:
    """The closed forms against ``eigh`` for ``carriages`` and 20 random ones."""
    worst = 0.0
    for p in carriages + random_carriages(20):
        cf = np.sort(np.array(list(closed_form_frequencies(p).values())))
        w, _ = eigen_frequencies(p)
        worst = max(worst, float(np.max(np.abs(cf - w) / w)))
    return at_most(1e-9, worst, "max relative difference ")


def check_sign_268(p: Carriage) -> ClaimResult:
    """(2.68) with '+' is an eigenvalue of ``p`` (a strongly coupled carriage); as printed not."""
    w, _ = eigen_frequencies(p)
    pair = sorted([coupled_frequency(p.Cx, p.Ky, p.m, p.Iy, p.h, s) for s in (+1, -1)])
    target = [v for v in w if any(abs(v - c) <= 1e-9 * v for c in pair)]
    printed = coupled_frequency_as_printed(p.Cx, p.Ky, p.m, p.Iy, p.h)
    plus_ok = len(target) >= 2 and abs(pair[0] - min(target)) <= 1e-9 * pair[0]
    printed_wrong = (not math.isfinite(printed)) or abs(printed - pair[0]) > 1e-3 * pair[0]
    return ClaimResult(
        f"'+': {pair[0]:.8g} rad/s = eigenvalue; '-' differs",
        f"'+': {pair[0]:.8g}, eigenvalues {', '.join(f'{v:.8g}' for v in target)}; "
        f"as printed: {printed:.8g}",
        plus_ok and printed_wrong,
    )


def check_h_zero() -> ClaimResult:
    """(2.67)-(2.68) with h = 0, C_x/m = 10 < K_y/I_y = 4000: the '+' root is the rotation."""
    p = Carriage(1.0, 1.0, 1.0, 1.0, 10.0, 10.0, 10.0, 4000.0, 4000.0, 4000.0, 0.0)
    up = coupled_frequency(10.0, 4000.0, 1.0, 1.0, 0.0, +1)
    lo = coupled_frequency(10.0, 4000.0, 1.0, 1.0, 0.0, -1)
    kind_up, kind_lo = mode_character(p, "x-phi_y upper"), mode_character(p, "x-phi_y lower")
    ok = (
        close(63.245553203367585, up, rtol=1e-12).passed
        and close(3.1622776601683795, lo, rtol=1e-12).passed
        and (kind_up, kind_lo) == ("rotation", "translation")
    )
    return ClaimResult(
        "+ root 63.2455532 (rotation), - root 3.16227766 (translation)",
        f"+ {up:.10g} ({kind_up}), - {lo:.10g} ({kind_lo})",
        ok,
    )


def check_mode_ratio(carriages: list[Carriage]) -> ClaimResult:
    """(2.64) gives eigenvectors for ``carriages`` and 5 random ones."""
    worst = 0.0
    for p in carriages + random_carriages(5, seed=3):
        M, K = p.matrices()
        for key in ("x-phi_y upper", "x-phi_y lower", "y-phi_x upper", "y-phi_x lower"):
            s = mode_shape(p, key)
            w2 = closed_form_frequencies(p)[key] ** 2
            worst = max(worst, float(np.linalg.norm(K @ s - w2 * (M @ s)) / np.linalg.norm(K @ s)))
    return at_most(1e-9, worst, "relative residual |K s - w^2 M s| ")


def check_jeffcott() -> ClaimResult:
    m, e, c, w = sp.symbols("m e c varpi", positive=True)
    zz = jeffcott_deflection(m, e, c, w)
    residual = sp.simplify(c * zz - m * w**2 * (e + zz))
    singular = sp.solve(sp.denom(sp.together(zz)), w)
    ok = residual == 0 and (singular == [sp.sqrt(c / m)] or sp.sqrt(c) / sp.sqrt(m) in singular)
    return ClaimResult(
        "residual 0; singular at sqrt(c/m)",
        f"residual {residual}; singular at {singular}",
        bool(ok),
    )


def check_torsional() -> ClaimResult:
    k, m, q = sp.symbols("k m q", positive=True)
    inertia = sp.Symbol("I", positive=True)
    d1 = sp.simplify(
        sp.sqrt(k / (m * q**2)) - sp.sqrt(k / inertia).subs(inertia, m * q**2)
    )  # (2.53) against (2.54) with I = m q^2
    fc = 1 / (2 * math.pi) * math.sqrt(50.0 / 2.0)
    return ClaimResult(
        "difference 0; f_c = 0.7957747 Hz for c/m = 25",
        f"{d1}; {fc:.7f}",
        d1 == 0 and abs(fc - 0.7957747) < 1e-7,
    )


def check_box_inertia() -> ClaimResult:
    a, b, H, m = sp.symbols("a b H m", positive=True)
    X, Y, Z = sp.symbols("X Y Z", real=True)
    rho = m / (a * b * H)
    lim = [(X, -b / 2, b / 2), (Y, -a / 2, a / 2), (Z, -H / 2, H / 2)]
    Ix = sp.integrate(rho * (Y**2 + Z**2), *lim)
    Iy = sp.integrate(rho * (X**2 + Z**2), *lim)
    Iz = sp.integrate(rho * (X**2 + Y**2), *lim)
    d_z = sp.simplify(Iz - m * (a**2 + b**2) / 12)
    d_x = sp.simplify(Ix - m * (a**2 + H**2) / 12)
    d_y = sp.simplify(Iy - m * (b**2 + H**2) / 12)
    printed = box_inertia_printed(1.0, 0.4, 0.5, 0.06)
    exact = box_inertia(1.0, 0.4, 0.5, 0.06)
    numeric_ok = abs(exact[2] - float(Iz.subs({a: 0.4, b: 0.5, H: 0.06, m: 1}))) < 1e-15
    printed_differs = abs(printed[0] - exact[0]) > 1e-6 and abs(printed[1] - exact[1]) > 1e-6
    return ClaimResult(
        "(2.75) and corrected (2.76)/(2.77): differences 0; printed differ",
        f"{d_z}, {d_x}, {d_y}; printed I_x, I_y = {printed[0]:.6g}, {printed[1]:.6g} "
        f"vs {exact[0]:.6g}, {exact[1]:.6g}",
        d_z == 0 and d_x == 0 and d_y == 0 and numeric_ok and printed_differs,
    )


def check_huygens() -> ClaimResult:
    a, b, H, m = sp.symbols("a b H m", positive=True)
    X, Y, Z, Xc, Yc, Zc = sp.symbols("X Y Z X_c Y_c Z_c", real=True)
    rho = m / (a * b * H)
    lim = [(X, Xc - b / 2, Xc + b / 2), (Y, Yc - a / 2, Yc + a / 2), (Z, Zc - H / 2, Zc + H / 2)]
    Iz = sp.integrate(rho * (X**2 + Y**2), *lim)
    d = sp.simplify(Iz - m * ((a**2 + b**2) / 12 + Xc**2 + Yc**2))
    num = box_inertia(2.0, 0.4, 0.5, 0.06, 0.1, -0.2, 0.05)[2]
    return ClaimResult(
        "difference 0; I_z(m=2, a=.4, b=.5, Xc=.1, Yc=-.2) = 0.168333",
        f"{d}; {num:.6f}",
        d == 0 and abs(num - 0.1683333333) < 1e-9,
    )


def check_free_response(p: Carriage, q0: np.ndarray, v0: np.ndarray) -> ClaimResult:
    """Modal superposition from (q0, v0) against solve_ivp of M q'' + K q = 0 over 0.05 s."""
    M, K = p.matrices()
    t = np.linspace(0.0, 0.05, 401)
    qs, _ = modal_propagate(p, q0, v0, t)
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.linalg.solve(M, K), np.zeros((6, 6))]])
    sol = solve_ivp(
        lambda _t, y: A @ y,
        (0.0, 0.05),
        np.concatenate([q0, v0]),
        method="DOP853",
        rtol=1e-12,
        atol=1e-15,
        t_eval=t,
    )
    err = float(np.max(np.abs(sol.y[:6].T - qs)) / np.max(np.abs(qs)))
    return at_most(1e-8, err, "max relative difference ")


# ---------------------------------------------------------------- Problem 2.7

#: the illustrative axis of the forced lesson: m = 2, b = 0.8, c = 50, F0 = 3, omega0 = 4
EXAMPLE = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 4.0)


def check_lagrange_forced() -> ClaimResult:
    S = forced_lagrange()
    t, q = S.t, S.q
    expected = S.m * sp.diff(q, t, 2) + S.c * q - (-S.b * sp.diff(q, t) + S.F0 * sp.sin(S.w0 * t))
    d = sp.simplify(S.lagrange.lhs - expected)
    return ClaimResult("difference 0", str(d), d == 0)


def check_MN() -> ClaimResult:
    S = forced_lagrange()
    f, om, tau, w0, t = S.f, S.omega, S.tau, S.w0, S.t
    M, N = S.M, S.N
    den = (om**2 - w0**2) ** 2 + 4 * f**2 * w0**2
    M_src, N_src = -2 * f * w0 * tau / den, tau * (om**2 - w0**2) / den
    qs = M * sp.cos(w0 * t) + N * sp.sin(w0 * t)
    residual = sp.simplify(
        sp.diff(qs, t, 2) + 2 * f * sp.diff(qs, t) + om**2 * qs - tau * sp.sin(w0 * t)
    )
    d = [
        sp.simplify(M - M_src),
        sp.simplify(N - N_src),
        sp.simplify(N - (w0**2 - om**2) / (2 * f * w0) * M),
        residual,
    ]
    return ClaimResult("all 0", str(d), all(x == 0 for x in d))


def check_amp_phase() -> ClaimResult:
    S = forced_lagrange()
    f, om, tau, w0 = S.f, S.omega, S.tau, S.w0
    # A0^2 (both sides positive) and tan phi1
    d1 = sp.simplify(S.M**2 + S.N**2 - tau**2 / ((om**2 - w0**2) ** 2 + 4 * f**2 * w0**2))
    d2 = sp.simplify(S.M / S.N - (-2 * f * w0 / (om**2 - w0**2)))
    o = EXAMPLE
    tt = np.linspace(0, 10, 101)
    M, N = o.MN
    steady = M * np.cos(o.w0 * tt) + N * np.sin(o.w0 * tt)
    d3 = float(np.max(np.abs(o.A0 * np.sin(o.w0 * tt + o.phi1) - steady)))
    return ClaimResult("0, 0, < 1e-14", f"{d1}, {d2}, {d3:.2e}", d1 == 0 and d2 == 0 and d3 < 1e-14)


def check_homogeneous() -> ClaimResult:
    t = sp.Symbol("t", real=True)
    A, ph0 = sp.symbols("A varphi_0", real=True)
    f, om = sp.symbols("f omega", positive=True)
    om1 = sp.sqrt(om**2 - f**2)
    q0 = A * sp.exp(-f * t) * sp.sin(om1 * t + ph0)
    residual = sp.simplify(sp.diff(q0, t, 2) + 2 * f * sp.diff(q0, t) + om**2 * q0)
    real_when = (
        ForcedOscillator(1, 2 * 1.0, 4.0, 0, 0).regime,
        ForcedOscillator(1, 2 * 3.0, 4.0, 0, 0).regime,
    )
    ok = residual == 0 and real_when == ("underdamped", "overdamped")
    return ClaimResult(
        "residual 0; f=1<omega=2 oscillates, f=3>omega=2 does not", f"{residual}; {real_when}", ok
    )


def check_numbers() -> ClaimResult:
    a, p = close(0.164094, EXAMPLE.A0, atol=5e-7), close(-0.175940, EXAMPLE.phi1, atol=5e-7)
    return ClaimResult(
        f"A0 {a.expected}; phi1 {p.expected}", f"A0 {a.got}; phi1 {p.got}", a.passed and p.passed
    )


def check_quadrant() -> ClaimResult:
    o = ForcedOscillator(2.0, 0.8, 50.0, 3.0, 7.0)
    M, N = o.MN
    t = np.linspace(0, 5, 501)
    qs = M * np.cos(7 * t) + N * np.sin(7 * t)
    e2 = float(np.max(np.abs(o.A0 * np.sin(7 * t + math.atan2(M, N)) - qs)))
    e1 = float(np.max(np.abs(o.A0 * np.sin(7 * t + math.atan(M / N)) - qs)))
    return ClaimResult(
        "atan2 error < 1e-14, atan error > 1e-2",
        f"atan2 {e2:.2e}, atan {e1:.2e}",
        e2 < 1e-14 and e1 > 1e-2,
    )


def _ivp_error(o: ForcedOscillator, q0: float, v0: float, t_end: float) -> float:
    t = np.linspace(0.0, t_end, 1001)
    q, _ = o.response(t, q0, v0)
    sol = solve_ivp(
        o.rhs, (0.0, t_end), [q0, v0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=t
    )
    return float(np.max(np.abs(sol.y[0] - q)))


def check_closed_vs_ivp() -> ClaimResult:
    cases = [  # m, b, c, F0, omega0, q(0), q'(0): every damping regime, undamped resonance
        (2, 0.8, 50, 3, 4, 0.05, 0),
        (2, 0.8, 50, 3, 7, 0.05, 0.3),
        (2, 20, 50, 3, 4, 0.05, 0),
        (2, 40, 50, 3, 4, 0.05, -0.2),
        (2, 0, 50, 3, 5, 0.0, 0.0),
        (2, 0, 0, 3, 2, 0.1, 0.1),
    ]
    worst = max(_ivp_error(ForcedOscillator(*c[:5]), c[5], c[6], 20.0) for c in cases)
    return at_most(1e-8, worst, "max |q_closed - q_ivp| (m) ")


def check_form_292() -> ClaimResult:
    t = np.linspace(0, 20, 2001)
    err = float(
        np.max(np.abs(EXAMPLE.response_292(t, 0.05, 0.0) - EXAMPLE.response(t, 0.05, 0.0)[0]))
    )
    return at_most(1e-12, err, "max difference (m) ")


def _zero_crossings(y: np.ndarray) -> int:
    return int(np.count_nonzero(np.diff(np.sign(y[np.abs(y) > 1e-14])) != 0))


def check_regimes() -> ClaimResult:
    t = np.linspace(0, 20, 20001)
    under, _ = ForcedOscillator(2, 0.8, 50, 0, 0).homogeneous(t, 0.05, 0.0)
    over, _ = ForcedOscillator(2, 40, 50, 0, 0).homogeneous(t, 0.05, -1.0)
    n_under, n_over = _zero_crossings(under), _zero_crossings(over)
    return ClaimResult(
        "f<omega: > 10 crossings; f>omega: <= 1",
        f"{n_under}; {n_over}",
        n_under > 10 and n_over <= 1,
    )


def check_peak() -> ClaimResult:
    o = EXAMPLE
    w = np.linspace(4.9, 5.1, 200001)
    A, _ = frequency_response(o.m, o.b, o.c, o.F0, w)
    w_num, A_num = float(w[np.argmax(A)]), float(np.max(A))
    ok = (
        abs(w_num - o.peak_frequency) < 2e-6
        and abs(o.peak_frequency - 4.99199) < 5e-6
        and abs(A_num - o.peak_amplitude) < 1e-9
        and abs(o.peak_amplitude - 0.750601) < 5e-7
    )
    return ClaimResult(
        "peak at 4.99199 rad/s, A0 0.750601 m",
        f"numeric peak at {w_num:.6f}, A0 {A_num:.7f}; "
        f"formula {o.peak_frequency:.6f}, {o.peak_amplitude:.7f}",
        ok,
    )
