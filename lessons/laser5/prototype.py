"""The numerical prototype of the LSP-2000 article: four segments on a paraboloid, measured.

The article's figures (Fig. 3-5) are lost; its statements are checked on four task
segments of the dish ``z = z0 - r^2/(4F)``, F = 500 mm, with R_C = 200 mm and
R_B = 300 mm (assumed values, see the lesson's notes): S1 azimuthal, S2 radial, S3
oblique, S4 past the apex where the beam is almost vertical.  Each check below measures
one statement (deviation of linear interpolation, bisection by quarters, method 1's
half angle, nonlinear interpolation on the chord, the rotary limits near the vertical)
and returns a :class:`ClaimResult` with the numbers.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from analyzer_lab.lessons.kit.contract import ClaimResult, at_most, close
from analyzer_lab.lessons.laser5.interpolation import (
    Bisection,
    Move,
    axis_path_length,
    bisect_segment,
    bisect_uniform,
    fixed_normal_move,
    mean_normal,
    move_deviation,
    moves_backwards,
    nonlinear_move,
    nonlinear_submoves,
    off_normal_max,
    point_speed_ratio,
    sagitta_estimate,
)
from analyzer_lab.lessons.laser5.kinematics import Machine5, angle_between, translate_poses
from analyzer_lab.lessons.laser5.task import Paraboloid, Task, make_task

#: The prototype's segments on the paraboloid F = 500 mm: (u, v) offsets of the ends [mm].
SEGMENTS: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {
    "S1": ((300.0, 0.0), (300.0, 60.0)),  # azimuthal
    "S2": ((100.0, 0.0), (160.0, 0.0)),  # radial
    "S3": ((250.0, -40.0), (300.0, 40.0)),  # oblique
    "S4": ((-30.0, 5.0), (30.0, 5.0)),  # past the apex: near-vertical beam
}


@dataclass
class SegmentStudy:
    """One segment of the prototype: the four controllers measured."""

    machine: Machine5
    task: Task
    qa: np.ndarray
    qb: np.ndarray

    @property
    def ends(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        return self.task.points[0], self.task.normals[0], self.task.points[1], self.task.normals[1]

    def linear(self) -> Move:
        pa, _, pb, _ = self.ends
        return Move("linear", self.qa, self.qb, pa, pb)

    def nonlinear(self) -> Move:
        pa, _, pb, _ = self.ends
        return nonlinear_move(self.qa, self.qb, pa, pb)


@lru_cache(maxsize=16)
def study(
    name: str, limits: str = "original", R_C: float = 200.0, R_B: float = 300.0
) -> SegmentStudy:
    """Segment ``name`` (S1..S4) of the prototype on the paraboloid F = 500 mm."""
    machine = Machine5(R_C=R_C, R_B=R_B, limits=limits)  # type: ignore[arg-type]
    a, b = SEGMENTS[name]
    task = make_task(Paraboloid(), "line", 1, a, b)
    qa = machine.inverse(task.points[0], task.normals[0])
    qb = machine.inverse(task.points[1], task.normals[1], float(qa[3]))
    return SegmentStudy(machine, task, qa, qb)


@lru_cache(maxsize=16)
def uniform_levels(name: str, limits: str, depth: int = 6) -> tuple[float, ...]:
    """Largest piece deviation after 0..depth uniform bisection levels [mm]."""
    s = study(name, limits)
    out = [move_deviation(s.machine, s.linear())]
    for d in range(1, depth + 1):
        out.append(
            max(move_deviation(s.machine, mv) for mv in bisect_uniform(s.machine, s.ends, s.qa, d))
        )
    return tuple(out)


@lru_cache(maxsize=16)
def adaptive(name: str, limits: str, tol: float = 0.020) -> Bisection:
    """Method 2 on segment ``name`` to the tolerance ``tol`` [mm] (depth cap 30)."""
    s = study(name, limits)
    return bisect_segment(s.machine, s.ends, s.qa, tol, 30)


# ---------------------------------------------------------------- claims


def _all(results: list[ClaimResult]) -> ClaimResult:
    return ClaimResult(
        expected="; ".join(r.expected for r in results),
        got="; ".join(r.got for r in results),
        passed=all(r.passed for r in results),
    )


def check_round_trip() -> ClaimResult:
    worst = 0.0
    for limits in ("original", "improved"):
        m = Machine5(limits=limits)  # type: ignore[arg-type]
        q = m.random_poses(np.random.default_rng(3), 1000)
        p, n = m.forward(q)
        for i in range(len(q)):
            q2 = m.inverse(p[i], n[i], C_ref=float(q[i, 3]))
            p2, n2 = m.forward(q2)
            worst = max(
                worst,
                float(np.abs(p2 - p[i]).max()),
                float(np.abs(q2[:3] - q[i, :3]).max()),
                float(np.abs(n2 - n[i]).max()),
            )
    return at_most(1e-9, worst, "max |p, n, X, Y, Z round-trip error| ")


def check_vertical() -> ClaimResult:
    m = Machine5()
    q1 = np.array([1000.0, 1000.0, 100.0, 1.0, 0.0])
    p, n = m.forward(q1)
    q0 = m.inverse(p, n)  # first variant: C = 0
    q_ref = m.inverse(p, n, C_ref=1.0)
    same = max(
        float(np.abs(m.forward(q0)[0] - p).max()), float(np.abs(m.forward(q_ref)[0] - p).max())
    )
    differ = float(np.hypot(*(q0[:2] - q1[:2])))
    ok = same <= 1e-9 and q0[3] == 0.0 and abs(q_ref[3] - 1.0) < 1e-12 and differ > 100.0
    return ClaimResult(
        expected="two axis sets (C = 0 and C = 1) give the same pose to 1e-9 mm;"
        " X, Y differ by R_C |2 sin(1/2)| = 191.8 mm",
        got=f"pose error {same:.2e} mm, C = {q0[3]:g} / {q_ref[3]:g}, |dXY| = {differ:.1f} mm",
        passed=ok,
    )


def check_linear_deviates() -> ClaimResult:
    s = study("S1")
    dev = move_deviation(s.machine, s.linear())
    est = sagitta_estimate(s.machine, s.qa, s.qb)
    r = [close(1.398, dev, atol=0.001), close(dev, est, rtol=0.005)]
    res = _all(r)
    res.passed = res.passed and dev > 0.020
    res.expected = (
        "S1 linear interpolation 1.398 mm > 0.020 mm;"
        " sagitta (R_C + R_B sin B) dC^2/8 within 0.5 %: " + res.expected
    )
    return res


def check_speed_nonuniform() -> ClaimResult:
    return _all(
        [
            close(1.008, point_speed_ratio(study("S1").machine, study("S1").linear()), atol=0.001),
            close(1.061, point_speed_ratio(study("S3").machine, study("S3").linear()), atol=0.001),
        ]
    )


def check_quarter() -> ClaimResult:
    ratios = {}
    for name in ("S1", "S2", "S3"):
        lv = uniform_levels(name, "original")
        ratios[name] = [lv[d] / lv[d + 1] for d in range(len(lv) - 1)]
    flat = [r for rs in ratios.values() for r in rs]
    last = [rs[-1] for rs in ratios.values()]
    lv = uniform_levels("S1", "original")
    ok = (
        min(flat) >= 3.4
        and max(flat) <= 4.05
        and all(abs(r - 4.0) < 0.02 for r in last)
        and abs(lv[1] - 0.355) < 0.001
    )
    return ClaimResult(
        expected="error ratio per split between 3.4 (first split of the oblique S3) and 4.05,"
        " 4.00 +- 0.02 at level 6; S1 level 1 = 0.355 mm",
        got="; ".join(f"{n}: " + ", ".join(f"{r:.3f}" for r in rs) for n, rs in ratios.items())
        + "; S1 levels "
        + ", ".join(f"{x:.3g}" for x in lv),
        passed=ok,
    )


def check_bisection_tolerance() -> ClaimResult:
    got = {n: adaptive(n, "original") for n in ("S1", "S2", "S3")}
    want = {"S1": (16, 4), "S2": (4, 2), "S3": (16, 4)}
    ok = all(
        b.converged and b.worst_mm <= 0.020 and (len(b.moves), b.max_depth) == want[n]
        for n, b in got.items()
    )
    return ClaimResult(
        expected="within 20 um: S1 16 pieces / depth 4, S2 4 / 2, S3 16 / 4",
        got=", ".join(
            f"{n} {len(b.moves)} / {b.max_depth} ({b.worst_mm * 1e3:.2f} um)"
            for n, b in got.items()
        ),
        passed=ok,
    )


def check_nonlinear_on_segment() -> ClaimResult:
    worst, ratio = 0.0, 0.0
    for limits in ("original", "improved"):
        for name in SEGMENTS:
            s = study(name, limits)
            worst = max(worst, move_deviation(s.machine, s.nonlinear()))
            ratio = max(ratio, abs(point_speed_ratio(s.machine, s.nonlinear()) - 1.0))
    ok = worst <= 1e-9 and ratio <= 1e-6
    return ClaimResult(
        expected="deviation <= 1e-9 mm and speed max/min - 1 <= 1e-6 on S1-S4, both limits",
        got=f"deviation {worst:.2e} mm, speed ratio - 1 = {ratio:.2e}",
        passed=ok,
    )


def check_sub_moves() -> ClaimResult:
    s = study("S1")
    pa, _, pb, _ = s.ends
    devs = [
        max(
            move_deviation(s.machine, mv, pa, pb)
            for mv in nonlinear_submoves(s.machine, s.nonlinear(), N)
        )
        for N in (4, 16, 64)
    ]
    return _all(
        [
            close(0.0874, devs[0], rtol=0.01),
            close(0.00547, devs[1], rtol=0.01),
            close(0.000342, devs[2], rtol=0.01),
        ]
    )


def check_fixed_normal() -> ClaimResult:
    s = study("S1")
    _, na, _, nb = s.ends
    mv = fixed_normal_move(s.machine, s.ends, float(s.qa[3]))
    dev = move_deviation(s.machine, mv)
    off = math.degrees(off_normal_max(s.machine, s.task, [mv], samples=1025))
    half = 0.5 * math.degrees(float(angle_between(na, nb)))
    r = _all(
        [
            close(half, off, atol=1e-6),
            close(1.645, off, atol=0.001),
            at_most(1e-9, dev, "deviation "),
        ]
    )
    r.expected = (
        "beam error = half the angle between end normals (1.645 deg), point on the chord: "
        + r.expected
    )
    return r


def near_vertical(limits: str) -> dict[str, float]:
    """S4 under ``limits``: rotary changes [deg], linear deviation and first split [mm],
    the adaptive bisection, XY travel [mm] and beam error [deg] of the nonlinear move."""
    s = study("S4", limits)
    bis = adaptive("S4", limits)
    nl = s.nonlinear()
    return {
        "dC": math.degrees(s.qb[3] - s.qa[3]),
        "dB": math.degrees(s.qb[4] - s.qa[4]),
        "linear": move_deviation(s.machine, s.linear()),
        "split": uniform_levels("S4", limits)[1],
        "converged": bis.converged,
        "pieces": len(bis.moves),
        "depth": bis.max_depth,
        "worst": bis.worst_mm,
        "xy": axis_path_length(s.machine, [nl], slice(0, 2)),
        "beam": math.degrees(off_normal_max(s.machine, s.task, [nl])),
    }


def _near_vertical_got(r: dict[str, float]) -> str:
    return (
        f"dC = {r['dC']:.3f}, dB = {r['dB']:.3f} deg, linear {r['linear']:.4g} mm, first split "
        f"{r['split']:.1f} mm, bisection {r['pieces']} pieces / depth {r['depth']} worst "
        f"{r['worst']:.4g} mm, XY travel {r['xy']:.1f} mm, beam {r['beam']:.3f} deg"
    )


def check_near_vertical_original() -> ClaimResult:
    r = near_vertical("original")
    _, na, _, nb = study("S4", "original").ends
    mid = mean_normal(na, nb)
    az = math.degrees(math.atan2(mid[0], mid[1]) % (2 * math.pi))
    ok = (
        abs(r["dC"] + 198.925) < 0.01
        and abs(r["linear"] - 243.5) < 0.1
        and not r["converged"]
        and r["worst"] > 400
        and abs(r["xy"] - 693.3) < 0.5
        and abs(r["beam"] - 2.029) < 0.002
        and az == 0.0
    )
    return ClaimResult(
        expected="S4, C in [0, 2pi): dC = -198.9 deg, linear 243.5 mm, mid normal azimuth 0 = 2pi,"
        " bisection never converges (worst > 400 mm), nonlinear: XY travel 693 mm, beam error "
        "2.03 deg",
        got=f"{_near_vertical_got(r)}, azimuth {az:g}",
        passed=ok,
    )


def check_near_vertical_improved() -> ClaimResult:
    r = near_vertical("improved")
    ok = (
        abs(r["dC"] + 18.925) < 0.01
        and abs(r["dB"] + 3.484) < 0.01
        and abs(r["linear"] - 1.509) < 0.001
        and abs(r["split"] - 41.4) < 0.1
        and r["converged"]
        and (r["pieces"], r["depth"]) == (122, 9)
        and abs(r["xy"] - 78.1) < 0.1
        and abs(r["beam"] - 0.286) < 0.002
    )
    return ClaimResult(
        expected="S4, B in (-pi/4, pi/4), C free: dC = -18.9, dB = -3.48 deg, linear 1.509 mm,"
        " first split 41.4 mm, bisection converges with 122 pieces / depth 9, nonlinear XY "
        "travel 78.1 mm, beam error 0.286 deg",
        got=_near_vertical_got(r),
        passed=ok,
    )


def check_backwards() -> ClaimResult:
    s = study("S4", "improved")
    pa, _, pb, _ = s.ends
    back = [
        moves_backwards(s.machine, bisect_uniform(s.machine, s.ends, s.qa, d), pa, pb)
        for d in range(1, 7)
    ]
    ordinary = []
    for name in ("S1", "S2", "S3"):
        t = study(name)
        a, _, b, _ = t.ends
        ordinary.append(
            moves_backwards(t.machine, bisect_uniform(t.machine, t.ends, t.qa, 2), a, b)
        )
    return ClaimResult(
        expected="S4 (improved limits) moves backwards at bisection levels 1-6; S1-S3 never",
        got=f"S4 levels 1-6: {back}; S1-S3 level 2: {ordinary}",
        passed=all(back) and not any(ordinary),
    )


def check_limits_circle() -> ClaimResult:
    out = {}
    for limits in ("original", "improved"):
        m = Machine5(limits=limits)  # type: ignore[arg-type]
        task = make_task(Paraboloid(), "circle", 32, radius=300.0)
        qs = translate_poses(m, task.points, task.normals)
        devs = [
            move_deviation(m, Move("linear", qs[i], qs[i + 1], task.points[i], task.points[i + 1]))
            for i in range(32)
        ]
        spin = max(abs(math.degrees(qs[i + 1][3] - qs[i][3])) for i in range(32))
        out[limits] = (max(devs), spin)
    ok = (
        out["original"][1] > 340
        and out["original"][0] > 100
        and out["improved"][1] < 12
        and out["improved"][0] < 1.5
    )
    return ClaimResult(
        expected="circle r = 300 mm, 32 segments, linear interpolation: original limits spin C"
        " by 348.75 deg on the segment crossing 2pi (deviation > 100 mm); improved limits: 11.25 "
        "deg per segment, < 1.5 mm",
        got=f"original: spin {out['original'][1]:.2f} deg, {out['original'][0]:.1f} mm; "
        f"improved: spin {out['improved'][1]:.2f} deg, {out['improved'][0]:.3f} mm",
        passed=ok,
    )


def check_method1_rule() -> ClaimResult:
    """Method 1 admissible iff angle(n0, n1) <= 2 eps: the mean normal is within eps of both."""
    worst = 0.0
    for name in SEGMENTS:
        s = study(name)
        _, na, _, nb = s.ends
        nm = mean_normal(na, nb)
        half = 0.5 * float(angle_between(na, nb))
        worst = max(
            worst,
            abs(float(angle_between(nm, na)) - half),
            abs(float(angle_between(nm, nb)) - half),
        )
    return at_most(1e-12, worst, "| angle(mean, ends) - angle(n0, n1)/2 | ")


# ---------------------------------------------------------------- the statements checked

CLAIMS: tuple[tuple[str, str, str, Callable[[], ClaimResult]], ...] = (
    (
        "kinematics-round-trip",
        "Forward and inverse kinematics are one-to-one under the limits (round trip within 1e-9 "
        "mm over random poses, both limit variants).",
        "LSP-2000 article, (1)-(3)",
        check_round_trip,
    ),
    (
        "vertical-beam",
        "For a vertical tool there are infinitely many positions of X, Y and C; the first "
        "variant of rule (2) removes the ambiguity.",
        "LSP-2000 article, rule (2)",
        check_vertical,
    ),
    (
        "linear-deviates",
        "Linear interpolation moves the working point off the segment (Fig. 3), far beyond the "
        "20 um tolerance on an ordinary segment.",
        "LSP-2000 article, linear interpolation, Fig. 3",
        check_linear_deviates,
    ),
    (
        "linear-speed",
        "Under linear interpolation the working point's speed is non-uniform.",
        "LSP-2000 article, linear interpolation, Fig. 3",
        check_speed_nonuniform,
    ),
    (
        "bisection-quarter",
        "Each bisection cuts the deviation to about a quarter.",
        "LSP-2000 article, method 2, Fig. 4",
        check_quarter,
    ),
    (
        "bisection-tolerance",
        "Recursive bisection brings ordinary segments within 20 um.",
        "LSP-2000 article, method 2, Fig. 4",
        check_bisection_tolerance,
    ),
    (
        "bisection-backwards",
        "Within tolerance-driven splitting the working point can move across the trajectory and "
        "even backwards.",
        "LSP-2000 article, method 2, Fig. 4",
        check_backwards,
    ),
    (
        "method1-double-tolerance",
        "Method 1: normals differing by at most twice the tolerance keep the mean normal within "
        "the tolerance of both ends.",
        "LSP-2000 article, method 1",
        check_method1_rule,
    ),
    (
        "fixed-normal",
        "Method 1 keeps the point on the segment; its beam error is half the angle between the "
        "end normals.",
        "LSP-2000 article, method 1",
        check_fixed_normal,
    ),
    (
        "nonlinear-on-segment",
        "Nonlinear interpolation keeps the working point on the segment at constant contour speed.",
        "LSP-2000 article, (4)",
        check_nonlinear_on_segment,
    ),
    (
        "nonlinear-sub-moves",
        "Executed as N linear moves, the nonlinear path deviates about 1/N^2 (S1: 0.0874, "
        "0.00547, 0.000342 mm for N = 4, 16, 64).",
        "LSP-2000 article, (4); lessons/laser5/prototype.py",
        check_sub_moves,
    ),
    (
        "near-vertical-original",
        "Near the vertical beam with C in [0, 2pi) the bisection does not converge; the rotary "
        "limits had to change.",
        "LSP-2000 article, Fig. 5a",
        check_near_vertical_original,
    ),
    (
        "near-vertical-improved",
        "With B in (-pi/4, pi/4) and C unrestricted the results are best.",
        "LSP-2000 article, Fig. 5c",
        check_near_vertical_improved,
    ),
    (
        "limits-circle",
        "Changing the rotary limits reduces the deviation (a closed path crossing C = 2pi).",
        "LSP-2000 article, Fig. 5",
        check_limits_circle,
    ),
)
