"""A run's 3D scene as one self-contained HTML page: the browser's "HTML replay"
(:func:`analyzer_lab.view.replay.replay_html`) of a session that played the run."""

from __future__ import annotations

import html
import math
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from analyzer_lab.serve.headless import AnalyzerLabError, find_lesson

if TYPE_CHECKING:
    from analyzer_lab.session.session import Session

#: Lesson seconds of one played frame, as the live page plays (times the lesson's time
#: scale); a longer run is played in at most :data:`MAX_FRAMES` frames.
FRAME_DT = 1.0 / 30.0
MAX_FRAMES = 2400


class Scene:
    """A self-contained HTML page of a run's scene (no network needed to view it).

    Attributes
    ----------
    html : str
        The whole page (viser's client, the recorded scene and a caption).
    title : str
        What the page shows.
    height : int
        The height in pixels of the scene shown in a notebook.
    """

    def __init__(self, page: str, title: str, height: int = 480) -> None:
        self.html = page
        self.title = title
        self.height = int(height)

    def __repr__(self) -> str:
        return f"Scene({self.title!r}, {len(self.html)} characters of HTML)"

    def _repr_html_(self) -> str:
        """The page in an ``iframe`` (``srcdoc``): Jupyter shows it inline."""
        return (
            '<div style="border:1px solid #ddd">'
            f'<iframe srcdoc="{html.escape(self.html, quote=True)}" width="100%"'
            f' height="{self.height}" style="border:none;display:block"'
            f' title="{html.escape(self.title, quote=True)}"></iframe></div>'
        )

    def save(self, path: str | Path) -> Path:
        """Write the page to ``path`` (open it in any browser, offline).

        Parameters
        ----------
        path : str or pathlib.Path
            The file to write (``.html``).

        Returns
        -------
        pathlib.Path
            The file written.
        """
        out = Path(path)
        out.write_text(self.html, encoding="utf-8")
        return out


def played(lesson_id: str, preset: str | None, values: Mapping[str, Any], t_end: float) -> Session:
    """A session that has played a run to its end, as the live page plays it.

    Parameters
    ----------
    lesson_id : str
        The lesson's id.
    preset : str or None
        The preset the run started from.
    values : mapping of str to Any
        Every parameter's value used (a run's ``values``).
    t_end : float
        Where the run ends (seconds).

    Returns
    -------
    Session
        Its run log holds frames of :data:`FRAME_DT` lesson seconds (at most
        :data:`MAX_FRAMES`, longer for a long run); a frame whose points are not finite
        is not kept.

    Raises
    ------
    AnalyzerLabError
        When the values are refused.
    """
    import numpy as np
    from analyzer_lab.lessons.kit.contract import ParamError
    from analyzer_lab.session.session import LabError, Session

    lesson = find_lesson(lesson_id)
    try:
        session = Session([lesson], lesson.id, preset)
        session.set_values({k: v for k, v in values.items() if session.raw_values().get(k) != v})
    except (ParamError, LabError) as exc:
        raise AnalyzerLabError(str(exc)) from None
    session.t_end = t_end
    frames = min(MAX_FRAMES, max(1, math.ceil(t_end / (FRAME_DT * lesson.time_scale))))
    stepper = session.stepper
    for k in range(1, frames + 1):
        target = t_end * k / frames
        before = stepper.t
        frame = stepper.advance(target - before)
        if stepper.t <= before:
            break  # the lesson's run cannot go on (an end condition)
        if all(np.isfinite(np.asarray(p, dtype=float)).all() for p in frame.points.values()):
            session.log.add(frame)  # a point undefined there is not drawn
            session.frame = frame
    return session


def scene_of(
    lesson_id: str,
    preset: str | None,
    values: Mapping[str, Any],
    t_end: float,
    label: str,
    height: int = 480,
) -> Scene:
    """A run's scene and trail as one HTML page (see :meth:`~analyzer_lab.api.Run.show`).

    Parameters
    ----------
    lesson_id, preset, values, t_end
        The run (as :func:`played` takes it).
    label : str
        The run's label, in the title.
    height : int
        The height in pixels of the scene shown in a notebook.

    Returns
    -------
    Scene
        The browser's HTML replay of the played run.
    """
    from analyzer_lab.view.replay import replay_html

    session = played(lesson_id, preset, values, t_end)
    lesson = session.lesson
    title = f"{lesson.problem} {lesson.title} ({label})".strip()
    return Scene(replay_html(session), title, height)


__all__ = ["FRAME_DT", "MAX_FRAMES", "Scene", "played", "scene_of"]
