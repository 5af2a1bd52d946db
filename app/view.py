"""The generic view: one browser tab's GUI and scene, drawn from a lesson's declarations.

:class:`SessionView` renders a :class:`~app.session.Session` into one viser client
(``client.gui`` / ``client.scene``, private to that tab): the lesson and preset
pickers, the Lesson / Controls / Plots / Export tabs built from the lesson's
``params``, ``derivation``, ``plots``; the scene from its :class:`SceneSpec`
(meshes, curves, markers, moving points with trails, vectors, bodies); and the
live frames the server's loop hands to :meth:`SessionView.tick`.

Cost per frame is kept small (DESIGN §5): one assignment for the moving points,
one for all vectors, the newest trail chunk every other frame, the readout and
one plot at a few Hz, all inside one ``client.atomic()`` (one wake-up of the
event loop).
"""

from __future__ import annotations

import contextlib
import html
import math
import time
import traceback
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from app.math_render import derivation_to_html
from app.session import SPEEDS, LabError, Session, SessionState, lesson_label
from lessons.core.contract import Frame, Lesson, Param, ParamError, PlotSpec, SceneSpec
from lessons.core.formula import Formula

if TYPE_CHECKING:
    import viser

STORAGE_KEY = "analyzer-lab-state"
NO_PRESET = "(defaults)"
_UNSHOWN = object()
RETIRE_DELAY = 1.5  # seconds a replaced GUI folder stays (hidden) before it is removed
PLOT_COLORS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b")
LEVEL_COLORS = {"info": "#1c4f8a", "warning": "#8a5a00", "error": "#a61b1b"}


def _units_of(lesson: Lesson, names: Sequence[str]) -> str:
    """The plot's unit when all its series share one (from the lesson's declarations)."""
    units = {x.name: x.unit for x in lesson.series}
    found = {units.get(n, "") for n in names}
    return found.pop() if len(found) == 1 else ""


def _speed_label(s: float) -> str:
    return f"{s:g}x"


@dataclass
class ViewConfig:
    """Rates of the view (per session)."""

    fps: float = 36.0  # app.server.DEFAULT_FPS
    trail_every: int = 2  # frames between trail uploads
    trail_chunk: int = 24  # points per trail chunk
    trail_max_points: int = 3000  # per moving point family member
    plot_every: int = 3  # frames between plot samples (12 Hz at 36 fps)
    plot_window: int = 100  # samples in the sliding window
    plot_send_every: int = 6  # frames between plot uploads (round-robin over plots)
    readout_every: int = 6  # frames between time readouts


class Trail:
    """A bounded polyline drawn as chunks of line segments; only the newest chunk
    is re-sent, full chunks stay, the oldest are removed past ``max_points``."""

    def __init__(
        self, scene: Any, name: str, color: tuple[int, int, int], chunk: int, max_points: int
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
        self.dirty = False

    def clear(self) -> None:
        while self.handles:
            self._remove(self.handles.popleft())
        self.current = []
        self.values = []
        self.dirty = False

    @staticmethod
    def _remove(handle: Any) -> None:
        try:
            handle.remove()
        except Exception:
            pass

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
        if not self.handles or getattr(self.handles[-1], "_al_full", False):
            self.counter += 1
            h = self.scene.add_line_segments(
                f"{self.name}/c{self.counter}",
                segs,
                colors,
                thickness=2.5,
                thickness_units="screen",
            )
            self.handles.append(h)
            while len(self.handles) > self.max_chunks:
                self._remove(self.handles.popleft())
        else:
            fast_set(self.handles[-1], "points", segs)
            if np.ndim(colors) == 3:
                fast_set(self.handles[-1], "colors", np.asarray(colors, dtype=np.uint8))
        if len(self.current) >= self.chunk + 1:
            self.handles[-1]._al_full = True
            self.current = [self.current[-1]]
            self.values = [self.values[-1]]


class PlotBuffer:
    """Sliding window of frame scalars for one :class:`PlotSpec`."""

    def __init__(self, spec: PlotSpec, window: int) -> None:
        self.spec = spec
        self.t: deque[float] = deque(maxlen=window)
        self.values = {name: deque(maxlen=window) for name in spec.series}
        self.dirty = False

    def clear(self) -> None:
        self.t.clear()
        for v in self.values.values():
            v.clear()
        self.dirty = True

    def add(self, frame: Frame) -> None:
        self.t.append(float(frame.t))
        for name, buf in self.values.items():
            v = frame.scalars.get(name, math.nan)
            buf.append(float(v) if v is not None and math.isfinite(float(v)) else math.nan)
        self.dirty = True

    def data(self) -> tuple[np.ndarray, ...]:
        if len(self.t) == 0:
            return (np.zeros(1),) + tuple(np.zeros(1) for _ in self.values)
        return (np.fromiter(self.t, float, len(self.t)),) + tuple(
            np.fromiter(v, float, len(v)) for v in self.values.values()
        )


def _bounds_info(scene: SceneSpec) -> tuple[np.ndarray, np.ndarray, float]:
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


class SessionView:
    """One browser tab: its GUI, its scene, and the frames of its session."""

    def __init__(
        self,
        client: viser.ClientHandle,
        session: Session,
        config: ViewConfig | None = None,
        on_state: Callable[[SessionView], None] | None = None,
    ) -> None:
        self.client = client
        self.session = session
        self.config = config or ViewConfig()
        self.on_state = on_state
        self.closed = False
        self.frame_count = 0
        self.derivation_due: float | None = None
        self._drawn_lesson: str | None = None
        self._drawn_scene_rev = -1
        self._drawn_reset_rev = -1
        self._drawn_revision = -1
        self._shown_notice: tuple[str, str] | None = None
        self._shown_frame_message = ""
        self._last_readout = ""
        self._param_widgets: dict[str, list[Any]] = {}
        self._shown: dict[int, Any] = {}  # widget id -> the session value it last showed
        self._retired: list[tuple[float, Any]] = []  # (when to remove, hidden GUI folder)
        self._current_target: Any = None  # the widget whose callback runs now
        self._lesson_folders: list[Any] = []
        self._plots: list[tuple[PlotBuffer, Any]] = []
        self._plot_rr = 0
        self._static_handles: list[Any] = []
        self._point_handles: dict[str, Any] = {}
        self._trails: dict[str, Trail] = {}
        self._vector_handle: Any = None
        self._vector_names: tuple[str, ...] = ()
        self._vector_scale: dict[str, float] = {}
        self._body_handles: dict[str, Any] = {}
        self._meshes_for_click: list[tuple[np.ndarray, np.ndarray]] = []
        self._size = 1.0
        self._frame_dirty = True
        self._visible_cache: set[str] | None = None
        self._plots_fresh_until = 0.0
        self.step_seconds = 0.0  # time spent in the lesson's stepper (frame loop)
        self.draw_seconds = 0.0  # time spent queueing the frame's updates
        # classroom hook: gate(view, event, retry) -> False refuses a GUI input (app.classroom)
        self.gate: Callable[[SessionView, Any, Callable[[Any], None] | None], bool] | None = None
        with session.lock:  # a callback of an early click waits until the page is built
            self._build_gui()

    # ------------------------------------------------------------------ helpers

    def _guard(self, fn: Callable[..., None]) -> Callable[..., None]:
        """Wrap a GUI callback: ignore programmatic updates, serialize on the session
        lock, turn refusals into visible messages, never let an error escape."""

        def wrapped(event: Any) -> None:
            if self.closed or getattr(event, "client", None) is None:
                return
            if self.gate is not None and not self.gate(self, event, wrapped):  # classroom hook
                return
            with self.session.lock:
                self._current_target = getattr(event, "target", None)
                try:
                    fn(event)
                except (ParamError, LabError) as exc:
                    self.session.notify(f"refused: {exc}", "error")
                    self._sync_widgets()
                except Exception as exc:  # a bug must not take the session down
                    traceback.print_exc()
                    self.session.notify(f"internal error: {type(exc).__name__}: {exc}", "error")
                    self._sync_widgets()
                finally:
                    self._current_target = None
                self.refresh(heavy=True)

        return wrapped

    # ------------------------------------------------------------------ GUI

    def _build_gui(self) -> None:
        gui = self.client.gui
        gui.configure_theme(
            control_width="large",
            show_share_button=False,
            show_logo=False,
            brand_color=(40, 90, 160),
        )
        gui.set_panel_label("Analyzer Lab")
        s = self.session
        self._labels = {lesson_label(l): l.id for l in s.lessons.values()}
        self._ids = {v: k for k, v in self._labels.items()}
        self.lesson_dd = gui.add_dropdown(
            "Lesson", tuple(self._labels), initial_value=self._ids[s.lesson.id]
        )
        self.lesson_dd.on_update(self._guard(self._on_lesson))
        self.preset_dd = gui.add_dropdown(
            "Preset", self._preset_options(), initial_value=s.preset or NO_PRESET
        )
        self.preset_dd.on_update(self._guard(self._on_preset))
        self.preset_note = gui.add_html("")
        self.transport = gui.add_button_group("Run", ("Play", "Pause", "Step", "Reset"))
        self.transport.on_click(self._guard(self._on_transport))
        self.speed_dd = gui.add_dropdown(
            "Speed", tuple(_speed_label(x) for x in SPEEDS), initial_value=_speed_label(s.speed)
        )
        self.speed_dd.on_update(self._guard(self._on_speed))
        self.readout = gui.add_html(self._readout_html())
        self.status = gui.add_html(self._status_html())
        self.tabs = gui.add_tab_group()
        self.tab_lesson = self.tabs.add_tab("Lesson")
        self.tab_controls = self.tabs.add_tab("Controls")
        self.tab_plots = self.tabs.add_tab("Plots")
        self.tab_export = self.tabs.add_tab("Export")
        with self.tab_lesson:
            self.lesson_head = gui.add_html("")
            self.derivation_html = gui.add_html("")
        with self.tab_export:
            gui.add_html(
                '<div style="font-size:0.9em">The run shown so far (every frame since the last reset):</div>'
            )
            self.btn_csv = gui.add_button("Download CSV")
            self.btn_json = gui.add_button("Download JSON")
            self.btn_html = gui.add_button("Download HTML replay")
            self.btn_csv.on_click(self._guard(lambda e: self.export("csv")))
            self.btn_json.on_click(self._guard(lambda e: self.export("json")))
            self.btn_html.on_click(self._guard(lambda e: self.export("html")))
        with self.session.lock:
            self.refresh(heavy=True)

    def _preset_options(self) -> tuple[str, ...]:
        return (NO_PRESET, *(p.name for p in self.session.lesson.presets))

    def _readout_html(self) -> str:
        s = self.session
        state = "playing" if s.playing else "paused"
        units = {x.name: x.unit for x in s.lesson.series}
        values = []
        for name in s.lesson.readout:
            v = s.frame.scalars.get(name)
            if v is None:
                continue
            unit = f" {units.get(name, '')}" if units.get(name) else ""
            values.append(f"{html.escape(name)} = {v:.6g}{html.escape(unit)}")
        quantities = (
            f'<div class="al-readout-values" style="font-size:0.9em">{" &nbsp; ".join(values)}</div>'
            if values
            else ""
        )
        return (
            '<div class="al-readout" style="font-family:monospace;font-size:1.05em">'
            f"t = {s.frame.t:8.3f} s &nbsp; {_speed_label(s.speed)} &nbsp; {state}{quantities}</div>"
        )

    def _status_html(self) -> str:
        parts = []
        if self.session.notices:
            level, text = self.session.notices[-1]
            color = LEVEL_COLORS.get(level, "#333")
            parts.append(
                f'<div class="al-message al-{level}" style="color:{color};font-size:0.9em">{html.escape(text)}</div>'
            )
        if self.session.frame.message:
            parts.append(
                '<div class="al-frame-message" style="color:#8a5a00;font-size:0.9em">'
                f"{html.escape(self.session.frame.message)}</div>"
            )
        return "".join(parts) or '<div class="al-message"></div>'

    def _build_lesson_gui(self) -> None:
        """(Re)build everything that depends on the lesson: controls, plots, header."""
        gui = self.client.gui
        # The old folders are hidden now and removed a little later: the page applies the
        # property updates of a batch of messages after the batch's removals, so a chart
        # update that is already on its way must still find its chart.
        self._plots = []
        due = time.monotonic() + RETIRE_DELAY
        for f in self._lesson_folders:
            try:
                f.visible = False
            except Exception:
                pass
            self._retired.append((due, f))
        self._lesson_folders = []
        self._param_widgets = {}
        self._shown = {}
        lesson = self.session.lesson
        groups: dict[str, list[Param]] = {}
        for p in lesson.params:
            groups.setdefault(p.group, []).append(p)
        # the lesson's declared groups in their order; its mode selectors come first
        order = [g.name for g in lesson.groups]
        modes = [lesson.param(m) for m in lesson.modes]
        with self.tab_controls:
            if modes:
                folder = gui.add_folder("Mode")
                self._lesson_folders.append(folder)
                with folder:
                    for p in modes:
                        self._add_param_widget(p)
            for name in sorted(groups, key=order.index):
                params = [p for p in groups[name] if p.name not in lesson.modes]
                if not params:
                    continue
                group = lesson.group(name)
                folder = gui.add_folder(group.title, expand_by_default=group.expanded)
                self._lesson_folders.append(folder)
                with folder:
                    for p in params:
                        self._add_param_widget(p)
                    if lesson.start_point is not None and lesson.start_point[0] in {
                        p.name for p in params
                    }:
                        snap = gui.add_button("Snap to surface")
                        snap.on_click(self._guard(self._on_snap))
                        gui.add_html(
                            '<div style="font-size:0.8em;color:#555">'
                            "Click the surface to set the start point.</div>"
                        )
            vec_names = tuple(self.session.scene.moving_vectors)
            if vec_names:
                folder = gui.add_folder("Vectors")
                self._lesson_folders.append(folder)
                with folder:
                    visible = self._visible_vectors()
                    for name in vec_names:
                        cb = gui.add_checkbox(f"show {name}", initial_value=name in visible)
                        cb.on_update(
                            self._guard(lambda e, n=name: self._on_vector_toggle(n, e.target.value))
                        )
            folder = gui.add_folder("Playback")
            self._lesson_folders.append(folder)
            with folder:
                self.pause_cb = gui.add_checkbox(
                    "pause at t_end", initial_value=self.session.pause_at_end
                )
                self.pause_cb.on_update(self._guard(self._on_pause_at_end))
        self._plots = []
        with self.tab_plots:
            folder = gui.add_folder("Live plots (sliding window)")
            self._lesson_folders.append(folder)
            with folder:
                for spec in lesson.plots:
                    buf = PlotBuffer(spec, self.config.plot_window)
                    series = [{"label": "t"}] + [
                        {"label": name, "stroke": PLOT_COLORS[i % len(PLOT_COLORS)], "width": 1.5}
                        for i, name in enumerate(spec.series)
                    ]
                    units = spec.units or _units_of(lesson, spec.series)
                    title = spec.title + (f" [{units}]" if units else "")
                    handle = gui.add_uplot(
                        buf.data(),
                        tuple(series),
                        title=title,
                        scales={"x": {"time": False}, "y": {"auto": True}},
                        aspect=2.0,
                    )
                    buf.dirty = False
                    self._plots.append((buf, handle))
        # no data updates while the browser is still creating the charts (a busy browser
        # can take a while; an early update is reported as an update of a missing component)
        self._plots_fresh_until = time.monotonic() + 1.5
        esc = html.escape
        self.lesson_head.content = (
            f'<div style="font-size:0.95em"><b>{esc(lesson.problem)} · {esc(lesson.title)}</b><br>'
            f'<span style="color:#555">{esc(lesson.source)}</span><br>{esc(lesson.summary)}</div>'
        )
        self._drawn_lesson = lesson.id

    def _visible_vectors(self) -> set[str]:
        names = list(self.session.scene.moving_vectors)
        if self.session.visible_vectors is not None:
            return {n for n in names if n in self.session.visible_vectors}
        return set(names[:1])

    def _add_param_widget(self, p: Param) -> None:
        gui = self.client.gui
        label = p.label or p.name
        if p.unit:
            label = f"{label} [{p.unit}]"
        value = self.session.params[p.name]
        widgets: list[Any] = []
        hint = p.help or None
        if p.kind == "formula":
            if p.min is not None and p.max is not None:
                const = self._const_of(value, p)
                step = p.step or (p.max - p.min) / 200.0
                slider = gui.add_slider(
                    f"{p.name}",
                    min=float(p.min),
                    max=float(p.max),
                    step=float(step),
                    initial_value=const,
                    hint=hint,
                )
                slider.on_update(self._guard(lambda e, p=p: self._on_slider(p, e.target.value)))
                widgets.append(slider)
            text = gui.add_text(
                f"{label} =",
                initial_value=value.text if isinstance(value, Formula) else str(value),
                hint=hint,
            )
            text.on_update(self._guard(lambda e, p=p: self._on_text(p, e.target.value)))
            widgets.append(text)
        elif p.kind == "choice":
            dd = gui.add_dropdown(label, tuple(p.choices), initial_value=str(value), hint=hint)
            dd.on_update(self._guard(lambda e, p=p: self._on_value(p, e.target.value)))
            widgets.append(dd)
        elif p.kind == "bool":
            cb = gui.add_checkbox(label, initial_value=bool(value), hint=hint)
            cb.on_update(self._guard(lambda e, p=p: self._on_value(p, e.target.value)))
            widgets.append(cb)
        elif p.kind == "int" and p.min is not None and p.max is not None and p.max - p.min <= 100:
            sl = gui.add_slider(
                label, min=int(p.min), max=int(p.max), step=1, initial_value=int(value), hint=hint
            )
            sl.on_update(self._guard(lambda e, p=p: self._on_value(p, e.target.value)))
            widgets.append(sl)
        else:
            num = gui.add_number(
                label,
                initial_value=float(value) if p.kind == "float" else int(value),
                step=float(p.step) if p.step else None,
                hint=hint,
            )
            num.on_update(self._guard(lambda e, p=p: self._on_value(p, e.target.value)))
            widgets.append(num)
        self._param_widgets[p.name] = widgets

    @staticmethod
    def _const_of(value: Any, p: Param) -> float:
        """Slider position for a formula value: its constant, else the range's midpoint."""
        lo, hi = float(p.min), float(p.max)
        if isinstance(value, Formula):
            if value.is_constant:
                try:
                    v = float(value.value(0.0))
                except Exception:
                    v = math.nan
            else:
                v = math.nan
        else:
            v = float(value)
        if not math.isfinite(v):
            v = min(max(0.0, lo), hi)
        return min(max(v, lo), hi)

    def _put(self, widget: Any, value: Any, force: bool) -> None:
        """Show ``value`` in ``widget`` when the session's value changed since this view
        last showed it (or when forced, or when it is the widget being handled).  A
        value the user has just set in another widget, whose callback has not run yet,
        is not overwritten with the session's old value."""
        key = id(widget)
        if force or widget is self._current_target or self._shown.get(key, _UNSHOWN) != value:
            if widget.value != value:
                widget.value = value
        self._shown[key] = value

    def _sync_widgets(self, force: bool = False) -> None:
        """Show the session's values in the widgets (programmatic: callbacks ignore it).

        ``force``: every widget, also those whose session value did not change."""
        s = self.session
        try:
            self._put(self.lesson_dd, self._ids[s.lesson.id], force)
            opts = self._preset_options()
            if tuple(self.preset_dd.options) != opts:
                self.preset_dd.options = opts
            self._put(self.preset_dd, s.preset or NO_PRESET, force)
            self._put(self.speed_dd, _speed_label(s.speed), force)
            if hasattr(self, "pause_cb"):
                self._put(self.pause_cb, bool(s.pause_at_end), force)
        except Exception:
            traceback.print_exc()
        for name, widgets in self._param_widgets.items():
            if name not in s.params:
                continue
            p = s.lesson.param(name)
            value = s.params[name]
            for w in widgets:
                try:
                    if p.kind == "formula":
                        if hasattr(w, "min") and hasattr(w, "max") and not hasattr(w, "multiline"):
                            if isinstance(value, Formula) and value.is_constant:
                                self._put(w, self._const_of(value, p), force)
                        else:
                            self._put(
                                w, value.text if isinstance(value, Formula) else str(value), force
                            )
                    elif p.kind == "bool":
                        self._put(w, bool(value), force)
                    elif p.kind == "choice":
                        self._put(w, str(value), force)
                    else:
                        self._put(w, int(value) if p.kind == "int" else float(value), force)
                except Exception:
                    traceback.print_exc()

    # ------------------------------------------------------------------ callbacks

    def _on_lesson(self, event: Any) -> None:
        lesson_id = self._labels.get(event.target.value)
        if lesson_id is None:
            raise LabError(f"unknown lesson {str(event.target.value)[:60]!r}")
        if lesson_id == self.session.lesson.id:
            return
        self.session.select_lesson(lesson_id)
        self.session.notify(f"lesson: {lesson_label(self.session.lesson)}")
        self._after_state_change()

    def _on_preset(self, event: Any) -> None:
        name = event.target.value
        if name == NO_PRESET:
            self.session.apply_preset(None)
        else:
            if name not in {p.name for p in self.session.lesson.presets}:
                raise LabError(f"unknown preset {str(name)[:60]!r}")
            self.session.apply_preset(name)
            self.session.notify(f"preset {name}: {self.session.lesson.preset(name).title}")
        self._after_state_change()

    def _on_transport(self, event: Any) -> None:
        what = event.target.value
        s = self.session
        if what == "Play":
            s.play()
        elif what == "Pause":
            s.pause()
        elif what == "Step":
            frames = s.step()
            self._push_frames(frames)
        elif what == "Reset":
            s.pause()
            s.reset()
        else:
            raise LabError(f"unknown transport command {str(what)[:40]!r}")
        self._frame_dirty = True

    def _on_speed(self, event: Any) -> None:
        text = str(event.target.value)
        if not text.endswith("x"):
            raise LabError(f"unknown speed {text[:20]!r}")
        self.session.set_speed(text[:-1])
        self._save_state()

    def _on_pause_at_end(self, event: Any) -> None:
        self.session.pause_at_end = bool(event.target.value)
        self._save_state()

    def _on_vector_toggle(self, name: str, value: Any) -> None:
        visible = self._visible_vectors()
        if value:
            visible.add(name)
        else:
            visible.discard(name)
        self.session.visible_vectors = visible
        self._vector_names = ()  # re-create the arrows node
        self._visible_cache = None
        self._frame_dirty = True
        self._save_state()

    def _on_slider(self, p: Param, value: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParamError(p.name, f"expected a number, got {type(value).__name__}")
        v = float(value)
        if not math.isfinite(v):
            raise ParamError(p.name, f"must be a finite number, got {v}")
        if v < float(p.min) or v > float(p.max):
            raise ParamError(p.name, f"{v:g} is outside the slider range [{p.min:g}, {p.max:g}]")
        v = round(v, 9)
        self.session.set_value(p.name, repr(v) if not v.is_integer() else str(int(v)))
        self._param_changed()

    def _on_text(self, p: Param, value: Any) -> None:
        if not isinstance(value, str):
            raise ParamError(p.name, "expected text")
        self.session.set_value(p.name, value)
        self._param_changed()

    def _on_value(self, p: Param, value: Any) -> None:
        self.session.set_value(p.name, value)
        self._param_changed()

    def _on_snap(self, event: Any) -> None:
        pt = self.session.snap_start()
        if pt is not None:
            self.session.notify(
                "start point snapped to the surface: (" + ", ".join(f"{v:.6g}" for v in pt) + ")"
            )
        self._param_changed()

    def _on_surface_click(self, event: Any) -> None:
        if self.closed:
            return
        if self.gate is not None and not self.gate(self, event, None):  # classroom hook
            return
        with self.session.lock:
            try:
                hit = None
                for vertices, faces in self._meshes_for_click:
                    h = ray_mesh_hit(
                        np.asarray(event.ray_origin),
                        np.asarray(event.ray_direction),
                        vertices,
                        faces,
                    )
                    if h is not None and (
                        hit is None
                        or np.linalg.norm(h - np.asarray(event.ray_origin))
                        < np.linalg.norm(hit - np.asarray(event.ray_origin))
                    ):
                        hit = h
                if hit is None:
                    raise LabError("the click did not hit the surface")
                self.session.set_start(hit)
                self.session.notify(
                    "start point set by click: (" + ", ".join(f"{v:.4g}" for v in hit) + ")"
                )
                self._param_changed()
            except (ParamError, LabError) as exc:
                self.session.notify(f"refused: {exc}", "error")
            except Exception as exc:
                traceback.print_exc()
                self.session.notify(f"internal error: {exc}", "error")
            self.refresh(heavy=True)

    def _param_changed(self) -> None:
        self._sync_widgets()
        self._frame_dirty = True
        self.derivation_due = time.monotonic() + 0.4
        self._save_state()

    def _after_state_change(self) -> None:
        self._sync_widgets()
        self._frame_dirty = True
        self.derivation_due = time.monotonic()
        self._save_state()

    # ------------------------------------------------------------------ state persistence

    def _save_state(self) -> None:
        try:
            self.client.local_storage.set_item(STORAGE_KEY, self.session.state().to_json())
        except Exception:
            pass
        if self.on_state is not None:
            self.on_state(self)

    def restore_saved_state(self, timeout: float = 3.0) -> bool:
        """Ask the browser for the state saved by this page before a reload; apply it."""
        try:
            text = self.client.local_storage.get_item(STORAGE_KEY, timeout=timeout)
        except Exception:
            return False
        if not text:
            return False
        with self.session.lock:
            try:
                state = SessionState.from_json(text)
                self.session.apply_state(state)
                self.session.notify(
                    f"restored your last lesson: {lesson_label(self.session.lesson)}"
                )
            except (LabError, ParamError) as exc:
                self.session.notify(f"saved state ignored: {exc}", "warning")
                return False
            self._after_state_change()
            self.refresh(heavy=True)
        return True

    def apply_state(self, state: SessionState) -> None:
        """Take a state from elsewhere (e.g. a classroom mode) and show it."""
        with self.session.lock:
            self.session.apply_state(state)
            self._after_state_change()
            self.refresh(heavy=True)

    # ------------------------------------------------------------------ scene

    def _clear_static(self) -> None:
        for h in self._static_handles:
            try:
                h.remove()
            except Exception:
                pass
        self._static_handles = []
        self._meshes_for_click = []

    def _draw_static(self, frame_camera: bool) -> None:
        scene_api = self.client.scene
        spec = self.session.scene
        self._clear_static()
        lo, hi, size = _bounds_info(spec)
        self._size = size
        center = (lo + hi) / 2
        add = self._static_handles.append
        grid_z = lo[2] if not spec.planar else 0.0
        add(
            scene_api.add_grid(
                "/lab/grid",
                width=float(hi[0] - lo[0]) * 1.4 + 1e-9,
                height=float(hi[1] - lo[1]) * 1.4 + 1e-9,
                cell_size=_nice(size / 10),
                section_size=_nice(size / 2),
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
        for m in spec.meshes:
            v = np.asarray(m.vertices, dtype=np.float32)
            f = np.asarray(m.faces, dtype=np.uint32)
            if len(v) == 0 or len(f) == 0:
                continue
            h = scene_api.add_mesh_simple(
                f"/lab/static/mesh/{_safe(m.name)}",
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
            h.on_click(self._on_surface_click)
            self._meshes_for_click.append((v, f))
            add(h)
        for c in spec.curves:
            pts = np.asarray(c.points, dtype=np.float32).reshape(-1, 3)
            if len(pts) < 2:
                continue
            segs = np.stack([pts[:-1], pts[1:]], axis=1)
            add(
                scene_api.add_line_segments(
                    f"/lab/static/curve/{_safe(c.name)}",
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
                    f"/lab/static/marker/{_safe(mk.name)}",
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
                        f"/lab/static/marker_label/{_safe(mk.name)}",
                        mk.label,
                        position=tuple(map(float, pts[0])),
                    )
                )
        # moving items: fresh nodes for this scene
        for h in self._point_handles.values():
            _remove(h)
        self._point_handles = {}
        for b in self._body_handles.values():
            _remove(b)
        self._body_handles = {}
        for body in spec.bodies:
            self._body_handles[body.name] = scene_api.add_mesh_simple(
                f"/lab/live/body/{_safe(body.name)}",
                np.asarray(body.vertices, dtype=np.float32),
                np.asarray(body.faces, dtype=np.uint32),
                color=tuple(body.color),
                opacity=float(body.opacity),
                cast_shadow=False,
                receive_shadow=False,
            )
        if self._vector_handle is not None:
            _remove(self._vector_handle)
            self._vector_handle = None
            self._vector_names = ()
        self._visible_cache = None
        for name in list(self._trails):
            if name not in spec.moving_points:
                self._trails.pop(name).clear()
        if frame_camera:
            self._frame_camera(lo, hi, size)

    def _frame_camera(self, lo: np.ndarray, hi: np.ndarray, size: float) -> None:
        center = (lo + hi) / 2
        direction = np.array([1.0, 0.75, 0.6])
        direction /= np.linalg.norm(direction)
        dist = 1.05 * float(np.linalg.norm(hi - lo)) + 1e-6
        try:
            cam = self.client.camera
            # clipping planes to the scene's size (a machine in millimetres, a unit sphere)
            cam.far = max(100.0, 20.0 * dist)
            cam.near = max(1e-4, 1e-4 * dist)
            cam.up_direction = (0.0, 0.0, 1.0)
            # viser moves look_at along with position: set the position first
            cam.position = tuple(map(float, center + direction * dist))
            cam.look_at = tuple(map(float, center))
        except Exception:
            traceback.print_exc()

    def _reset_live(self) -> None:
        for t in self._trails.values():
            t.clear()
        for buf, _ in self._plots:
            buf.clear()
        self._vector_scale = {}

    def _push_frames(self, frames: list[Frame]) -> None:
        """Draw a batch of frames (the last one fully; all of them into the trails)."""
        if not frames:
            return
        spec = self.session.scene
        scene_api = self.client.scene
        cfg = self.config
        for fr in frames:
            for name, color in spec.moving_points.items():
                if name in fr.points:
                    tr = self._trails.get(name)
                    if tr is None:
                        tr = self._trails[name] = Trail(
                            scene_api,
                            f"/lab/live/trail/{_safe(name)}",
                            tuple(color),
                            cfg.trail_chunk,
                            cfg.trail_max_points,
                        )
                    by = spec.trail_color_by.get(name)
                    tr.color_by = (float(by[1]), float(by[2])) if by else None
                    tr.add(fr.points[name], fr.scalars.get(by[0]) if by else None)
        last = frames[-1]
        for name, color in spec.moving_points.items():
            pts = last.points.get(name)
            if pts is None:
                continue
            pts = np.asarray(pts, dtype=np.float32).reshape(-1, 3)
            h = self._point_handles.get(name)
            if h is None or h.points.shape != pts.shape:
                if h is not None:
                    _remove(h)
                self._point_handles[name] = scene_api.add_point_cloud(
                    f"/lab/live/point/{_safe(name)}",
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
                h.position = tuple(map(float, pos))
                h.wxyz = tuple(map(float, wxyz))
        if self.frame_count % cfg.trail_every == 0 or len(frames) > 1 or not self.session.playing:
            for tr in self._trails.values():
                tr.flush()

    def _draw_vectors(self, frame: Frame) -> None:
        spec = self.session.scene
        shown = self._visible_cache
        if shown is None:
            shown = self._visible_cache = self._visible_vectors()
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
                _remove(self._vector_handle)
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
                _remove(self._vector_handle)
            r = 0.006 * self._size
            self._vector_handle = self.client.scene.add_arrows(
                "/lab/live/vectors",
                pts,
                np.asarray(colors, dtype=np.uint8),
                shaft_radius=r,
                head_radius=2.5 * r,
                head_length=6 * r,
            )
            self._vector_names = names
        else:
            fast_set(self._vector_handle, "points", pts)

    def _send_plots(self, all_plots: bool = False) -> None:
        if not self._plots:
            return
        if time.monotonic() < self._plots_fresh_until:
            return
        if all_plots:
            for buf, handle in self._plots:
                if buf.dirty:
                    fast_set(handle, "data", buf.data())
                    buf.dirty = False
            return
        for _ in range(len(self._plots)):
            self._plot_rr = (self._plot_rr + 1) % len(self._plots)
            buf, handle = self._plots[self._plot_rr]
            if buf.dirty:
                fast_set(handle, "data", buf.data())
                buf.dirty = False
                return

    # ------------------------------------------------------------------ per frame

    def refresh(self, heavy: bool = False) -> None:
        """Bring GUI and scene in line with the session (caller holds the session lock).

        ``heavy``: also rebuild lesson-dependent GUI (from GUI callbacks, not the loop).
        """
        s = self.session
        if self.closed:
            return
        if heavy and self._drawn_lesson != s.lesson.id:
            self._build_lesson_gui()
            self._sync_widgets()
            self.derivation_due = time.monotonic()
            new_lesson = True
        else:
            new_lesson = False
        if self._drawn_scene_rev != s.scene_revision:
            self._draw_static(frame_camera=new_lesson or self._drawn_scene_rev < 0)
            self._drawn_scene_rev = s.scene_revision
            self._frame_dirty = True
        if self._drawn_reset_rev != s.reset_revision:
            self._reset_live()
            self._drawn_reset_rev = s.reset_revision
            self._frame_dirty = True
        if heavy:
            note = ""
            if s.preset:
                try:
                    pr = s.lesson.preset(s.preset)
                    note = f"<b>{html.escape(pr.title)}</b>" + (
                        f"<br>{html.escape(pr.note)}" if pr.note else ""
                    )
                except ParamError:
                    note = ""
            content = f'<div class="al-preset-note" style="font-size:0.85em">{note}</div>'
            if self.preset_note.content != content:
                self.preset_note.content = content
        if self._frame_dirty:
            self._frame_dirty = False
            self._push_frames([s.frame])
            for buf, _ in self._plots:
                if not buf.t or buf.t[-1] != s.frame.t:
                    buf.add(s.frame)
            self._send_plots(all_plots=True)
        self._update_texts()

    def render_derivation(self) -> None:
        """The derivation with the current parameters, as MathML (caller holds the lock;
        the server renders it off the lock and calls :meth:`set_derivation`)."""
        s = self.session
        self.derivation_due = None
        try:
            content = derivation_to_html(s.lesson.derivation(s.params))
        except Exception as exc:
            content = f'<div class="al-error">The derivation could not be built: {html.escape(str(exc))}</div>'
        self.set_derivation(content)

    def set_derivation(self, content: str) -> None:
        if self.derivation_html.content != content:
            self.derivation_html.content = content

    def _update_texts(self) -> None:
        ro = self._readout_html()
        if ro != self._last_readout:
            fast_set(self.readout, "content", ro)
            self._last_readout = ro
        notice = self.session.notices[-1] if self.session.notices else None
        fmsg = self.session.frame.message
        if notice != self._shown_notice or fmsg != self._shown_frame_message:
            if (
                notice is not None
                and notice != self._shown_notice
                and notice[0] in ("warning", "error")
            ):
                try:
                    self.client.add_notification(
                        "Analyzer Lab",
                        notice[1],
                        auto_close_seconds=6.0,
                        color="red" if notice[0] == "error" else "yellow",
                    )
                except Exception:
                    pass
            self._shown_notice = notice
            self._shown_frame_message = fmsg
            self.status.content = self._status_html()

    def tick(self, wall_dt: float, atomic: bool = True) -> None:
        """One frame of the server loop (caller holds the session lock).

        ``atomic=False``: the caller groups the messages (and wakes the event loop once
        for all sessions, see :class:`app.server.LabServer`)."""
        if self.closed:
            return
        if self._retired and time.monotonic() >= self._retired[0][0]:
            self._remove_retired()
        s = self.session
        was_playing = s.playing
        t0 = time.perf_counter()
        frames = s.tick(wall_dt) if s.playing else []
        self.step_seconds += time.perf_counter() - t0
        self.frame_count += 1
        cfg = self.config
        if (
            not frames
            and not self._frame_dirty
            and s.scene_revision == self._drawn_scene_rev
            and s.reset_revision == self._drawn_reset_rev
        ):
            if was_playing != s.playing or self.frame_count % cfg.readout_every == 0:
                self._update_texts()
            return
        t1 = time.perf_counter()
        with self.client.atomic() if atomic else contextlib.nullcontext():
            if (
                s.scene_revision != self._drawn_scene_rev
                or s.reset_revision != self._drawn_reset_rev
                or self._frame_dirty
            ):
                self.refresh()
            if frames:
                self._push_frames(frames)
                if self.frame_count % cfg.plot_every == 0 or not s.playing:
                    for buf, _ in self._plots:
                        buf.add(frames[-1])
                if self.frame_count % cfg.plot_send_every == 0 or not s.playing:
                    self._send_plots(all_plots=not s.playing)
            if self.frame_count % cfg.readout_every == 0 or not s.playing:
                self._update_texts()
        self.draw_seconds += time.perf_counter() - t1

    def _remove_retired(self) -> None:
        """Remove the hidden folders whose delay has passed."""
        now = time.monotonic()
        while self._retired and now >= self._retired[0][0]:
            _, folder = self._retired.pop(0)
            try:
                folder.remove()
            except Exception:
                pass

    def close(self) -> None:
        self.closed = True
        self._retired = []

    # ------------------------------------------------------------------ export

    def export(self, kind: str) -> None:
        """Send the run as a CSV/JSON download or the scene as an HTML replay."""
        import json

        s = self.session
        stem = f"analyzer-lab-{s.lesson.id}" + (f"-{s.preset}" if s.preset else "")
        if kind == "csv":
            data = s.run_result().to_csv().encode()
            name = stem + ".csv"
        elif kind == "json":
            data = json.dumps(s.run_result().to_json_dict(), indent=1).encode()
            name = stem + ".json"
        elif kind == "html":
            from app.replay import replay_html

            data = replay_html(s).encode()
            name = stem + "-replay.html"
        else:
            raise LabError(f"unknown export {kind[:20]!r}")
        self.client.send_file_download(name, data, save_immediately=True)
        s.notify(f"exported {name} ({len(data) / 1024:.1f} kB, {len(s.log)} samples)")


def fast_set(handle: Any, name: str, value: Any) -> None:
    """Assign one property of a viser handle on the hot path: the value is already of
    the right type and dtype (fresh array), so viser's generic casting and comparison
    (``props_setattr``) are skipped; state and wire message are the same."""
    impl = handle._impl
    if impl.removed:
        return
    setattr(impl.props, name, value)
    handle._queue_update(name, value)


def _remove(handle: Any) -> None:
    try:
        handle.remove()
    except Exception:
        pass


def _safe(name: str) -> str:
    return "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in str(name))[:60] or "item"


def _nice(x: float) -> float:
    """A round number near ``x`` (1, 2, 5 times a power of ten)."""
    if not math.isfinite(x) or x <= 0:
        return 1.0
    e = math.floor(math.log10(x))
    m = x / 10**e
    m = 1 if m < 1.5 else 2 if m < 3.5 else 5 if m < 7.5 else 10
    return m * 10**e


__all__ = ["SessionView", "ViewConfig", "Trail", "ray_mesh_hit", "STORAGE_KEY"]
