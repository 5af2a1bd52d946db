"""Self-study tasks of chapter 2, C2.1-C2.6: the equations of simple manipulators.

Each task is a choice of ``task`` (and a preset with the textbook's numbers): its
Lagrange equations (2.5), (2.13) are derived by ``sympy.physics.mechanics.LagrangesMethod``
(:mod:`analyzer_lab.lessons.mechanics.manipulators.models`) and run live
(:mod:`analyzer_lab.lessons.mechanics.manipulators.tasks`).
The figures 2.13-2.16 survive only as labels, so every arrangement beyond the labels
is a reading, marked ``reconstructed`` where it is shown.  C2.6 uses holonomic
constraints with Lagrange multipliers, the route of §2.2 (2.25), (2.30)-(2.34).

The formulas of C2.1b and C2.1c are read from garbled tokens: M_c = 0.1 phi or the
constant 0.1 (C2.1b); M_g = 2 phi up to 4 pi and 8 pi beyond, or the constants 2 and 8,
or the switch at pi/4 (C2.1c).  Each reading is a choice with its own preset and claims.
"""

from __future__ import annotations

import math
from typing import Any

import analyzer_lab.lessons.mechanics.manipulators.tasks as tasks
import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import (
    Claim,
    ClaimResult,
    DerivationStep,
    Group,
    Note,
    Param,
    ParamError,
    Params,
    Preset,
    close,
)
from analyzer_lab.lessons.mechanics.manipulators.lesson import ManipulatorLesson
from analyzer_lab.lessons.mechanics.manipulators.models import by_hand, model_for
from analyzer_lab.lessons.mechanics.manipulators.pages import caveat, derivation_steps, source_of
from analyzer_lab.lessons.mechanics.manipulators.tasks import (
    AXES,
    MC_READINGS,
    MG_READINGS,
    TASKS,
    Solution,
    family,
    model_of,
)
from scipy.optimize import brentq

MG_READING = tuple(MG_READINGS)


def _num(
    name: str, default: float, label: str, unit: str, lo: float, hi: float, group: str
) -> Param:
    return Param(name, "float", default, label, unit, lo, hi, 0.01, group=group)


def _force(name: str, default: str, label: str, group: str, unit: str = "") -> Param:
    return Param(name, "formula", default, label, unit, group=group)


def _masses(prefix: str, names: tuple[str, ...], group: str) -> tuple[Param, ...]:
    defaults = (0.4, 0.3, 0.2)
    return tuple(
        _num(f"{prefix}_{n}", v, n, "kg", 0.001, 1e4, group) for n, v in zip(names, defaults)
    )


def _task_preset(
    task: str, title: str, values: dict[str, Any], t_end: float, note: str = "", suffix: str = ""
) -> Preset:
    name = task.lower().replace(".", "-") + suffix
    return Preset(name, f"{task}: {title}", {"task": task, **values}, t_end, note)


def _task(prefix: str) -> tuple[str, tuple[str, ...]]:
    """The group belongs to the tasks whose names start with ``prefix``."""
    return ("task", tuple(t for t in TASKS if t.startswith(prefix)))


class SelfStudy2(ManipulatorLesson):
    id = "self-study-2"
    title = "Self-study C2.1-C2.6: equations of simple manipulators"
    chapter = "2"
    problem = "C2.1-C2.6"
    source = "Textbook chapter 2, self-study tasks C2.1-C2.6 (Figs 2.13-2.16, 2.3, 2.6)"
    summary = (
        "Each task's Lagrange equations of the 2nd kind, derived symbolically and integrated live: "
        "a rotating link, a slider on a line, two-DOF arms, a Cartesian 3-axis stage, a planar "
        "positioner with rotation, and the three-inductor table with fixed or circular inductors."
    )
    order = 2.99
    t_end = 2.0
    groups = (
        Group("mode", "Task", change="restart"),
        Group("plane", "Plane of motion", change="restart"),
        Group("c2_1", "C2.1: link turning about O (Fig. 2.13)", when=_task("C2.1")),
        Group("c2_2", "C2.2: slider on y = x + 1 (Fig. 2.14)", when=_task("C2.2")),
        Group("c2_3", "C2.3: two-DOF arms (Fig. 2.15)", when=_task("C2.3")),
        Group("c2_4", "C2.4: Cartesian stages X, Y, Z (Fig. 2.16)", when=_task("C2.4")),
        Group("c2_5", "C2.5: positioner element that turns (Fig. 2.3)", when=_task("C2.5")),
        Group("c2_6", "C2.6: three inductors (Fig. 2.6)", when=_task("C2.6")),
    )
    modes = ("task",)
    params = (
        Param("task", "choice", "C2.1a", "task", choices=TASKS, group="mode"),
        Param(
            "vertical",
            "bool",
            False,
            "motion plane vertical (gravity along -Y; -Z for C2.4)",
            group="plane",
            help="C2.1-C2.4: the figures do not say; off = horizontal plane",
        ),
        Param(
            "inertia",
            "choice",
            "J0",
            "moment of inertia J",
            choices=("J0", "J0 + m1 l_OM^2"),
            group="c2_1",
            help="J0 alone, or J0 plus m1 concentrated at M (the source does not say)",
        ),
        Param(
            "Mc_reading",
            "choice",
            "0.1 phi",
            "C2.1b: M_c",
            choices=MC_READINGS,
            group="c2_1",
            when=_task("C2.1b"),
        ),
        Param(
            "Mg_reading",
            "choice",
            MG_READING[0],
            "C2.1c: M_g",
            choices=MG_READING,
            group="c2_1",
            when=_task("C2.1c"),
        ),
        _num("l_OM", 0.2, "l_OM", "m", 0.001, 10.0, "c2_1"),
        _num("m1", 0.4, "m1", "kg", 0.001, 1e4, "c2_1"),
        _num("J0", 0.01, "J0", "kg m^2", 1e-6, 1e3, "c2_1"),
        _num("phi0", 0.0, "phi(0)", "rad", -100.0, 100.0, "c2_1"),
        _num("phidot0", 0.0, "phi'(0)", "rad/s", -1e3, 1e3, "c2_1"),
        _num("m", 0.5, "m", "kg", 0.001, 1e4, "c2_2"),
        _num("l_AM", 0.2, "l_AM (drawn link)", "m", 0.0, 10.0, "c2_2"),
        _force("F_g", "5", "driving force F_g(t)", "c2_2", "N"),
        _force("F_c", "0", "resistance F_c(t)", "c2_2", "N"),
        *_masses("c23", ("m1", "m2"), "c2_3"),
        _num("c23_J", 0.005, "J (a: arm; c: link)", "kg m^2", 1e-6, 1e3, "c2_3"),
        _num("c23_l", 0.2, "l (a: S(0); c: link length)", "m", 0.0, 10.0, "c2_3"),
        _force("c23_Q1", "0.5", "Q1(t) on the first coordinate (a: phi, b: S1, c: S)", "c2_3"),
        _force(
            "c23_Q2", "0.2*sin(t)", "Q2(t) on the second coordinate (a: S, b: S2, c: phi)", "c2_3"
        ),
        Param("axes", "choice", "xyz", "moving axes", choices=AXES, group="c2_4"),
        *_masses("c24", ("m1", "m2", "m3"), "c2_4"),
        _force("c24_Qx", "0.5", "Q_x(t) on the X stage", "c2_4", "N"),
        _force("c24_Qy", "0.2*sin(t)", "Q_y(t) on the Y stage", "c2_4", "N"),
        _force("c24_Qz", "0", "Q_z(t) on the Z stage", "c2_4", "N"),
        _num("c25_m", 0.4, "m", "kg", 0.001, 1e4, "c2_5"),
        _num("c25_J", 0.005, "J about G", "kg m^2", 1e-6, 1e3, "c2_5"),
        _num("c25_l", 0.2, "l: A to the centre of mass G", "m", 0.0, 10.0, "c2_5"),
        _force("c25_Qx", "0.5", "Q_x(t) at A", "c2_5", "N"),
        _force("c25_Qy", "0.2*sin(t)", "Q_y(t) at A", "c2_5", "N"),
        _force("c25_Qphi", "0", "Q_phi(t): moment", "c2_5", "N m"),
        *_masses("c26", ("mA", "mB", "mC"), "c2_6"),
        _force("c26_QA", "0.5", "Q_A(t) along the tangent", "c2_6", "N"),
        _force("c26_QB", "0.2*sin(t)", "Q_B(t) along the tangent", "c2_6", "N"),
        _force("c26_QC", "0", "Q_C(t) along the tangent", "c2_6", "N"),
        _num("a", 0.1, "x_A = a", "m", -10.0, 10.0, "c2_6"),
        _num("b", 0.1, "y_A = b", "m", -10.0, 10.0, "c2_6"),
        _num("c", -0.1, "x_B = c", "m", -10.0, 10.0, "c2_6"),
        _num("d", 0.1, "y_B = d", "m", -10.0, 10.0, "c2_6"),
        _num("R", 0.15, "circle radius R (c)", "m", 0.001, 10.0, "c2_6"),
    )
    presets = (
        _task_preset(
            "C2.1a",
            "M_g = 2 N m, M_c = 0",
            {},
            0.5,
            "l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2; runs to phi = 180 deg.",
        ),
        _task_preset(
            "C2.1b",
            "M_g = 2 N m, M_c = 0.1 phi, phi from 0 to 180 deg",
            {},
            0.5,
            "M_c = 0.1 phi: three phi tokens and no dots in the formula of C2.1b.",
        ),
        _task_preset(
            "C2.1b",
            "M_g = 2 N m, M_c = 0.1 N m (the other reading)",
            {"Mc_reading": "0.1"},
            0.5,
            "M_c read as the constant 0.1 N m.",
            "-constant",
        ),
        _task_preset(
            "C2.1c",
            "M_g = 2 phi (phi <= 4 pi), 8 pi beyond; M_c = 0.1 sin phi",
            {"phidot0": 1.0},
            1.0,
            "phi = 0 at rest is an equilibrium; the source gives no start, phi'(0) = 1 rad/s is "
            "chosen here.",
        ),
        _task_preset(
            "C2.1c",
            "M_g = 2 N m (phi <= 4 pi), 8 N m beyond (the constants reading)",
            {"Mg_reading": MG_READING[1]},
            1.0,
            "With constant moments the link starts from rest.",
            "-constants",
        ),
        _task_preset(
            "C2.1c",
            "M_g = 2 phi (phi <= pi/4), 8 pi beyond (the switch at pi/4 reading)",
            {"Mg_reading": MG_READING[2], "phidot0": 1.0},
            1.0,
            "phi = 0 at rest is an equilibrium here too: phi'(0) = 1 rad/s.",
            "-switch-pi-4",
        ),
        _task_preset(
            "C2.2a",
            "F_g = 5 N, F_c = 0",
            {"F_g": "5", "F_c": "0"},
            2.0,
            "m = 0.5 kg, l_AM = 0.2 m, line y = x + 1.",
        ),
        _task_preset(
            "C2.2b", "F_g = 2 sin t, F_c = 0, t from 0 to 10", {"F_g": "2*sin(t)", "F_c": "0"}, 10.0
        ),
        _task_preset(
            "C2.2c", "F_g = 2 sin t, F_c = t, t from 0 to 10", {"F_g": "2*sin(t)", "F_c": "t"}, 10.0
        ),
        _task_preset(
            "C2.3a",
            "rotation phi and translation S (polar arm)",
            {"c23_Q1": "0.02", "c23_Q2": "-0.05"},
            5.0,
            "Illustrative masses and forces; the figure's arrangement is a reading.",
        ),
        _task_preset(
            "C2.3b",
            "two translations S1, S2",
            {"c23_Q1": "0.3*sin(t)", "c23_Q2": "0.2"},
            5.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.3c",
            "translation S carrying a rotating link phi",
            {"c23_Q1": "0.5*sin(2*t)", "c23_Q2": "0.02"},
            5.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.4a",
            "one axis at a time (here Z, vertical)",
            {"axes": "z", "vertical": True, "c24_Qz": "2.5"},
            2.0,
            "Illustrative masses and forces.",
        ),
        _task_preset(
            "C2.4b",
            "two axes together (here x and y)",
            {"axes": "xy", "c24_Qx": "0.5", "c24_Qy": "0.3*sin(2*t)"},
            3.0,
        ),
        _task_preset(
            "C2.4c",
            "x, y and z together",
            {"axes": "xyz", "vertical": True, "c24_Qy": "0.3*sin(2*t)", "c24_Qz": "2.2"},
            3.0,
        ),
        _task_preset(
            "C2.5",
            "x, y and the rotation phi of the moving element",
            {"c25_Qx": "0", "c25_Qy": "0.4"},
            3.0,
            "A force at A across the offset l only: the element both moves and turns.",
        ),
        _task_preset(
            "C2.6a",
            "inductor A fixed at (a, b, 0)",
            {"c26_QA": "0.2", "c26_QB": "0.05", "c26_QC": "-0.05"},
            2.0,
        ),
        _task_preset(
            "C2.6b",
            "A fixed at (a, b, 0), B fixed at (c, d, 0)",
            {"c26_QA": "0.2", "c26_QB": "0.2", "c26_QC": "0.05"},
            2.0,
        ),
        _task_preset(
            "C2.6c",
            "A, B, C on the circle of radius R about O",
            {"c26_QA": "0.05", "c26_QB": "0.1*sin(t)"},
            5.0,
        ),
    )
    # -- parameters ---------------------------------------------------------------

    def validate(self, params: Params) -> None:
        task, axes = params["task"], params["axes"]
        need = {"C2.4a": 1, "C2.4b": 2, "C2.4c": 3}.get(task)
        if need is not None and len(axes) != need:
            raise ParamError(
                "axes",
                f"{task} moves {need} axis{'es' if need > 1 else ''} at a time; choose "
                + ", ".join(a for a in AXES if len(a) == need),
            )
        if (
            task == "C2.6b"
            and math.hypot(params["a"] - params["c"], params["b"] - params["d"]) < 1e-6
        ):
            raise ParamError("c", "A and B cannot be fixed at the same point")

    def notes(self, params: Params) -> list[Note]:
        task = params["task"]
        text, evidence = caveat(params)
        out = [Note("reconstructed", text, source_of(task), evidence)]
        if family(task) == "C2.1" and params["vertical"] and params["inertia"] == "J0":
            out.append(
                Note(
                    "warning",
                    "With J = J0 the place of m1 is not known, so no gravity moment is applied; "
                    "choose J0 + m1 l_OM^2 for a vertical plane.",
                    task,
                )
            )
        if task == "C2.1c" and params["Mg_reading"] != MG_READING[1]:
            if params["phi0"] == 0.0 and params["phidot0"] == 0.0:
                out.append(
                    Note(
                        "info",
                        "M_g(0) = M_c(0) = 0: phi = 0 at rest is an equilibrium and the link "
                        "stays; give phi(0) or phi'(0) (the source gives none).",
                        "C2.1c",
                    )
                )
        if family(task) in ("C2.5", "C2.6") and params["vertical"]:
            out.append(Note("info", f"{task} moves in a horizontal plane: 'vertical' is not used."))
        return out

    def derivation(self, params: Params) -> list[DerivationStep]:
        return derivation_steps(params, model_of(params))

    def claims(self) -> list[Claim]:
        c21c = "C2.1c: M_g = 2 phi up to 4 pi, 8 pi beyond (reading 1)"
        return [
            Claim(
                "c2-1-numbers",
                "C2.1: l_OM = 0.2 m, m1 = 0.4 kg, J0 = 0.01 kg m^2 (presets); "
                "J0 + m1 l_OM^2 = 0.026 kg m^2.",
                "C2.1",
                _check_c21_numbers,
            ),
            Claim(
                "c2-1-equation",
                "C2.1: LagrangesMethod gives J phi'' = M_g - M_c - m1 g l_OM cos phi "
                "(J = J0 + m1 l_OM^2; g = 0 in a horizontal plane).",
                "C2.1",
                lambda: _check_equations(("C2.1a", "xyz")),
            ),
            Claim(
                "c2-1a-time",
                "C2.1a: phi reaches 180 deg at t = sqrt(pi J) = 0.1772 s (J0) or 0.2858 s "
                "(J0 + m1 l^2).",
                "C2.1a",
                lambda: _check_t180("c2-1a", (0.1772, 0.2858), (math.pi * 0.01, math.pi * 0.026)),
            ),
            Claim(
                "c2-1b-time",
                "C2.1b (M_c = 0.1 phi): phi reaches 180 deg at 0.1797 s (J0) or 0.2897 s "
                "(J0 + m1 l^2).",
                "C2.1b",
                lambda: _check_t180(
                    "c2-1b",
                    (0.1797, 0.2897),
                    tuple(
                        (math.acos(1 - math.pi / 20) / math.sqrt(0.1 / J)) ** 2
                        for J in (0.01, 0.026)
                    ),
                ),
            ),
            Claim(
                "c2-1b-constant-time",
                "C2.1b read with M_c = 0.1 N m: phi reaches 180 deg at sqrt(2 pi J/1.9) = "
                "0.1818 s (J0) or 0.2932 s (J0 + m1 l^2).",
                "C2.1b",
                lambda: _check_t180(
                    "c2-1b-constant",
                    (0.1818, 0.2932),
                    (2 * math.pi * 0.01 / 1.9, 2 * math.pi * 0.026 / 1.9),
                ),
            ),
            Claim(
                "c2-1c-equilibrium",
                f"{c21c}: M_g(0) = M_c(0) = 0, so phi = 0 at rest is an equilibrium and a start "
                "is needed (the source gives none).",
                "C2.1c",
                _check_c21c_rest,
            ),
            Claim(
                "c2-1c-speed",
                f"{c21c}: M_g is continuous at 4 pi (2 * 4 pi = 8 pi); with J = J0 and "
                "phi'(0) = 1 rad/s phi reaches 4 pi with phi' = sqrt(1 + 3200 pi^2) = 177.72 rad/s "
                "(energy integral).",
                "C2.1c",
                lambda: _check_switch("c2-1c", 8 * math.pi, 8 * math.pi, 1 + 3200 * math.pi**2),
            ),
            Claim(
                "c2-1c-constants",
                "C2.1c read with M_g = 2 N m up to 4 pi, 8 N m beyond: M_g jumps from 2 to 8 at "
                "4 pi, and from rest phi reaches 4 pi with phi' = sqrt(1600 pi) = 70.898 rad/s.",
                "C2.1c",
                lambda: _check_switch("c2-1c-constants", 2.0, 8.0, 1600 * math.pi),
            ),
            Claim(
                "c2-1c-switch-pi-4",
                "C2.1c read with the switch at pi/4: M_g jumps from pi/2 to 8 pi there, and from "
                "phi'(0) = 1 rad/s phi reaches pi/4 with phi' = "
                "sqrt(1 + 200 (pi^2/16 - 0.1 (1 - cos pi/4))) = 10.886 rad/s.",
                "C2.1c",
                lambda: _check_switch(
                    "c2-1c-switch-pi-4",
                    math.pi / 2,
                    8 * math.pi,
                    1 + 200 * (math.pi**2 / 16 - 0.1 * (1 - math.cos(math.pi / 4))),
                ),
            ),
            Claim(
                "c2-2-equation",
                "C2.2: 2 m x'' = sqrt(2) (F_g - F_c) - m g [vertical]; on the line s = sqrt(2) x.",
                "C2.2",
                lambda: _check_equations(("C2.2a", "xyz")),
            ),
            Claim(
                "c2-2-runs",
                "C2.2 with m = 0.5 kg: (a) s(1 s) = 5 m; (b) s(10 s) = 4 (10 - sin 10) = 42.176 m; "
                "(c) s(10 s) = 42.176 - 1000/3 = -291.157 m.",
                "C2.2a-c",
                _check_c22_runs,
            ),
            Claim(
                "c2-3-equations",
                "C2.3a-c: LagrangesMethod reproduces the hand-derived equations of the three "
                "arrangements.",
                "C2.3",
                lambda: _check_equations(*((f"C2.3{v}", "xyz") for v in "abc")),
            ),
            Claim(
                "c2-4-equations",
                "C2.4: (m1+m2+m3) x'' = Q1, (m2+m3) y'' = Q2, m3 z'' = Q3 - m3 g; a locked axis "
                "drops its equation.",
                "C2.4",
                lambda: _check_equations(("C2.4c", "xyz"), ("C2.4a", "y"), ("C2.4b", "xz")),
            ),
            Claim(
                "c2-5-equations",
                "C2.5: the x, y, phi equations couple through the offset l of the centre of mass "
                "from A.",
                "C2.5",
                _check_c25,
            ),
            Claim(
                "c2-6-constraints",
                "C2.6: fixed inductors stay at (a, b) and (c, d), the circle keeps radius R "
                "(error <= 1e-8 over the run), and on the circle the multiplier gives the "
                "centripetal force m v^2/R.",
                "C2.6, (2.17), (2.25)-(2.34)",
                _check_c26,
            ),
        ]


LESSON = SelfStudy2()


# ---------------------------------------------------------------- claim checks


def _check_c21_numbers() -> ClaimResult:
    vals = [LESSON.resolve(preset=p.name) for p in LESSON.presets if p.name.startswith("c2-1")]
    ok = all((v["l_OM"], v["m1"], v["J0"]) == (0.2, 0.4, 0.01) for v in vals)
    r = close(0.026, vals[0]["J0"] + vals[0]["m1"] * vals[0]["l_OM"] ** 2, atol=1e-15)
    return ClaimResult(f"presets 0.2, 0.4, 0.01; J = {r.expected}", f"J = {r.got}", ok and r.passed)


def _check_t180(
    preset: str, printed: tuple[float, float], square: tuple[float, ...]
) -> ClaimResult:
    """t_180 with J = J0 and J = J0 + m1 l^2: the closed form sqrt(square) and the printed
    four digits."""
    got = [
        LESSON.run(preset=preset, values={"inertia": j}).metrics["t_180"]
        for j in ("J0", "J0 + m1 l_OM^2")
    ]
    ok = all(
        abs(g - math.sqrt(s)) < 1e-7 and round(g, 4) == p for g, s, p in zip(got, square, printed)
    )
    return ClaimResult(f"{printed[0]} s, {printed[1]} s", f"{got[0]:.6f} s, {got[1]:.6f} s", ok)


def _check_c21c_rest() -> ClaimResult:
    params = LESSON.resolve({"phidot0": 0.0}, preset="c2-1c")
    m_g, m_c = tasks.c21_moments(params, np.zeros(1))
    moved = float(np.max(np.abs(LESSON.simulate(params, 1.0).series["phi"])))
    return ClaimResult(
        "M_g(0) = M_c(0) = 0; phi stays 0 for 1 s",
        f"M_g(0) = {m_g[0]:.3g}, M_c(0) = {m_c[0]:.3g}; max |phi| = {moved:.3g}",
        m_g[0] == 0.0 and m_c[0] == 0.0 and moved == 0.0,
    )


def _check_switch(preset: str, below: float, above: float, speed2: float) -> ClaimResult:
    """M_g on both sides of the switch angle, and the speed there from the run (energy
    integral: phi'^2 = ``speed2``)."""
    params = LESSON.resolve(preset=preset)
    switch = MG_READINGS[params["Mg_reading"]][3]
    m_g = tasks.c21_moments(params, np.array([switch, switch * (1 + 1e-12)]))[0]
    solution = Solution(params, 0.0, tasks.initial_state(params, model_of(params)))
    t = LESSON.sample_grid(1.0)
    k = int(np.argmax(solution(t)[:, 0] >= switch))
    hit = brentq(lambda s: solution(np.array([s]))[0, 0] - switch, t[k - 1], t[k], xtol=1e-14)
    speed = float(solution(np.array([hit]))[0, 1])
    r = close(math.sqrt(speed2), speed, rtol=1e-7)
    ok = r.passed and abs(m_g[0] - below) < 1e-9 and abs(m_g[1] - above) < 1e-9
    return ClaimResult(
        f"M_g {below:.6g} -> {above:.6g} N m; phi' = {r.expected} rad/s",
        f"M_g {m_g[0]:.6g} -> {m_g[1]:.6g} N m; phi' = {r.got} rad/s at t = {hit:.6f} s",
        ok,
    )


def _check_c22_runs() -> ClaimResult:
    got = [
        float(LESSON.run(preset=p, t_end=t_end).series["s"][-1])
        for p, t_end in (("c2-2a", 1.0), ("c2-2b", 10.0), ("c2-2c", 10.0))
    ]
    want = [5.0, 4 * (10 - math.sin(10)), 4 * (10 - math.sin(10)) - 1000 / 3]
    ok = all(abs(g - w) <= 1e-7 * max(1.0, abs(w)) for g, w in zip(got, want))
    return ClaimResult(
        ", ".join(f"{w:.6f}" for w in want) + " m", ", ".join(f"{g:.6f}" for g in got) + " m", ok
    )


def _check_equations(*cases: tuple[str, str]) -> ClaimResult:
    """LagrangesMethod against the equations derived by hand, for ``(task, axes)`` cases."""
    diffs = []
    for task, axes in cases:
        model = model_for(task, axes)
        diffs += [sp.simplify(e - h) for e, h in zip(model.equations, by_hand(model))]
    return ClaimResult("all differences 0", str(diffs), all(d == 0 for d in diffs))


def _check_c25() -> ClaimResult:
    equations = _check_equations(("C2.5", "xyz"))
    end = float(LESSON.run(preset="c2-5").series["phi"][-1])
    return ClaimResult(
        f"{equations.expected}; a force at A alone turns the element",
        f"{equations.got}; phi(end) = {end:.4g}",
        equations.passed and abs(end) > 1e-3,
    )


def _check_c26() -> ClaimResult:
    runs = {p: LESSON.run(preset=p) for p in ("c2-6a", "c2-6b", "c2-6c")}
    errs = [float(r.metrics["max_constraint_error"]) for r in runs.values()]
    fixed = max(
        float(
            np.max(np.abs(runs[p].series["x_A"] - 0.1))
            + np.max(np.abs(runs[p].series["y_A"] - 0.1))
        )
        for p in ("c2-6a", "c2-6b")
    )
    # on the circle H^T lambda = 2 lambda (x_A, y_A): radial 2 |lambda| R = m v^2 / R (no radial drive)
    run, p = runs["c2-6c"], LESSON.resolve(preset="c2-6c")
    cent = p["c26_mA"] * (run.series["x_A_dot"] ** 2 + run.series["y_A_dot"] ** 2) / p["R"]
    radial = 2 * np.abs(run.series["lambda_A"]) * p["R"]
    rel = float(np.max(np.abs(radial - cent)) / max(float(np.max(cent)), 1e-300))
    ok = max(errs) <= 1e-8 and fixed <= 1e-12 and rel <= 1e-6
    return ClaimResult(
        "constraint error <= 1e-8; fixed points exact; |reaction| = m v^2/R",
        f"errors {', '.join(f'{e:.1e}' for e in errs)}; fixed drift {fixed:.1e}; "
        f"reaction vs m v^2/R {rel:.1e}",
        ok,
    )
