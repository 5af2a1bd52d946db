"""The readout: time, play state and the lesson's key quantities; notices."""

from __future__ import annotations

import html

from analyzer_lab.i18n import ENGLISH, Language
from analyzer_lab.session.session import Session
from analyzer_lab.view.notation import name_html, unit_text
from analyzer_lab.viser_boundary import language_marker

LEVEL_COLORS = {"info": "#1c4f8a", "warning": "#8a5a00", "error": "#a61b1b"}


def speed_label(s: float) -> str:
    return f"{s:g}x"


def readout_html(s: Session, language: Language = ENGLISH) -> str:
    """Time, speed, play state and the lesson's declared readout quantities (numbers as
    the page's language writes them)."""
    tr = language.gettext
    playing = html.escape(tr("playing"))
    state = playing if s.playing else html.escape(tr("paused"))
    if s.playing and s.slowed:
        slow = html.escape(language.message(s.slow_text()))
        state = f'{playing} <span class="al-slow" style="color:#8a5a00">({slow})</span>'
    units = {x.name: x.unit for x in s.lesson.series}
    values = []
    for name in s.lesson.readout:
        v = s.frame.scalars.get(name)
        if v is None:
            continue
        unit = language.unit(unit_text(units.get(name, "")))
        shown = f"{name_html(name, language.quantity)} = {language.number(v)}" + (
            f"&nbsp;{html.escape(unit)}" if unit else ""
        )
        # one quantity never wraps inside itself; the line breaks between quantities
        values.append(f'<span class="al-quantity" style="white-space:nowrap">{shown}</span>')
    quantities = (
        f'<div class="al-readout-values" style="font-size:0.9em">{" &ensp; ".join(values)}</div>'
        if values
        else ""
    )
    return (
        '<div class="al-readout" style="font-family:monospace;font-size:1.05em">'
        f"t = {language.number(s.frame.t, '8.3f')} {html.escape(language.unit('s'))} &nbsp;"
        f" {speed_label(s.speed)} &nbsp; {state}{quantities}</div>"
    )


def status_html(s: Session, language: Language = ENGLISH) -> str:
    """The newest notice (in the page's language: a session's message, a lesson's note)
    and the frame's message; with the hidden marker of the page's language (its
    ``<html lang>``)."""
    parts = [language_marker(language.html_lang)]
    if s.notice is not None:
        level, message = s.notice
        text = language.notice(message)
        color = LEVEL_COLORS.get(level, "#333")
        parts.append(
            f'<div class="al-message al-{level}" style="color:{color};font-size:0.9em">{html.escape(text)}</div>'
        )
    if s.frame.message:
        parts.append(
            '<div class="al-frame-message" style="color:#8a5a00;font-size:0.9em">'
            f"{html.escape(language.prose(s.frame.message))}</div>"
        )
    if len(parts) == 1:
        parts.append('<div class="al-message"></div>')
    return "".join(parts)


def preset_note_html(s: Session, language: Language = ENGLISH) -> str:
    """The preset's title and note, or "custom (from ...)" with what differs once the
    student changed a value."""
    esc = html.escape
    tr = language.gettext
    edits = s.edits()
    origin = s.preset or tr("the defaults")
    if edits:
        was_text = tr("(was {value})")
        rows = "".join(
            f"<li><code>{esc(k)}</code> = {esc(str(now))} "
            f'<span style="color:#5f5f5f">{esc(was_text.format(value=was))}</span></li>'
            for k, (was, now) in list(edits.items())[:8]
        )
        n = len(edits) - 8
        more_text = language.ngettext("... and {n} more", "... and {n} more", n).format(n=n)
        more = f"<li>{esc(more_text)}</li>" if n > 0 else ""
        custom = tr("custom (from {origin})").format(origin=origin)
        body = (
            f'<b class="al-custom">{esc(custom)}</b>'
            f'<ul style="margin:2px 0 0 1em;padding:0">{rows}{more}</ul>'
        )
    elif s.preset:
        pr = s.lesson.preset(s.preset)
        title, note = language.lesson_text(pr.title), language.prose(pr.note)
        body = f"<b>{esc(title)}</b>" + (f"<br>{esc(note)}" if note else "")
    else:
        body = ""
    return f'<div class="al-preset-note" style="font-size:max(11px,0.85em)">{body}</div>'
