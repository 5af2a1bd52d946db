"""The declarations every analyzer lesson (Problems 1.3-1.6) shares: its parameter
groups, the controls, speed, start-point, family and integrator parameters, the series it
observes (with their units) and its plots.  :mod:`analyzer_lab.lessons.analyzers.field.lesson` appends
them to a lesson's own surface parameters.
"""

from __future__ import annotations

from analyzer_lab.lessons.kit.contract import Group, Param, PlotSpec, Series

#: Gauss-Legendre with s stages (order 2s) keeps F to round-off; RK45/DOP853 are scipy's.
METHODS = ("gauss-legendre-3", "gauss-legendre-6", "gauss-legendre-2", "RK45", "DOP853")

#: The groups of every analyzer lesson (a lesson adds its surface groups before them).
DIRECTION = Group("mode", "Direction of motion", change="live")
CONTROLS = Group("controls", "Controls u1(t), u2(t), u3(t)", change="live")
SPEED_CONTROLS = Group("controls", "Controls u1(t), u2(t), u3(t) and speed V(t)", change="live")
INITIAL = Group("initial", "Start point and family of curves", change="restart")

CONTROL_PARAMS: tuple[Param, ...] = (
    Param(
        "u1",
        "formula",
        "5",
        "u1(t)",
        min=-20,
        max=20,
        step=0.1,
        group="controls",
        help="control u1: a number or a formula of t",
    ),
    Param("u2", "formula", "5", "u2(t)", min=-20, max=20, step=0.1, group="controls"),
    Param("u3", "formula", "5", "u3(t)", min=-20, max=20, step=0.1, group="controls"),
)
SPEED_PARAMS: tuple[Param, ...] = (
    Param(
        "direction",
        "choice",
        "+",
        "direction (sign of omega)",
        choices=("+", "-"),
        group="mode",
        help="the sign of omega in (1.58): the -1 scale block of Fig. 1.27",
    ),
    Param(
        "V",
        "formula",
        "1",
        "V(t)",
        unit="units/s",
        min=0,
        max=20,
        step=0.1,
        group="controls",
        help="speed along the curve (1.58)",
    ),
)
START_PARAMS: tuple[Param, ...] = (
    Param("x0", "float", 1.0, "x0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param("y0", "float", 0.0, "y0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param("z0", "float", 0.0, "z0", min=-1e4, max=1e4, step=0.05, group="initial"),
    Param(
        "family",
        "int",
        1,
        "curves in the family",
        min=1,
        max=24,
        step=1,
        group="initial",
        help="several start points at once (Figs. 1.12, 1.26)",
    ),
    Param(
        "family_axis",
        "choice",
        "z",
        "family spread along",
        choices=("x", "y", "z"),
        group="initial",
    ),
    Param(
        "family_step", "float", 0.3, "family spacing", min=-1e3, max=1e3, step=0.05, group="initial"
    ),
)
METHOD_PARAMS: tuple[Param, ...] = (
    Param(
        "integrator",
        "choice",
        "gauss-legendre-3",
        "integrator",
        choices=METHODS,
        group="method",
        help="Gauss-Legendre (s stages, order 2s) keeps F to round-off; order 12 (6 stages)"
        " takes about 8 times order 6's step at equal accuracy; RK45/DOP853 are scipy's"
        " solve_ivp",
    ),
    Param(
        "h",
        "float",
        1e-2,
        "step h",
        unit="s",
        min=1e-5,
        max=0.1,
        step=1e-3,
        group="method",
        help="Gauss-Legendre step; order 6 (3 stages): 0.01 s keeps the textbook examples to"
        " ~1e-9; order 12 (6 stages): 0.1 s keeps the integrator benchmark's runs to ~1e-13",
    ),
    Param("rtol", "float", 1e-3, "solve_ivp rtol", min=1e-14, max=1e-1, group="method"),
    Param("atol", "float", 1e-6, "solve_ivp atol", min=1e-16, max=1e-1, group="method"),
)

#: What an analyzer lesson observes; the point's series repeat for every family member.
ANALYZER_SERIES: tuple[Series, ...] = (
    Series("x", "units", "x of the point", member=True),
    Series("y", "units", "y of the point", member=True),
    Series("z", "units", "z of the point", member=True),
    Series("vx", "units/s", "velocity component dx/dt", member=True),
    Series("vy", "units/s", "velocity component dy/dt", member=True),
    Series("vz", "units/s", "velocity component dz/dt", member=True),
    Series("v2", "units²/s²", "squared speed vx² + vy² + vz²", member=True),
    Series("speed", "units/s", "speed |v|", member=True),
    Series(
        "drift",
        "",
        "invariant drift (F(r) - F(r0)) / scale: 0 while the point stays on its surface",
        member=True,
    ),
    Series("u1", "", "control u1(t)"),
    Series("u2", "", "control u2(t)"),
    Series("u3", "", "control u3(t)"),
)
ANALYZER_PLOTS = (
    PlotSpec("velocity components", ("vx", "vy", "vz"), "units/s"),
    PlotSpec("squared speed |v|²", ("v2",), "units²/s²"),
    PlotSpec("invariant drift (F - F0) / scale", ("drift",)),
)
