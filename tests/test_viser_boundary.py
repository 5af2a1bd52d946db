"""Each patch of viser's private internals (app/viser_boundary.py), checked on its own
against the installed viser: a viser update that moves one of them fails here first."""

from __future__ import annotations

import asyncio
import urllib.request
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from app import viser_boundary as vb


@pytest.fixture(scope="module")
def server() -> Iterator[Any]:
    s = vb.make_viser_server("127.0.0.1", 0, verbose=False)
    yield s
    s.stop()


def test_the_installed_viser_is_the_checked_one() -> None:
    import viser

    assert viser.__version__ == vb.VISER_VERSION
    vb.check_viser_version()


def test_the_page_is_titled_and_the_share_tunnel_cannot_start(server: Any) -> None:
    from viser import _messages

    page = urllib.request.urlopen(f"http://127.0.0.1:{server.get_port()}/").read().decode()
    assert f"<title>{vb.PAGE_TITLE}</title>" in page
    assert vb.KEYS_STAY_IN_FIELDS in page  # typed keys do not reach the camera
    handlers = server._websock_server._incoming_handlers
    assert _messages.ShareUrlRequest not in handlers
    assert server.request_share_url() is None


def test_websocket_consumer_is_replaced_by_the_paced_one(server: Any) -> None:
    from viser.infra import _infra

    assert _infra._message_consumer.__name__ == "paced_consumer"
    assert vb.WS_MAX_BYTES == 256 * 1024


def test_callbacks_go_through_the_ordered_executor(server: Any) -> None:
    assert isinstance(server._thread_executor, vb.OrderedExecutor)
    assert server.gui._thread_executor is server._thread_executor
    order: list[int] = []
    futures = []
    token = vb.CONNECTION.set(7)
    try:
        for k in range(20):
            futures.append(server._thread_executor.submit(order.append, k))
    finally:
        vb.CONNECTION.reset(token)
    for f in futures:
        f.result(timeout=5)
    assert order == list(range(20))


def test_event_loop_is_reachable(server: Any) -> None:
    loop = vb.event_loop(server)
    assert isinstance(loop, asyncio.AbstractEventLoop) and loop.is_running()


def test_fast_set_updates_a_handle_like_an_assignment(server: Any) -> None:
    h = server.scene.add_point_cloud("/t/points", np.zeros((2, 3), np.float32), (255, 0, 0))
    new = np.ones((2, 3), np.float32)
    vb.fast_set(h, "points", new)
    assert np.array_equal(h.points, new)
    h.remove()
    vb.fast_set(h, "points", np.zeros((2, 3), np.float32))  # removed: ignored, no error


def test_recording_scene_serializes_to_html() -> None:
    scene, serializer = vb.recording_scene()
    scene.add_point_cloud("/p", np.zeros((1, 3), np.float32), (0, 0, 255))
    serializer.insert_sleep(0.1)
    html = serializer.as_html()
    assert html.lstrip().lower().startswith("<!doctype html") or "<html" in html.lower()
    assert len(html) > 1000


def test_gui_updates_go_through_the_type_check(server: Any) -> None:
    from viser import _messages

    handlers = server._websock_server._incoming_handlers[_messages.GuiUpdateMessage]
    assert [h.__name__ for h in handlers] == ["checked"]


@pytest.mark.parametrize(
    "current,value,ok",
    [
        (1.0, 2, True),
        (1.0, [1, 2], False),
        (1.0, "3", False),
        (1.0, float("nan"), False),
        (1.0, True, False),
        (True, False, True),
        (True, "yes", False),
        ("text", "t*2", True),
        ("text", 2.5, True),  # a number typed into a text field reads as its text
        ("text", None, False),
        ("text", {"a": 1}, False),
        ((1.0, 2.0), [3, 4], True),
        ((1.0, 2.0), [3], False),
        ((1.0, 2.0), ["a", 4], False),
    ],
)
def test_a_value_of_the_wrong_type_is_named(current: Any, value: Any, ok: bool) -> None:
    why = vb.value_problem(current, value)
    assert (why is None) == ok, why
    if not ok:
        assert why.startswith("expected ")
