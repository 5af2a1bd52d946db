"""The scene renderer: a lesson's :class:`SceneSpec` and its live frames in one page.

Static items (meshes, curves, markers, grid, axes) are drawn once per scene; moving
points with their trails, vectors and posed bodies are updated per frame with as few
property assignments as possible (DESIGN §5).
"""

from __future__ import annotations

import logging
import math
import time
from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from analyzer_lab.lessons.kit.contract import Frame, SceneSpec
from analyzer_lab.view.bodies import (
    LIVE_ROOT,
    BodyGroup,
    body_groups,
    body_node,
    instance_colors,
    live_node,
    node_name,
)
from analyzer_lab.view.extents import frame_points
from analyzer_lab.viser_boundary import fast_set, set_pose

if TYPE_CHECKING:
    import viser

log = logging.getLogger(__name__)


class Trail:
    """A bounded polyline drawn as chunks of line segments; only the newest chunk
    is re-sent, full chunks stay, the oldest are removed past ``max_points``."""

    def __init__(
        self,
        scene: viser.SceneApi,
        name: str,
        color: tuple[int, int, int],
        chunk: int,
        max_points: int,
    ) -> None:
        self.scene = scene
        self.name = name
        self.color = color
        self.chunk = max(2, chunk)
        self.max_chunks = max(2, max_points // self.chunk)
        self.handles: deque[Any] = deque()
        self.current: list[np.ndarray] = []
        self.values: list[float | None] = []
        self.color_by: tuple[float, float] | None = None
        self.counter = 0
        self._newest_full = False  # the newest chunk holds ``chunk`` segments: start another
        self.dirty = False

    def clear(self) -> None:
        while self.handles:
            remove_handle(self.handles.popleft())
        self.current = []
        self.values = []
        self.dirty = False
        self._newest_full = False

    def add(self, points: np.ndarray, value: float | None = None) -> None:
        self.current.append(np.asarray(points, dtype=np.float32).reshape(-1, 3))
        self.values.append(value)
        self.dirty = True

    def _segments(self) -> np.ndarray:
        n = min(len(p) for p in self.current)
        arr = np.stack([p[:n] for p in self.current], axis=1)  # (members, K, 3)
        return np.stack([arr[:, :-1], arr[:, 1:]], axis=2).reshape(-1, 2, 3)

    def _colors(self, segs: np.ndarray) -> Any:
        """One colour for the trail, or per segment from the scalar (green -> red)."""
        if self.color_by is None or any(v is None for v in self.values):
            return self.color
        lo, hi = self.color_by
        vals = np.asarray(self.values, dtype=float)
        frac = np.clip((np.nan_to_num(vals, nan=hi) - lo) / (hi - lo if hi > lo else 1.0), 0.0, 1.0)
        seg = np.maximum(frac[:-1], frac[1:])  # a segment takes its worse end
        rgb = np.stack([40 + 200 * seg, 170 - 140 * seg, 60 - 30 * seg], axis=-1).astype(np.uint8)
        members = len(segs) // max(1, len(seg))
        per = np.repeat(np.tile(rgb, (members, 1))[:, None, :], 2, axis=1)
        return per

    def flush(self) -> None:
        """Send the newest chunk (creating a node when a chunk starts)."""
        if not self.dirty or len(self.current) < 2:
            return
        self.dirty = False
        if len({len(p) for p in self.current}) > 1:  # family size changed: restart
            self.clear()
            return
        segs = self._segments()
        colors = self._colors(segs)
        if not self.handles or self._newest_full:
            self.counter += 1
            h = self.scene.add_line_segments(
                f"{self.name}/c{self.counter}",
                segs,
                colors,
                thickness=2.5,
                thickness_units="screen",
            )
            self.handles.append(h)
            self._newest_full = False
            while len(self.handles) > self.max_chunks:
                remove_handle(self.handles.popleft())
        else:
            fast_set(self.handles[-1], "points", segs)
            if np.ndim(colors) == 3:
                fast_set(self.handles[-1], "colors", np.asarray(colors, dtype=np.uint8))
        if len(self.current) >= self.chunk + 1:
            self._newest_full = True
            self.current = [self.current[-1]]
            self.values = [self.values[-1]]


def scene_bounds(scene: SceneSpec) -> tuple[np.ndarray, np.ndarray, float]:
    """The scene's box (low corner, high corner) and its largest side."""
    lo = np.asarray(scene.bounds[0], dtype=float)
    hi = np.asarray(scene.bounds[1], dtype=float)
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
        lo, hi = -np.ones(3), np.ones(3)
    size = float(np.max(hi - lo)) if np.max(hi - lo) > 0 else 1.0
    return lo, hi, size


def ray_mesh_hit(
    origin: np.ndarray, direction: np.ndarray, vertices: np.ndarray, faces: np.ndarray
) -> np.ndarray | None:
    """Nearest intersection of a ray with a triangle mesh (Moller-Trumbore, vectorized)."""
    o = np.asarray(origin, dtype=float)
    d = np.asarray(direction, dtype=float)
    if not (np.all(np.isfinite(o)) and np.all(np.isfinite(d))) or np.linalg.norm(d) == 0:
        return None
    d = d / np.linalg.norm(d)
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) == 0:
        return None
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    e1, e2 = b - a, c - a
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = np.abs(det) > 1e-14
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    s = o - a
    u = np.einsum("ij,ij->i", s, p) * inv
    q = np.cross(s, e1)
    w = (q @ d) * inv
    t = np.einsum("ij,ij->i", e2, q) * inv
    hit = ok & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 1e-9)
    if not np.any(hit):
        return None
    k = np.argmin(np.where(hit, t, np.inf))
    return o + t[k] * d


#: Share of the canvas's shorter side the scene's bounding sphere fills when framed.
FILL = 0.62
DEFAULT_FOV = math.radians(50.0)
#: A canvas side below this (px) is a page between two layouts, not a size to frame for.
MIN_CANVAS_PX = 48
#: Room left ahead of a run that left the framed box (share of the new box's side).
RUN_MARGIN = 0.25
#: Seconds after a framing at which the page's camera is checked: a page whose camera still
#: stands where the framing before put it (the new position did not take, e.g. the page
#: reported its old camera just after it was moved) is framed again, at most
#: :data:`FRAMING_RESENDS` times.
FRAMING_CHECK_AFTER = 1.0
FRAMING_RESENDS = 3
#: What reading a camera the page has not reported yet (or a page between layouts) raises.
CAMERA_READ_ERRORS = (AssertionError, TypeError, ValueError, AttributeError, RuntimeError)


def _fov_aspect(cam: viser.CameraHandle) -> tuple[float, float]:
    """The page's vertical field of view and aspect (defaults before it reported them)."""
    try:
        fov = float(cam.fov) or DEFAULT_FOV
        aspect = float(cam.image_width) / float(cam.image_height)
    except (AssertionError, TypeError, ValueError, ArithmeticError, AttributeError):
        return DEFAULT_FOV, 1.6  # viser asserts that the page reported its camera once
    if not (math.isfinite(aspect) and aspect > 0):
        aspect = 1.6
    if not (math.radians(5.0) <= fov <= math.radians(150.0)):  # a page between two layouts
        fov = DEFAULT_FOV
    return fov, aspect


def axis_ticks(lo: float, hi: float, count: int = 4) -> list[float]:
    """A few round tick values inside ``[lo, hi]`` (at most ``count + 1``)."""
    span = hi - lo
    if not (math.isfinite(span) and span > 0):
        return []
    step = nice_step(span / count)
    first = math.ceil(lo / step - 1e-9) * step
    ticks = []
    k = 0
    while first + k * step <= hi + 1e-9 * span and k <= count + 1:
        v = first + k * step
        ticks.append(0.0 if abs(v) < 1e-12 * span else v)
        k += 1
    return ticks


class SceneRenderer:
    """Draws one session's scene into one page (``client.scene``, private to it)."""

    def __init__(self, client: viser.ClientHandle, config: Any) -> None:
        self.client = client
        self.config = config
        self.spec: SceneSpec | None = None
        #: called with viser's click event on a surface mesh (set by the view)
        self.on_surface_click: Callable[[Any], None] | None = None
        #: names of the vectors the user chose to see (``None``: the first one)
        self.chosen_vectors: set[str] | None = None
        self._static_handles: list[Any] = []
        self._point_handles: dict[str, Any] = {}
        self._trails: dict[str, Trail] = {}
        self._vector_handle: Any = None
        self._vector_names: tuple[str, ...] = ()
        self._vector_scale: dict[str, float] = {}
        self._body_handles: dict[str, Any] = {}
        #: bodies of one mesh drawn as one batched node (the 6-DOF table's three legs)
        self._body_groups: list[BodyGroup] = []
        self.meshes_for_click: list[tuple[np.ndarray, np.ndarray]] = []
        self._size = 1.0
        self._visible_cache: set[str] | None = None
        self.label_scale = 1.0  # larger in presenter mode
        #: where the camera was put by the last framing: (position, look_at)
        self.framed: tuple[np.ndarray, np.ndarray] | None = None
        #: the box the last framing fitted (low, high corners) and the canvas it fitted
        #: it into (width, height in the page's pixels)
        self.framed_box: tuple[np.ndarray, np.ndarray] | None = None
        self.framed_canvas: tuple[int, int] | None = None
        #: The box the run will cover (a preset's, :mod:`~analyzer_lab.view.extents`):
        #: framed with the scene's; ``None`` for values whose run is not known ahead.
        self.run_box: tuple[np.ndarray, np.ndarray] | None = None
        #: The scene's own words (a marker's label) in the page's language.
        self.text: Callable[[str], str] = str
        #: a framing to check: (when, the camera position of the framing before, resends)
        self._unconfirmed: tuple[float, np.ndarray, int] | None = None

    def visible_vectors(self) -> set[str]:
        names = list(self.spec.moving_vectors) if self.spec is not None else []
        if self.chosen_vectors is not None:
            return {n for n in names if n in self.chosen_vectors}
        return set(names[:1])

    def vectors_changed(self) -> None:
        """Re-create the arrows node at the next frame (the visible set changed)."""
        self._vector_names = ()
        self._visible_cache = None

    def reset_live(self) -> None:
        for t in self._trails.values():
            t.clear()
        self._vector_scale = {}

    def hit(self, origin: np.ndarray, direction: np.ndarray) -> np.ndarray | None:
        """The nearest point where a click ray meets a surface mesh."""
        o = np.asarray(origin, dtype=float)
        best = None
        for vertices, faces in self.meshes_for_click:
            h = ray_mesh_hit(o, np.asarray(direction, dtype=float), vertices, faces)
            if h is not None and (best is None or np.linalg.norm(h - o) < np.linalg.norm(best - o)):
                best = h
        return best

    def _clear_static(self) -> None:
        for h in self._static_handles:
            remove_handle(h)
        self._static_handles = []
        self.meshes_for_click = []

    def draw_static(self, spec: SceneSpec, frame_camera: bool) -> None:
        """Draw the scene's fixed items and fresh nodes for its moving ones."""
        scene_api = self.client.scene
        self.spec = spec
        self._clear_static()
        lo, hi, size = scene_bounds(spec)
        self._size = size
        center = (lo + hi) / 2
        add = self._static_handles.append
        grid_z = lo[2] if not spec.planar else 0.0
        add(
            scene_api.add_grid(
                "/lab/grid",
                width=float(hi[0] - lo[0]) * 1.4 + 1e-9,
                height=float(hi[1] - lo[1]) * 1.4 + 1e-9,
                cell_size=nice_step(size / 10),
                section_size=nice_step(size / 2),
                position=(float(center[0]), float(center[1]), float(grid_z)),
                shadow_opacity=0.0,
            )
        )
        add(
            scene_api.add_frame(
                "/lab/axes",
                axes_length=0.35 * size,
                axes_radius=0.006 * size,
                origin_radius=0.012 * size,
            )
        )
        self._draw_axis_labels(lo, hi, size)
        for m in spec.meshes:
            v = np.asarray(m.vertices, dtype=np.float32)
            f = np.asarray(m.faces, dtype=np.uint32)
            if len(v) == 0 or len(f) == 0:
                continue
            h = scene_api.add_mesh_simple(
                f"/lab/static/mesh/{node_name(m.name)}",
                v,
                f,
                color=tuple(m.color),
                opacity=float(m.opacity),
                wireframe=bool(m.wireframe),
                side="double",
                cast_shadow=False,
                receive_shadow=False,
                flat_shading=False,
            )
            if self.on_surface_click is not None:
                h.on_click(self.on_surface_click)
            self.meshes_for_click.append((v, f))
            add(h)
        for c in spec.curves:
            pts = np.asarray(c.points, dtype=np.float32).reshape(-1, 3)
            if len(pts) < 2:
                continue
            segs = np.stack([pts[:-1], pts[1:]], axis=1)
            add(
                scene_api.add_line_segments(
                    f"/lab/static/curve/{node_name(c.name)}",
                    segs,
                    tuple(c.color),
                    thickness=float(c.width),
                    thickness_units="screen",
                )
            )
        for mk in spec.markers:
            pts = np.asarray(mk.points, dtype=np.float32).reshape(-1, 3)
            add(
                scene_api.add_point_cloud(
                    f"/lab/static/marker/{node_name(mk.name)}",
                    pts,
                    tuple(mk.color),
                    point_size=float(mk.size) * 1.2,
                    point_shape="diamond",
                    precision="float32",
                )
            )
            if mk.label and len(pts):
                add(
                    scene_api.add_label(
                        f"/lab/static/marker_label/{node_name(mk.name)}",
                        self.text(mk.label),
                        position=tuple(map(float, pts[0])),
                        font_screen_scale=self.label_scale,
                    )
                )
        # moving items: fresh nodes for this scene
        for h in self._point_handles.values():
            remove_handle(h)
        self._point_handles = {}
        for b in self._body_handles.values():
            remove_handle(b)
        for g in self._body_groups:
            remove_handle(g.handle)
        self._body_handles, self._body_groups = {}, []
        for names, bodies in body_groups(spec).items():
            first = bodies[0]
            vertices = np.asarray(first.vertices, dtype=np.float32)
            faces = np.asarray(first.faces, dtype=np.uint32)
            if len(bodies) == 1:
                self._body_handles[first.name] = scene_api.add_mesh_simple(
                    live_node("body", first.name),
                    vertices,
                    faces,
                    color=tuple(first.color),
                    opacity=float(first.opacity),
                    cast_shadow=False,
                    receive_shadow=False,
                )
                continue
            n = len(bodies)
            group = BodyGroup(names, np.zeros((n, 3), np.float32), np.zeros((n, 4), np.float32))
            group.wxyzs[:, 0] = 1.0
            group.handle = scene_api.add_batched_meshes_simple(
                body_node(names),
                vertices,
                faces,
                batched_wxyzs=group.wxyzs.copy(),
                batched_positions=group.positions.copy(),
                batched_colors=instance_colors([b.color for b in bodies]),
                lod="off",
                opacity=None if float(first.opacity) >= 1.0 else float(first.opacity),
                cast_shadow=False,
                receive_shadow=False,
            )
            self._body_groups.append(group)
        if self._vector_handle is not None:
            remove_handle(self._vector_handle)
            self._vector_handle = None
            self._vector_names = ()
        self._visible_cache = None
        for name in list(self._trails):
            if name not in spec.moving_points:
                self._trails.pop(name).clear()
        if frame_camera:
            self.frame_camera(*self._framing_box(lo, hi))

    def _framing_box(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
        """The scene's box joined with :attr:`run_box` (what the run will cover), and its
        largest side."""
        if self.run_box is not None:
            lo = np.minimum(lo, self.run_box[0])
            hi = np.maximum(hi, self.run_box[1])
        size = float(np.max(hi - lo))
        return lo, hi, size if size > 0 else 1.0

    def _draw_axis_labels(self, lo: np.ndarray, hi: np.ndarray, size: float) -> None:
        """Axis names at the ends of the axes and a few tick values along each axis, in
        the lesson's units (planar lessons: x and y only)."""
        scene_api = self.client.scene
        add = self._static_handles.append
        axes = 2 if self.spec is not None and self.spec.planar else 3
        for k in range(axes):
            name = "xyz"[k]
            end = np.zeros(3)
            end[k] = max(float(hi[k]), 0.0) + 0.12 * size
            add(
                scene_api.add_label(
                    f"/lab/axis/{name}",
                    name,
                    position=tuple(map(float, end)),
                    font_screen_scale=1.3 * self.label_scale,
                )
            )
            for v in axis_ticks(float(lo[k]), float(hi[k])):
                if v == 0.0:
                    continue
                pos = np.zeros(3)
                pos[k] = v
                add(
                    scene_api.add_label(
                        f"/lab/axis/{name}_tick_{len(self._static_handles)}",
                        f"{v:g}",
                        position=tuple(map(float, pos)),
                        font_screen_scale=0.85 * self.label_scale,
                    )
                )

    def frame_scene(self) -> None:
        """Frame the camera on the current scene (lesson, preset or reset changed)."""
        if self.spec is not None:
            lo, hi, _ = scene_bounds(self.spec)
            self.frame_camera(*self._framing_box(lo, hi))

    def canvas_size(self) -> tuple[int, int] | None:
        """The canvas's size the page reported last (None before it reported one)."""
        try:
            cam = self.client.camera
            size = (int(cam.image_width), int(cam.image_height))
        except (AssertionError, TypeError, ValueError, AttributeError, RuntimeError):
            return None  # viser asserts that the page reported its camera once
        if min(size) < MIN_CANVAS_PX:  # a page between two layouts: wait for its size
            return None
        return size

    def follow_canvas(self) -> bool:
        """Frame the same box again, from where the camera looks now, when the canvas
        changed shape since it was framed (a phone turned, a panel docked or collapsed);
        True when it did."""
        size = self.canvas_size()
        if size is None or self.framed_box is None or size == self.framed_canvas:
            return False
        if self.framed_canvas is not None:
            w0, h0 = self.framed_canvas
            if abs(math.log((size[0] / size[1]) / (w0 / h0))) < 0.05 and (
                abs(math.log(min(size) / min(w0, h0))) < 0.05
            ):
                self.framed_canvas = size
                return False
        lo, hi = self.framed_box
        self.frame_camera(lo, hi, float(np.max(hi - lo)), keep_direction=True)
        return True

    def confirm_framing(self) -> bool:
        """Put the camera where the last framing put it again when, a while after it, the
        page's camera still stands where the framing before left it; True when it did."""
        pending, framed = self._unconfirmed, self.framed
        if pending is None or framed is None or time.monotonic() < pending[0]:
            return False
        _, before, resends = pending
        try:
            cam = self.client.camera
            at = np.asarray(cam.position, dtype=float)
        except CAMERA_READ_ERRORS:
            return False  # not reported yet: checked again later
        tol = 1e-3 * max(float(np.linalg.norm(framed[0] - framed[1])), 1e-9)
        stuck = np.allclose(at, before, rtol=0.0, atol=tol) and not np.allclose(
            at, framed[0], rtol=0.0, atol=tol
        )
        if not stuck or resends >= FRAMING_RESENDS:
            self._unconfirmed = None
            return False
        try:
            cam.position = tuple(map(float, framed[0]))
            cam.look_at = tuple(map(float, framed[1]))
        except CAMERA_READ_ERRORS:
            log.debug("page %s: the framing was not sent again", self.client.client_id)
        self._unconfirmed = (time.monotonic() + FRAMING_CHECK_AFTER, before, resends + 1)
        return True

    def follow_run(self, frame: Frame) -> bool:
        """Frame again, from where the camera looks now, when the run's moving points or
        bodies left the framed box: the new box holds the old one and the run, with
        :data:`RUN_MARGIN` of room ahead; True when it did."""
        if self.framed_box is None:
            return False
        run = frame_points(frame)
        if not len(run):
            return False
        lo, hi = self.framed_box
        slack = 0.02 * float(np.max(hi - lo))
        if np.all(run >= lo - slack) and np.all(run <= hi + slack):
            return False
        new_lo = np.minimum(lo, run.min(axis=0))
        new_hi = np.maximum(hi, run.max(axis=0))
        room = RUN_MARGIN * (new_hi - new_lo)
        new_lo = np.where(run.min(axis=0) < lo - slack, new_lo - room, new_lo)
        new_hi = np.where(run.max(axis=0) > hi + slack, new_hi + room, new_hi)
        self.frame_camera(new_lo, new_hi, float(np.max(new_hi - new_lo)), keep_direction=True)
        return True

    def frame_camera(
        self, lo: np.ndarray, hi: np.ndarray, size: float, keep_direction: bool = False
    ) -> None:
        """Look at the scene's box from an oblique direction (``keep_direction``: from
        where the camera looks now), from the distance at which its bounding sphere fills
        :data:`FILL` of the canvas's shorter side (from the field of view and aspect the
        page reports); clipping planes and orbit limits sized to the scene (a machine in
        millimetres, a unit sphere)."""
        center = (lo + hi) / 2
        radius = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-6)
        # a plane lesson is seen from above (slightly tilted), a space scene obliquely
        planar = self.spec is not None and self.spec.planar
        direction = np.array([0.12, -0.35, 1.0]) if planar else np.array([1.0, 0.75, 0.6])
        try:
            cam = self.client.camera
            if keep_direction and self.canvas_size() is not None:  # the page reported it
                seen = np.asarray(cam.position, dtype=float) - np.asarray(cam.look_at, dtype=float)
                if np.all(np.isfinite(seen)) and np.linalg.norm(seen) > 0:
                    direction = seen
            direction = direction / np.linalg.norm(direction)
            canvas = self.canvas_size()  # the size this framing is for (read before the fit)
            fov, aspect = _fov_aspect(cam)
            if canvas is not None:
                aspect = canvas[0] / canvas[1]
            half = math.tan(fov / 2.0) * min(1.0, aspect)
            dist = radius / (FILL * half)
            cam.far = max(100.0, 20.0 * dist)
            cam.near = max(1e-5, 1e-4 * dist)
            cam.max_orbit_distance = max(1e4, 50.0 * dist)
            cam.min_orbit_distance = min(0.01, 1e-3 * dist)
            cam.up_direction = (0.0, 0.0, 1.0)
            # viser moves look_at along with position: set the position first
            cam.position = tuple(map(float, center + direction * dist))
            cam.look_at = tuple(map(float, center))
            before = self.framed
            self.framed = (center + direction * dist, center)
            self._unconfirmed = (
                (time.monotonic() + FRAMING_CHECK_AFTER, before[0], 0)
                if before is not None
                else None
            )
            self.framed_box = (np.asarray(lo, dtype=float), np.asarray(hi, dtype=float))
            self.framed_canvas = canvas  # a size reported meanwhile is framed at the next check
        except Exception:
            log.exception("the camera of page %s was not framed", self.client.client_id)

    def push_frames(self, frames: list[Frame], playing: bool, frame_count: int) -> None:
        """Draw a batch of frames (the last one fully; all of them into the trails)."""
        if not frames:
            return
        spec = self.spec
        scene_api = self.client.scene
        cfg = self.config
        for fr in frames:
            for name, color in spec.moving_points.items():
                if name in fr.points:
                    tr = self._trails.get(name)
                    if tr is None:
                        tr = self._trails[name] = Trail(
                            scene_api,
                            live_node("trail", name),
                            tuple(color),
                            cfg.trail_chunk,
                            cfg.trail_max_points,
                        )
                    by = spec.trail_color_by.get(name)
                    tr.color_by = (float(by[1]), float(by[2])) if by else None
                    tr.add(fr.points[name], fr.scalars.get(by[0]) if by else None)
        last = frames[-1]
        self.follow_run(last)
        for name, color in spec.moving_points.items():
            pts = last.points.get(name)
            if pts is None:
                continue
            pts = np.asarray(pts, dtype=np.float32).reshape(-1, 3)
            h = self._point_handles.get(name)
            if h is None or h.points.shape != pts.shape:
                if h is not None:
                    remove_handle(h)
                self._point_handles[name] = scene_api.add_point_cloud(
                    live_node("point", name),
                    pts,
                    tuple(color),
                    point_size=0.045 * self._size,
                    point_shape="circle",
                    precision="float32",
                )
            else:
                fast_set(h, "points", pts)
        self._draw_vectors(last)
        for name, (pos, wxyz) in last.poses.items():
            h = self._body_handles.get(name)
            if h is not None:
                set_pose(h, pos, wxyz)
        for group in self._body_groups:
            group.pose(last.poses)
        if frame_count % cfg.trail_every == 0 or len(frames) > 1 or not playing:
            for tr in self._trails.values():
                tr.flush()

    def _draw_vectors(self, frame: Frame) -> None:
        spec = self.spec
        shown = self._visible_cache
        if shown is None:
            shown = self._visible_cache = self.visible_vectors()
        visible = [n for n in spec.moving_vectors if n in shown and n in frame.vectors]
        segs = []
        colors = []
        length = 0.3 * self._size
        for name in visible:
            origins, dirs = frame.vectors[name]
            o = np.asarray(origins, dtype=float).reshape(-1, 3)
            d = np.asarray(dirs, dtype=float).reshape(-1, 3)
            mag = math.sqrt(float(np.max((d * d).sum(axis=1)))) if len(d) else 0.0
            prev = self._vector_scale.get(name, 0.0)
            ref = max(mag, prev * 0.995)
            self._vector_scale[name] = ref
            k = length / ref if ref > 1e-12 else 0.0
            end = o + d * k
            segs.append(np.stack([o, end], axis=1))
            colors.extend([spec.moving_vectors[name]] * len(o))
        names = tuple(visible)
        if not segs:
            if self._vector_handle is not None:
                remove_handle(self._vector_handle)
                self._vector_handle = None
            self._vector_names = names
            return
        pts = np.concatenate(segs, axis=0).astype(np.float32)
        if (
            self._vector_handle is None
            or names != self._vector_names
            or self._vector_handle.points.shape != pts.shape
        ):
            if self._vector_handle is not None:
                remove_handle(self._vector_handle)
            r = 0.006 * self._size
            self._vector_handle = self.client.scene.add_arrows(
                live_node("vectors"),
                pts,
                np.asarray(colors, dtype=np.uint8),
                shaft_radius=r,
                head_radius=2.5 * r,
                head_length=6 * r,
            )
            self._vector_names = names
        else:
            fast_set(self._vector_handle, "points", pts)


def remove_handle(handle: viser.SceneNodeHandle) -> None:
    """Remove a scene node; one already gone with its page is logged and passed over."""
    try:
        handle.remove()
    except Exception:
        log.debug("scene node not removed", exc_info=True)


def nice_step(x: float) -> float:
    """A round number near ``x`` (1, 2, 5 times a power of ten)."""
    if not math.isfinite(x) or x <= 0:
        return 1.0
    e = math.floor(math.log10(x))
    m = x / 10**e
    m = 1 if m < 1.5 else 2 if m < 3.5 else 5 if m < 7.5 else 10
    return m * 10**e


__all__ = [
    "LIVE_ROOT",
    "SceneRenderer",
    "Trail",
    "live_node",
    "ray_mesh_hit",
]
