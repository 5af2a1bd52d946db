"""LSP-2000 five-axis laser machine (LSP-2000 article): linear against nonlinear interpolation.

The machine: portal X on granite guides, portal Y on it, portal Z carrying the rotary
mechanism C (a horizontal lever of length R_C), at its end the rotary mechanism B (a
lever of length R_B along the beam); the working point is at the end of the B lever.
The article's kinematics (1), (2) are lost and (3) survives as tokens: (1a), (1b), (2),
(3) here are rebuilt (shown with a "reconstructed" tag); the interpolation formulas (4)
are the article's.

A task is a list of surface points with the beam along the surface normal; the working
point must follow the polyline through them within the tolerance delta_p (20 um).
Four controllers run along every segment: linear interpolation of all axes, method 1
(no rotation within a segment, beam along the mean normal), method 2 (recursive
bisection, the mean normal at every split), and the nonlinear interpolation (4).
The machinery is the package's modules: :mod:`.kinematics` (the machine), :mod:`.task`
(workpieces and paths), :mod:`.interpolation` (the controllers), :mod:`.program` (the
executed program), :mod:`.prototype` (the four segments measured) and :mod:`.scene` (the
drawing).

Series and metrics are in the machine's left-handed frame (Z towards the workpiece).
"""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache
from typing import Any

import analyzer_lab.lessons.laser5.prototype as proto
import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.contract import (
    Claim,
    DerivationStep,
    Group,
    Lesson,
    Note,
    Param,
    ParamError,
    Params,
    PlotSpec,
    Preset,
    RunResult,
    SceneSpec,
    Series,
    Stepper,
)
from analyzer_lab.lessons.laser5.kinematics import LimitError, Machine5, translate_poses, vertical
from analyzer_lab.lessons.laser5.program import (
    MAX_MOVES,
    METHODS,
    Playhead,
    Program,
    build_program,
    program_metrics,
)
from analyzer_lab.lessons.laser5.prototype import SEGMENTS
from analyzer_lab.lessons.laser5.scene import ProgramStepper, machine_scene
from analyzer_lab.lessons.laser5.task import Paraboloid, SphereCap, Task, Workpiece, make_task

SOURCE = "LSP-2000 article (five-axis laser complex), eqs (1)-(4), Figs 3-5"


# ---------------------------------------------------------------- from the values to a program


def machine_of(params: Params) -> Machine5:
    geometry = (float(params[n]) for n in ("R_C", "R_B", "k_C1", "k_C2", "k_X", "k_Y", "k_Z"))
    return Machine5(*geometry, limits=params["limits"])


def workpiece_of(params: Params) -> Workpiece:
    if params["surface"] == "sphere":
        R = float(params["R_s"])
        return SphereCap(R=R, radius=0.7 * R)
    return Paraboloid(F=float(params["F"]))


def task_of(params: Params) -> Task:
    return make_task(
        workpiece_of(params),
        str(params["path"]),
        int(params["segments"]),
        (float(params["u0"]), float(params["v0"])),
        (float(params["u1"]), float(params["v1"])),
        float(params["radius"]),
    )


def program_of(params: Params) -> Program:
    """The executed program for these values (built once per parameter set)."""
    return _program(tuple(sorted(params.raw().items())))


@lru_cache(maxsize=16)
def _program(values: tuple[tuple[str, Any], ...]) -> Program:
    params = Params(values)
    return build_program(
        machine_of(params),
        task_of(params),
        str(params["method"]),
        float(params["delta_p"]) * 1e-3,
        float(params["V"]),
        max_depth=int(params["max_depth"]),
        sub_moves=int(params["sub_moves"]),
    )


# ---------------------------------------------------------------- parameters and presets


GROUPS = (
    Group("interpolation", "Interpolation", change="restart"),
    Group("limits", "Rotary limits", change="restart"),
    Group("machine", "Machine geometry", change="restart"),
    Group("workpiece", "Workpiece", change="restart"),
    Group("path", "Task path", change="restart"),
)


def _grouped(group: str, *params: Param) -> tuple[Param, ...]:
    """The parameters of one panel group."""
    return tuple(replace(p, group=group) for p in params)


PARAMS: tuple[Param, ...] = (
    *_grouped(
        "interpolation",
        Param(
            "method",
            "choice",
            "bisection",
            "controller",
            choices=METHODS,
            help="linear: all axes proportional; bisection: method 2; nonlinear: interpolation"
            " (4); fixed-normal: method 1",
        ),
        Param("delta_p", "float", 20.0, "tolerance delta_p", "um", 1.0, 1000.0, 1.0),
        Param("V", "float", 50.0, "contour feed V", "mm/s", 0.1, 1000.0, 1.0),
        Param("max_depth", "int", 30, "bisection depth cap", "", 1, 30, 1),
        Param("sub_moves", "int", 0, "nonlinear as N linear moves (0: exact)", "", 0, 256, 1),
    ),
    *_grouped(
        "limits",
        Param(
            "limits",
            "choice",
            "improved",
            "rotary limits",
            choices=("original", "improved"),
            help="original: C in [0, 2pi), B in [0, pi/2]; improved: B in (-pi/4, pi/4), C free",
        ),
    ),
    *_grouped(
        "machine",
        Param("R_C", "float", 200.0, "C lever R_C", "mm", 0.0, 1000.0, 10.0),
        Param("R_B", "float", 300.0, "B lever R_B", "mm", 10.0, 1000.0, 10.0),
        Param("k_C1", "choice", "1", "sense of C, k_C1", choices=("1", "-1")),
        Param("k_C2", "float", 0.0, "C zero offset k_C2", "rad", -math.pi, math.pi, 0.01),
        Param("k_X", "float", 0.0, "X offset k_X", "mm", -500.0, 500.0, 1.0),
        Param("k_Y", "float", 0.0, "Y offset k_Y", "mm", -500.0, 500.0, 1.0),
        Param("k_Z", "float", 0.0, "Z offset k_Z", "mm", -500.0, 500.0, 1.0),
    ),
    *_grouped(
        "workpiece",
        Param("surface", "choice", "paraboloid", "workpiece", choices=("paraboloid", "sphere")),
        Param("F", "float", 500.0, "paraboloid focal length F", "mm", 100.0, 5000.0, 10.0),
        Param("R_s", "float", 1000.0, "sphere radius", "mm", 200.0, 5000.0, 10.0),
    ),
    *_grouped(
        "path",
        Param("path", "choice", "circle", "task path", choices=("line", "circle")),
        Param("u0", "float", 300.0, "start offset u0", "mm", -1000.0, 1000.0, 1.0),
        Param("v0", "float", 0.0, "start offset v0", "mm", -1000.0, 1000.0, 1.0),
        Param("u1", "float", 300.0, "end offset u1", "mm", -1000.0, 1000.0, 1.0),
        Param("v1", "float", 60.0, "end offset v1", "mm", -1000.0, 1000.0, 1.0),
        Param("radius", "float", 300.0, "circle radius", "mm", 1.0, 1000.0, 1.0),
        Param("segments", "int", 32, "task segments", "", 1, 200, 1),
    ),
)


def _preset_duration(values: dict[str, Any]) -> float:
    """The task's length over the feed V: the program's duration."""
    p = Params({prm.name: prm.parse(values.get(prm.name, prm.default)) for prm in PARAMS})
    return task_of(p).length / float(p["V"])


def _preset(name: str, title: str, values: dict[str, Any], note: str = "") -> Preset:
    return Preset(name, title, values, t_end=_preset_duration(values), note=note)


def _segment(name: str, method: str, **more: Any) -> dict[str, Any]:
    """One of the prototype's segments S1-S4 (lessons/laser5/prototype.py) at V = 10 mm/s."""
    (u0, v0), (u1, v1) = SEGMENTS[name]
    values = {"path": "line", "segments": 1, "u0": u0, "v0": v0, "u1": u1, "v1": v1}
    return {**values, "V": 10.0, "limits": "original", "method": method, **more}


_CIRCLE = {"path": "circle", "segments": 32, "radius": 300.0}

PRESETS: tuple[Preset, ...] = (
    _preset(
        "final-test",
        "Final test: paraboloid dish, circle r = 300 mm, bisection",
        {**_CIRCLE, "method": "bisection", "limits": "improved", "V": 50.0},
        "The article's acceptance test machined a parabolic surface (Conclusions); F = 500 mm "
        "and the path are assumed.",
    ),
    _preset(
        "segment-linear",
        "Ordinary segment S1: linear interpolation (1.398 mm)",
        _segment("S1", "linear"),
        "All axes proportional: the point sweeps an arc, 70 x the 20 um tolerance.",
    ),
    _preset(
        "segment-bisection",
        "Ordinary segment S1: bisection to 20 um (16 pieces)",
        _segment("S1", "bisection"),
    ),
    _preset(
        "segment-nonlinear",
        "Ordinary segment S1: nonlinear interpolation",
        _segment("S1", "nonlinear"),
        "The point stays on the chord at constant speed.",
    ),
    _preset(
        "segment-nonlinear-16",
        "S1 nonlinear as 16 linear moves",
        _segment("S1", "nonlinear", sub_moves=16),
    ),
    _preset(
        "segment-fixed-normal",
        "S1 method 1: no rotation, mean normal",
        _segment("S1", "fixed-normal"),
    ),
    _preset(
        "oblique-linear",
        "Oblique segment S3: linear interpolation (3.06 mm)",
        _segment("S3", "linear"),
    ),
    _preset(
        "radial-bisection", "Radial segment S2: B leads, bisection", _segment("S2", "bisection")
    ),
    _preset(
        "near-vertical-original",
        "Near-vertical beam S4, original limits: bisection fails",
        _segment("S4", "bisection"),
        "The mean normal at the split has azimuth 0 = 2 pi: the next piece spins C by almost 360 "
        "deg.",
    ),
    _preset(
        "near-vertical-improved",
        "Near-vertical beam S4, improved limits: bisection converges",
        _segment("S4", "bisection", limits="improved"),
        "122 pieces; the point moves backwards on the way.",
    ),
    _preset(
        "near-vertical-nonlinear",
        "Near-vertical beam S4, original limits: nonlinear",
        _segment("S4", "nonlinear"),
        "On the chord, but the linear axes travel 693 mm for a 60 mm cut.",
    ),
    _preset(
        "circle-original",
        "Circle with the original limits (C wraps at 2 pi)",
        {**_CIRCLE, "method": "linear", "limits": "original"},
    ),
    _preset(
        "circle-improved",
        "Circle with the improved limits (C free)",
        {**_CIRCLE, "method": "linear", "limits": "improved"},
    ),
    _preset(
        "sphere-dome",
        "Spherical dome, nonlinear interpolation",
        {"surface": "sphere", "method": "nonlinear", "limits": "improved", "path": "circle"}
        | {"segments": 24, "radius": 400.0},
    ),
)

SERIES = (
    Series("x", "mm", "working point x"),
    Series("y", "mm", "working point y"),
    Series("z", "mm", "working point z (towards the workpiece)"),
    Series("deviation", "um", "distance of the working point from the programmed segment"),
    Series("tolerance", "um", "admissible deviation delta_p"),
    Series("speed", "mm/s", "contour speed of the working point"),
    Series("feed", "mm/s", "programmed contour feed V"),
    Series("off_normal", "deg", "angle between the beam and the surface normal below the point"),
    Series("travel_linear", "mm", "path travelled by the linear axes X, Y, Z since the start"),
    Series("travel_tool", "mm", "path travelled by the working point since the start"),
    Series("axis_x", "mm", "CNC axis X (portal X)"),
    Series("axis_y", "mm", "CNC axis Y (portal Y)"),
    Series("axis_z", "mm", "CNC axis Z (portal Z)"),
    Series("axis_c", "deg", "rotary axis C (the horizontal lever R_C)"),
    Series("axis_b", "deg", "rotary axis B (the lever R_B along the beam)"),
    Series("move", "", "number of the CNC move being executed (1: the first)"),
)


RECONSTRUCTED = Note(
    "reconstructed",
    "Equations (1) and (2) are lost in the article and (3) survives as tokens: the kinematics"
    " are rebuilt from the machine description.",
    source="LSP-2000 article, (1)-(3)",
    evidence="the tokens of (3), X x R n R C k k k, fit"
    " X = x - R_B n_x - R_C sin(k_C1 C + k_C2) - k_X using each once",
)
ASSUMED = Note(
    "info",
    "The article's test part has 'a parabolic surface'; F, the dish's size and place, R_C and"
    " R_B are assumed values.",
    source="LSP-2000 article, Conclusions",
)
VERTICAL_START = Note(
    "info",
    "A task point has a vertical beam: rule (2)'s first variant leaves C free; it takes the C"
    " of the next tilted pose (no lever swing).",
    source="LSP-2000 article, rule (2)",
)


class Laser5Axis(Lesson):
    id = "laser-5axis"
    title = "LSP-2000 five-axis laser: linear vs nonlinear interpolation"
    chapter = "Articles"
    problem = "LSP-2000 article"
    source = SOURCE
    summary = (
        "A 5-axis laser machine follows a polyline on a paraboloid with the beam along the "
        "normal. Linear interpolation of the axes bows the working point off the segment; "
        "bisection, fixed normals and nonlinear interpolation (4) repair it differently, and the "
        "rotary limits decide near the vertical."
    )
    order = 300.0
    params = PARAMS
    presets = PRESETS
    t_end = PRESETS[0].t_end or 40.0
    groups = GROUPS
    modes = ("method", "limits")
    series = SERIES
    readout = ("deviation", "speed", "off_normal", "axis_c", "axis_b", "move")
    plots = (
        PlotSpec("Deviation from the programmed segment", ("deviation", "tolerance"), "um"),
        PlotSpec("Contour speed", ("speed", "feed"), "mm/s"),
        PlotSpec("Beam off-normal angle", ("off_normal",), "deg"),
        PlotSpec("Path travelled", ("travel_linear", "travel_tool"), "mm"),
        PlotSpec("Rotary axes", ("axis_c", "axis_b"), "deg"),
    )

    # -- parameters ---------------------------------------------------------------

    def validate(self, params: Params) -> None:
        wp = workpiece_of(params)
        u0, v0, u1, v1 = (float(params[n]) for n in ("u0", "v0", "u1", "v1"))
        if params["path"] == "circle":
            r_max = float(params["radius"])
            if int(params["segments"]) < 3:
                raise ParamError("segments", "a circle needs at least 3 segments")
        else:
            r_max = max(math.hypot(u0, v0), math.hypot(u1, v1))
            if math.hypot(u1 - u0, v1 - v0) < 1e-6:
                raise ParamError("u1", "the path's start and end coincide: nothing to machine")
        if r_max > wp.radius:
            raise ParamError(
                "radius" if params["path"] == "circle" else "u1",
                f"the path reaches {r_max:.0f} mm from the axis; the {params['surface']} covers"
                f" {wp.radius:.0f} mm",
            )
        moves = int(params["segments"]) * int(params["sub_moves"])
        if params["method"] == "nonlinear" and moves > MAX_MOVES:
            raise ParamError(
                "sub_moves", f"segments x sub_moves must stay within {MAX_MOVES} CNC moves"
            )
        task = task_of(params)
        try:
            translate_poses(machine_of(params), task.points, task.normals)
        except LimitError as exc:
            raise ParamError("limits", f"the task is out of reach: {exc}") from None

    def notes(self, params: Params) -> list[Note]:
        out = [RECONSTRUCTED]
        if params["surface"] == "paraboloid":
            out.append(ASSUMED)
        if any(vertical(n) for n in task_of(params).normals):
            out.append(VERTICAL_START)
        return out + program_of(params).notes

    # -- derivation -----------------------------------------------------------------

    def derivation(self, params: Params) -> list[DerivationStep]:
        X, Y, Z, C, B = sp.symbols("X Y Z C B", real=True)
        R_C, R_B, k1, k2, kX, kY, kZ = sp.symbols("R_C R_B k_C1 k_C2 k_X k_Y k_Z", real=True)
        x, y, z, t = sp.symbols("x y z t", real=True)
        th = sp.Symbol("theta", real=True)
        n = sp.Matrix([sp.sin(B) * sp.sin(th), sp.sin(B) * sp.cos(th), sp.cos(B)])
        nx, ny, nz = sp.symbols("n_x n_y n_z", real=True)
        recon13 = (
            "equations (1) and (2) are lost in the source; rebuilt from the machine description "
            "and the tokens of (3)"
        )
        C0, C1, B0, B1, Ct, Bt = sp.symbols("C_0 C_1 B_0 B_1 C_t B_t", real=True)
        return [
            DerivationStep(
                "Frame and tool pose",
                "World axes x, y, z point like the CNC axes X, Y, Z and form a left-handed "
                "triple (Z towards the part). The tool pose is the working point p = (x, y, z) "
                "and the unit beam vector n; the working point lies at the end of the B lever. "
                "Axes: X, Y, Z linear; C turns the horizontal lever R_C (C = 0: along Y); B "
                "tilts the lever R_B, which points along Z at B = 0.",
                r"\mathbf q=(X,Y,Z,C,B),\qquad \theta=k_{C1}C+k_{C2}",
                source="LSP-2000 article, text before (1)",
            ),
            DerivationStep(
                "Beam direction",
                "Forward kinematics, orientation part.",
                sp.Eq(sp.Symbol("n"), n, evaluate=False),
                source="(1a)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Working point",
                "Forward kinematics, position part: C lever plus B lever along the beam.",
                sp.Eq(
                    sp.Matrix([x, y, z]),
                    sp.Matrix(
                        [
                            X + kX + R_C * sp.sin(th) + R_B * n[0],
                            Y + kY + R_C * sp.cos(th) + R_B * n[1],
                            Z + kZ + R_B * n[2],
                        ]
                    ),
                    evaluate=False,
                ),
                source="(1b)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Rotary axes from the beam (rule 2)",
                "Under the limits the map is one-to-one except for a vertical beam, where "
                "infinitely many X, Y, C give the same pose; the rule's first variant fixes C "
                "there (here: keeps the current C, 0 at the start). Improved limits: of (theta, "
                "B) and (theta + pi, -B), shifted by whole turns, the one nearest the previous C.",
                r"B=\arccos n_z,\qquad C=\begin{cases}C^{*} & n_x=n_y=0\\ "
                r"\dfrac{\operatorname{atan2}(n_x,n_y)\bmod 2\pi-k_{C2}}{k_{C1}} & "
                r"\text{otherwise}\end{cases}",
                source="(2)",
                reconstructed=recon13,
            ),
            DerivationStep(
                "Linear axes from the pose",
                "The inverse for the linear axes; all operators of (3) are lost glyphs.",
                [
                    sp.Eq(X, x - R_B * nx - R_C * sp.sin(k1 * C + k2) - kX),
                    sp.Eq(Y, y - R_B * ny - R_C * sp.cos(k1 * C + k2) - kY),
                    sp.Eq(Z, z - R_B * nz - kZ),
                ],
                source="(3)",
                reconstructed="operator signs lost in the source; chosen to invert (1b)",
            ),
            DerivationStep(
                "Rotary limits",
                "As built: C in [0, 2 pi), B in [0, pi/2]. Best found by simulation (Fig. 5c): B "
                "in (-pi/4, pi/4), C unrestricted, which makes the pose-to-axes map ambiguous.",
                r"C\in[0,2\pi),\;B\in[0,\tfrac{\pi}{2}]\qquad\text{vs}\qquad "
                r"B\in(-\tfrac{\pi}{4},\tfrac{\pi}{4}),\;C\in\mathbb R",
                source="LSP-2000 article, machine description and Fig. 5",
                reconstructed="the range glyphs (pi, the dash) are lost; read from the digits left",
            ),
            DerivationStep(
                "Linear interpolation",
                "The LSP-2000 CNC changes all axes proportionally along a segment; the C and B "
                "terms of (1b) then sweep arcs, so the point bows off the chord by about the "
                "arc's sagitta.",
                sp.Eq(
                    sp.Symbol("q(s)"),
                    (1 - sp.Symbol("s")) * sp.Symbol("q_0") + sp.Symbol("s") * sp.Symbol("q_1"),
                ),
                source="LSP-2000 article, linear interpolation, Fig. 3",
            ),
            DerivationStep(
                "Sagitta estimate",
                "Deviation for small angle changes.",
                sp.Eq(
                    sp.Symbol("delta"),
                    (R_C + R_B * sp.sin(B)) * sp.Symbol("Delta_C") ** 2 / 8
                    + R_B * sp.Symbol("Delta_B") ** 2 / 8,
                ),
                source="LSP-2000 article, Fig. 3 (an estimate)",
                reconstructed="not in the article: the sagitta of the swept arc, an estimate",
            ),
            DerivationStep(
                "First method: no rotation within a segment",
                "The beam is set along the mean normal and kept; admissible if the end normals "
                "differ by at most twice the tolerance epsilon (then the mean is within epsilon "
                "of both). The laser is switched off and on for every re-orientation.",
                r"\bar{\mathbf n}=\frac{\mathbf n_0+\mathbf n_1}{|\mathbf n_0+\mathbf "
                r"n_1|},\qquad \angle(\mathbf n_0,\mathbf n_1)\le 2\varepsilon",
                source="LSP-2000 article, method 1",
                reconstructed="'difference of normals within double tolerance' read as an angle",
            ),
            DerivationStep(
                "Second method: recursive bisection",
                "A segment deviating by more than delta_p is halved; the normal at the split is "
                "the mean of the end normals. The sagitta is quadratic in the angle change, so "
                "each split cuts the deviation to about a quarter. Near the vertical the point "
                "can move across and even backwards.",
                r"\mathbf p_m=\tfrac12(\mathbf p_a+\mathbf p_b),\quad \mathbf n_m=\frac{\mathbf "
                r"n_a+\mathbf n_b}{|\mathbf n_a+\mathbf n_b|},\quad "
                r"\delta_{k+1}\approx\tfrac14\delta_k",
                source="LSP-2000 article, method 2, Fig. 4",
            ),
            DerivationStep(
                "Nonlinear interpolation: the chord",
                "The point moves on the chord with parameter t in [0, 1].",
                sp.Eq(
                    sp.Matrix([sp.Symbol("x_t"), sp.Symbol("y_t"), sp.Symbol("z_t")]),
                    (1 - t) * sp.Matrix(sp.symbols("x_0 y_0 z_0"))
                    + t * sp.Matrix(sp.symbols("x_1 y_1 z_1")),
                    evaluate=False,
                ),
                source="(4)",
            ),
            DerivationStep(
                "Nonlinear interpolation: the leading axis",
                "The rotary axis that changes more leads; t follows from it, the other rotary "
                "axis is linear in t, and (1a), (3) give n_t and X_t, Y_t, Z_t. At constant "
                "contour speed t runs uniformly.",
                [sp.Eq(t, (Ct - C0) / (C1 - C0)), sp.Eq(Bt, (1 - t) * B0 + t * B1)],
                source="LSP-2000 article, nonlinear interpolation algorithm",
            ),
            DerivationStep(
                "B leading",
                "By symmetry when B changes more.",
                [sp.Eq(t, (Bt - B0) / (B1 - B0)), sp.Eq(Ct, (1 - t) * C0 + t * C1)],
                source="LSP-2000 article, nonlinear interpolation algorithm",
                reconstructed="implied by the text, not printed",
            ),
        ]

    # -- runs ---------------------------------------------------------------------------

    def observe(self, params: Params, t: np.ndarray, state: Playhead) -> dict[str, Any]:
        """Every series from the program at the playhead (one function for runs and frames)."""
        s = state.values
        p, q = s["p"], s["q"]
        return {
            "x": p[:, 0],
            "y": p[:, 1],
            "z": p[:, 2],
            "deviation": 1e3 * s["deviation"],
            "tolerance": float(params["delta_p"]),
            "speed": s["speed"],
            "feed": float(params["V"]),
            "off_normal": np.degrees(s["off_normal"]),
            "travel_linear": s["travel_linear"],
            "travel_tool": s["travel_tool"],
            "axis_x": q[:, 0],
            "axis_y": q[:, 1],
            "axis_z": q[:, 2],
            "axis_c": np.degrees(q[:, 3]),
            "axis_b": np.degrees(q[:, 4]),
            "move": state.move + 1.0,
        }

    def simulate(self, params: Params, t_end: float | None = None) -> RunResult:
        prog = program_of(params)
        duration = prog.duration
        t_end = duration if t_end is None else float(t_end)
        t = prog.sample_times(t_end)
        messages = [note.text for note in self.notes(params)]
        if t_end > duration * (1 + 1e-9):
            messages.append(f"the task ends at t = {duration:.3g} s; the tool holds after that")
        elif t_end < duration * (1 - 1e-9):
            messages.append(
                f"run stops at t = {t_end:.3g} s of {duration:.3g} s; metrics cover the whole task"
            )
        return self.result(params, t, prog.playhead(t), program_metrics(prog), messages)

    def stepper(self, params: Params) -> Stepper:
        return ProgramStepper(params, program_of, self.frame_scalars)

    def scene(self, params: Params) -> SceneSpec:
        return machine_scene(machine_of(params), task_of(params), float(params["delta_p"]))

    def claims(self) -> list[Claim]:
        return [Claim(*row) for row in proto.CLAIMS]


LESSON = Laser5Axis()
