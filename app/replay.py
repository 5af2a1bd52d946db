"""A self-contained HTML replay of a session's scene (viser's scene serializer).

The scene of a session is private to its browser tab, so it is not in the
broadcast buffer that ``server.get_scene_serializer()`` records.  Instead the
scene is drawn a second time into a recording-only scene API (messages go to a
:class:`viser.infra.StateSerializer`, nowhere else): the static items, the run's
full trail, and the moving point animated over the recorded samples
(``insert_sleep`` between them).  ``as_html()`` then gives one HTML file that
plays back offline.
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numpy as np

from app.session import Session

#: Frames per second of the replay animation and its longest duration.
REPLAY_FPS = 20.0
MAX_REPLAY_FRAMES = 1200


class _NullBuffer:
    """Message buffer that drops everything (the recording keeps its own copy)."""

    def push(self, message: Any) -> None:
        pass

    def atomic_start(self) -> None:
        pass

    def atomic_end(self) -> None:
        pass

    def remove_entity_state_from_buffer(self, entity_type: str, entity_id: str) -> None:
        pass

    def flush(self) -> None:
        pass


def _recording_scene(filter_all: bool = True) -> tuple[Any, Any]:
    """A SceneApi whose messages only reach a fresh StateSerializer."""
    from viser import infra
    from viser._scene_api import SceneApi

    class _Conn(infra.WebsockMessageHandler):
        def __init__(self) -> None:
            super().__init__()
            self._buffer = _NullBuffer()

        def get_message_buffer(self) -> Any:  # type: ignore[override]
            return self._buffer

    class _Server:
        _scene_lifecycle_lock = threading.RLock()
        _connected_clients: dict[int, Any] = {}

    class _Owner:
        client_id = 0

        def __init__(self) -> None:
            self._websock_connection = _Conn()
            self._viser_server = _Server()

        def flush(self) -> None:
            pass

    owner = _Owner()
    serializer = owner._websock_connection.get_message_serializer(
        filter=lambda m: getattr(m, "include_in_scene_serialization", True)
    )
    import asyncio

    loop = asyncio.new_event_loop()
    scene = SceneApi(owner, thread_executor=ThreadPoolExecutor(max_workers=1), event_loop=loop)  # type: ignore[arg-type]
    return scene, serializer


def replay_html(session: Session) -> str:
    """The session's scene and recorded run as one self-contained HTML page."""
    from app.view import _bounds_info, _nice, _safe

    scene_api, ser = _recording_scene()
    spec = session.scene
    lo, hi, size = _bounds_info(spec)
    center = (lo + hi) / 2
    scene_api.add_grid(
        "/lab/grid",
        width=float(hi[0] - lo[0]) * 1.4 + 1e-9,
        height=float(hi[1] - lo[1]) * 1.4 + 1e-9,
        cell_size=_nice(size / 10),
        section_size=_nice(size / 2),
        position=(float(center[0]), float(center[1]), float(lo[2] if not spec.planar else 0.0)),
        shadow_opacity=0.0,
    )
    scene_api.add_frame(
        "/lab/axes", axes_length=0.35 * size, axes_radius=0.006 * size, origin_radius=0.012 * size
    )
    for m in spec.meshes:
        if len(m.vertices) and len(m.faces):
            scene_api.add_mesh_simple(
                f"/lab/static/mesh/{_safe(m.name)}",
                np.asarray(m.vertices, np.float32),
                np.asarray(m.faces, np.uint32),
                color=tuple(m.color),
                opacity=float(m.opacity),
                side="double",
                cast_shadow=False,
                receive_shadow=False,
            )
    for c in spec.curves:
        pts = np.asarray(c.points, np.float32).reshape(-1, 3)
        if len(pts) >= 2:
            scene_api.add_line_segments(
                f"/lab/static/curve/{_safe(c.name)}",
                np.stack([pts[:-1], pts[1:]], 1),
                tuple(c.color),
                thickness=float(c.width),
                thickness_units="screen",
            )
    for mk in spec.markers:
        pts = np.asarray(mk.points, np.float32).reshape(-1, 3)
        scene_api.add_point_cloud(
            f"/lab/static/marker/{_safe(mk.name)}",
            pts,
            tuple(mk.color),
            point_size=float(mk.size) * 1.2,
            point_shape="diamond",
            precision="float32",
        )
    samples = session.log.samples
    if samples:
        stride = max(1, int(np.ceil(len(samples) / MAX_REPLAY_FRAMES)))
        chosen_idx = list(range(0, len(samples), stride))
        if chosen_idx[-1] != len(samples) - 1:
            chosen_idx.append(len(samples) - 1)
        for name, color in spec.moving_points.items():
            seq = [
                np.asarray(s.points[name], np.float32).reshape(-1, 3)
                for s in samples
                if name in s.points
            ]
            if not seq:
                continue
            n = min(len(p) for p in seq)
            arr = np.stack([p[:n] for p in seq], axis=1)  # (members, K, 3)
            handle = scene_api.add_point_cloud(
                f"/lab/live/point/{_safe(name)}",
                arr[:, 0],
                tuple(color),
                point_size=0.045 * size,
                point_shape="circle",
                precision="float32",
            )
            trail = None
            t_prev = samples[0].t
            for k, idx in enumerate(chosen_idx):
                s = samples[idx]
                if name not in s.points:
                    continue
                handle.points = np.asarray(s.points[name], np.float32).reshape(-1, 3)[:n]
                upto = idx + 1 if k % 10 == 0 or k == len(chosen_idx) - 1 else None
                if upto is not None and upto >= 2:
                    segs = np.stack([arr[:, : upto - 1], arr[:, 1:upto]], axis=2).reshape(-1, 2, 3)
                    if trail is None:
                        trail = scene_api.add_line_segments(
                            f"/lab/live/trail/{_safe(name)}",
                            segs,
                            tuple(color),
                            thickness=2.5,
                            thickness_units="screen",
                        )
                    else:
                        trail.points = segs
                dt = (s.t - t_prev) / max(session.speed, 1e-9)
                ser.insert_sleep(min(max(dt, 0.0), 1.0 / REPLAY_FPS * 4) if k else 0.0)
                t_prev = s.t
    return ser.as_html()


__all__ = ["replay_html"]
