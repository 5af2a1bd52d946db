"""A scene API whose messages are only recorded: the HTML replay's serializer."""

from __future__ import annotations

import asyncio
import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Any


class _NullBuffer:
    """Message buffer that drops everything (the recording keeps its own copy)."""

    def push(self, message: Any) -> None:
        pass

    def atomic_start(self) -> None:
        pass

    def atomic_end(self) -> None:
        pass

    def remove_entity_state_from_buffer(self, entity_type: str, entity_id: str) -> None:
        pass

    def flush(self) -> None:
        pass


def recording_scene() -> tuple[Any, Any]:
    """A SceneApi whose messages only reach a fresh StateSerializer."""
    from viser import infra
    from viser._scene_api import SceneApi

    class _Conn(infra.WebsockMessageHandler):
        def __init__(self) -> None:
            super().__init__()
            self._buffer = _NullBuffer()

        def get_message_buffer(self) -> Any:  # type: ignore[override]
            return self._buffer

    class _Server:
        _scene_lifecycle_lock = threading.RLock()
        _connected_clients: dict[int, Any] = {}

    class _Owner:
        client_id = 0

        def __init__(self) -> None:
            self._websock_connection = _Conn()
            self._viser_server = _Server()

        def flush(self) -> None:
            pass

    owner = _Owner()
    serializer = owner._websock_connection.get_message_serializer(
        filter=lambda m: getattr(m, "include_in_scene_serialization", True)
    )
    loop = asyncio.new_event_loop()
    scene = SceneApi(owner, thread_executor=ThreadPoolExecutor(max_workers=1), event_loop=loop)  # type: ignore[arg-type]
    return scene, serializer
