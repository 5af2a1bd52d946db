"""Runs drawn with matplotlib (the optional extra ``plot``): one axes, time on x, the
series on y, titled and labelled with their units."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, Protocol

import numpy as np
from analyzer_lab.api.extras import optional


class Plottable(Protocol):
    """What a curve is drawn from (a :class:`~analyzer_lab.api.results.Run`)."""

    label: str
    t: np.ndarray
    series: Mapping[str, np.ndarray]
    units: Mapping[str, str]


def with_unit(name: str, unit: str) -> str:
    """A series' label with its unit.

    Parameters
    ----------
    name : str
        The series' name.
    unit : str
        Its unit (``""`` for a pure number).

    Returns
    -------
    str
        ``"x [m]"``, or the name alone for a pure number.
    """
    return f"{name} [{unit}]" if unit else name


def y_label(names: Sequence[str], units: Sequence[str]) -> str:
    """The y axis' label.

    Parameters
    ----------
    names : sequence of str
        The series drawn.
    units : sequence of str
        Their units, in the same order.

    Returns
    -------
    str
        The names with their one unit (``"x, y [m]"``), or each name with its own.
    """
    if len(set(units)) == 1:
        return with_unit(", ".join(names), units[0])
    return ", ".join(with_unit(n, u) for n, u in zip(names, units))


def draw(
    runs: Sequence[Plottable],
    series: Sequence[str],
    title: str,
    ax: Any = None,
    label_runs: bool = False,
) -> Any:
    """Draw ``series`` of every run on ``ax`` (a new figure's axes when ``None``).

    Parameters
    ----------
    runs : sequence of Plottable
        The runs, each with every name of ``series``.
    series : sequence of str
        The series to draw.
    title : str
        The axes' title.
    ax : matplotlib.axes.Axes, optional
        Where to draw; a new figure when ``None``.
    label_runs : bool
        Put each run's label in the legend (a family of runs).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.
    """
    pyplot = optional("matplotlib.pyplot", "plot", "plot()")
    if ax is None:
        _, ax = pyplot.subplots()
    units = [runs[0].units.get(name, "") for name in series]
    for run in runs:
        for name, unit in zip(series, units):
            label = with_unit(name, unit)
            if label_runs:
                label = f"{run.label}: {label}"
            ax.plot(run.t, run.series[name], label=label)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(y_label(series, units))
    ax.set_title(title)
    if len(series) > 1 or label_runs:
        ax.legend()
    ax.grid(True, alpha=0.3)
    return ax


__all__ = ["Plottable", "draw", "with_unit", "y_label"]
