"""The lesson contract: what every lesson declares and returns.

A lesson is the model of one textbook page.  It declares typed parameters and the
textbook's presets, gives its derivation as symbolic steps, runs headless
(:meth:`Lesson.simulate` -> :class:`RunResult`), runs live (:meth:`Lesson.stepper`
-> :class:`Stepper` yielding :class:`Frame` objects), describes what to draw
(:meth:`Lesson.scene` -> :class:`SceneSpec`) and states the textbook's checkable
claims (:meth:`Lesson.claims` -> :class:`Claim`).  Everything here is plain data:
the view (``app/``) renders it, scripts read it; nothing here imports the view.
"""

from __future__ import annotations

import csv
import io
import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import sympy as sp

from lessons.core.formula import Formula, FormulaError, parse_formula, parse_number

ParamKind = Literal["float", "int", "formula", "choice", "bool"]
Value = float | int | str | bool | Formula


class ParamError(ValueError):
    """A parameter value was refused.  ``str(err)`` is one line a user can act on."""

    def __init__(self, name: str, message: str) -> None:
        super().__init__(f"{name}: {message}")
        self.name = name
        self.message = message


@dataclass(frozen=True)
class Param:
    """One typed parameter, named as in the textbook (Greek letters spelled out).

    ``kind``:
      * ``float``/``int``: a number in ``[min, max]`` (typed text may be a constant
        expression such as ``pi/2``);
      * ``formula``: a formula of ``t`` (a constant is a formula too);
      * ``choice``: one of ``choices``;
      * ``bool``: on/off (text ``on/off/true/false/1/0`` accepted).
    ``group`` names one of the lesson's declared :class:`Group` entries (its title and
    place in the panel come from there, never from the name).
    """

    name: str
    kind: ParamKind
    default: Any
    label: str = ""
    unit: str = ""
    min: float | None = None
    max: float | None = None
    step: float | None = None
    choices: tuple[str, ...] = ()
    group: str = "controls"
    help: str = ""

    def parse(self, raw: Any) -> Value:
        """Validate one raw value (text or number); raise :class:`ParamError`."""
        try:
            return self._parse(raw)
        except FormulaError as exc:
            raise ParamError(self.name, str(exc)) from None

    def _parse(self, raw: Any) -> Value:
        if self.kind == "formula":
            if isinstance(raw, Formula):
                return raw
            if isinstance(raw, bool):
                raise ParamError(self.name, "expected a formula of t, got a boolean")
            if isinstance(raw, (int, float, np.floating, np.integer)):
                if not math.isfinite(float(raw)):
                    raise ParamError(self.name, f"must be finite, got {float(raw)}")
                raw = (
                    str(int(raw))
                    if float(raw).is_integer() and abs(raw) < 1e15
                    else repr(float(raw))
                )
            if not isinstance(raw, str):
                raise ParamError(self.name, f"expected a formula of t, got {type(raw).__name__}")
            return parse_formula(raw, variables=("t",))
        if self.kind == "choice":
            text = str(raw).strip()
            if text not in self.choices:
                raise ParamError(
                    self.name, f"must be one of {', '.join(self.choices)}; got {text[:40]!r}"
                )
            return text
        if self.kind == "bool":
            if isinstance(raw, bool):
                return raw
            text = str(raw).strip().lower()
            if text in ("1", "true", "on", "yes"):
                return True
            if text in ("0", "false", "off", "no"):
                return False
            raise ParamError(self.name, f"expected on/off, got {text[:40]!r}")
        # float / int
        if isinstance(raw, bool):
            raise ParamError(self.name, "expected a number, got a boolean")
        if isinstance(raw, (int, float, np.floating, np.integer)):
            value = float(raw)
        elif isinstance(raw, str):
            value = parse_number(raw)
        else:
            raise ParamError(self.name, f"expected a number, got {type(raw).__name__}")
        if not math.isfinite(value):
            raise ParamError(self.name, f"must be a finite number, got {value}")
        if self.kind == "int":
            if not float(value).is_integer():
                raise ParamError(self.name, f"must be a whole number, got {value:g}")
            value = int(value)
        if self.min is not None and value < self.min:
            raise ParamError(
                self.name,
                f"{value:g} is below the minimum {self.min:g}{self.unit and ' ' + self.unit}",
            )
        if self.max is not None and value > self.max:
            raise ParamError(
                self.name,
                f"{value:g} is above the maximum {self.max:g}{self.unit and ' ' + self.unit}",
            )
        return value


class Params(dict):
    """Validated parameter values by name (numbers, :class:`Formula`, choices, bools)."""

    def raw(self) -> dict[str, Any]:
        """JSON-friendly view: formulas as their text."""
        return {k: (v.text if isinstance(v, Formula) else v) for k, v in self.items()}


GroupChange = Literal["live", "scene", "restart"]


@dataclass(frozen=True)
class Group:
    """A titled group of parameters; a lesson shows its groups in the declared order.

    ``expanded``: open when the panel is built (an integrator's settings start closed).
    ``change``: what a changed value of the group does to a running session:
    ``"live"`` takes effect at once and the run goes on (the scene is redrawn a little
    later, off the hot path); ``"scene"`` the same, with the scene redrawn at once;
    ``"restart"`` starts the run again from the new initial state.
    ``when``: ``(mode, values)``: the group matters (and is shown) only while the mode
    parameter ``mode`` has one of ``values`` (e.g. one self-study task's parameters).
    """

    name: str
    title: str
    expanded: bool = True
    change: GroupChange = "scene"
    when: tuple[str, tuple[str, ...]] | None = None

    def applies(self, params: Mapping[str, Any]) -> bool:
        """Whether the group matters for these values (see ``when``)."""
        if self.when is None:
            return True
        mode, values = self.when
        return str(params.get(mode)) in values


#: The groups most lessons use, in panel order (a lesson may declare its own).
MODE = Group("mode", "Mode", change="restart")
CONTROLS = Group("controls", "Controls", change="live")
INITIAL = Group("initial", "Start point", change="restart")
SURFACE = Group("surface", "Surface")
METHOD = Group("method", "Integrator", expanded=False, change="live")
DEFAULT_GROUPS: tuple[Group, ...] = (MODE, CONTROLS, INITIAL, SURFACE, METHOD)


@dataclass(frozen=True)
class Series:
    """One observed quantity: a column of a run and a live value of a frame.

    ``member``: for a lesson with a family of start points, members 2..N add the
    columns ``name_2 .. name_N`` (member 1 keeps ``name``).
    """

    name: str
    unit: str = ""
    description: str = ""
    member: bool = False


NoteKind = Literal["info", "warning", "reconstructed", "corrected"]


@dataclass(frozen=True)
class Note:
    """A message for the user: what the lesson did with the values, or a source caveat.

    ``reconstructed``/``corrected`` notes name the equation (``source``) and give one
    line of ``evidence``.
    """

    kind: NoteKind
    text: str
    source: str = ""
    evidence: str = ""

    def __str__(self) -> str:
        return self.text


class ObservationError(ValueError):
    """A lesson's observation does not match its declared series."""


@dataclass(frozen=True)
class Preset:
    """A textbook example: parameter values by name (text or numbers)."""

    name: str
    title: str
    values: Mapping[str, Any]
    t_end: float | None = None
    note: str = ""


@dataclass(frozen=True)
class DerivationStep:
    """One step of a derivation: prose plus one symbolic statement.

    ``math`` is a sympy expression/equation (rendered by sympy's MathML printer) or a
    LaTeX string; ``source`` is the textbook's equation number (e.g. ``"(1.54)"``);
    ``reconstructed`` is ``None`` or one line on why the equation had to be rebuilt;
    ``svg`` is an optional figure (a self-contained SVG built by the lesson from its own
    equations, every label escaped, no scripts or links), e.g. a block diagram.
    """

    title: str
    text: str = ""
    math: sp.Basic | Sequence[sp.Basic] | str | None = None
    source: str = ""
    reconstructed: str | None = None
    svg: str | None = None


@dataclass
class ClaimResult:
    expected: str
    got: str
    passed: bool


@dataclass(frozen=True)
class Claim:
    """A checkable statement of the source: ``check()`` computes and compares."""

    id: str
    statement: str
    source: str
    check: Callable[[], ClaimResult]


@dataclass
class RunResult:
    """A finished run: samples, named series and scalar metrics (a response object)."""

    lesson: str
    preset: str | None
    params: dict[str, Any]
    t: np.ndarray
    series: dict[str, np.ndarray]
    metrics: dict[str, Any] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)
    #: series name -> unit (from the lesson's declarations; "" for a pure number)
    units: dict[str, str] = field(default_factory=dict)

    def to_json_dict(self) -> dict[str, Any]:
        def clean(v: Any) -> Any:
            if isinstance(v, np.ndarray):
                return [clean(x) for x in v.tolist()]
            if isinstance(v, (np.floating, float)):
                f = float(v)
                return f if math.isfinite(f) else None
            if isinstance(v, (np.integer,)):
                return int(v)
            if isinstance(v, np.bool_):
                return bool(v)
            if isinstance(v, Formula):
                return v.text
            if isinstance(v, dict):
                return {str(k): clean(x) for k, x in v.items()}
            if isinstance(v, (list, tuple)):
                return [clean(x) for x in v]
            return v

        return {
            "lesson": self.lesson,
            "preset": self.preset,
            "params": clean(self.params),
            "t": clean(np.asarray(self.t, dtype=float)),
            "series": {k: clean(np.asarray(v, dtype=float)) for k, v in self.series.items()},
            "units": {k: self.units.get(k, "") for k in self.series},
            "metrics": clean(self.metrics),
            "messages": list(self.messages),
        }

    def to_csv(self) -> str:
        """One row per sample: ``t`` then every series (1-D series only)."""
        names = [k for k, v in self.series.items() if np.ndim(v) == 1 and len(v) == len(self.t)]
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["t", *names])
        cols = [np.asarray(self.t, dtype=float)] + [
            np.asarray(self.series[n], dtype=float) for n in names
        ]
        for row in zip(*cols):
            w.writerow([repr(float(x)) for x in row])
        return buf.getvalue()


# ---------------------------------------------------------------- scene description


@dataclass
class MeshItem:
    """A triangle mesh (surface or body) in lesson coordinates."""

    name: str
    vertices: np.ndarray  # (N, 3)
    faces: np.ndarray  # (M, 3) int
    color: tuple[int, int, int] = (120, 160, 220)
    opacity: float = 0.45
    wireframe: bool = False


@dataclass
class CurveItem:
    """A fixed polyline (a programmed path, a family member, an axis)."""

    name: str
    points: np.ndarray  # (N, 3)
    color: tuple[int, int, int] = (40, 40, 40)
    width: float = 2.0


@dataclass
class MarkerItem:
    """Fixed labelled points (start markers, foci, centres)."""

    name: str
    points: np.ndarray  # (N, 3)
    color: tuple[int, int, int] = (220, 60, 60)
    size: float = 0.05
    label: str = ""


@dataclass
class SceneSpec:
    """What to draw for a lesson, as data.

    Static items are drawn once; moving items come from :class:`Frame` by the names
    listed in ``moving_points`` (a trail is kept for each), ``moving_vectors`` and
    ``bodies`` (meshes posed by the frame).
    """

    bounds: tuple[tuple[float, float, float], tuple[float, float, float]]
    meshes: list[MeshItem] = field(default_factory=list)
    curves: list[CurveItem] = field(default_factory=list)
    markers: list[MarkerItem] = field(default_factory=list)
    moving_points: dict[str, tuple[int, int, int]] = field(default_factory=dict)
    moving_vectors: dict[str, tuple[int, int, int]] = field(default_factory=dict)
    bodies: list[MeshItem] = field(default_factory=list)
    planar: bool = False
    #: moving point name -> (frame scalar, low, high): its trail is coloured from green
    #: (scalar <= low) to red (scalar >= high), e.g. the tool point by its deviation.
    trail_color_by: dict[str, tuple[str, float, float]] = field(default_factory=dict)


@dataclass
class PlotSpec:
    """A live plot: a title and the frame scalars it shows (by name)."""

    title: str
    series: tuple[str, ...]
    units: str = ""


@dataclass
class Frame:
    """The live state after a step.

    ``points``: name -> (N, 3) positions (N points of one family);
    ``vectors``: name -> ((N, 3) origins, (N, 3) directions);
    ``poses``: body name -> (position (3,), wxyz quaternion (4,));
    ``scalars``: plot values by series name; ``message``: a note for the user
    (e.g. why the point holds), or ``""``.
    """

    t: float
    points: dict[str, np.ndarray] = field(default_factory=dict)
    vectors: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    poses: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    scalars: dict[str, float] = field(default_factory=dict)
    message: str = ""


class Stepper(ABC):
    """Incremental run for the live view: advance, change parameters live, reset."""

    @property
    @abstractmethod
    def t(self) -> float: ...

    @abstractmethod
    def frame(self) -> Frame:
        """The current state (no stepping)."""

    @abstractmethod
    def advance(self, dt: float) -> Frame:
        """Integrate forward by ``dt`` (lesson time) and return the new state."""

    @abstractmethod
    def set_params(self, params: Params) -> None:
        """Take new validated parameters while running (state is kept)."""

    @abstractmethod
    def reset(self) -> Frame:
        """Back to the initial state of the current parameters."""


class Lesson(ABC):
    """One textbook page.  Subclasses set the class attributes and implement the methods."""

    id: str = ""
    title: str = ""
    chapter: str = ""  # e.g. "1"
    problem: str = ""  # e.g. "Problem 1.4"
    source: str = ""  # e.g. "Textbook §1.3, Problem 1.4, eqs (1.52)-(1.54)"
    summary: str = ""
    order: float = 0.0  # sort key in the catalog
    params: tuple[Param, ...] = ()
    presets: tuple[Preset, ...] = ()
    t_end: float = 10.0
    plots: tuple[PlotSpec, ...] = ()
    #: parameter groups in panel order; every ``Param.group`` names one of them
    groups: tuple[Group, ...] = DEFAULT_GROUPS
    #: the parameters that select the lesson's mode (choices or on/off), shown first
    modes: tuple[str, ...] = ()
    #: the parameters of the start point ((x, y) in a plane or (x, y, z)), if any
    start_point: tuple[str, ...] | None = None
    #: the whole-number parameter giving the size of a family of start points, if any
    family: str | None = None
    #: every quantity the lesson observes: the columns of a run, the values of a frame
    series: tuple[Series, ...] = ()
    #: the series shown live beside the time (in this order)
    readout: tuple[str, ...] = ()
    #: the source's sampling step for tables and exports (``None``: t_end / 100)
    sampling: float | None = None
    #: lesson seconds played per wall-clock second at 1x (below 1: slow motion for
    #: fast phenomena such as vibrations of hundreds of hertz)
    time_scale: float = 1.0

    # -- parameters -------------------------------------------------------------

    def param(self, name: str) -> Param:
        for p in self.params:
            if p.name == name:
                return p
        raise ParamError(
            name,
            f"unknown parameter for lesson {self.id!r}; known: {', '.join(p.name for p in self.params)}",
        )

    def preset(self, name: str) -> Preset:
        for p in self.presets:
            if p.name == name:
                return p
        raise ParamError(
            "preset",
            f"unknown preset {name[:60]!r} for {self.id}; known: {', '.join(p.name for p in self.presets)}",
        )

    def resolve(self, values: Mapping[str, Any] | None = None, preset: str | None = None) -> Params:
        """Defaults, then the preset, then ``values``; every value validated.

        Raises :class:`ParamError` naming the first bad value; then nothing is returned.
        """
        raw: dict[str, Any] = {p.name: p.default for p in self.params}
        if preset is not None:
            raw.update(self.preset(preset).values)
        for name, value in (values or {}).items():
            self.param(name)
            raw[name] = value
        out = Params()
        for p in self.params:
            out[p.name] = p.parse(raw[p.name])
        self.validate(out)
        return out

    def validate(self, params: Params) -> None:
        """Cross-parameter checks (override); raise :class:`ParamError`."""

    def group(self, name: str) -> Group:
        """The declared group ``name`` (``KeyError`` naming the known ones otherwise)."""
        for g in self.groups:
            if g.name == name:
                return g
        known = [g.name for g in self.groups]
        raise KeyError(f"{self.id}: no parameter group {name!r}; declared: {known}")

    def notes(self, params: Params) -> list[Note]:
        """What the lesson did with these values (e.g. a start point projected onto the
        surface) and the source caveats that apply to them.  Override; default none."""
        return []

    def declaration_errors(self) -> list[str]:
        """Inconsistencies between the declarations (empty when the lesson is well formed)."""
        errors: list[str] = []
        names = {p.name for p in self.params}
        groups = {g.name for g in self.groups}
        for p in self.params:
            if p.group not in groups:
                errors.append(f"parameter {p.name}: group {p.group!r} is not declared")
        for m in self.modes:
            if m not in names:
                errors.append(f"mode {m!r} is not a parameter")
            elif self.param(m).kind not in ("choice", "bool"):
                errors.append(f"mode {m!r} is neither a choice nor on/off")
        for n in self.start_point or ():
            if n not in names:
                errors.append(f"start point {n!r} is not a parameter")
        if self.start_point is not None and len(self.start_point) not in (2, 3):
            errors.append("the start point has 2 or 3 coordinates")
        for g in self.groups:
            if g.when is not None:
                mode, values = g.when
                if mode not in self.modes:
                    errors.append(f"group {g.name!r}: {mode!r} is not one of the modes")
                elif self.param(mode).kind == "choice":
                    unknown = set(values) - set(self.param(mode).choices)
                    if unknown:
                        errors.append(f"group {g.name!r}: {sorted(unknown)} are not choices")
        if self.family is not None and (
            self.family not in names or self.param(self.family).kind != "int"
        ):
            errors.append(f"family {self.family!r} is not a whole-number parameter")
        series = [s.name for s in self.series]
        if len(series) != len(set(series)):
            errors.append("series names repeat")
        for r in self.readout:
            if r not in series:
                errors.append(f"readout {r!r} is not a declared series")
        for plot in self.plots:
            for n in plot.series:
                if n not in series:
                    errors.append(f"plot {plot.title!r}: series {n!r} is not declared")
        return errors

    # -- observation --------------------------------------------------------------

    def series_for(self, params: Params) -> tuple[Series, ...]:
        """The series a run with these values has: the declared ones, plus the family's
        members 2..N of every ``member`` series."""
        out = list(self.series)
        n = int(params[self.family]) if self.family is not None else 1
        for k in range(2, n + 1):
            out += [
                Series(f"{s.name}_{k}", s.unit, f"{s.description} (curve {k})")
                for s in self.series
                if s.member
            ]
        return tuple(out)

    def observe(self, params: Params, t: np.ndarray, state: Any) -> Mapping[str, Any]:
        """The declared series at the times ``t`` (1-D) from the lesson's own ``state`` at
        those times (leading axis = time).  One function serves both :meth:`simulate`
        (a grid) and the live stepper (one time): every lesson implements it."""
        raise NotImplementedError(f"{self.id}: observe() is not implemented")

    def observation(self, params: Params, t: Any, state: Any) -> dict[str, np.ndarray]:
        """:meth:`observe`, checked against :meth:`series_for` (names exactly, one value
        per time); raises :class:`ObservationError` naming what differs."""
        tt = np.atleast_1d(np.asarray(t, dtype=float))
        raw = self.observe(params, tt, state)
        names = [s.name for s in self.series_for(params)]
        missing = [n for n in names if n not in raw]
        extra = [n for n in raw if n not in names]
        if missing or extra:
            raise ObservationError(
                f"{self.id}: observation differs from the declared series"
                f" (missing {missing}, undeclared {extra})"
            )
        out: dict[str, np.ndarray] = {}
        for n in names:
            v = np.asarray(raw[n], dtype=float)
            if v.shape != tt.shape:
                v = np.broadcast_to(v, tt.shape)
            out[n] = np.array(v, dtype=float)
        return out

    def frame_scalars(self, params: Params, t: float, state: Any) -> dict[str, float]:
        """The observation at one time (``state`` with a leading time axis of length 1)."""
        return {k: float(v[0]) for k, v in self.observation(params, [t], state).items()}

    def result(
        self,
        params: Params,
        t: np.ndarray,
        state: Any,
        metrics: dict[str, Any] | None = None,
        messages: Sequence[str] = (),
    ) -> RunResult:
        """A finished run from the state on the grid ``t``: the observation as its series,
        the declared units, and a message for every series that is not finite somewhere
        (saying from when), so that a missing value is explained, never a silent NaN."""
        tt = np.asarray(t, dtype=float)
        series = self.observation(params, tt, state)
        msgs = list(messages)
        for name, v in series.items():
            bad = ~np.isfinite(v)
            if bad.any():
                first = float(tt[int(np.argmax(bad))])
                msgs.append(
                    f"{name} is not defined from t = {first:g} on"
                    f" ({int(bad.sum())} of {len(v)} samples)"
                )
        units = {s.name: s.unit for s in self.series_for(params)}
        return RunResult(self.id, None, params.raw(), tt, series, dict(metrics or {}), msgs, units)

    def sample_grid(self, t_end: float, step: float | None = None) -> np.ndarray:
        """t = 0, step, 2 step, ... up to ``t_end`` (the source's sampling by default)."""
        h = float(step or self.sampling or t_end / 100.0)
        n = int(math.floor(t_end / h + 1e-9))
        grid = np.arange(n + 1) * h
        if t_end - grid[-1] > 1e-9 * max(1.0, t_end):
            grid = np.append(grid, t_end)
        return grid

    def preset_t_end(self, preset: str | None) -> float:
        if preset is not None:
            t = self.preset(preset).t_end
            if t is not None:
                return float(t)
        return float(self.t_end)

    # -- the page ---------------------------------------------------------------

    @abstractmethod
    def derivation(self, params: Params) -> list[DerivationStep]: ...

    @abstractmethod
    def simulate(self, params: Params, t_end: float | None = None) -> RunResult: ...

    @abstractmethod
    def stepper(self, params: Params) -> Stepper: ...

    @abstractmethod
    def scene(self, params: Params) -> SceneSpec: ...

    @abstractmethod
    def claims(self) -> list[Claim]: ...

    # -- convenience --------------------------------------------------------------

    def run(
        self,
        preset: str | None = None,
        values: Mapping[str, Any] | None = None,
        t_end: float | None = None,
    ) -> RunResult:
        """Resolve and simulate in one call (what ``analyzer-lab run`` does)."""
        params = self.resolve(values, preset)
        result = self.simulate(params, self.preset_t_end(preset) if t_end is None else t_end)
        result.preset = preset
        return result

    def describe(self) -> dict[str, Any]:
        """JSON-friendly declaration (``analyzer-lab lessons --json``)."""
        return {
            "id": self.id,
            "title": self.title,
            "chapter": self.chapter,
            "problem": self.problem,
            "source": self.source,
            "params": [
                {
                    "name": p.name,
                    "kind": p.kind,
                    "default": p.default,
                    "label": p.label,
                    "unit": p.unit,
                    "min": p.min,
                    "max": p.max,
                    "choices": list(p.choices),
                    "group": p.group,
                }
                for p in self.params
            ],
            "groups": [{"name": g.name, "title": g.title, "change": g.change} for g in self.groups],
            "modes": list(self.modes),
            "start_point": list(self.start_point) if self.start_point else None,
            "family": self.family,
            "series": [
                {"name": s.name, "unit": s.unit, "description": s.description} for s in self.series
            ],
            "readout": list(self.readout),
            "sampling": self.sampling,
            "time_scale": self.time_scale,
            "presets": [
                {"name": p.name, "title": p.title, "values": dict(p.values), "t_end": p.t_end}
                for p in self.presets
            ],
        }


def close(expected: float, got: float, rtol: float = 0.0, atol: float = 0.0) -> ClaimResult:
    """A numeric claim result: ``|got - expected| <= atol + rtol |expected|``."""
    ok = bool(np.isfinite(got) and abs(got - expected) <= atol + rtol * abs(expected))
    tol = f" (atol {atol:g}, rtol {rtol:g})"
    return ClaimResult(expected=f"{expected:.10g}{tol}", got=f"{got:.10g}", passed=ok)


def at_most(bound: float, got: float, what: str = "") -> ClaimResult:
    """A bound claim result: ``got <= bound``."""
    ok = bool(np.isfinite(got) and got <= bound)
    return ClaimResult(expected=f"{what}<= {bound:.3g}", got=f"{got:.3g}", passed=ok)


__all__ = [
    "Claim",
    "ClaimResult",
    "CurveItem",
    "DerivationStep",
    "Formula",
    "FormulaError",
    "Frame",
    "Group",
    "Note",
    "ObservationError",
    "Series",
    "DEFAULT_GROUPS",
    "MODE",
    "CONTROLS",
    "INITIAL",
    "SURFACE",
    "METHOD",
    "Lesson",
    "MarkerItem",
    "MeshItem",
    "Param",
    "ParamError",
    "Params",
    "PlotSpec",
    "Preset",
    "RunResult",
    "SceneSpec",
    "Stepper",
    "at_most",
    "close",
]
