"""Each patch of viser's private internals (app/viser_boundary/__init__.py), checked on its own
against the installed viser: a viser update that moves one of them fails here first."""

from __future__ import annotations

import asyncio
import copy
import time
import urllib.request
from collections.abc import Iterator
from typing import Any

import analyzer_lab.viser_boundary as vb
import numpy as np
import pytest

from tests.support.waiting import until, wait_until
from tests.support.wire import camera_message, encode


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
    assert vb.PHONE_LAYOUT in page  # on a phone the panel is a sheet below the canvas
    assert vb.READABLE_TEXT in page
    handlers = server._websock_server._incoming_handlers
    assert _messages.ShareUrlRequest not in handlers
    assert server.request_share_url() is None


def test_websocket_consumer_is_replaced_by_the_paced_one(server: Any) -> None:
    from viser.infra import _infra

    assert _infra._message_consumer.__name__ == "paced_consumer"
    assert _infra.websockets.asyncio.server.serve.__name__ == "limited_serve"
    assert vb.WS_MAX_BYTES == 64 * 1024


async def _connect(server: Any) -> Any:
    import viser
    import websockets

    ws = await websockets.connect(
        f"ws://127.0.0.1:{server.get_port()}/",
        subprotocols=[f"viser-v{viser.__version__}"],
        max_size=None,
        compression=None,
    )
    await ws.send(encode(camera_message()))
    return ws


def test_the_transport_refuses_an_oversized_message_before_reading_it(server: Any) -> None:
    async def go() -> tuple[int | None, float, int | None]:
        small = await _connect(server)
        ws = await _connect(server)
        t0 = time.monotonic()
        # one byte over the limit: refused from the frame header, the payload unread
        await ws.send(b"\x00" * (vb.WS_MAX_BYTES + 1))
        try:
            await asyncio.wait_for(ws.wait_closed(), 5)
        except asyncio.TimeoutError:
            pass
        took = time.monotonic() - t0
        code = ws.close_code
        await small.send(b"\x00" * 1000)  # under the limit: read (and ignored as malformed)
        await asyncio.sleep(0.2)  # a close for it would have come by now
        still = small.close_code
        await small.close()
        return code, took, still

    code, took, still = asyncio.run(go())
    assert code == 1009 and took < 2.0  # "message too big"
    assert still is None  # the page that sent a normal-sized message stays connected


def test_only_allowed_message_types_reach_viser(server: Any) -> None:
    from viser import _messages

    buffer = server._websock_server._broadcast_buffer
    before = len(buffer.message_from_id)
    dropped = vb.WS_STATS["dropped_type"]

    async def go() -> None:
        ws = await _connect(server)
        for k in range(20):
            await ws.send(encode(_messages.GuiFormDirtyMessage(uuid=f"junk-{k}" * 50)))
        await ws.send(encode(_messages.ShareUrlRequest()))
        await until(lambda: vb.WS_STATS["dropped_type"] - dropped >= 21, 5, "the 21 dropped")
        await ws.close()

    asyncio.run(go())
    assert vb.WS_STATS["dropped_type"] - dropped == 21
    assert vb.WS_DROPPED_TYPES["GuiFormDirtyMessage"] >= 20
    assert "GuiFormDirtyMessage" in vb.dropped_types()
    assert len(buffer.message_from_id) == before  # nothing was broadcast or kept
    assert "ViewerCameraMessage" in vb.ALLOWED_MESSAGES  # the camera of each page still comes


def test_client_address_is_the_page_host(server: Any) -> None:
    ids: list[int] = []
    server.on_client_connect(lambda c: ids.append(c.client_id))

    async def go() -> str:
        ws = await _connect(server)
        await until(lambda: ids, 30, "the page connected")
        # the connection is registered beside the connect callbacks: read it once it is
        address = await until(lambda: vb.client_address(server, ids[-1]), 30, "its address")
        await ws.close()
        return address

    assert asyncio.run(go()) == "127.0.0.1"
    assert vb.client_address(server, 10**9) == ""


def test_callbacks_take_turns_within_the_cpu_budget() -> None:
    from concurrent.futures import ThreadPoolExecutor

    ex = vb.OrderedExecutor(ThreadPoolExecutor(2), share=0.2, burst=0.05, workers=2)
    try:
        order: list[str] = []

        def burn(tag: str) -> None:
            t = time.thread_time()
            while time.thread_time() - t < 0.02:
                pass
            order.append(tag)

        t0 = time.monotonic()
        futs = [ex.submit_for("flood", burn, "flood") for _ in range(20)]
        quiet = ex.submit_for("quiet", burn, "quiet")
        quiet.result(timeout=10)
        # the quiet source runs after at most a turn of the flooding one, not after all 20
        assert order.index("quiet") <= 3
        for f in futs:
            f.result(timeout=30)
        took = time.monotonic() - t0
        # 21 x 20 ms of CPU at a share of 0.2 needs about (0.42 - 0.05) / 0.2 = 1.85 s
        assert took > 1.4, took
        assert ex.stats["cpu"] >= 0.4
        assert ex.pending() == 0
    finally:
        ex.shutdown(wait=False)


def _burn(seconds: float, paced: bool) -> None:
    """``seconds`` of this thread's CPU; ``paced``: charged as it goes (an export's loop)."""
    from analyzer_lab.limits import charge_running

    end = time.thread_time() + seconds
    mark = time.thread_time()
    while time.thread_time() < end:
        if paced and time.thread_time() - mark >= 0.004:
            charge_running()
            mark = time.thread_time()


def test_a_long_callback_is_charged_as_it_runs_and_others_keep_their_turn() -> None:
    from concurrent.futures import ThreadPoolExecutor

    ex = vb.OrderedExecutor(ThreadPoolExecutor(2), share=0.2, burst=0.05, workers=3)
    try:
        t0 = time.monotonic()
        long = ex.submit_for("export", _burn, 0.4, True)
        waits: list[float] = []
        while not long.done():
            t = time.monotonic()
            ex.submit_for("other", _burn, 0.002, False).result(timeout=30)
            waits.append(time.monotonic() - t)
            time.sleep(0.1)  # a page's next input
        took = time.monotonic() - t0
        # 0.4 s of CPU at a share of 0.2: the export itself waited its turns (about 2 s)
        assert took > 1.2, took
        # the share held while it ran: CPU <= burst + share x wall time (+ one slice)
        assert ex.stats["cpu"] <= 0.05 + 0.2 * took + 0.03, (ex.stats, took)
        assert len(waits) >= 5, waits
        # the other page answered all along, each in a small part of the export's time
        assert max(waits) < 0.25 * took, (max(waits), took)
        # and right after: the export left at most one slice unpaid (not 0.4 / 0.2 = 2 s)
        assert ex.budget.wait_time() < 0.2 * took, (ex.budget.wait_time(), took)
        t = time.monotonic()
        ex.submit_for("other", _burn, 0.002, False).result(timeout=30)
        assert time.monotonic() - t < 0.25 * took, (time.monotonic() - t, took)

        # a callback that never calls charge_running pays at its end: the next one waits
        ex.budget.wait()
        ex.submit_for("export", _burn, 0.3, False).result(timeout=30)
        assert ex.budget.wait_time() > 0.8, (
            ex.budget.wait_time()
        )  # about (0.3 - 0.05) / 0.2 = 1.25 s
    finally:
        ex.shutdown(wait=False)


def test_charge_running_outside_a_callback_charges_nothing() -> None:
    from analyzer_lab.limits import charge_running, charged_by

    assert charge_running() == 0.0
    calls: list[int] = []
    with charged_by(lambda: float(calls.append(1) or 0.25)):
        assert charge_running() == 0.25
        with charged_by(lambda: 0.5):
            assert charge_running() == 0.5
        assert charge_running() == 0.25
    assert charge_running() == 0.0 and calls == [1, 1]


def test_submit_callback_goes_through_the_ordered_executor(server: Any) -> None:
    done: list[int] = []
    assert vb.submit_callback(server, ("replay", 1), done.append, 5)
    wait_until(lambda: done, 5, "the callback")
    assert done == [5]
    assert not vb.submit_callback(object(), "k", done.append, 6)


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


def test_set_pose_matches_viser_setters_on_edge_cases(server: Any) -> None:
    """The same node state and the same messages as ``h.position = ...; h.wxyz = ...``,
    unchanged values (within numpy.allclose) sending nothing, on a run of poses."""
    poses = [
        ((1.0, 2.0, 3.0), (1.0, 0.0, 0.0, 0.0)),  # wxyz: the default, not sent
        ((1.0, 2.0, 3.0), (1.0, 0.0, 0.0, 0.0)),  # unchanged: nothing sent
        ((1.0 + 1e-9, 2.0, 3.0), (0.6, 0.8, 0.0, 0.0)),  # position within tolerance
        ((1.0 + 1e-3, 2.0, 3.0), (0.6, 0.8, 0.0, 0.0)),  # orientation unchanged
        ((0.0, 0.0, 0.0), (0.6, 0.8 * (1 + 2e-5), 0.0, 0.0)),  # just beyond rtol
        ((float("inf"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
        ((float("inf"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),  # inf equals inf: nothing
        ((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),
        ((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)),  # nan: sent again, like viser
    ]
    sent: dict[str, list[tuple[str, tuple[float, ...]]]] = {"old": [], "new": []}
    handles = {}
    for key in sent:
        h = server.scene.add_frame(f"/t/pose_{key}")
        handles[key] = h
        log = sent[key]
        h._impl.api = copy.copy(h._impl.api)
        h._impl.api._queue_scene_message = lambda m, log=log: log.append(
            (type(m).__name__, tuple(getattr(m, "position", getattr(m, "wxyz", ()))))
        )
    for pos, wxyz in poses:
        old = handles["old"]
        old.position = pos
        old.wxyz = wxyz
        vb.set_pose(handles["new"], np.array(pos), np.array(wxyz))
        for name in ("position", "wxyz"):
            a, b = getattr(old, name), getattr(handles["new"], name)
            assert np.array_equal(a, b, equal_nan=True)
    assert len(sent["old"]) == 9
    assert str(sent["new"]) == str(sent["old"])  # nan == nan as text
    handles["new"].remove()
    vb.set_pose(handles["new"], np.zeros(3), np.array([1.0, 0.0, 0.0, 0.0]))  # ignored


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


def test_set_pose_sends_what_the_setters_send() -> None:
    """The hot path of a posed body: the same state and messages as viser's setters
    (none for a part that did not move beyond ``np.allclose``)."""
    poses = [
        ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0)),  # unchanged from the start: nothing sent
        ((0.1, -0.2, 0.3), (1.0, 0.0, 0.0, 0.0)),  # moved only
        ((0.1, -0.2, 0.3), (0.8, 0.6, 0.0, 0.0)),  # turned only
        ((0.1 + 1e-10, -0.2, 0.3), (0.8, 0.6, 0.0, 0.0)),  # within allclose: nothing
        ((0.5, 0.5, 0.5), (0.0, 0.0, 0.6, 0.8)),  # both
    ]
    sent: list[list[tuple[str, str, tuple[float, ...]]]] = []
    handles = []
    for fast in (False, True):
        scene, _ = vb.recording_scene()
        h = scene.add_box("/body", color=(1, 0, 0), dimensions=(1, 1, 1))
        log: list[tuple[str, str, tuple[float, ...]]] = []
        scene._queue_scene_message = lambda m, log=log: log.append(  # type: ignore[method-assign]
            (type(m).__name__, m.name, tuple(m.position if hasattr(m, "position") else m.wxyz))
        )
        for pos, wxyz in poses:
            if fast:
                vb.set_pose(h, np.array(pos), np.array(wxyz))
            else:
                h.position, h.wxyz = pos, wxyz
        sent.append(log)
        handles.append(h)
    assert sent[0] == sent[1] and len(sent[0]) == 4
    assert np.array_equal(handles[0].position, handles[1].position)
    assert np.array_equal(handles[0].wxyz, handles[1].wxyz)


def test_prop_hints_are_worked_out_once_per_class(server: Any) -> None:
    from typing import get_type_hints

    a = server.scene.add_line_segments("/t/hints_a", np.zeros((1, 2, 3)), (1, 2, 3))
    b = server.scene.add_line_segments("/t/hints_b", np.zeros((2, 2, 3)), (4, 5, 6))
    assert a._prop_hints is b._prop_hints  # one dict for the class
    assert a._prop_hints == get_type_hints(type(a._impl.props))
    # writes still cast and check as viser does
    b.colors = np.full((2, 2, 3), 7, np.uint8)
    assert b.colors.dtype == np.uint8 and np.all(b.colors == 7)
    a.remove()
    with pytest.raises(RuntimeError):
        a.colors = np.zeros((1, 2, 3), np.uint8)


def test_send_lag_reads_the_senders_cursor_and_is_zero_for_an_unknown_page(
    make_lab: Any,
) -> None:
    from analyzer_lab.viser_boundary import send_lag

    lab = make_lab(lesson="sphere", warm_up=False)
    assert send_lag(lab.server, 12345) == 0
    state = lab.server._websock_server._client_state_from_id
    assert isinstance(state, dict)


def test_relabel_tabs_renames_the_tabs_in_place(server: Any) -> None:
    group = server.gui.add_tab_group()
    tabs = [group.add_tab(name) for name in ("Lesson", "Controls")]
    ids = group._tab_container_ids
    with tabs[1]:
        inside = server.gui.add_html("kept")
    vb.relabel_tabs(group, ("Урок", "Параметры"))
    assert group._tab_labels == ("Урок", "Параметры")
    assert group._tab_container_ids == ids  # the same tabs, their contents kept
    assert inside.content == "kept"
    with pytest.raises(ValueError):
        vb.relabel_tabs(group, ("one",))
    group.remove()


def test_a_callback_reads_the_value_its_page_sent(server: Any) -> None:
    """A page's input resets another widget in its callback (a lesson change resets the
    preset picker); the page's next input, a value of that widget sent before the first
    callback ran, is read as the page sent it."""
    from tests.support.client import ProtoClient

    seen: list[tuple[Any, Any]] = []
    picker = server.gui.add_dropdown("picker", ("a", "b", "c"), initial_value="a")

    def reset_picker(_: Any) -> None:
        time.sleep(0.3)  # the picker's own update arrives meanwhile
        picker.value = "a"

    server.gui.add_text("first", "x").on_update(reset_picker)
    picker.on_update(
        lambda e: seen.append((vb.sent_value(e), e.target.value)) if e.client else None
    )  # the server's own set of the picker is an event without a page
    url = f"ws://127.0.0.1:{server.get_port()}/"

    async def go() -> None:
        c = await ProtoClient(url).start()
        try:
            await c.set("first", "y", 0.0)
            await c.set("picker", "b", 0.0)
            await until(lambda: seen, 10, "the picker's callback")
        finally:
            await c.close()

    asyncio.run(go())
    assert seen == [("b", "a")]


def test_an_event_made_in_the_server_reads_the_widget() -> None:
    class Widget:
        value = 3.0

    class Event:
        target = Widget()

    assert vb.sent_value(Event()) == 3.0
