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

import html
import re
from typing import TYPE_CHECKING, Any

import numpy as np
from analyzer_lab.i18n import ENGLISH, N_, Language
from analyzer_lab.lessons.kit.contract import SceneSpec
from analyzer_lab.limits import Pacer
from analyzer_lab.session.runlog import LogSample
from analyzer_lab.session.session import Session
from analyzer_lab.view.scene import nice_step, node_name, scene_bounds
from analyzer_lab.viser_boundary import recording_scene

if TYPE_CHECKING:
    import viser

#: Frames per second of the replay animation and its longest duration.
REPLAY_FPS = 20.0
MAX_REPLAY_FRAMES = 1200
#: Trail points in a replay at most (frames x curves of a family); decimated past it.
MAX_REPLAY_POINTS = 60_000
#: Samples appended to the trail as one new chunk.
TRAIL_CHUNK = 20
#: Points per line of the caption's static charts.
PLOT_POINTS = 400
#: The replay's heading (``lesson``: the lesson's problem and title).
REPLAY_TITLE = N_("Analyzer Lab replay: {lesson}")
#: The caption's texts (translated where they are shown).
CAPTION_TEXTS = (N_("preset: {name}"), N_("(defaults)"), N_("(from {low} to {high})"))


def replay_html(session: Session, language: Language = ENGLISH) -> str:
    """The session's scene and recorded run as one self-contained HTML page: titled
    with the lesson, a caption with its values and plots, the time shown in the scene
    (its heading and captions in ``language``; the run's data as recorded).
    At most :data:`MAX_REPLAY_FRAMES` frames and :data:`MAX_REPLAY_POINTS` trail points
    (decimated; the caption says so)."""
    scene_api, ser = recording_scene()
    spec = session.scene
    lo, hi, size = scene_bounds(spec)
    _static(scene_api, spec, lo, hi, size)
    log = session.log
    count = len(log)
    notes: list[str] = []
    if count:
        first = log.sample(0)
        members = max(
            (len(np.asarray(first.points[n]).reshape(-1, 3)) for n in first.points), default=1
        )
        budget = max(50, MAX_REPLAY_POINTS // max(1, members * max(1, len(spec.moving_points))))
        frames = min(MAX_REPLAY_FRAMES, budget)
        stride = max(1, int(np.ceil(count / frames)))
        chosen = list(range(0, count, stride))
        if chosen[-1] != count - 1:
            chosen.append(count - 1)
        if stride > 1:
            notes.append(
                language.ngettext(
                    "every {stride}th of {count} recorded frame shown",
                    "every {stride}th of {count} recorded frames shown",
                    count,
                ).format(stride=stride, count=count)
            )
        # only the chosen rows are built (not all of a long run's rows)
        pace = Pacer()
        rows = []
        for k in chosen:
            rows.append(log.sample(k))
            pace()
        _animate(scene_api, ser, session, spec, rows, size, hi, language)
    page = ser.as_html()
    return _dress(page, session, notes, language)


def _static(
    scene_api: viser.SceneApi, spec: SceneSpec, lo: np.ndarray, hi: np.ndarray, size: float
) -> None:
    center = (lo + hi) / 2
    scene_api.add_grid(
        "/lab/grid",
        width=float(hi[0] - lo[0]) * 1.4 + 1e-9,
        height=float(hi[1] - lo[1]) * 1.4 + 1e-9,
        cell_size=nice_step(size / 10),
        section_size=nice_step(size / 2),
        position=(float(center[0]), float(center[1]), float(lo[2] if not spec.planar else 0.0)),
        shadow_opacity=0.0,
    )
    scene_api.add_frame(
        "/lab/axes", axes_length=0.35 * size, axes_radius=0.006 * size, origin_radius=0.012 * size
    )
    for m in spec.meshes:
        if len(m.vertices) and len(m.faces):
            scene_api.add_mesh_simple(
                f"/lab/static/mesh/{node_name(m.name)}",
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
                f"/lab/static/curve/{node_name(c.name)}",
                np.stack([pts[:-1], pts[1:]], 1),
                tuple(c.color),
                thickness=float(c.width),
                thickness_units="screen",
            )
    for mk in spec.markers:
        scene_api.add_point_cloud(
            f"/lab/static/marker/{node_name(mk.name)}",
            np.asarray(mk.points, np.float32).reshape(-1, 3),
            tuple(mk.color),
            point_size=float(mk.size) * 1.2,
            point_shape="diamond",
            precision="float32",
        )


def _animate(
    scene_api: viser.SceneApi,
    ser: Any,
    session: Session,
    spec: SceneSpec,
    chosen: list[LogSample],
    size: float,
    hi: np.ndarray,
    language: Language = ENGLISH,
) -> None:
    """The moving points over the chosen samples, their trails as chunks that are only
    appended (linear in the run's length), and the time as a label."""
    second = language.unit("s")
    clock = scene_api.add_label(
        "/lab/time", f"t = {language.number(chosen[0].t, '.3f')} {second}", position=tuple(hi)
    )
    handles: dict[str, Any] = {}
    last: dict[str, np.ndarray] = {}
    pending: dict[str, list[np.ndarray]] = {}
    t_prev = chosen[0].t
    pace = Pacer()
    for k, s in enumerate(chosen):
        pace()
        for name, color in spec.moving_points.items():
            if name not in s.points:
                continue
            pts = np.asarray(s.points[name], np.float32).reshape(-1, 3)
            h = handles.get(name)
            if h is None or h.points.shape != pts.shape:
                handles[name] = scene_api.add_point_cloud(
                    f"/lab/live/point/{node_name(name)}",
                    pts,
                    tuple(color),
                    point_size=0.045 * size,
                    point_shape="circle",
                    precision="float32",
                )
                last[name], pending[name] = pts, []
                continue
            h.points = pts
            pending[name].append(np.stack([last[name], pts], axis=1))  # (members, 2, 3)
            last[name] = pts
            if len(pending[name]) >= TRAIL_CHUNK or k == len(chosen) - 1:
                segs = np.concatenate(pending[name], axis=0)
                scene_api.add_line_segments(
                    f"/lab/live/trail/{node_name(name)}/{k}",
                    segs,
                    tuple(color),
                    thickness=2.5,
                    thickness_units="screen",
                )
                pending[name] = []
        clock.text = f"t = {language.number(s.t, '.3f')} {second}"
        dt = (s.t - t_prev) / max(session.speed * session.lesson.time_scale, 1e-12)
        ser.insert_sleep(min(max(dt, 0.0), 4.0 / REPLAY_FPS) if k else 0.0)
        t_prev = s.t


def _dress(page: str, session: Session, notes: list[str], language: Language = ENGLISH) -> str:
    """The page titled with the lesson, with a caption: values, time span, plots (in
    ``language``, the page's ``lang`` too)."""
    esc = html.escape
    tr, text = language.gettext, language.lesson_text
    lesson = session.lesson
    name = f"{text(lesson.problem)} {text(lesson.title)}".strip()
    title = tr(REPLAY_TITLE).format(lesson=name).strip()
    page = re.sub(r"<title>.*?</title>", f"<title>{esc(title)}</title>", page, count=1)
    page = re.sub(r"<html lang=\"[^\"]*\"", f'<html lang="{language.code}"', page, count=1)
    values = "".join(
        f"<tr><td>{esc(k)}</td><td>{esc(str(v))}</td></tr>" for k, v in session.raw_values().items()
    )
    t = session.log.t
    second = language.unit("s")
    span = (
        f"t = {language.number(t[0], 'g')} ... {language.number(t[-1], 'g')} {second}"
        if len(t)
        else ""
    )
    result = session.run_result()
    units = result.units
    plots = "".join(
        _svg_plot(
            text(spec.title),
            result.t,
            {n: result.series[n] for n in spec.series if n in result.series},
            units,
            language,
        )
        for spec in lesson.plots
    )
    caption = (
        '<div id="al-caption" style="position:fixed;left:8px;top:8px;z-index:10;max-width:360px;'
        "max-height:95vh;overflow:auto;background:rgba(255,255,255,0.92);padding:8px;"
        'font:13px sans-serif;border-radius:6px">'
        f"<b>{esc(title)}</b><br>{esc(text(lesson.source))}<br>"
        f"{esc(tr('preset: {name}').format(name=session.preset or tr('(defaults)')))}"
        f" &middot; {esc(span)}"
        + "".join(f"<br><i>{esc(n)}</i>" for n in notes)
        + f'<table style="font-size:12px">{values}</table>{plots}</div>'
    )
    return page.replace("<body>", "<body>" + caption, 1) if "<body>" in page else caption + page


def _svg_plot(
    title: str,
    t: np.ndarray,
    series: dict[str, np.ndarray],
    units: dict[str, str],
    language: Language = ENGLISH,
) -> str:
    """A small static chart of the run (SVG), at most :data:`PLOT_POINTS` points a line."""
    if len(t) < 2 or not series:
        return ""
    w, h, pad = 340.0, 120.0, 4.0
    step = max(1, len(t) // PLOT_POINTS)
    tt = np.asarray(t, dtype=float)[::step]
    ys = {n: np.asarray(v, dtype=float)[::step] for n, v in series.items()}
    finite = np.concatenate([v[np.isfinite(v)] for v in ys.values()] + [np.zeros(1)])
    lo, hi = float(finite.min()), float(finite.max())
    hi = hi if hi > lo else lo + 1.0
    colors = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf")
    lines = []
    for k, (name, v) in enumerate(ys.items()):
        ok = np.isfinite(v)
        px = pad + (tt[ok] - tt[0]) / max(tt[-1] - tt[0], 1e-300) * (w - 2 * pad)
        py = h - pad - (v[ok] - lo) / (hi - lo) * (h - 2 * pad)
        pts = " ".join(f"{a:.1f},{b:.1f}" for a, b in zip(px, py))
        lines.append(
            f'<polyline fill="none" stroke="{colors[k % len(colors)]}" stroke-width="1.2" '
            f'points="{pts}"/>'
        )
    unit = {units.get(n, "") for n in series}
    label = f" [{language.unit(unit.pop())}]" if len(unit) == 1 and "" not in unit else ""
    names = ", ".join(series)
    span = language.gettext("(from {low} to {high})").format(
        low=language.number(lo, ".4g"), high=language.number(hi, ".4g")
    )
    return (
        f'<div style="margin-top:6px"><b>{html.escape(title)}</b>{html.escape(label)}: '
        f"{html.escape(names)} {html.escape(span)}</div>"
        f'<svg width="{w:.0f}" height="{h:.0f}" style="background:#fafafa">{"".join(lines)}</svg>'
    )


__all__ = ["replay_html"]
