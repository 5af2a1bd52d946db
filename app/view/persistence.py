"""Persistence: a page's state saved in its browser and restored after a reload."""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from analyzer_lab.session.session import Session, SessionState

if TYPE_CHECKING:
    import viser

STORAGE_KEY = "analyzer-lab-state"
#: The page's language (its code), chosen on the page and kept by the browser.
LANGUAGE_KEY = "analyzer-lab-language"

log = logging.getLogger(__name__)


def save_state(client: viser.ClientHandle, session: Session) -> None:
    """Save the session's state (lesson, preset, values, playback) in the page."""
    try:
        client.local_storage.set_item(STORAGE_KEY, session.state().to_json())
    except Exception:  # a page that closed meanwhile
        log.debug("state not saved in page %s", client.client_id, exc_info=True)


def save_language(client: viser.ClientHandle, code: str) -> None:
    """Keep the page's language in its browser (for its next pages)."""
    try:
        client.local_storage.set_item(LANGUAGE_KEY, code)
    except Exception:  # a page that closed meanwhile
        log.debug("language not saved in page %s", client.client_id, exc_info=True)


def saved_language(client: viser.ClientHandle, timeout: float = 2.0) -> tuple[bool, str | None]:
    """(whether the page answered, the language code its browser kept, if any); the code
    is unchecked: the caller resolves it.  A page that does not answer is not asked for
    its saved state either (it would keep its page waiting twice)."""
    try:
        saved = client.local_storage.get_item(LANGUAGE_KEY, timeout=timeout)
    except Exception:  # no answer in time, or a page that closed meanwhile
        log.debug("no language read from page %s", client.client_id, exc_info=True)
        return False, None
    return True, (str(saved)[:40] if saved else None)


def restore_state(client: viser.ClientHandle, session: Session, timeout: float = 2.0) -> None:
    """Apply the state the page saved before a reload, if any; a stale or hand-made
    state is ignored with a message."""
    try:
        saved = client.local_storage.get_item(STORAGE_KEY, timeout=timeout)
    except Exception:  # no answer in time, or a page that closed meanwhile
        log.debug("no saved state read from page %s", client.client_id, exc_info=True)
        return
    if not saved:
        return
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
