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

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import sympy as sp
from analyzer_lab.lessons.kit.formula import Formula, FormulaError
from analyzer_lab.lessons.kit.once import once
from analyzer_lab.lessons.kit.params import (
    CONTROLS,
    DEFAULT_GROUPS,
    INITIAL,
    METHOD,
    MODE,
    SURFACE,
    Group,
    Param,
    ParamError,
    Params,
)
from analyzer_lab.lessons.kit.results import Claim, ClaimResult, RunResult, at_most, close
from analyzer_lab.lessons.kit.scene_spec import (
    CurveItem,
    Frame,
    MarkerItem,
    MeshItem,
    PlotSpec,
    SceneSpec,
)


@dataclass(frozen=True)
class Series:
    """One observed quantity: a column of a run and a live value of a frame.

    ``member``: for a lesson with a family of start points, members 2..N add the
    columns ``name_2 .. name_N`` (member 1 keeps ``name``).
    ``undefined``: where the quantity is undefined by the textbook's own formula (e.g.
    the controls (1.15) at the origin); a non-finite value of it there is part of the
    lesson (reported by the lesson's notes), not a failed run.  Empty: always defined.
    """

    name: str
    unit: str = ""
    description: str = ""
    member: bool = False
    undefined: str = ""


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

    @property
    def computing(self) -> bool:
        """Whether the time stood still at the last :meth:`advance` only because work
        under way paused at the budget (a step of many substeps): it moves on later."""
        return False


@dataclass(frozen=True, eq=False)
class LessonSetup:
    """A lesson opened with a preset and values (:meth:`Lesson.open`): what a run or a page
    needs, each computed once.  The validated parameters and the run's length are there at
    once; the stepper, the scene and the notes are built the first time they are read (a
    change of a live value needs neither a new stepper nor a new scene).

    ``scene_of``: where the scene comes from (e.g. a cache shared by the pages showing the
    same values); ``None``: :meth:`Lesson.scene`.
    """

    lesson: Lesson
    preset: str | None
    params: Params
    t_end: float
    scene_of: Callable[[Lesson, Params], SceneSpec] | None = None

    @once
    def stepper(self) -> Stepper:
        """The live run of these values (:meth:`Lesson.stepper`)."""
        return self.lesson.stepper(self.params)

    @once
    def scene(self) -> SceneSpec:
        """What to draw for these values (:meth:`Lesson.scene`)."""
        if self.scene_of is None:
            return self.lesson.scene(self.params)
        return self.scene_of(self.lesson, self.params)

    @once
    def notes(self) -> tuple[Note, ...]:
        """What the lesson did with these values and the caveats that apply (:meth:`Lesson.notes`)."""
        return tuple(self.lesson.notes(self.params))


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
        return self._resolved(values, self.preset(preset) if preset is not None else None)

    def open(
        self,
        values: Mapping[str, Any] | None = None,
        preset: str | None = None,
        *,
        scene_of: Callable[[Lesson, Params], SceneSpec] | None = None,
    ) -> LessonSetup:
        """The lesson with ``values`` over ``preset`` (over the defaults), in one call: the
        preset looked up once, the values validated once (:meth:`resolve`), the run's
        length (:meth:`preset_t_end`); the stepper, scene and notes when first read.

        Raises :class:`ParamError` for an unknown preset or the first bad value.
        """
        chosen = self.preset(preset) if preset is not None else None
        params = self._resolved(values, chosen)
        return LessonSetup(self, preset, params, self._t_end_of(chosen), scene_of)

    def _resolved(self, values: Mapping[str, Any] | None, preset: Preset | None) -> Params:
        raw: dict[str, Any] = {p.name: p.default for p in self.params}
        if preset is not None:
            raw.update(preset.values)
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
        conditions = [(f"group {g.name!r}", g.when) for g in self.groups]
        conditions += [(f"parameter {p.name!r}", p.when) for p in self.params]
        for what, when in conditions:
            if when is not None:
                mode, values = when
                if mode not in self.modes:
                    errors.append(f"{what}: {mode!r} is not one of the modes")
                elif self.param(mode).kind == "choice":
                    unknown = set(values) - set(self.param(mode).choices)
                    if unknown:
                        errors.append(f"{what}: {sorted(unknown)} are not choices")
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
                Series(
                    f"{s.name}_{k}", s.unit, f"{s.description} (curve {k})", undefined=s.undefined
                )
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

    def series_key(self, params: Params) -> Any:
        """What :meth:`series_for` depends on (the family size; a lesson whose series
        depend on more of its values says so): the names are kept per key."""
        return int(params[self.family]) if self.family is not None else 1

    def series_names(self, params: Params) -> tuple[str, ...]:
        """The names of :meth:`series_for` (kept per :meth:`series_key`: a frame reads them)."""
        key = self.series_key(params)
        cache = self.__dict__.setdefault("_series_names", {})
        names = cache.get(key)
        if names is None:
            names = cache[key] = tuple(s.name for s in self.series_for(params))
        return names

    def observe_one(self, params: Params, t: float, state: Any) -> Mapping[str, float] | None:
        """The observation at one time as plain numbers, for a lesson with a faster way to
        it than :meth:`observe` at ``[t]`` (the same values to round-off, which its tests
        show); ``None`` (the default): :meth:`observe` at ``[t]`` is read."""
        return None

    def frame_scalars(self, params: Params, t: float, state: Any) -> dict[str, float]:
        """The observation at one time (``state`` with a leading time axis of length 1).

        The same values as :meth:`observation` at ``[t]``, read without its copies (from
        :meth:`observe_one` where the lesson has it): the names are checked against the
        cached declared ones, each value is one number or one per time (anything else goes
        through :meth:`observation`, which says what differs)."""
        raw = self.observe_one(params, t, state)
        if raw is None:
            raw = self.observe(params, np.array([float(t)]), state)
        names = self.series_names(params)
        out: dict[str, float] = {}
        if len(raw) == len(names):
            try:
                for n in names:
                    v = raw[n]
                    if type(v) is float:
                        out[n] = v
                    elif type(v) is np.ndarray and v.shape == (1,):
                        out[n] = float(v[0])
                    elif isinstance(v, float) or np.ndim(v) == 0:
                        out[n] = float(v)
                    elif np.shape(v) == (1,):
                        out[n] = float(v[0])
                    else:
                        break
                else:
                    return out
            except KeyError:
                pass
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
        """The run's length for ``preset``: its own, else the lesson's."""
        return self._t_end_of(self.preset(preset) if preset is not None else None)

    def _t_end_of(self, preset: Preset | None) -> float:
        if preset is not None and preset.t_end is not None:
            return float(preset.t_end)
        return float(self.t_end)

    # -- the page ---------------------------------------------------------------

    @abstractmethod
    def derivation(self, params: Params) -> list[DerivationStep]: ...

    @abstractmethod
    def simulate(self, params: Params, t_end: float | None = None) -> RunResult: ...

    @abstractmethod
    def stepper(self, params: Params) -> Stepper: ...

    def work_bound(self, params: Params, t_end: float) -> float:
        """Units of work (:func:`analyzer_lab.lessons.kit.budget.charge`) a run up to
        ``t_end`` needs at least, known from counts before it starts (fixed steps times
        stages times points); 0 where the lesson cannot tell in advance."""
        return 0.0

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
        """Open and simulate in one call (what ``analyzer-lab run`` does)."""
        setup = self.open(values, preset)
        result = self.simulate(setup.params, setup.t_end if t_end is None else t_end)
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
                    "when": [p.when[0], list(p.when[1])] if p.when else None,
                }
                for p in self.params
            ],
            "groups": [
                {
                    "name": g.name,
                    "title": g.title,
                    "change": g.change,
                    "when": [g.when[0], list(g.when[1])] if g.when else None,
                }
                for g in self.groups
            ],
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
    "LessonSetup",
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
