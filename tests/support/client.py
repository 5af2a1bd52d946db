"""One page as a websocket client speaking viser's protocol: it learns the GUI (label ->
uuid) from the server's messages, counts the moving point's updates and can send any
message (the hand-made client of the hardening tests and of the classroom benchmarks)."""

from __future__ import annotations

import asyncio
import itertools
import time
from typing import Any

from tests.support.waiting import until
from tests.support.wire import (
    POINT_NODE,
    camera_message,
    decode_frame,
    encode,
    gui_update,
    storage_answer,
)


class ProtoClient:
    """One page as a websocket client: GUI by label, point updates, bytes."""

    def __init__(
        self,
        url: str,
        storage: dict[str, str] | None = None,
        source: str = "",
        rcvbuf: int = 0,
    ) -> None:
        """``storage``: the page's local storage as the server writes and reads it (share
        one dict between clients: two tabs of one browser, or a reload); ``source``: the
        loopback address to connect from (another "machine", e.g. ``127.0.0.2``);
        ``rcvbuf``: a small socket receive buffer (a page that stops reading fills it,
        and the server's send buffer, quickly)."""
        self.url = url if url.startswith("ws") else url.replace("http", "ws", 1)
        self.storage: dict[str, str] = {} if storage is None else storage
        self.source = source
        self.rcvbuf = rcvbuf
        self.gui: dict[str, str] = {}  # label -> uuid (the newest element with that label)
        self.values: dict[str, Any] = {}  # uuid -> value the server set
        self.stamps: dict[str, float] = {}  # uuid -> when the server last set its value
        self.html: dict[str, str] = {}  # uuid -> content of html elements
        self.notifications: list[str] = []
        self.seen: dict[str, int] = {}  # message type -> count
        self.last: dict[str, dict[str, Any]] = {}  # message type -> the newest of that type
        self.point_updates = 0
        self.frames = 0
        self.bytes = 0
        self.measuring = False
        #: read the socket but decode nothing (an attacker that only sends: its own CPU
        #: stays off the machine the server shares)
        self.skim = False
        self.last_points: Any = None
        self.ws: Any = None
        self.error = ""
        self.connected = asyncio.Event()
        self._task: asyncio.Task | None = None

    async def start(self) -> ProtoClient:
        self._task = asyncio.create_task(self._run())
        await asyncio.wait_for(self.connected.wait(), 30)
        return self

    async def _run(self) -> None:
        import viser
        import websockets
        import zstandard

        dec = zstandard.ZstdDecompressor()
        try:
            async with websockets.connect(
                self.url,
                **self._socket(),
                subprotocols=[f"viser-v{viser.__version__}"],
                max_size=None,
                compression=None,
                open_timeout=30,
            ) as ws:
                self.ws = ws
                await ws.send(encode(camera_message()))
                self.connected.set()
                async for raw in ws:
                    if not isinstance(raw, bytes) or self.skim:
                        continue
                    point = False
                    for m in decode_frame(raw, dec):
                        t = m.get("type", "")
                        self.seen[t] = self.seen.get(t, 0) + 1
                        self.last[t] = m
                        if t == "SceneNodeUpdateMessage":
                            if m.get("name") == POINT_NODE and "points" in m.get("updates", {}):
                                point = True
                        elif t == "GuiUpdateMessage":
                            upd = m.get("updates", {})
                            if "value" in upd:
                                self.values[m.get("uuid")] = upd["value"]
                                self.stamps[m.get("uuid")] = time.monotonic()
                            if "content" in upd:
                                self.html[m.get("uuid")] = upd["content"]
                        elif (
                            t.startswith("Gui") and isinstance(m.get("props"), dict) and "uuid" in m
                        ):
                            props = m["props"]
                            label = props.get("label")
                            if isinstance(label, str):
                                self.gui[label] = m["uuid"]
                            if "value" in m:
                                self.values[m["uuid"]] = m["value"]
                            if "content" in props:
                                self.html[m["uuid"]] = props["content"]
                        elif t == "LocalStorageSetItemMessage":
                            self.storage[str(m.get("key"))] = str(m.get("value"))
                        elif t == "LocalStorageRemoveItemMessage":
                            self.storage.pop(str(m.get("key")), None)
                        elif t == "LocalStorageGetItemRequestMessage":
                            await ws.send(encode(storage_answer(m, self.storage)))
                        elif t == "NotificationShowMessage":
                            props = m.get("props", {}) if isinstance(m.get("props"), dict) else m
                            self.notifications.append(
                                f"{props.get('title', '')}: {props.get('body', '')}"
                            )
                    if self.measuring:
                        self.frames += 1
                        self.bytes += len(raw)
                        self.point_updates += point
        except Exception as exc:
            self.error = f"{type(exc).__name__}: {exc}"
            self.connected.set()

    async def wait_for(self, label: str, timeout: float = 20.0) -> str:
        deadline = time.monotonic() + timeout
        while label not in self.gui:
            if time.monotonic() > deadline or self.error:
                raise TimeoutError(f"no GUI element {label!r} ({self.error})")
            await asyncio.sleep(0.05)
        return self.gui[label]

    async def send(self, message: Any) -> None:
        await self.ws.send(encode(message))

    async def set(self, label: str, value: Any, pause: float = 0.06) -> None:
        """Set a GUI value (a click for buttons: value True) as the browser would."""
        uuid = await self.wait_for(label)
        await self.send(gui_update(uuid, value))
        if pause:
            await asyncio.sleep(pause)

    async def click(self, label: str, pause: float = 0.06) -> None:
        await self.set(label, True, pause)

    async def become_instructor(self, code: str) -> None:
        await self.set("Instructor code", code, 0.1)
        await self.click("Become instructor")
        await self.wait_for("Follow me")

    def _socket(self) -> dict[str, Any]:
        """``sock=`` a connected socket from :attr:`source` with :attr:`rcvbuf` (nothing:
        the default connection)."""
        if not (self.source or self.rcvbuf):
            return {}
        import socket
        from urllib.parse import urlsplit

        parts = urlsplit(self.url)
        sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        if self.rcvbuf:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, self.rcvbuf)
        if self.source:
            sock.bind((self.source, 0))
        sock.connect((parts.hostname or "127.0.0.1", parts.port or 80))
        sock.setblocking(False)
        return {"sock": sock}

    def stop_reading(self) -> None:
        """Never read the websocket again (the connection stays open)."""
        self.ws.transport.pause_reading()

    async def close(self) -> None:
        if self.ws is not None:
            await self.ws.close()
        if self._task is not None:
            await asyncio.gather(self._task, return_exceptions=True)


async def play(c: ProtoClient, preset: str = "example-1.1") -> None:
    """Load ``preset``, untick "pause at t_end" and press Play."""
    await c.set("Preset", preset, 0.3)
    await c.set("pause at t_end", False, 0.1)
    await c.set("Run", "Play", 0.1)


_REPORTS = itertools.count(1)


async def handled(c: ProtoClient, view: Any, timeout: float = 10.0) -> None:
    """Wait until an in-process server has handled every message ``c`` sent so far: a
    page's messages are handled in arrival order, so a camera report sent now reaches the
    page's server-side camera (``view.client.camera``) after all of them."""
    x = 3.0 + next(_REPORTS) / 1024
    await c.send(camera_message((x, 3.0, 3.0)))
    await until(
        lambda: float(view.client.camera.position[0]) == x,
        timeout,
        "the server to handle the page's messages",
    )


async def open_page(lab: Any, first_label: str) -> tuple[ProtoClient, Any]:
    """A page on the in-process server ``lab``: the client once ``first_label`` is shown,
    and the server's view of it."""
    before = set(lab.views)
    c = await ProtoClient(lab.url).start()
    await c.wait_for(first_label)
    new = await until(lambda: set(lab.views) - before, 10, "the view")
    return c, lab.views[max(new)]
