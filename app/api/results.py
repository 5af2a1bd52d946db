"""Response objects: one run of a lesson (:class:`Run`) and a family of runs (:class:`Runs`).

A :class:`Run` holds what ``analyzer-lab run`` prints (the same object: ``to_dict()`` is
its JSON, ``to_csv()`` its CSV) as numpy arrays, and turns it into a table (pandas, an
optional extra), a figure (matplotlib, the extra ``plot``) or a 3D scene (:meth:`Run.show`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from analyzer_lab.api.extras import optional
from analyzer_lab.api.plotting import draw
from analyzer_lab.api.scene import Scene, scene_of
from analyzer_lab.serve.headless import AnalyzerLabError, find_lesson

if TYPE_CHECKING:
    from analyzer_lab.lessons.kit.contract import RunResult


class Run:
    """One run of a lesson: samples, named series with units, metrics and messages.

    Made by :func:`analyzer_lab.api.run`; the numbers are those of
    ``analyzer-lab run --format json`` for the same lesson, preset and values.

    Attributes
    ----------
    lesson : str
        The lesson's id.
    preset : str or None
        The textbook example the run started from (``None``: the defaults).
    t : numpy.ndarray
        The sample times (seconds), 1-D.
    series : dict of str to numpy.ndarray
        Every series the lesson observes, by name, one value per sample.
    units : dict of str to str
        The unit of each series (``""`` for a pure number).
    metrics : dict of str to Any
        The run's scalar results (errors, extrema, the integrator's counts).
    messages : list of str
        What the lesson says about the run (a projected start point, a series that
        stops being defined).
    values : dict of str to Any
        Every parameter's value actually used (formulas as their text).
    given : dict of str to Any
        The values passed over the preset.
    t_end : float
        The run's length asked for (seconds).
    """

    def __init__(self, result: RunResult, t_end: float, given: Mapping[str, Any]) -> None:
        self._result = result
        self.lesson: str = result.lesson
        self.preset: str | None = result.preset
        self.t: np.ndarray = np.asarray(result.t, dtype=float)
        self.series: dict[str, np.ndarray] = {
            name: np.asarray(v, dtype=float) for name, v in result.series.items()
        }
        self.units: dict[str, str] = {name: result.units.get(name, "") for name in self.series}
        self.metrics: dict[str, Any] = dict(result.metrics)
        self.messages: list[str] = list(result.messages)
        self.values: dict[str, Any] = dict(result.params)
        self.given: dict[str, Any] = dict(given)
        self.t_end: float = float(t_end)

    @property
    def label(self) -> str:
        """The preset (or ``"defaults"``) and the values given over it, e.g.
        ``"example-1.1, u1=t"``."""
        given = ", ".join(f"{k}={v}" for k, v in self.given.items())
        return ", ".join(x for x in (self.preset or "defaults", given) if x)

    def __getitem__(self, name: str) -> np.ndarray:
        """The series ``name`` (or ``"t"``, the times).

        Raises
        ------
        AnalyzerLabError
            For a series the run does not have (the message lists the known ones).
        """
        if name == "t":
            return self.t
        self._check_names([name])
        return self.series[name]

    def __repr__(self) -> str:
        return (
            f"Run(lesson={self.lesson!r}, preset={self.preset!r}, samples={len(self.t)},"
            f" t_end={self.t_end:g}, series={list(self.series)})"
        )

    def _check_names(self, names: Iterable[str]) -> None:
        for name in names:
            if name not in self.series:
                known = ", ".join(self.series)
                raise AnalyzerLabError(f"{self.lesson}: no series {name[:60]!r}; known: {known}")

    def to_dict(self) -> dict[str, Any]:
        """The run as ``analyzer-lab run --format json`` prints it.

        Returns
        -------
        dict
            ``{"lesson", "preset", "params", "t", "series", "units", "metrics",
            "messages"}`` with lists of numbers (``None`` where a value is not finite).
        """
        return self._result.to_json_dict()

    def to_csv(self, path: str | Path | None = None) -> str:
        """The run as ``analyzer-lab run --format csv`` writes it: one row per sample,
        ``t`` then every series.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            Also write the text to this file.

        Returns
        -------
        str
            The CSV text.
        """
        text = self._result.to_csv()
        if path is not None:
            Path(path).write_text(text, encoding="utf-8")
        return text

    def to_pandas(self) -> Any:
        """The run as a table: one row per sample, indexed by ``t``, a column per series.

        Returns
        -------
        pandas.DataFrame
            The series as columns; ``frame.attrs["units"]`` holds their units.

        Raises
        ------
        AnalyzerLabError
            When pandas is not installed (the message names the extra to install).
        """
        pandas = optional("pandas", "pandas", "Run.to_pandas()")
        frame = pandas.DataFrame(self.series, index=pandas.Index(self.t, name="t"))
        frame.attrs["units"] = dict(self.units)
        frame.attrs["lesson"] = self.lesson
        frame.attrs["preset"] = self.preset
        return frame

    def _default_plot(self) -> tuple[tuple[str, ...], str]:
        """The series of the lesson's first live plot and its title."""
        for spec in find_lesson(self.lesson).plots:
            names = tuple(n for n in spec.series if n in self.series)
            if names:
                return names, spec.title
        return tuple(self.series)[:1], self.lesson

    def plot(self, *series: str, ax: Any = None, title: str | None = None) -> Any:
        """Plot series against time (matplotlib, the optional extra ``plot``).

        Parameters
        ----------
        *series : str
            The series to draw on one axes (default: those of the lesson's first live
            plot, e.g. the sphere's velocity components).
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure when ``None``.
        title : str, optional
            The axes' title (default: the lesson, the run's label and the plot's title).

        Returns
        -------
        matplotlib.axes.Axes
            The axes, titled, with ``t [s]`` on x and the series' units on y.

        Raises
        ------
        AnalyzerLabError
            For a series the run does not have, or when matplotlib is not installed.
        """
        names, what = (tuple(series), ", ".join(series)) if series else self._default_plot()
        self._check_names(names)
        return draw([self], names, title or f"{self.lesson} ({self.label}): {what}", ax)

    def show(self, height: int = 480) -> Scene:
        """The run's 3D scene and trail as a self-contained HTML page, the browser's
        "HTML replay" (viser's scene serialization; nothing is fetched to view it).

        The lesson is played from the start as the live page plays it, up to
        :attr:`t_end`, and recorded.

        Parameters
        ----------
        height : int
            The height in pixels of the scene shown in a notebook.

        Returns
        -------
        Scene
            Shown inline by Jupyter (``_repr_html_``); ``Scene.html`` is the page,
            ``Scene.save(path)`` writes it.
        """
        return scene_of(self.lesson, self.preset, self.values, self.t_end, self.label, height)


class Runs(list[Run]):
    """A family of runs, drawn together (a ``list`` of :class:`Run`).

    Made by :func:`analyzer_lab.api.runs`.
    """

    def plot(self, *series: str, ax: Any = None, title: str | None = None) -> Any:
        """Plot the same series of every run on one axes, each run labelled.

        Parameters
        ----------
        *series : str
            The series to draw (default: those of the first run's lesson's first plot).
        ax : matplotlib.axes.Axes, optional
            Where to draw; a new figure when ``None``.
        title : str, optional
            The axes' title (default: the lessons and the series).

        Returns
        -------
        matplotlib.axes.Axes
            The axes, titled, with ``t [s]`` on x, the units on y and a legend.

        Raises
        ------
        AnalyzerLabError
            For an empty family, a series a run does not have, or when matplotlib is
            not installed.
        """
        if not self:
            raise AnalyzerLabError("runs: no runs to plot")
        names, what = (tuple(series), ", ".join(series)) if series else self[0]._default_plot()
        for run in self:
            run._check_names(names)
        lessons = ", ".join(dict.fromkeys(run.lesson for run in self))
        return draw(self, names, title or f"{lessons}: {what}", ax, label_runs=True)

    def to_pandas(self) -> Any:
        """Every run's table, one above the other, indexed by the run's label and ``t``.

        Returns
        -------
        pandas.DataFrame
            Indexed by (``run``, ``t``).

        Raises
        ------
        AnalyzerLabError
            When pandas is not installed (the message names the extra to install).
        """
        pandas = optional("pandas", "pandas", "Runs.to_pandas()")
        frames = [run.to_pandas() for run in self]
        labels = [f"{k}: {run.lesson} {run.label}" for k, run in enumerate(self)]
        return pandas.concat(frames, keys=labels, names=["run", "t"])


__all__ = ["Run", "Runs"]
