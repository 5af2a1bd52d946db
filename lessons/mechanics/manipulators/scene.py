"""What the self-study tasks C2.1-C2.6 draw: the bodies of each manipulator and their poses.

Each task's figure (Figs 2.13-2.16, 2.3, 2.6) becomes a few boxes posed from the model's
points and coordinates: the link of C2.1 turning about O, the slider of C2.2 on
y = x + 1, the arms and stages of C2.3 and C2.4, the turning element of C2.5 and the
three inductors of C2.6 (with their fixed points or circle).  Bodies are built once per
scene; :func:`poses` places them for one state.
"""

from __future__ import annotations

import math

import numpy as np
from analyzer_lab.lessons.kit.bodies import IDENTITY_Q, box, quat_z
from analyzer_lab.lessons.kit.contract import CurveItem, MarkerItem, MeshItem, Params
from analyzer_lab.lessons.mechanics.manipulators.models import Model
from analyzer_lab.lessons.mechanics.manipulators.tasks import family

BLUE, ORANGE, GREEN = (120, 160, 220), (220, 120, 60), (120, 200, 120)
GUIDE = (80, 80, 80)


def _body(name: str, extents: tuple[float, ...], color, center=(0.0, 0.0, 0.0)) -> MeshItem:
    return box(name, extents, color, center, opacity=0.8)


def _circle(name: str, radius: float, color: tuple[int, int, int], width: float) -> CurveItem:
    a = np.linspace(0, 2 * math.pi, 181)
    ring = np.column_stack([radius * np.cos(a), radius * np.sin(a), np.zeros_like(a)])
    return CurveItem(name, ring, color, width)


def moving_points(task: str) -> dict[str, tuple[int, int, int]]:
    """The model points drawn with trails: name -> colour."""
    if family(task) == "C2.4":
        return {"PZ": (220, 60, 60)}
    if task == "C2.5":
        return {"A": (60, 60, 220), "G": (220, 60, 60)}
    if family(task) == "C2.6":
        return {"A": (220, 60, 60), "B": (60, 160, 60), "C": (60, 60, 220)}
    return {"M": (220, 60, 60)}


def drawing(
    params: Params, s: float, lo: np.ndarray, hi: np.ndarray
) -> tuple[list[MeshItem], list[CurveItem], list[MarkerItem]]:
    """Bodies, fixed curves and markers of the task (``s``: the scene's body size)."""
    task = params["task"]
    bodies: list[MeshItem] = []
    curves: list[CurveItem] = []
    markers = [MarkerItem("O", np.zeros((1, 3)), (40, 40, 40), 0.3 * s, "O")]
    x_guide = CurveItem("X guide", np.array([[lo[0], 0, 0], [hi[0], 0, 0]]), GUIDE)
    if family(task) == "C2.1":
        L = params["l_OM"]
        bodies.append(_body("link", (L, 0.15 * L, 0.05 * L), BLUE, (L / 2, 0, 0)))
        curves.append(_circle("circle of M", L, (160, 160, 160), 1.0))
    elif family(task) == "C2.2":
        xs = np.array([lo[0], hi[0]])
        curves.append(CurveItem("y = x + 1", np.column_stack([xs, xs + 1, np.zeros(2)]), GUIDE))
        L = max(params["l_AM"], 1e-3)
        bodies.append(_body("link AM", (L, 0.1 * L, 0.05 * L), BLUE, (-L / 2, 0, 0)))
        bodies.append(_body("slider M", (0.3 * L, 0.2 * L, 0.1 * L), ORANGE))
    elif task == "C2.3a":
        L = max(float(hi[0] - lo[0]), float(hi[1] - lo[1])) / 2
        bodies.append(_body("arm", (L, 0.05 * L, 0.02 * L), BLUE, (L / 2, 0, 0)))
        bodies.append(_body("slider", (2 * s, 1.2 * s, 0.8 * s), ORANGE))
    elif task == "C2.3b":
        bodies.append(_body("stage 1", (3 * s, 1.5 * s, 0.5 * s), BLUE))
        bodies.append(_body("stage 2", (1.5 * s, 1.5 * s, 0.6 * s), ORANGE))
        curves.append(x_guide)
    elif task == "C2.3c":
        L = max(params["c23_l"], 1e-3)
        bodies.append(_body("carriage", (3 * s, 1.5 * s, 0.6 * s), BLUE))
        bodies.append(_body("link", (L, 0.08 * L, 0.04 * L), ORANGE, (L / 2, 0, 0)))
        curves.append(x_guide)
    elif family(task) == "C2.4":
        bodies.append(_body("X stage", (3 * s, 3 * s, 0.4 * s), BLUE))
        bodies.append(_body("Y stage", (2 * s, 2 * s, 0.4 * s), GREEN))
        bodies.append(_body("Z stage", (0.8 * s, 0.8 * s, 2 * s), ORANGE))
    elif task == "C2.5":
        L = max(params["c25_l"], 2 * s)
        bodies.append(box("element", (2 * L, L, 0.2 * L), BLUE, opacity=0.6))
    else:
        for name, col in moving_points(task).items():
            bodies.append(_body(f"inductor {name}", (1.2 * s, 1.2 * s, 0.5 * s), col))
        if task == "C2.6c":
            curves.append(_circle("circle R", params["R"], GUIDE, 2.0))
        else:
            fixed = [[params["a"], params["b"], 0.0]] + (
                [[params["c"], params["d"], 0.0]] if task == "C2.6b" else []
            )
            markers.append(
                MarkerItem("fixed inductors", np.array(fixed), (0, 0, 0), 0.5 * s, "fixed")
            )
    return bodies, curves, markers


def poses(
    params: Params, model: Model, q: np.ndarray, consts: list[float]
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Position and wxyz quaternion of every body of :func:`drawing` for coordinates ``q``."""
    task = params["task"]

    def at(name: str) -> np.ndarray:
        return model.point(name, q, consts)

    if family(task) == "C2.1":
        return {"link": (np.zeros(3), quat_z(q[0]))}
    if family(task) == "C2.2":
        along = quat_z(math.pi / 4)
        return {"link AM": (at("M"), along), "slider M": (at("M"), along)}
    if task == "C2.3a":
        return {"arm": (np.zeros(3), quat_z(q[0])), "slider": (at("M"), quat_z(q[0]))}
    if task == "C2.3b":
        return {"stage 1": (at("P1"), IDENTITY_Q), "stage 2": (at("M"), IDENTITY_Q)}
    if task == "C2.3c":
        return {"carriage": (at("C"), IDENTITY_Q), "link": (at("C"), quat_z(q[1]))}
    if family(task) == "C2.4":
        return {f"{a} stage": (at(f"P{a}"), IDENTITY_Q) for a in "XYZ"}
    if task == "C2.5":
        return {"element": (at("G"), quat_z(q[2]))}
    return {f"inductor {n}": (at(n), quat_z(math.atan2(at(n)[1], at(n)[0]))) for n in "ABC"}
