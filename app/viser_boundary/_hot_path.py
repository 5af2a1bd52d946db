"""The frame loop's hot path: property hints worked out once, one wake-up per tick,
properties and poses set without viser's generic casting."""

from __future__ import annotations

import asyncio
from typing import Any

from analyzer_lab.viser_boundary._patches import PATCH_LOCK

_PROP_HINTS: dict[type, dict[str, Any]] = {}


def share_prop_hints() -> None:
    """Every viser handle works out the type hints of its properties class once, on its
    first property write (``AssignablePropsBase._prop_hints``, ``typing.get_type_hints``,
    about 0.3 ms); a live trail makes a new line-segments node every chunk, so the
    frame loop paid it again and again.  The hints depend only on the class: they are
    worked out once per class.  Idempotent; process-wide."""
    from typing import get_type_hints

    from viser._assignable_props_api import AssignablePropsBase

    def hints(self: Any) -> dict[str, Any]:
        cls = type(self._impl.props)
        found = _PROP_HINTS.get(cls)
        if found is None:
            found = _PROP_HINTS[cls] = get_type_hints(cls)
        return found

    with PATCH_LOCK:
        if not isinstance(AssignablePropsBase.__dict__.get("_prop_hints"), property):
            AssignablePropsBase._prop_hints = property(hints)  # type: ignore[assignment]


class WakeBatch:
    """Groups the messages of one loop tick for every client and wakes viser's event
    loop once for all of them (instead of once per client: each wake-up is a write to
    the loop's self-pipe).  Uses viser's message buffers directly; when they are not
    reachable, :meth:`hold` returns False and the view uses ``client.atomic()``."""

    def __init__(self, server: Any) -> None:
        self.loop = getattr(server._websock_server, "_background_event_loop", None)
        self.held: list[tuple[Any, int]] = []

    def hold(self, client: Any) -> bool:
        try:
            buf = client._websock_connection._state.message_buffer
            buf.atomic_start()
        except AttributeError:  # viser's buffer is not reachable for this client
            return False
        self.held.append((buf, buf.message_counter))
        return True

    def release(self) -> None:
        woken = []
        for buf, before in self.held:
            with buf.buffer_lock:
                buf.atomic_counter -= 1
                ready = buf.atomic_counter == 0
            if ready and buf.message_counter != before:
                woken.append(buf)
        self.held = []
        if woken and self.loop is not None:

            def wake() -> None:
                for b in woken:
                    b.message_event.set()

            try:
                self.loop.call_soon_threadsafe(wake)
            except RuntimeError:
                pass


def fast_set(handle: Any, name: str, value: Any) -> None:
    """Assign one property of a viser handle on the hot path: the value is already of
    the right type and dtype (fresh array), so viser's generic casting and comparison
    (``props_setattr``) are skipped; state and wire message are the same."""
    impl = handle._impl
    if impl.removed:
        return
    setattr(impl.props, name, value)
    handle._queue_update(name, value)


def _moved(current: Any, value: tuple[float, ...]) -> bool:
    """Whether ``value`` differs from ``current`` beyond ``np.allclose`` (viser's test
    for an unchanged pose, its default tolerances), compared number by number: equal
    infinities are unchanged, a NaN always moved."""
    for v, c in zip(value, current.tolist(), strict=True):
        if v != c and not abs(v - c) <= 1e-8 + 1e-5 * abs(c):
            return True
    return False


def set_pose(handle: Any, pos: Any, wxyz: Any) -> None:
    """Set a posed body's position and orientation as its ``position`` and ``wxyz``
    setters do (one message each, none for a part that did not move), without their
    generic casting and array comparison on the hot path."""
    from viser import _messages

    impl = handle._impl
    if impl.removed:
        return
    queue = impl.api._queue_scene_message
    p = tuple(map(float, pos))
    if _moved(impl.position, p):
        impl.position[:] = p
        queue(_messages.SetPositionMessage(impl.name, p))
    q = tuple(map(float, wxyz))
    if _moved(impl.wxyz, q):
        impl.wxyz[:] = q
        queue(_messages.SetOrientationMessage(impl.name, q))


def event_loop(server: Any) -> asyncio.AbstractEventLoop | None:
    """The event loop viser's websocket server runs in (``None`` if not reachable)."""
    return getattr(server._websock_server, "_background_event_loop", None)
