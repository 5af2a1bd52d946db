"""The classroom across two ``serve`` processes in a real browser: the instructor's page on
worker 1, a student's page on worker 2, joined by a real redis-server started here
(Playwright + Debian's Chromium; skipped without them or without redis-server, failing
under CI=true)."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.support.browser import ARTIFACTS, require_browser
from tests.support.redis_server import RedisServer
from tests.support.servers import free_port, start_worker, stop_process
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(400)]
CODE = "remote-3306-follow"


class RemotePage:
    """A tab on a server running in another process (only what the page shows)."""

    def __init__(self, browser: Any, url: str) -> None:
        self.context = browser.new_context(viewport={"width": 1100, "height": 760})
        self.page = self.context.new_page()
        self.errors: list[str] = []
        self.page.on("console", lambda m: self.errors.append(m.text) if m.type == "error" else None)
        self.page.on("pageerror", lambda e: self.errors.append(f"pageerror: {e}"))
        self.page.goto(url)
        self.label("Lesson").wait_for(timeout=60000)

    def label(self, text: str) -> Any:
        return self.page.locator("label").filter(has_text=re.compile(f"^{re.escape(text)}$")).first

    def input_for(self, label: str) -> Any:
        return (
            self.label(label)
            .locator("xpath=ancestor::div[.//input[not(@type='hidden')]][1]")
            .locator("input:not([type='hidden'])")
            .first
        )

    def select(self, label: str, option: str) -> None:
        self.input_for(label).click()
        self.page.get_by_role("option", name=option, exact=True).click()
        time.sleep(0.15)  # viser's 50 ms input throttle

    def button(self, name: str) -> None:
        self.page.get_by_role("button", name=name, exact=True).click()
        time.sleep(0.15)  # viser's 50 ms input throttle

    def fill(self, label: str, text: str) -> None:
        box = self.input_for(label)
        box.fill(text)
        box.press("Enter")
        time.sleep(0.3)  # typed and sent (viser's input throttle) before the next input

    def close(self) -> None:
        self.context.close()


@pytest.fixture(scope="module")
def servers(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, str]]:
    require_browser()
    redis_server = RedisServer().start()
    tmp: Path = tmp_path_factory.mktemp("workers")
    ports = [free_port(), free_port()]
    procs = [
        start_worker(p, redis_server.url, f"w{k + 1}", CODE, open(tmp / f"w{k + 1}.log", "w"))
        for k, p in enumerate(ports)
    ]
    yield f"http://127.0.0.1:{ports[0]}/", f"http://127.0.0.1:{ports[1]}/"
    for p in procs:
        stop_process(p)
    redis_server.stop()


def test_a_student_on_worker_2_follows_the_instructor_on_worker_1(
    servers: tuple[str, str], browser: Any
) -> None:
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.session.session import lesson_label

    inst = RemotePage(browser, servers[0])
    student = RemotePage(browser, servers[1])
    try:
        # the instructor signs in on worker 1
        inst.page.get_by_text("Instructor", exact=True).first.click()
        inst.label("Instructor code").wait_for(state="visible", timeout=10000)
        inst.fill("Instructor code", CODE)
        inst.button("Become instructor")
        inst.page.get_by_role("button", name="Follow me", exact=True).wait_for(timeout=10000)
        # the student's page on worker 2 is counted on the instructor's panel
        counts = inst.page.locator(".al-class-counts")
        wait_until(
            lambda: "1 student(s) connected on 2 servers" in counts.inner_text(), 15, "count"
        )
        # a demo on another lesson and preset, playing, then follow me
        ellipsoid = lesson_label(get_lesson("ellipsoid"))
        inst.select("Lesson", ellipsoid)
        wait_until(lambda: inst.input_for("Lesson").input_value() == ellipsoid, 10, "lesson")
        preset = get_lesson("ellipsoid").presets[0].name
        inst.select("Preset", preset)
        inst.page.get_by_role("tab", name="Controls").click()
        inst.page.get_by_text("pause at t_end").click()
        inst.button("Play")
        inst.button("Follow me")
        wait_until(
            lambda: student.input_for("Lesson").input_value() == ellipsoid, 20, "demo's lesson"
        )
        wait_until(lambda: student.input_for("Preset").input_value() == preset, 10, "preset")
        banner = student.page.locator(".al-following-banner")
        wait_until(
            lambda: banner.count() and "Following the instructor" in banner.inner_text(),
            10,
            "banner",
        )
        # the instructor's edit reaches the student's page on the other worker
        inst.fill("u3(t) =", "4")
        student.page.get_by_role("tab", name="Controls").click()
        wait_until(lambda: student.input_for("u3(t) =").input_value() == "4", 15, "u3 shown")
        assert student.input_for("u3(t) =").is_disabled()
        wait_until(
            lambda: (
                '<b class="al-following">1</b>' in counts.inner_html()
                or "1</b> following" in counts.inner_html()
            ),
            10,
            "following count",
        )
        student.page.screenshot(path=str(ARTIFACTS / "classroom-remote-student.png"))
        # release: the student's own controls come back, from the demo's values
        inst.button("Release")
        wait_until(lambda: not student.input_for("u3(t) =").is_disabled(), 15, "released")
        assert student.input_for("u3(t) =").input_value() == "4"
        assert student.page.locator(".al-following-banner").count() == 0 or (
            not student.page.locator(".al-following-banner").is_visible()
        )
        for p in (inst, student):
            assert p.errors == [], p.errors
    finally:
        inst.close()
        student.close()
