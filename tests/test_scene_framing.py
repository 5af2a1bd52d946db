"""The camera's framing reaches the page (app/view/scene.py): a framing whose position the
page's camera did not take (it reported its old camera after the server moved it) is sent
again; a page that took it, or a student who turned the camera, is left alone.  A real
viser server and a real websocket page."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from typing import Any

import analyzer_lab.view.scene as scene
import analyzer_lab.viser_boundary as vb
import numpy as np
import pytest
from analyzer_lab.view.scene import SceneRenderer

from tests.support.client import ProtoClient
from tests.support.waiting import until
from tests.support.wire import camera_message

pytestmark = pytest.mark.timeout(60)


@pytest.fixture(scope="module")
def server() -> Iterator[Any]:
    s = vb.make_viser_server("127.0.0.1", 0, verbose=False)
    yield s
    s.stop()


async def _page(server: Any) -> tuple[ProtoClient, Any, SceneRenderer]:
    """A websocket page on ``server``, its client handle once it reported its camera, and
    a renderer drawing into it."""
    before = set(server.get_clients())
    page = await ProtoClient(f"http://127.0.0.1:{server.get_port()}/").start()
    new = await until(lambda: sorted(set(server.get_clients()) - before), 10, "the page")
    client = server.get_clients()[new[0]]
    await until(lambda: client.camera.image_width == 1280, 10, "the page's camera")
    return page, client, SceneRenderer(client, None)


def test_a_framing_the_page_did_not_take_is_sent_again(
    server: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(scene, "FRAMING_CHECK_AFTER", 0.0)

    async def go() -> None:
        page, client, r = await _page(server)
        r.frame_camera(np.full(3, -1.0), np.full(3, 1.0), 2.0)
        first = r.framed[0].copy()
        r.frame_camera(np.full(3, -2.0), np.full(3, 2.0), 4.0, keep_direction=True)
        second = r.framed[0].copy()
        assert not np.allclose(first, second)
        # the page reports the camera of the first framing after the second was sent
        await page.send(camera_message(tuple(map(float, first))))
        await until(lambda: np.allclose(client.camera.position, first), 10, "the old camera")
        assert r.confirm_framing()
        assert np.allclose(client.camera.position, second)
        # the page took it: nothing more is sent
        await page.send(camera_message(tuple(map(float, second))))
        await until(lambda: np.allclose(client.camera.position, second), 10, "the new camera")
        assert not r.confirm_framing() and not r.confirm_framing()
        # a student who turns the camera after a framing keeps the view chosen
        r.frame_camera(np.full(3, -1.0), np.full(3, 1.0), 2.0, keep_direction=True)
        turned = (0.5, -4.0, 2.0)
        await page.send(camera_message(turned))
        await until(lambda: np.allclose(client.camera.position, turned), 10, "the turned camera")
        assert not r.confirm_framing()
        assert np.allclose(client.camera.position, turned)
        await page.close()

    asyncio.run(go())


def test_a_page_that_never_takes_the_framing_is_sent_it_a_few_times(
    server: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(scene, "FRAMING_CHECK_AFTER", 0.0)

    async def go() -> None:
        page, client, r = await _page(server)
        r.frame_camera(np.full(3, -1.0), np.full(3, 1.0), 2.0)
        first = r.framed[0].copy()
        r.frame_camera(np.full(3, -3.0), np.full(3, 3.0), 6.0, keep_direction=True)
        sent = 0
        for _ in range(scene.FRAMING_RESENDS + 2):
            await page.send(camera_message(tuple(map(float, first))))
            await until(lambda: np.allclose(client.camera.position, first), 10, "stuck")
            sent += r.confirm_framing()
        assert sent == scene.FRAMING_RESENDS
        await page.close()

    asyncio.run(go())
