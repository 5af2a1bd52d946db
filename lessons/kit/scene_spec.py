"""What to draw, as data: the scene of a lesson, its live frames and its plots.

Part of the lesson contract (:mod:`analyzer_lab.lessons.kit.contract` re-exports every name).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


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
