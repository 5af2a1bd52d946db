"""The second place that reaches into viser's private internals: the GUI value guard.

viser 1.1.1 casts a page's GUI update to the widget's type and raises (a traceback per
message) when it cannot; :func:`guard_gui_updates` puts a check in front of viser's
handler on one connection, so a value of the wrong type is refused with one message to
its sender.  Like :mod:`analyzer_lab.viser_boundary` (which checks the viser version), it was
written and tested against viser 1.1.1 (``tests/test_viser_boundary.py``).
"""

from __future__ import annotations

import logging
import math
import sys
import time
from typing import Any

#: Seconds between two log lines about refused GUI values (the count is kept).
REFUSED_LOG_EVERY = 10.0
REFUSED_UPDATES = {"count": 0, "logged": 0.0}

log = logging.getLogger(__name__)


def value_problem(current: Any, value: Any) -> str | None:
    """Why ``value`` cannot replace a widget's ``current`` value (viser casts it with the
    current value's type), or None: numbers for numbers (finite), on/off for on/off,
    text (or a finite number, read as its text) for text, a tuple of the same length and
    kinds for a tuple."""
    if isinstance(current, bool):
        return None if isinstance(value, bool) else "expected on/off"
    if isinstance(current, (int, float)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return "expected a number"
        return None if math.isfinite(value) else "expected a finite number"
    if isinstance(current, str):  # a number typed into a text field reads as its text
        if isinstance(value, str):
            return None
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return None if math.isfinite(value) else "expected a finite number"
        return "expected text"
    if isinstance(current, tuple):
        if not isinstance(value, (list, tuple)) or len(value) != len(current):
            return f"expected {len(current)} values"
        for c, v in zip(current, value):
            why = value_problem(c, v)
            if why is not None:
                return why
        return None
    return None


def guard_gui_updates(gui: Any, server: Any) -> None:
    """Check each GUI update's value against its widget before viser casts it: a wrong
    type (a list for a number, text for a checkbox, NaN) is refused with one notice to
    the sender and a log line at most every :data:`REFUSED_LOG_EVERY` seconds; nothing
    changes and nothing is sent to other pages.  ``gui``: the server's or a client's GUI
    API (each registers its own handler on its connection)."""
    from viser import _messages

    ws = gui._websock_interface
    original = gui._handle_gui_updates

    async def checked(client_id: Any, message: Any) -> None:
        handle = gui._gui_input_handle_from_uuid.get(message.uuid, None)
        if handle is None or handle._impl.removed:
            return
        state = handle._impl
        updates = message.updates if isinstance(message.updates, dict) else {}
        why = None if updates else "an empty update"
        for name, value in updates.items():
            if name != "value":
                why = f"the page may only change a widget's value, not {str(name)[:30]!r}"
                break
            why = value_problem(state.value, value)
            if why is not None:
                break
        if why is None:
            await original(client_id, message)
            return
        label = str(getattr(handle, "label", "") or "a widget")[:60]
        REFUSED_UPDATES["count"] += 1
        now = time.monotonic()
        if now - REFUSED_UPDATES["logged"] >= REFUSED_LOG_EVERY:
            REFUSED_UPDATES["logged"] = now
            print(
                f"analyzer-lab: refused GUI values so far: {REFUSED_UPDATES['count']}"
                f" (latest: {label}: {why})",
                file=sys.stderr,
                flush=True,
            )
        client = server.get_clients().get(client_id)
        if client is not None:
            try:
                client.add_notification(
                    "Analyzer Lab",
                    f"{label}: value refused ({why})",
                    auto_close_seconds=6.0,
                    color="yellow",
                )
            except Exception:  # a page that closed meanwhile
                log.debug("refusal not shown to page %s", client_id, exc_info=True)

    try:
        ws.unregister_handler(_messages.GuiUpdateMessage, original)
    except (AssertionError, ValueError):
        return  # viser's handler is not where it was checked: keep it
    ws.register_handler(_messages.GuiUpdateMessage, checked)


__all__ = ["REFUSED_LOG_EVERY", "REFUSED_UPDATES", "guard_gui_updates", "value_problem"]
