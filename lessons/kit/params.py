"""Typed parameters and their groups: what a lesson's values are and where they show.

Part of the lesson contract (:mod:`analyzer_lab.lessons.kit.contract` re-exports every name).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from analyzer_lab.lessons.kit.formula import (
    Formula,
    FormulaError,
    parse_formula,
    parse_number,
)
from analyzer_lab.lessons.kit.message import N_, Message, Unit

#: Relative round-off within which a value at a bound counts as the bound.
_ROUND_OFF = 4 * 2.0**-52

ParamKind = Literal["float", "int", "formula", "choice", "bool"]
Value = float | int | str | bool | Formula


class ParamError(ValueError):
    """A parameter value was refused.  ``str(err)`` is one line a user can act on."""

    def __init__(self, name: str, message: str) -> None:
        super().__init__(Message(N_("{name}: {message}"), name=name, message=message))
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
    ``when``: ``(mode, values)``: the parameter matters (and is shown) only while the mode
    parameter ``mode`` has one of ``values`` (e.g. the cone's c but not the paraboloid's p).
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
    when: tuple[str, tuple[str, ...]] | None = None

    def applies(self, params: Mapping[str, Any]) -> bool:
        """Whether the parameter matters for these values (see ``when``)."""
        if self.when is None:
            return True
        mode, values = self.when
        return str(params.get(mode)) in values

    def parse(self, raw: Any) -> Value:
        """Validate one raw value (text or number); raise :class:`ParamError`."""
        try:
            return self._parse(raw)
        except FormulaError as exc:
            raise ParamError(self.name, exc.args[0] if exc.args else str(exc)) from None

    def _parse(self, raw: Any) -> Value:
        if self.kind == "formula":
            if isinstance(raw, Formula):
                return raw
            if isinstance(raw, bool):
                raise ParamError(self.name, Message(N_("expected a formula of t, got a boolean")))
            if isinstance(raw, (int, float, np.floating, np.integer)):
                if not math.isfinite(float(raw)):
                    raise ParamError(
                        self.name, Message(N_("must be finite, got {value}"), value=float(raw))
                    )
                raw = (
                    str(int(raw))
                    if float(raw).is_integer() and abs(raw) < 1e15
                    else repr(float(raw))
                )
            if not isinstance(raw, str):
                raise ParamError(
                    self.name,
                    Message(N_("expected a formula of t, got {kind}"), kind=type(raw).__name__),
                )
            return parse_formula(raw, variables=("t",))
        if self.kind == "choice":
            text = str(raw).strip()
            if text not in self.choices:
                raise ParamError(
                    self.name,
                    Message(
                        N_("must be one of {choices}; got {text}"),
                        choices=", ".join(self.choices),
                        text=repr(text[:40]),
                    ),
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
            raise ParamError(
                self.name, Message(N_("expected on/off, got {text}"), text=repr(text[:40]))
            )
        # float / int
        if isinstance(raw, bool):
            raise ParamError(self.name, Message(N_("expected a number, got a boolean")))
        if isinstance(raw, (int, float, np.floating, np.integer)):
            value = float(raw)
        elif isinstance(raw, str):
            value = parse_number(raw)
        else:
            raise ParamError(
                self.name, Message(N_("expected a number, got {kind}"), kind=type(raw).__name__)
            )
        if not math.isfinite(value):
            raise ParamError(
                self.name, Message(N_("must be a finite number, got {value}"), value=value)
            )
        if self.kind == "int":
            if not float(value).is_integer():
                raise ParamError(
                    self.name, Message(N_("must be a whole number, got {value}"), value=value)
                )
            value = int(value)
        unit = Unit(self.unit)
        # a bound typed as printed is accepted: within a few units of round-off of the
        # bound, the value is the bound (e.g. a limit computed as pi/2 and typed so)
        if self.min is not None and value < self.min:
            if value < self.min - _ROUND_OFF * max(abs(self.min), 1e-300):
                raise ParamError(
                    self.name,
                    Message(
                        N_("{value} is below the minimum {low} {unit}")
                        if unit
                        else N_("{value} is below the minimum {low}"),
                        value=value,
                        low=self.min,
                        unit=unit,
                    ),
                )
            value = int(self.min) if self.kind == "int" else float(self.min)
        if self.max is not None and value > self.max:
            if value > self.max + _ROUND_OFF * max(abs(self.max), 1e-300):
                raise ParamError(
                    self.name,
                    Message(
                        N_("{value} is above the maximum {high} {unit}")
                        if unit
                        else N_("{value} is above the maximum {high}"),
                        value=value,
                        high=self.max,
                        unit=unit,
                    ),
                )
            value = int(self.max) if self.kind == "int" else float(self.max)
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
