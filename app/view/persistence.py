"""Persistence: a page's state saved in its browser and restored after a reload."""

from __future__ import annotations

import json
import logging
from typing import TYPE_CHECKING

from analyzer_lab.session.session import Session, SessionState

if TYPE_CHECKING:
    import viser

STORAGE_KEY = "analyzer-lab-state"
#: The entry of the saved state that holds the language chosen on the page (its code).
LANGUAGE_ENTRY = "language"

log = logging.getLogger(__name__)


def save_state(client: viser.ClientHandle, session: Session, language: str | None = None) -> None:
    """Save the session's state (lesson, preset, values, playback) in the page, with the
    language chosen on it (one entry: the page reads it back in one request)."""
    text = session.state().to_json()
    if language:
        data = json.loads(text)
        data[LANGUAGE_ENTRY] = language
        text = json.dumps(data)
    try:
        client.local_storage.set_item(STORAGE_KEY, text)
    except Exception:  # a page that closed meanwhile
        log.debug("state not saved in page %s", client.client_id, exc_info=True)


def saved_language(saved: str) -> str | None:
    """The language code in a saved state, if any (unchecked: the caller resolves it)."""
    try:
        data = json.loads(saved)
    except (ValueError, RecursionError):
        return None
    code = data.get(LANGUAGE_ENTRY) if isinstance(data, dict) else None
    return code[:40] if isinstance(code, str) and code else None


def restore_state(client: viser.ClientHandle, session: Session, timeout: float = 2.0) -> str | None:
    """Apply the state the page saved before a reload, if any; a stale or hand-made
    state is ignored with a message.  Returns the language chosen on the page, if any."""
    try:
        saved = client.local_storage.get_item(STORAGE_KEY, timeout=timeout)
    except Exception:  # no answer in time, or a page that closed meanwhile
        log.debug("no saved state read from page %s", client.client_id, exc_info=True)
        return None
    if not saved:
        return None
    language = saved_language(saved)
    try:
        problems = session.apply_state(SessionState.from_json(saved))
        restored = f"restored your last lesson and parameters ({session.lesson.id})"
        if problems:
            # one notice with both: the newest notice is the one the page shows
            session.notify(f"{restored}, but: {'; '.join(problems)}", "warning")
        else:
            session.notify(restored)
    except Exception as exc:
        log.warning("saved state of page %s ignored", client.client_id, exc_info=True)
        session.notify(f"saved state ignored: {exc}", "warning")
    return language
