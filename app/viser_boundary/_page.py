"""The lab's viser server: our page (title, keys kept in fields), no share tunnel, the
websocket hardened, callbacks ordered and the GUI guarded."""

from __future__ import annotations

import html
import tempfile
from pathlib import Path
from typing import Any

from analyzer_lab.viser_boundary._callbacks import order_callbacks
from analyzer_lab.viser_boundary._gui_guard import guard_gui_updates
from analyzer_lab.viser_boundary._hot_path import share_prop_hints
from analyzer_lab.viser_boundary._patches import PATCH_LOCK, check_viser_version
from analyzer_lab.viser_boundary._websocket import harden_websocket

PAGE_TITLE = "Analyzer Lab"

#: Keys typed into a field (arrows on a focused slider, letters in a formula) stay in that
#: field: they do not reach the page's camera controls, which listen further up.
KEYS_STAY_IN_FIELDS = """<script>
document.addEventListener("keydown", function (e) {
  var t = e.target;
  if (t && t.closest && t.closest('input, textarea, select, [role="slider"]')) {
    e.stopImmediatePropagation();
  }
}, false);
</script>"""


#: Phones (viser's bottom sheet, under Mantine's ``xs`` breakpoint of 36em): the sheet leaves
#: its fixed place over the canvas for a row of its own below it, as wide as the screen and at
#: most half its height (its content scrolls), so the canvas, and the scene framed in it, is
#: exactly the part of the screen the panel leaves free.  Notifications stay on the screen
#: at every size (viser centres their box on its left edge once a panel is docked).
#: The sheet is the only fixed Paper of viser's page; its parent is the row that holds the
#: canvas.
PHONE_LAYOUT = """<style>
@media (max-width: 36em) {
  div:has(> .mantine-Paper-root[style*="position: fixed"]) {
    flex-direction: column !important;
  }
  div:has(> .mantine-Paper-root[style*="position: fixed"]) > div:has(canvas) {
    flex: 1 1 0 !important; min-height: 0 !important; height: auto !important;
  }
  .mantine-Paper-root[style*="position: fixed"] {
    position: static !important; width: 100% !important; max-height: 50vh !important;
    flex: 0 0 auto !important;
  }
  .mantine-Paper-root[style*="position: fixed"] [style*="width: 20em"] {
    width: 100% !important;
  }
}
.mantine-Notifications-root {
  left: 0.5em !important; right: auto !important; transform: none !important;
  width: min(20em, calc(100% - 1em)) !important; max-width: none !important;
}
</style>"""


#: No text of viser's own widgets below 11 px (its compact buttons print 10 px).
#: Text a small screen and a projector can read: buttons' text no smaller than 11 px, and
#: the labels' grey and the brand blue dark enough for 4.5:1 on white (WCAG's minimum for
#: small text; viser's theme gives 3.3:1 and 4.4:1); the lab's own texts (readout, notes,
#: messages, derivations) indented as far as viser's labels, not flush at the panel's edge.
READABLE_TEXT = """<style>
.al-readout, .al-preset-note, .al-message, .al-frame-message, .al-derivation, .al-lesson-head,
.al-plots-undefined, .al-error, .al-field-error {
  padding-left: 0.55rem; padding-right: 0.55rem; box-sizing: border-box;
}
.mantine-Button-root { --button-fz: max(11px, 0.75rem) !important; }
.mantine-Slider-markLabel { color: #5c636a !important; }
:root, [data-mantine-color-scheme] {
  --mantine-color-dimmed: #5c636a !important;
  --mantine-color-custom-outline: #2b5fa8 !important;
  --mantine-color-custom-filled: #2b5fa8 !important;
  --mantine-color-custom-filled-hover: #234d8a !important;
  --mantine-color-custom-light-color: #2b5fa8 !important;
  --mantine-color-custom-text: #2b5fa8 !important;
  --mantine-color-custom-6: #2b5fa8 !important;
  --mantine-primary-color-filled: #2b5fa8 !important;
  --mantine-primary-color-filled-hover: #234d8a !important;
  --mantine-primary-color-light-color: #2b5fa8 !important;
}
</style>"""


#: The attribute of the hidden element that carries the page's language (:func:`language_marker`).
LANG_ATTRIBUTE = "data-al-lang"

#: The page's ``<html lang>`` follows the language its panel shows (viser serves
#: ``lang="en"``): the panel carries it in a hidden element (:func:`language_marker`),
#: read again whenever the panel changes.
FOLLOW_LANGUAGE = """<script>
(function () {
  var root = document.documentElement;
  function follow() {
    var marker = document.querySelector("[ATTR]");
    var code = marker && marker.getAttribute("ATTR");
    if (code && /^[a-z]{2,3}(-[A-Z]{2})?$/.test(code) && root.lang !== code) { root.lang = code; }
  }
  new MutationObserver(follow).observe(root, {
    subtree: true, childList: true, attributes: true, attributeFilter: ["ATTR"]
  });
})();
</script>""".replace("ATTR", LANG_ATTRIBUTE)


def language_marker(code: str) -> str:
    """The hidden element that sets the page's ``<html lang>`` to ``code``."""
    return f'<span {LANG_ATTRIBUTE}="{html.escape(code)}" hidden></span>'


def _client_root() -> Path:
    """viser's client page with our title (with :data:`KEYS_STAY_IN_FIELDS`,
    :data:`PHONE_LAYOUT`, :data:`READABLE_TEXT` and :data:`FOLLOW_LANGUAGE`), in a private
    temporary directory."""
    import viser

    src = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"
    text = src.read_text(encoding="utf-8")
    text = text.replace("<title>Viser</title>", f"<title>{PAGE_TITLE}</title>", 1)
    text = text.replace('content="Viser client"', f'content="{PAGE_TITLE}"', 1)
    text = text.replace(
        "</head>",
        KEYS_STAY_IN_FIELDS + PHONE_LAYOUT + READABLE_TEXT + FOLLOW_LANGUAGE + "</head>",
        1,
    )
    root = Path(tempfile.mkdtemp(prefix="analyzer-lab-page-"))
    (root / "index.html").write_text(text, encoding="utf-8")
    return root


def make_viser_server(host: str, port: int, verbose: bool) -> Any:
    """A ViserServer serving our page (title) whose share tunnel cannot be started."""
    import viser
    from viser import _messages, infra

    check_viser_version()
    harden_websocket()  # before the server starts listening
    share_prop_hints()
    root = _client_root()
    original = infra.WebsockServer

    def factory(*args: Any, **kwargs: Any) -> Any:
        kwargs["http_server_root"] = root
        return original(*args, **kwargs)

    with PATCH_LOCK:
        infra.WebsockServer = factory  # type: ignore[misc]
        try:
            server = viser.ViserServer(host=host, port=port, verbose=verbose)
        finally:
            infra.WebsockServer = original  # type: ignore[misc]
    # the share tunnel: drop the handlers any client could trigger, and the method
    ws = server._websock_server
    for msg in (_messages.ShareUrlRequest, _messages.ShareUrlDisconnect):
        try:
            ws.unregister_handler(msg)
        except (AssertionError, KeyError):
            pass
    server.request_share_url = lambda *a, **k: None  # type: ignore[method-assign]
    guard_gui_updates(server.gui, server)
    order_callbacks(server)  # one connection's callbacks run in the order its messages came
    server.gui.configure_theme(show_share_button=False, show_logo=False, control_width="large")
    server.gui.set_panel_label(PAGE_TITLE)
    return server
