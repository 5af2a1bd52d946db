"""The layout checks of a page at a screen size (shared by the browser tests of the
layout in every language): the panel leaves the canvas free, the scene's box (and the
run's) is framed inside it and covers 15-85 % of its shorter side, nothing of the panel runs
over, no text below 11 px or 4.5:1 contrast, the lab's texts indented as viser's labels."""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
from analyzer_lab.view.extents import frame_points, preset_extent

from tests.support.browser import DISMISS_JS, Page, quat_matrix
from tests.support.waiting import wait_until

SIZES = {
    "phone": (390, 844),
    "tablet": (820, 1180),
    "laptop": (1400, 900),
    "projector": (1280, 720),
    "hd": (1920, 1080),
}
#: The scene's projected box covers this share of the free canvas's shorter side.
COVER = (0.15, 0.85)
#: Smallest text of the panel (CSS px).
MIN_TEXT_PX = 11.0
#: Play this long (wall seconds) at this speed; on the phone, go to the time it leads to.
PLAY_SECONDS, PLAY_SPEED = 5.0, "8x"
SHOTS = Path(os.environ.get("LAYOUT_SHOTS", "/tmp/layout-shots"))

#: The canvas's rectangle, and what of the page outside the canvas runs past the screen,
#: past a clipping box (content cut off), or into the canvas; the smallest panel texts.
GEOMETRY_JS = """(minText) => {
  const parse = (c) => {
    const m = c.match(/rgba?\\(([^)]+)\\)/);
    if (!m) return null;
    const p = m[1].split(/[ ,\\/]+/).filter(Boolean).map(Number);
    return {r: p[0], g: p[1], b: p[2], a: p.length > 3 ? p[3] : 1};
  };
  const blend = (top, bottom) => ({r: top.r * top.a + bottom.r * (1 - top.a),
      g: top.g * top.a + bottom.g * (1 - top.a), b: top.b * top.a + bottom.b * (1 - top.a), a: 1});
  const lum = (c) => {
    const f = (v) => { v /= 255; return v <= 0.03928 ? v / 12.92 : Math.pow((v + 0.055) / 1.055, 2.4); };
    return 0.2126 * f(c.r) + 0.7152 * f(c.g) + 0.0722 * f(c.b);
  };
  const contrast = (el, cs) => {  // the text's colour against what lies under it
    const layers = [];
    for (let a = el; a; a = a.parentElement) {
      const c = parse(getComputedStyle(a).backgroundColor);
      if (c && c.a > 0) { layers.push(c); if (c.a >= 1) break; }
    }
    let bg = {r: 255, g: 255, b: 255, a: 1};
    for (let i = layers.length - 1; i >= 0; i--) bg = blend(layers[i], bg);
    const fg = parse(cs.color);
    if (!fg) return 21;
    const L1 = lum(blend(fg, bg)), L2 = lum(bg);
    return (Math.max(L1, L2) + 0.05) / (Math.min(L1, L2) + 0.05);
  };
  const low = [];
  const canvas = document.querySelector('canvas');
  const c = canvas.getBoundingClientRect();
  const scene = canvas.parentElement.parentElement;  // the canvas and its 3D labels
  const W = window.innerWidth, H = window.innerHeight;
  const over = [], small = [];
  const name = (el) => el.tagName.toLowerCase() + (typeof el.className === 'string' && el.className
      ? '.' + el.className.split(' ')[0] : '') + ' "' + (el.textContent || '').trim().slice(0, 30) + '"';
  const scrollsByDesign = (el) => {
    for (let a = el.parentElement; a; a = a.parentElement) {
      if (typeof a.className === 'string' && /(^|\\s)al-/.test(a.className)) {
        const o = getComputedStyle(a).overflowX;
        if (o === 'auto' || o === 'scroll') return true;
      }
    }
    return false;
  };
  for (const el of document.body.querySelectorAll('*')) {
    if (scene.contains(el)) continue;
    if (el.closest('.mantine-Notifications-root')) continue;  // toasts slide in and out
    const cs = getComputedStyle(el);
    if (cs.display === 'none' || cs.visibility === 'hidden') continue;
    if (el.offsetParent === null && cs.position !== 'fixed') continue;
    const r = el.getBoundingClientRect();
    if (r.width < 1 || r.height < 1) continue;
    let clip = null;  // what of the page the boxes that clip this element leave visible
    for (let a = el.parentElement; a && a !== document.body; a = a.parentElement) {
      if (getComputedStyle(a).overflowX === 'visible') continue;
      const b = a.getBoundingClientRect();
      clip = clip === null ? {left: b.left, right: b.right, top: b.top, bottom: b.bottom} : {
        left: Math.max(clip.left, b.left), right: Math.min(clip.right, b.right),
        top: Math.max(clip.top, b.top), bottom: Math.min(clip.bottom, b.bottom)};
    }
    if (clip && (r.bottom <= clip.top || r.top >= clip.bottom)) continue;  // scrolled out of sight
    if (!scrollsByDesign(el)) {
      if (r.left < -1 || r.right > W + 1) over.push(name(el) + ' runs past the screen: '
          + Math.round(r.left) + '..' + Math.round(r.right) + ' of ' + W);
      else if (clip && (r.left < clip.left - 1 || r.right > clip.right + 1)) over.push(name(el)
          + ' is cut off: ' + Math.round(r.left) + '..' + Math.round(r.right) + ' in '
          + Math.round(clip.left) + '..' + Math.round(clip.right));
    }
    const ix = Math.min(r.right, c.right) - Math.max(r.left, c.left);
    const iy = Math.min(r.bottom, c.bottom) - Math.max(r.top, c.top);
    if (ix > 1 && iy > 1 && cs.position !== 'fixed' && !el.contains(canvas)
        && !el.closest('.mantine-Notification-root, .mantine-Notifications-root')) {
      over.push(name(el) + ' lies over the canvas');
    }
    if (el.closest('math')) continue;  // formulas: their sizes are the derivations' own test
    let px = parseFloat(cs.fontSize);
    if (el.ownerSVGElement && el.getScreenCTM) {  // a figure's text, as the figure is scaled
      const m = el.getScreenCTM();
      if (m) px *= Math.sqrt(Math.abs(m.a * m.d - m.b * m.c));
    }
    for (const n of el.childNodes) {
      if (n.nodeType === 3 && n.textContent.trim() && px < minText) {
        small.push(name(el) + ' ' + px.toFixed(1) + 'px');
        break;
      }
    }
    // WCAG's 4.5:1 for text (a disabled control's text is exempt)
    if ([...el.childNodes].some((n) => n.nodeType === 3 && n.textContent.trim())
        && !el.closest('[disabled], [data-disabled="true"], [aria-disabled="true"]')) {
      const ratio = contrast(el, cs);
      if (ratio < 4.5) low.push(name(el) + ' ' + cs.color + ' ' + ratio.toFixed(2) + ':1');
    }
  }
  // the lab's own texts start where viser's labels do, not flush at the panel's edge
  const flush = [];
  const labels = [...document.querySelectorAll('label')].filter((l) => l.offsetParent
      && l.textContent.trim());
  const labelLeft = labels.length ? Math.min(...labels.map((l) => l.getBoundingClientRect().left))
      : null;
  for (const el of document.querySelectorAll('.al-readout, .al-preset-note, .al-message, .al-lesson-head')) {
    if (!el.offsetParent || labelLeft === null) continue;
    const text = el.getBoundingClientRect().left + parseFloat(getComputedStyle(el).paddingLeft);
    if (text < labelLeft - 4) flush.push(el.className + ' at ' + Math.round(text)
        + ', labels at ' + Math.round(labelLeft));
  }
  return {canvas: [c.left, c.top, c.width, c.height], size: [W, H], over: over.slice(0, 8),
          small: small.slice(0, 8), low: low.slice(0, 8), flush: flush,
          dpr: window.devicePixelRatio};
}"""


def projected_box(camera: Any, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The box's corners on the canvas in pixels from its centre (x right, y down), from
    the camera the page reports (viser's camera frame: x right, y down, z forward)."""
    corners = np.array(
        [[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
    )
    R = quat_matrix(np.asarray(camera.wxyz, dtype=float))
    p = (corners - np.asarray(camera.position, dtype=float)) @ R  # world -> camera
    assert np.all(p[:, 2] > 0), "the scene is (partly) behind the camera"
    f = (float(camera.image_height) / 2) / math.tan(float(camera.fov) / 2)
    return f * p[:, 0] / p[:, 2], f * p[:, 1] / p[:, 2]


def run_box(session: Any) -> tuple[np.ndarray, np.ndarray]:
    """The declared scene's box together with where the run's points and bodies are now
    and, for a preset's own values, everything its run will cover up to its t_end."""
    lo = np.asarray(session.scene.bounds[0], dtype=float)
    hi = np.asarray(session.scene.bounds[1], dtype=float)
    run = frame_points(session.frame)
    if len(run):
        lo, hi = np.minimum(lo, run.min(axis=0)), np.maximum(hi, run.max(axis=0))
    ahead = None if session.edits() else preset_extent(session.lesson.id, session.preset)
    if ahead is not None:
        lo, hi = np.minimum(lo, ahead[0]), np.maximum(hi, ahead[1])
    return lo, hi


def settled_camera(tab: Page, canvas_px: tuple[int, int]) -> Any | None:
    """The camera the page reports once it is the one the view framed for this canvas."""
    r = tab.view.renderer
    cam = tab.view.client.camera
    # viser may draw into a smaller buffer than the canvas (adaptive resolution): compare
    # shapes, not pixel counts
    shape = canvas_px[0] / canvas_px[1]
    if r.framed is None or r.framed_canvas is None:
        return None
    if abs(r.framed_canvas[0] / r.framed_canvas[1] / shape - 1) > 0.01:
        return None
    if abs(float(cam.image_width) / float(cam.image_height) / shape - 1) > 0.01:
        return None
    position, look_at = np.asarray(cam.position, float), np.asarray(cam.look_at, float)
    scale = float(np.linalg.norm(r.framed[0] - r.framed[1]))
    forward = quat_matrix(np.asarray(cam.wxyz, dtype=float))[:, 2]
    aim = (r.framed[1] - r.framed[0]) / scale
    if not (
        np.allclose(position, r.framed[0], rtol=0.0, atol=1e-3 * scale)
        and np.allclose(look_at, r.framed[1], rtol=0.0, atol=1e-3 * scale)
        and float(forward @ aim) > 1 - 1e-4
    ):
        return None
    return cam


def check_screen(tab: Page, size: str, what: str) -> None:
    """The page at one screen size: the panel leaves the canvas, the scene's box (and
    the run's) is framed inside it, nothing runs over, no small text."""
    w, h = SIZES[size]
    page = tab.page
    if page.viewport_size != {"width": w, "height": h}:
        page.set_viewport_size({"width": w, "height": h})
    geo = wait_until(
        lambda: (g := page.evaluate(GEOMETRY_JS, MIN_TEXT_PX))["size"] == [w, h] and g,
        10,
        "the resized page",
    )

    def canvas_px() -> tuple[int, int]:
        g = page.evaluate(GEOMETRY_JS, MIN_TEXT_PX)
        return round(g["canvas"][2] * g["dpr"]), round(g["canvas"][3] * g["dpr"])

    def framed_inside() -> tuple[Any, np.ndarray, np.ndarray, float, float] | None:
        # the camera framed for this canvas, with the scene's box (and the run's) inside
        # it: a framing for a layout the page passed through on its way here is followed
        # by the framing for this one
        cam = settled_camera(tab, canvas_px())
        if cam is None:
            return None
        # the camera's values read once (the page may report a new camera meanwhile)
        W, H = float(cam.image_width), float(cam.image_height)
        u, v = projected_box(cam, *run_box(tab.session))
        inside = np.all(np.abs(u) <= W / 2) and np.all(np.abs(v) <= H / 2)
        return (cam, u, v, W, H) if inside else None

    try:
        cam, u, v, W, H = wait_until(framed_inside, 20, f"the framed camera ({size})")
    except AssertionError as exc:
        r, c = tab.view.renderer, tab.view.client.camera
        seen = settled_camera(tab, canvas_px())
        box = ""
        if seen is not None:
            u, v = projected_box(seen, *run_box(tab.session))
            box = (
                f", the scene's box x {u.min():.0f}..{u.max():.0f}, y {v.min():.0f}..{v.max():.0f}"
            )
        raise AssertionError(
            f"{exc}: canvas {canvas_px()}, framed {r.framed} for {r.framed_canvas} (box "
            f"{r.framed_box}, the run's {run_box(tab.session)}), the page's camera "
            f"{c.position} -> {c.look_at} ({c.image_width}x{c.image_height}){box}"
        ) from None
    geo = page.evaluate(GEOMETRY_JS, MIN_TEXT_PX)
    where = f"{tab.session.lesson.id} / {tab.session.preset} at {size} {what}"
    assert geo["over"] == [], f"{where}: {geo['over']}"
    assert geo["small"] == [], f"{where}: text below {MIN_TEXT_PX} px: {geo['small']}"
    assert geo["low"] == [], f"{where}: text below 4.5:1 contrast: {geo['low']}"
    assert geo["flush"] == [], f"{where}: texts at the panel's edge: {geo['flush']}"
    left, top, cw, ch = geo["canvas"]
    if size == "phone":
        assert cw >= w - 1 and ch >= 0.4 * h, f"{where}: the canvas is {cw}x{ch}"
    else:
        assert ch >= h - 1 and cw >= 0.5 * w, f"{where}: the canvas is {cw}x{ch}"
    lo, hi = run_box(tab.session)
    cover = float(max(np.ptp(u), np.ptp(v)) / min(W, H))
    assert COVER[0] <= cover <= COVER[1], (
        f"{where}: the scene covers {cover:.0%} of the canvas; box {lo} - {hi}, framed "
        f"{tab.view.renderer.framed_box}, camera {cam.position} -> {cam.look_at}"
    )


def choose(tab: Page, lesson_id: str, preset: str) -> None:
    """Open ``lesson_id`` with ``preset`` on the page (paused), and wait for its panel."""
    s = tab.session
    with s.lock:
        s.pause()
        if s.lesson.id != lesson_id:
            s.select_lesson(lesson_id)
        s.apply_preset(preset)
        tab.view.after_state_change()
        tab.view.refresh(heavy=True)
    wait_until(lambda: tab.view._drawn_lesson == lesson_id, 10, f"lesson {lesson_id}")


def dismissed(tab: Page) -> None:
    """Close the page's notices (a screenshot without them)."""
    wait_until(lambda: tab.page.evaluate(DISMISS_JS) == 0, 30, "the notices closed")
