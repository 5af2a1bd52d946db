"""The token a page keeps in its browser's local storage to say which student it is:
class and student signed with the server's secret (HMAC-SHA256); the server checks it
on every reload, so a page cannot name another student."""

from __future__ import annotations

import hashlib
import hmac
import time

from analyzer_lab.classroom.store.records import JoinError
from analyzer_lab.lessons.kit.message import N_, Message

VERSION = "s1"
MAX_TOKEN = 200


def _mac(secret: bytes, body: str) -> str:
    return hmac.new(secret, body.encode("ascii"), hashlib.sha256).hexdigest()


def sign(secret: bytes, class_id: int, student_id: int, issued: float | None = None) -> str:
    body = f"{VERSION}.{int(class_id)}.{int(student_id)}.{int(issued if issued is not None else time.time())}"
    return f"{body}.{_mac(secret, body)}"


def verify(secret: bytes, token: object, class_id: int) -> int:
    """The student id the token names; :class:`JoinError` saying why it is refused."""
    if not isinstance(token, str) or len(token) > MAX_TOKEN:
        raise JoinError(Message(N_("the saved student token is not a token")))
    parts = token.split(".")
    if len(parts) != 5 or parts[0] != VERSION or not all(p.isdigit() for p in parts[1:4]):
        raise JoinError(Message(N_("the saved student token is malformed")))
    body = ".".join(parts[:4])
    if not hmac.compare_digest(parts[4], _mac(secret, body)):
        raise JoinError(
            Message(N_("the saved student token was not signed by this server (tampered with)"))
        )
    if int(parts[1]) != class_id:
        raise JoinError(Message(N_("the saved student token belongs to another class")))
    return int(parts[2])


__all__ = ["sign", "verify"]
