"""How far behind a page's connection is: messages queued for it since its sender last
took a window to send (a page that does not read its websocket stops its sender, and
the count grows with every frame drawn for it)."""

from __future__ import annotations

from typing import Any


def send_progress(server: Any, client_id: int) -> tuple[int, int]:
    """``(lag, taken)`` for page ``client_id``: messages pushed for it that its sender has
    not yet taken, and the number of the last message its sender took (it stays put
    while the page does not read); ``(0, -1)`` for a page that is not connected, or
    whose sender has not started."""
    try:
        buffer = server._websock_server._client_state_from_id[client_id].message_buffer
    except (AttributeError, KeyError):
        return 0, -1
    cursor = buffer.generator_cursors.get(client_id)
    if cursor is None:
        return 0, -1
    return max(0, buffer.message_counter - 1 - cursor), cursor


def send_lag(server: Any, client_id: int) -> int:
    """Messages pushed for page ``client_id`` that its sender has not yet taken (0 for a
    page that is not connected, or whose sender has not started)."""
    return send_progress(server, client_id)[0]
