"""The numbers of the self-study tasks C2.1-C2.6: parameters into a model, one solution, series.

For one task and one parameter set this module gives the model's constants and inputs
(the moments of C2.1 in the reading chosen, the typed forces of the other tasks), the
start state, the state over time and every observed series.  The state is one
:class:`Solution`: DOP853 with dense output on fixed segments of :data:`SEGMENT`
seconds, built lazily from the start, so that a headless run and the live stepper
evaluate the very same interpolants (a live frame costs one evaluation).  C2.1a and
C2.1b end when phi reaches phi_k = 180 deg: the state holds there.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, Params, Series, Stepper
from analyzer_lab.lessons.mechanics.manipulators.models import Model, model_for
from scipy.integrate import solve_ivp

G = 9.81
TASKS = (
    "C2.1a",
    "C2.1b",
    "C2.1c",
    "C2.2a",
    "C2.2b",
    "C2.2c",
    "C2.3a",
    "C2.3b",
    "C2.3c",
    "C2.4a",
    "C2.4b",
    "C2.4c",
    "C2.5",
    "C2.6a",
    "C2.6b",
    "C2.6c",
)
AXES = ("x", "y", "z", "xy", "xz", "yz", "xyz")
#: C2.1b: the readings of M_c; C2.1c: the readings of M_g (low law, high law, switch angle)
MC_READINGS = ("0.1 phi", "0.1")
MG_READINGS = {
    "2 phi / 8 pi, switch at 4 pi": (2.0, 0.0, 8 * math.pi, 4 * math.pi),
    "2 / 8, switch at 4 pi": (0.0, 2.0, 8.0, 4 * math.pi),
    "2 phi / 8 pi, switch at pi/4": (2.0, 0.0, 8 * math.pi, math.pi / 4),
}
#: length of one segment of the solution (s)
SEGMENT = 0.25
PHI_K = math.pi

# model constant (symbol name) -> parameter name, per task family
_CONSTANTS = {
    "C2.1": {"l_OM": "l_OM", "J_0": "J0", "m_1e": "m1"},
    "C2.2": {"m": "m"},
    "C2.3": {"J": "c23_J", "m_1": "c23_m1", "m_2": "c23_m2", "l": "c23_l"},
    "C2.4": {"m_1": "c24_m1", "m_2": "c24_m2", "m_3": "c24_m3"},
    "C2.5": {"m_1": "c25_m", "J": "c25_J", "l": "c25_l"},
    "C2.6": {"m_1": "c26_mA", "m_2": "c26_mB", "m_3": "c26_mC"}
    | {k: k for k in ("a", "b", "c", "d", "R")},
}
# the typed forces of a task family, in the order of the model's inputs
FORCES = {
    "C2.2": ("F_g", "F_c"),
    "C2.3": ("c23_Q1", "c23_Q2"),
    "C2.4": ("c24_Qx", "c24_Qy", "c24_Qz"),
    "C2.5": ("c25_Qx", "c25_Qy", "c25_Qphi"),
    "C2.6": ("c26_QA", "c26_QB", "c26_QC"),
}
# points observed as series (x, y in the plane of motion)
_POINTS = {"C2.1": ("M",), "C2.3a": ("M",), "C2.3c": ("M",), "C2.5": ("G",)}

_ANGLES = ("phi",)
_INDUCTORS = ("A", "B", "C")


def _coordinate_series() -> list[Series]:
    meaning = {
        "phi": "angle phi (C2.1: link about O; C2.3: arm or link; C2.5: element in its plane)",
        "S": "translation S (C2.3a: slider along the arm; C2.3c: carriage along X)",
        "S1": "translation S1 of stage 1 along X (C2.3b)",
        "S2": "translation S2 of stage 2 along Y (C2.3b)",
        "x": "coordinate x (C2.2: point M; C2.4: X stage; C2.5: drive point A)",
        "y": "coordinate y (C2.2: point M on y = x + 1; C2.4: Y stage; C2.5: drive point A)",
        "z": "coordinate z of the Z stage (C2.4)",
    } | {f"{a}_{k}": f"coordinate {a} of inductor {k} (C2.6)" for k in _INDUCTORS for a in "xy"}
    out = []
    for name, text in meaning.items():
        unit = "rad" if name in _ANGLES else "m"
        out.append(Series(name, unit, text))
        out.append(Series(f"{name}_dot", f"{unit}/s", f"rate of {text}"))
    return out


#: every series of the lesson (each task observes a part: :func:`series_names`)
SERIES: tuple[Series, ...] = (
    *_coordinate_series(),
    Series("s", "m", "path length s = sqrt(2) x along y = x + 1 (C2.2)"),
    Series("M_g", "N m", "driving moment M_g (C2.1)"),
    Series("M_c", "N m", "resisting moment M_c (C2.1)"),
    Series("F_g", "N", "driving force F_g along the line (C2.2)"),
    Series("F_c", "N", "resisting force F_c along the line (C2.2)"),
    Series("Q_phi", "N m", "generalized force of phi: a moment (C2.3a, C2.3c, C2.5)"),
    *(
        Series(f"Q_{c}", "N", f"generalized force of {c}: a force (C2.3-C2.5)")
        for c in ("S", "S1", "S2", "x", "y", "z")
    ),
    *(
        Series(f"Q_{k}", "N", f"drive force of inductor {k} along the tangent about O (C2.6)")
        for k in _INDUCTORS
    ),
    Series("M_x", "m", "x of the end point M (C2.1, C2.3a, C2.3c)"),
    Series("M_y", "m", "y of the end point M (C2.1, C2.3a, C2.3c)"),
    Series("G_x", "m", "x of the element's centre of mass G (C2.5)"),
    Series("G_y", "m", "y of the element's centre of mass G (C2.5)"),
    *(
        Series(f"lambda_{i}", "N", f"multiplier of fixed coordinate {i} (C2.6a, C2.6b), (2.33)")
        for i in range(1, 5)
    ),
    *(
        Series(f"lambda_{k}", "N/m", f"multiplier of the circle of {k} (C2.6c), (2.33)")
        for k in _INDUCTORS
    ),
    Series("constraint_error", "m", "largest distance of an inductor from its constraint (C2.6)"),
)


def family(task: str) -> str:
    return task[:4]


def model_of(params: Params) -> Model:
    task = params["task"]
    return model_for(task, params["axes"] if family(task) == "C2.4" else "xyz")


def constants(params: Params, model: Model) -> list[float]:
    """The model's constants, in its order, from the parameters.

    C2.1: m1 is a point mass at M only when J is read as J0 + m1 l_OM^2; the gravity
    g_e is g in a vertical plane (C2.1-C2.4), else 0.
    """
    names = _CONSTANTS[family(params["task"])]
    values = {sym: float(params[p]) for sym, p in names.items()}
    if family(params["task"]) == "C2.1" and params["inertia"] == "J0":
        values["m_1e"] = 0.0
    values["g_e"] = G if params["vertical"] else 0.0
    values["epsilon"] = 1e-9
    return [values[s.name] for s in model.consts]


def c21_moments(params: Params, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """M_g, M_c of C2.1a-c at the angles ``phi`` in the readings chosen."""
    task, phi = params["task"], np.asarray(phi, dtype=float)
    one = np.ones_like(phi)
    if task == "C2.1a":
        return 2.0 * one, 0.0 * one
    if task == "C2.1b":
        return 2.0 * one, (0.1 * phi if params["Mc_reading"] == "0.1 phi" else 0.1 * one)
    slope, const, high, switch = MG_READINGS[params["Mg_reading"]]
    return np.where(phi <= switch, slope * phi + const, high), 0.1 * np.sin(phi)


def inputs(params: Params, t: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The model's inputs at the times ``t`` (coordinates ``q`` of shape ``(n, N)``):
    shape ``(k, N)``."""
    fam = family(params["task"])
    if fam == "C2.1":
        return np.array(c21_moments(params, q[0]))
    t = np.asarray(t, dtype=float)
    with np.errstate(all="ignore"):
        return np.array(
            [np.broadcast_to(np.asarray(params[f](t), dtype=float), t.shape) for f in FORCES[fam]]
        )


def input_series(params: Params) -> tuple[str, ...]:
    """The series names of the inputs (C2.4: the free axes only)."""
    task = params["task"]
    fam = family(task)
    if fam == "C2.1":
        return ("M_g", "M_c")
    if fam == "C2.2":
        return ("F_g", "F_c")
    if fam == "C2.6":
        return tuple(f"Q_{k}" for k in _INDUCTORS)
    return tuple(f"Q_{c}" for c in model_of(params).coords)


def initial_state(params: Params, model: Model) -> np.ndarray:
    """(q(0), q'(0)): C2.1 from phi0, phi'(0); C2.3a starts with S = l; C2.6 from the
    fixed points (C at (0, -0.12)) or spaced by 120 deg on the circle; else at rest at 0."""
    task, p = params["task"], params
    q, v = np.zeros(model.n), np.zeros(model.n)
    if family(task) == "C2.1":
        q[0], v[0] = p["phi0"], p["phidot0"]
    elif task == "C2.3a":
        q[1] = p["c23_l"]
    elif task == "C2.6c":
        ang = np.radians([90.0, 210.0, 330.0])
        q[:] = np.column_stack([p["R"] * np.cos(ang), p["R"] * np.sin(ang)]).ravel()
    elif family(task) == "C2.6":
        q[:] = [p["a"], p["b"], p["c"], p["d"], 0.0, -0.12]
    return np.concatenate([q, v])


def series_names(params: Params) -> set[str]:
    """The series a run of this task observes."""
    task = params["task"]
    model = model_of(params)
    names = {*model.coords, *(f"{c}_dot" for c in model.coords), *input_series(params)}
    if family(task) == "C2.2":
        names |= {"y", "s"}
    for point in _POINTS.get(task, _POINTS.get(family(task), ())):
        names |= {f"{point}_x", f"{point}_y"}
    if task == "C2.6c":
        names |= {f"lambda_{k}" for k in _INDUCTORS} | {"constraint_error"}
    elif family(task) == "C2.6":
        names |= {f"lambda_{i + 1}" for i in range(len(model.constraints))}
        names.add("constraint_error")
    return names


def observe(params: Params, t: np.ndarray, state: np.ndarray) -> dict[str, np.ndarray]:
    """Every series of :func:`series_names` at the times ``t`` from the states
    ``(len(t), 2n)``."""
    task = params["task"]
    model = model_of(params)
    consts = constants(params, model)
    n = model.n
    Y = np.asarray(state, dtype=float).reshape(len(t), 2 * n)
    q, qd = Y[:, :n].T, Y[:, n:].T
    out: dict[str, np.ndarray] = {}
    for i, c in enumerate(model.coords):
        out[c], out[f"{c}_dot"] = q[i], qd[i]
    U = inputs(params, t, q)
    rows = ["xyz".index(c) for c in model.coords] if family(task) == "C2.4" else range(len(U))
    out |= dict(zip(input_series(params), U[list(rows)]))
    if family(task) == "C2.2":
        out["y"], out["s"] = q[0] + 1.0, math.sqrt(2.0) * q[0]
    for point in _POINTS.get(task, _POINTS.get(family(task), ())):
        xyz = model.point(point, q, consts)
        out[f"{point}_x"], out[f"{point}_y"] = xyz[:, 0], xyz[:, 1]
    if model.constraints:
        out |= _constraint_series(params, model, consts, t, Y, U)
    return out


def _constraint_series(
    params: Params,
    model: Model,
    consts: list[float],
    t: np.ndarray,
    Y: np.ndarray,
    U: np.ndarray,
) -> dict[str, np.ndarray]:
    """C2.6: the multipliers (2.33) at every sample and the distance from the constraints."""
    n = model.n
    lam = np.full((len(model.constraints), len(t)), np.nan)
    for j, tj in enumerate(t):
        if np.all(np.isfinite(Y[j])) and np.all(np.isfinite(U[:, j])):
            lam[:, j] = model.accelerations(float(tj), Y[j, :n], Y[j, n:], consts, list(U[:, j]))[1]
    x, y = Y[:, 0:n:2].T, Y[:, 1:n:2].T
    if params["task"] == "C2.6c":
        names = [f"lambda_{k}" for k in _INDUCTORS]
        error = np.abs(np.hypot(x, y) - params["R"])
    else:
        names = [f"lambda_{i + 1}" for i in range(len(model.constraints))]
        fixed = [params[k] for k in "abcd"][: len(model.constraints)]
        error = np.abs(Y[:, : len(fixed)].T - np.array(fixed)[:, None])
    return dict(zip(names, lam)) | {"constraint_error": np.max(error, axis=0)}


def equations(params: Params) -> Callable[[float, np.ndarray], np.ndarray]:
    """The right-hand side y' = (q', q'') of the task's Lagrange equations."""
    model = model_of(params)
    consts = constants(params, model)
    n = model.n

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        u = inputs(params, np.array([t]), y[:n, None])[:, 0]
        return np.concatenate([y[n:], model.accelerations(t, y[:n], y[n:], consts, list(u))[0]])

    return rhs


@dataclass
class _Piece:
    start: float
    end: float
    sol: Callable[[np.ndarray], np.ndarray]


class Solution:
    """The state of one task for one parameter set from ``(t0, y0)`` on.

    Built on demand on the segments ``[t0 + k SEGMENT, t0 + (k + 1) SEGMENT]`` by DOP853
    (rtol 1e-10, atol 1e-12) with dense output.  After ``stop`` (phi_k reached in
    C2.1a/b) the state holds; after a failure (a non-finite force or a singular
    position) it is NaN and ``reason`` says why.
    """

    def __init__(self, params: Params, t0: float, y0: np.ndarray) -> None:
        self._rhs = equations(params)
        self._to_phi_k = params["task"] in ("C2.1a", "C2.1b")
        self.t0 = float(t0)
        self.end = self.t0
        self._y_end = np.asarray(y0, dtype=float)
        self._pieces: list[_Piece] = []
        self.stop = math.inf
        self.y_stop = np.full_like(self._y_end, np.nan)
        self.reached = False
        self.reason = ""

    def _extend(self, t: float) -> None:
        while (self.end < t or not self._pieces) and math.isinf(self.stop):
            k = len(self._pieces)
            self._segment(self.t0 + k * SEGMENT, self.t0 + (k + 1) * SEGMENT)

    def _segment(self, a: float, b: float) -> None:
        bad: list[float] = []

        def guarded(t: float, y: np.ndarray) -> np.ndarray:
            if bad:
                return np.zeros_like(y)
            try:
                with np.errstate(all="ignore"):
                    out = self._rhs(t, y)
            except np.linalg.LinAlgError:
                out = np.array([np.nan])
            if not np.all(np.isfinite(out)):
                bad.append(t)
                return np.zeros_like(y)
            return out

        def failed(t: float, y: np.ndarray) -> float:
            return -1.0 if bad else 1.0

        def phi_k(t: float, y: np.ndarray) -> float:
            return y[0] - PHI_K

        failed.terminal = True  # type: ignore[attr-defined]
        phi_k.terminal, phi_k.direction = True, 1  # type: ignore[attr-defined]
        events: Sequence[Callable[..., float]] = (failed, phi_k) if self._to_phi_k else (failed,)
        sol = solve_ivp(
            guarded,
            (a, b),
            self._y_end,
            method="DOP853",
            rtol=1e-10,
            atol=1e-12,
            events=list(events),
            dense_output=True,
        )
        if len(sol.t) > 1:
            self._pieces.append(_Piece(a, float(sol.t[-1]), sol.sol))
        self.end, self._y_end = float(sol.t[-1]), sol.y[:, -1]
        if self._to_phi_k and sol.status == 1 and len(sol.t_events[1]):
            self.stop, self.y_stop = float(sol.t_events[1][0]), sol.y_events[1][0]
            self.reached = True
        elif bad or sol.status != 0:
            self.stop = bad[0] if bad else self.end
            why = "the equations gave a non-finite value" if bad else sol.message
            self.reason = f"integration stopped at t = {self.stop:.6g} s: {why}"

    @property
    def last(self) -> np.ndarray:
        """The last state computed (finite: a failing step freezes the state)."""
        return self._y_end

    def message(self, t: float) -> str:
        """Why the state holds or is missing at ``t`` ("" while it runs)."""
        if t < self.stop:
            return ""
        if self.reached:
            return f"phi reaches 180 deg (phi_k) at t = {self.stop:.6g} s; the link holds there."
        return self.reason

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """The states at the times ``t`` (1-D, >= t0): shape ``(len(t), 2n)``."""
        t = np.asarray(t, dtype=float)
        self._extend(float(np.max(t, initial=self.t0)))
        Y = np.empty((len(t), len(self._y_end)))
        Y[:] = self.y_stop
        starts = np.array([p.start for p in self._pieces])
        k = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, None)
        live = t < self.stop
        for i in np.unique(k[live]):
            sel = live & (k == i)
            Y[sel] = self._pieces[i].sol(t[sel]).T
        return Y


class SolutionStepper(Stepper):
    """The live run: plays the :class:`Solution` a headless run evaluates.

    ``frame_of(params, t, state, drawn, message)`` makes the frame of one state (shape
    ``(1, 2n)``); the bodies are drawn at ``drawn``: the state, or after a failure the
    last state computed.  New
    values of the same task continue from the current state; another task (or a run
    that failed) starts again; a link that reached phi_k keeps holding.
    """

    def __init__(
        self,
        params: Params,
        frame_of: Callable[[Params, float, np.ndarray, np.ndarray, str], Frame],
    ) -> None:
        self._frame_of = frame_of
        self.params = params
        self.reset()

    @property
    def t(self) -> float:
        return self._t

    def frame(self) -> Frame:
        state = self._solution(np.array([self._t]))
        drawn = state[0] if np.all(np.isfinite(state)) else self._solution.last
        message = self._solution.message(self._t)
        return self._frame_of(self.params, self._t, state, drawn, message)

    def advance(self, dt: float) -> Frame:
        self._t += max(float(dt), 0.0)
        return self.frame()

    def set_params(self, params: Params) -> None:
        same = all(params[k] == self.params[k] for k in ("task", "axes"))
        self.params = params
        stopped = self._t >= self._solution.stop
        if not same or (stopped and not self._solution.reached):
            self.reset()
        elif not stopped:
            self._solution = Solution(params, self._t, self._solution(np.array([self._t]))[0])

    def reset(self) -> Frame:
        self._t = 0.0
        self._solution = Solution(
            self.params, 0.0, initial_state(self.params, model_of(self.params))
        )
        return self.frame()
