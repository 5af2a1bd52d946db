"""What a student set, as plain JSON data (saved in the browser, copied between
sessions), and the refusal every part of the app raises."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from typing import Any

#: Size limit of a saved state (bytes of JSON) accepted from a browser.
MAX_STATE_BYTES = 20000


class LabError(ValueError):
    """A refused request; ``str(err)`` is one line for the user."""


@dataclass
class SessionState:
    """What a student set: enough to rebuild the session (JSON-friendly)."""

    lesson: str
    preset: str | None = None
    values: dict[str, Any] = field(default_factory=dict)
    speed: float = 1.0
    pause_at_end: bool = True
    visible_vectors: list[str] | None = None

    def to_json(self) -> str:
        return json.dumps(asdict(self), allow_nan=False, default=str)

    @classmethod
    def from_json(cls, text: str) -> SessionState:
        """Parse a saved state; raise :class:`LabError` on anything malformed."""
        if not isinstance(text, str) or len(text) > MAX_STATE_BYTES:
            raise LabError("saved state is missing or too large")
        try:
            data = json.loads(text)
        except (ValueError, RecursionError) as exc:
            raise LabError(f"saved state is not valid JSON: {exc}") from None
        if not isinstance(data, dict) or not isinstance(data.get("lesson"), str):
            raise LabError("saved state has no lesson")
        values = data.get("values") or {}
        if not isinstance(values, dict) or not all(isinstance(k, str) for k in values):
            raise LabError("saved state: values must be an object")
        clean: dict[str, Any] = {}
        for k, v in values.items():
            if isinstance(v, (str, int, float, bool)) and not (isinstance(v, str) and len(v) > 400):
                clean[k] = v
        preset = data.get("preset")
        speed = data.get("speed", 1.0)
        vectors = data.get("visible_vectors")
        return cls(
            lesson=data["lesson"][:80],
            preset=preset[:80] if isinstance(preset, str) else None,
            values=clean,
            speed=float(speed)
            if isinstance(speed, (int, float)) and not isinstance(speed, bool)
            else 1.0,
            pause_at_end=bool(data.get("pause_at_end", True)),
            visible_vectors=[str(v)[:40] for v in vectors][:20]
            if isinstance(vectors, list)
            else None,
        )
