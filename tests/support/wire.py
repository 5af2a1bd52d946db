"""viser's wire format, as a hand-made page speaks it.

A server frame (viser ``_message_producer``): 8 bytes msgpack length, 8 bytes compressed
length, a zstd-compressed msgpack ``{"messages": [...]}``, then raw binary buffers.  Client
messages are plain msgpack dicts with a ``type``.
"""

from __future__ import annotations

from typing import Any

from analyzer_lab.view.scene import LIVE_ROOT, live_node

#: The moving point of the quadric lessons (sphere, example 1.1), as the classroom counts it.
POINT_NODE = live_node("point", "point")
#: Messages that change an existing scene node (besides the messages that create one).
NODE_UPDATES = frozenset({"SceneNodeUpdateMessage", "SetPositionMessage", "SetOrientationMessage"})


def encode(message: Any) -> bytes:
    """A client message as sent on the websocket."""
    import msgspec

    return msgspec.msgpack.encode(message.as_serializable_dict())


def camera_message(position: tuple[float, float, float] = (3.0, 3.0, 3.0)) -> Any:
    """The camera report a page sends (its first one makes it a connected client)."""
    from viser import _messages

    return _messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0),
        position=position,
        fov=1.0,
        near=0.01,
        far=100.0,
        image_height=720,
        image_width=1280,
        look_at=(0.0, 0.0, 0.0),
        up_direction=(0.0, 0.0, 1.0),
    )


def gui_update(uuid: str, value: Any) -> Any:
    """A GUI element's new value, as the page sends it (a click: ``True``)."""
    from viser import _messages

    return _messages.GuiUpdateMessage(uuid=uuid, updates={"value": value})


def storage_answer(request: dict[str, Any], storage: dict[str, str]) -> Any:
    """The page's answer to the server's request for one item of its local storage."""
    from viser import _messages

    return _messages.LocalStorageGetItemResponseMessage(
        value=storage.get(str(request.get("key"))),
        error=None,
        request_uuid=str(request.get("request_uuid")),
    )


def decode_frame(raw: bytes, decompressor: Any = None) -> list[dict[str, Any]]:
    """The messages of one server frame (binary buffers are not decoded)."""
    import msgspec
    import zstandard

    inner = int.from_bytes(raw[0:8], "little")
    comp = int.from_bytes(raw[8:16], "little")
    payload = (decompressor or zstandard.ZstdDecompressor()).decompress(
        raw[16 : 16 + comp], max_output_size=inner
    )
    return list(msgspec.msgpack.decode(payload).get("messages", ()))


def live_update(message: dict[str, Any]) -> bool:
    """Does this message draw part of a played frame (create or update a node under
    :data:`LIVE_ROOT`)?  Removals do not count."""
    name = message.get("name")
    if not isinstance(name, str) or not name.startswith(LIVE_ROOT + "/"):
        return False
    kind = message.get("type", "")
    return kind in NODE_UPDATES or (
        kind.endswith("Message") and isinstance(message.get("props"), dict)
    )
