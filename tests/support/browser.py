"""The lab in a real browser: Debian's Chromium driven by Playwright.

Without Chromium (or the ``playwright`` package) the browser tests skip; with CI=true
they fail instead.  Screenshots go to tests/artifacts/ (git-ignored).
"""

from __future__ import annotations

import json
import os
import re
import time
from pathlib import Path
from typing import Any

import numpy as np

from tests.support.requirements import skip_or_fail
from tests.support.waiting import wait_until

CHROMIUM = "/usr/bin/chromium"
LAUNCH_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
ARTIFACTS = Path(__file__).resolve().parents[1] / "artifacts"
#: Closes the page's notifications (e.g. viser's software-WebGL notice); returns how many
#: closable ones are still shown (a closed one stays until its closing animation ends).
DISMISS_JS = """() => {
  for (const b of document.querySelectorAll('.mantine-Notification-closeButton, '
      + '[class*=Notification] button[aria-label], [class*=Notification] button')) b.click();
  return document.querySelectorAll('.mantine-Notification-closeButton').length;
}"""
#: Where viser keeps what the server stores in the page (``client.local_storage``).
STORAGE_PREFIX = "viser-user:"
#: viser sends a page's input to the server at most every 50 ms: the next input waits
#: this long, or the two would be merged into one.
INPUT_THROTTLE = 0.12


def require_browser() -> None:
    """Skip without Chromium or Playwright (fail under CI=true)."""
    missing = None
    if not os.path.exists(CHROMIUM):
        missing = f"Chromium not found at {CHROMIUM}; install it with `apt-get install chromium`"
    else:
        try:
            import playwright.sync_api  # noqa: F401
        except ImportError:
            missing = (
                "the python package `playwright` is missing (pip install playwright;"
                " the browser comes from `apt-get install chromium`)"
            )
    if missing:
        skip_or_fail(missing)


def quat_matrix(wxyz: np.ndarray) -> np.ndarray:
    """The rotation matrix of a quaternion (w, x, y, z), normalized first."""
    w, x, y, z = wxyz / np.linalg.norm(wxyz)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


class Page:
    """One tab of the lab: the Playwright page, its console errors and its server-side view."""

    def __init__(
        self,
        lab: Any,
        browser: Any,
        context: Any = None,
        ready_seconds: float = 60.0,
        first_label: str = "Lesson",
    ) -> None:
        """``first_label``: the lesson picker's label in the page's language."""
        self.lab = lab
        self.context = context or browser.new_context(
            viewport={"width": 1100, "height": 760}, accept_downloads=True
        )
        self.page = self.context.new_page()
        self.errors: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(f"pageerror: {e}"))
        before = set(lab.views)
        self.page.goto(lab.url)
        self.label(first_label).wait_for(timeout=90000)
        new = wait_until(lambda: set(lab.views) - before, 20, "the session")
        self.view = lab.views[max(new)]
        wait_until(
            lambda: self.page.locator("math").count() > 0, ready_seconds, "rendered equations"
        )

    @property
    def session(self) -> Any:
        return self.view.session

    def label(self, text: str) -> Any:
        return self.page.locator("label").filter(has_text=re.compile(f"^{re.escape(text)}$")).first

    def input_for(self, label: str) -> Any:
        """The visible input in the row of this label (viser puts label and input side by side)."""
        return (
            self.label(label)
            .locator("xpath=ancestor::div[.//input[not(@type='hidden')]][1]")
            .locator("input:not([type='hidden'])")
            .first
        )

    def options(self, label: str) -> list[str]:
        self.input_for(label).click()
        opts = self.page.get_by_role("option")
        opts.first.wait_for(timeout=5000)
        texts = opts.all_inner_texts()
        self.page.keyboard.press("Escape")
        return [t.strip() for t in texts]

    def select(self, label: str, option: str) -> None:
        self.input_for(label).click()
        self.page.get_by_role("option", name=option, exact=True).click()
        time.sleep(INPUT_THROTTLE)

    def button(self, name: str) -> None:
        self.page.get_by_role("button", name=name, exact=True).click()
        time.sleep(INPUT_THROTTLE)

    def tab(self, name: str) -> None:
        tab = self.page.get_by_role("tab", name=name)
        tab.click()
        wait_until(lambda: tab.get_attribute("aria-selected") == "true", 10, f"the {name} tab")

    def fill(self, label: str, text: str) -> None:
        box = self.input_for(label)
        box.fill(text)
        box.press("Enter")
        time.sleep(0.3)  # typed and sent (viser's input throttle) before the next input

    def open_folder(self, title: str, shows: str) -> None:
        """Open the panel's folder ``title``; returns once its text ``shows`` is visible."""
        self.page.get_by_text(title, exact=True).first.click()
        self.page.get_by_text(shows, exact=True).first.wait_for(state="visible", timeout=10000)

    def status(self) -> str:
        return self.page.locator(".al-message").first.inner_text()

    def field_errors(self) -> str:
        """The messages shown next to fields now (one line each)."""
        errs = self.page.locator(".al-field-error")
        return "\n".join(t for t in errs.all_inner_texts() if t.strip())

    def shot(self, name: str) -> bytes:
        """A screenshot without the browser's software-rendering notice (a machine
        without a GPU shows it; a student's laptop does not)."""
        wait_until(lambda: self.page.evaluate(DISMISS_JS) == 0, 30, "the notices closed")
        return self.page.screenshot(path=str(ARTIFACTS / f"{name}.png"))

    def saved_state(self) -> dict[str, Any] | None:
        """The state the server saved in this page (lesson, preset, values), if any."""
        from analyzer_lab.view.persistence import STORAGE_KEY

        text = self.page.evaluate("k => localStorage.getItem(k)", STORAGE_PREFIX + STORAGE_KEY)
        return json.loads(text) if text else None

    def camera_revision(self) -> int:
        """The session's camera revision (read once a load has finished: it is set)."""
        with self.session.lock:
            return self.session.camera_revision

    def framed_camera(self, revision: int) -> Any | None:
        """The camera the page reports when it is the one the view framed for the
        camera ``revision``; None before."""
        view = self.view
        framed = view.renderer.framed
        if view._drawn_camera_rev != revision or framed is None:
            return None
        cam = view.client.camera
        position = np.asarray(cam.position, dtype=float)
        scale = float(np.linalg.norm(framed[0] - framed[1]))
        look_at = np.asarray(cam.look_at, dtype=float)
        forward = quat_matrix(np.asarray(cam.wxyz, dtype=float))[:, 2]
        aim = (framed[1] - framed[0]) / scale
        if not (
            np.allclose(position, framed[0], rtol=0.0, atol=1e-4 * scale)
            and np.allclose(look_at, framed[1], rtol=0.0, atol=1e-4 * scale)
            and float(forward @ aim) > 1 - 1e-4
        ):
            return None  # the page has not reported the framed camera yet
        return cam

    def load(self, lesson_label: str, preset: str) -> None:
        if self.page.locator("label").filter(has_text=re.compile("^Lesson$")).count():
            current = self.input_for("Lesson").input_value()
            if current != lesson_label:
                self.select("Lesson", lesson_label)
        self.select("Preset", preset)
        wait_until(
            lambda: self.session.preset == (None if preset == "(defaults)" else preset),
            10,
            f"preset {preset}",
        )

    def close(self) -> None:
        self.context.close()
