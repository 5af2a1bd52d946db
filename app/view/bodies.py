"""Posed bodies that share a mesh, drawn as one batched node.

A frame moves every posed body; each body node costs two messages a frame (position and
orientation).  Bodies with the same mesh (the 6-DOF table's three legs, its three
inductors in their own colors) are one batched node instead: one message for all their
positions and one for all their orientations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from analyzer_lab.lessons.kit.contract import SceneSpec
from analyzer_lab.viser_boundary import fast_set

#: The root of the nodes a played frame updates: moving points, their trails, the
#: vectors and the posed bodies (everything else is drawn once per scene).
LIVE_ROOT = "/lab/live"


def live_node(kind: str, name: str = "") -> str:
    """The node of one moving item: ``kind`` is ``point``, ``trail``, ``body`` or
    ``vectors`` (one node for all arrows, no ``name``)."""
    return f"{LIVE_ROOT}/{kind}/{node_name(name)}" if name else f"{LIVE_ROOT}/{kind}"


def node_name(name: str) -> str:
    """A scene node's name part: letters, digits, "-" and "_" only, at most 60 characters."""
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in str(name))[:60] or "item"


def body_groups(spec: SceneSpec) -> dict[tuple[str, ...], list[Any]]:
    """The posed bodies by mesh: bodies with the same vertices, faces and opacity (colors
    may differ) are drawn as one batched node, moved by one message per frame for all of
    them instead of two per body; by their names, in the declared order."""
    by_mesh: dict[bytes, list[Any]] = {}
    for body in spec.bodies:
        key = (
            np.asarray(body.vertices, dtype=np.float32).tobytes()
            + b"|"
            + np.asarray(body.faces, dtype=np.uint32).tobytes()
            + repr(float(body.opacity)).encode()
        )
        by_mesh.setdefault(key, []).append(body)
    return {tuple(b.name for b in bodies): bodies for bodies in by_mesh.values()}


def body_node(names: tuple[str, ...]) -> str:
    """The scene node of the bodies ``names`` (one body: its own node)."""
    return live_node("body", names[0] if len(names) == 1 else "+".join(names))


def instance_colors(colors: list[tuple[int, int, int]]) -> np.ndarray:
    """``(n, 3)`` uint8 colors for a batched node that look like ``colors`` on a single
    mesh: the browser reads a mesh's color as sRGB but an instance's as linear, so the
    instances get the linear values (the sRGB transfer function undone)."""
    c = np.asarray(colors, dtype=float) / 255.0
    linear = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return np.round(linear * 255.0).astype(np.uint8)


@dataclass
class BodyGroup:
    """Bodies of one mesh as one batched node: their last poses sent."""

    names: tuple[str, ...]
    positions: np.ndarray  # (n, 3) float32
    wxyzs: np.ndarray  # (n, 4) float32
    handle: Any = None

    def pose(self, poses: dict[str, tuple[Any, Any]]) -> None:
        """Send the members' poses of a frame (one message each for positions and
        orientations, none when nothing moved beyond numpy.allclose)."""
        pos, rot = self.positions.copy(), self.wxyzs.copy()
        for i, name in enumerate(self.names):
            hit = poses.get(name)
            if hit is not None:
                pos[i], rot[i] = hit
        if not np.allclose(pos, self.positions):
            self.positions = pos
            fast_set(self.handle, "batched_positions", pos.copy())
        if not np.allclose(rot, self.wxyzs):
            self.wxyzs = rot
            fast_set(self.handle, "batched_wxyzs", rot.copy())


__all__ = ["LIVE_ROOT", "BodyGroup", "body_groups", "body_node", "instance_colors", "live_node"]
