"""``run.show()`` in a real browser with every request to the network refused: the page draws
its scene from what it holds (Debian's Chromium through Playwright; skipped with a message
where it is missing, except under ``CI=true``)."""

from __future__ import annotations

import os
import time
from pathlib import Path

import analyzer_lab as al
import pytest

pytestmark = [pytest.mark.browser, pytest.mark.live, pytest.mark.timeout(300)]

CHROMIUM = "/usr/bin/chromium"
LAUNCH_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
LOCAL = ("file:", "data:", "blob:", "about:")


def require_browser() -> None:
    missing = None
    if not os.path.exists(CHROMIUM):
        missing = f"Chromium not found at {CHROMIUM}; install it with `apt-get install chromium`"
    else:
        try:
            import playwright.sync_api  # noqa: F401
        except ImportError:
            missing = "the python package `playwright` is missing (pip install playwright)"
    if missing:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(missing + " (CI=true: browser tests must run)")
        pytest.skip(missing)


def test_the_scene_plays_offline(tmp_path: Path) -> None:
    require_browser()
    from playwright.sync_api import Route, sync_playwright

    page_file = al.run("sphere", preset="example-1.2").show().save(tmp_path / "scene.html")
    outside: list[str] = []
    errors: list[str] = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=LAUNCH_ARGS)
        try:
            page = browser.new_page(viewport={"width": 900, "height": 600})

            def route(r: Route) -> None:
                if r.request.url.startswith(LOCAL):
                    r.continue_()
                else:
                    outside.append(r.request.url)
                    r.abort()

            page.route("**/*", route)
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto(page_file.as_uri())
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                if page.evaluate("() => document.querySelectorAll('canvas').length") > 0:
                    break
                time.sleep(0.25)
            assert page.evaluate("() => document.querySelectorAll('canvas').length") > 0
            assert "Curve on a sphere" in page.inner_text("#al-caption")
            time.sleep(2)  # the replay plays
        finally:
            browser.close()
    assert outside == [] and errors == []
