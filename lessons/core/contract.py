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
from dataclasses import dataclass, field
from typing import Any, Callable, Literal, Mapping, Sequence

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
    ``group`` places it in the view: ``controls``, ``initial``, ``surface``, ``method``.
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
                raw = str(int(raw)) if float(raw).is_integer() and abs(raw) < 1e15 else repr(float(raw))
            if not isinstance(raw, str):
                raise ParamError(self.name, f"expected a formula of t, got {type(raw).__name__}")
            return parse_formula(raw, variables=("t",))
        if self.kind == "choice":
            text = str(raw).strip()
            if text not in self.choices:
                raise ParamError(self.name, f"must be one of {', '.join(self.choices)}; got {text[:40]!r}")
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
            raise ParamError(self.name, f"{value:g} is below the minimum {self.min:g}{self.unit and ' ' + self.unit}")
        if self.max is not None and value > self.max:
            raise ParamError(self.name, f"{value:g} is above the maximum {self.max:g}{self.unit and ' ' + self.unit}")
        return value


class Params(dict):
    """Validated parameter values by name (numbers, :class:`Formula`, choices, bools)."""

    def raw(self) -> dict[str, Any]:
        """JSON-friendly view: formulas as their text."""
        return {k: (v.text if isinstance(v, Formula) else v) for k, v in self.items()}


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
            "metrics": clean(self.metrics),
            "messages": list(self.messages),
        }

    def to_csv(self) -> str:
        """One row per sample: ``t`` then every series (1-D series only)."""
        names = [k for k, v in self.series.items() if np.ndim(v) == 1 and len(v) == len(self.t)]
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow(["t", *names])
        cols = [np.asarray(self.t, dtype=float)] + [np.asarray(self.series[n], dtype=float) for n in names]
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

    # -- parameters -------------------------------------------------------------

    def param(self, name: str) -> Param:
        for p in self.params:
            if p.name == name:
                return p
        raise ParamError(name, f"unknown parameter for lesson {self.id!r}; known: {', '.join(p.name for p in self.params)}")

    def preset(self, name: str) -> Preset:
        for p in self.presets:
            if p.name == name:
                return p
        raise ParamError("preset", f"unknown preset {name[:60]!r} for {self.id}; known: {', '.join(p.name for p in self.presets)}")

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

    def run(self, preset: str | None = None, values: Mapping[str, Any] | None = None, t_end: float | None = None) -> RunResult:
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
            "presets": [{"name": p.name, "title": p.title, "values": dict(p.values), "t_end": p.t_end} for p in self.presets],
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
