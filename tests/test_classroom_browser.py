"""The classroom in a real browser: one instructor page and two student pages (Playwright +
Debian's Chromium; skipped without it, failing with CI=true, like tests/test_browser.py)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import pytest

from tests.support.browser import Page
from tests.support.waiting import wait_until

pytestmark = [
    pytest.mark.browser,
    pytest.mark.timeout(600),
]  # three SwiftShader pages on a shared 2-core machine
CODE = "demo-7391-4826"
INSTRUCTOR_BUTTONS = ("Follow me", "Release", "Push preset to all", "Notify all")


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    from analyzer_lab.lessons.catalog import get_lesson

    return make_lab(
        lesson="sphere",
        lessons=[get_lesson("sphere"), get_lesson("ellipsoid")],
        instructor_code=CODE,
        warm_up=False,
    )


def _label(lesson_id: str) -> str:
    from analyzer_lab.lessons.catalog import get_lesson
    from analyzer_lab.session.session import lesson_label

    return lesson_label(get_lesson(lesson_id))


def _instructor_buttons_visible(p: Page) -> list[str]:
    return [
        name
        for name in INSTRUCTOR_BUTTONS
        if p.page.get_by_role("button", name=name, exact=True).count()
    ]


def test_follow_me_and_release_with_two_students(lab: Any, browser: Any) -> None:
    inst, s1, s2 = Page(lab, browser), Page(lab, browser), Page(lab, browser)
    try:
        # students explore on their own first
        s1.load(_label("sphere"), "example-1.2")
        # the instructor signs in with the code (the panel exists only on that page)
        inst.open_folder("Instructor", "Instructor code")
        inst.fill("Instructor code", CODE)
        time.sleep(0.15)  # viser's 50 ms input throttle
        inst.button("Become instructor")
        inst.page.get_by_role("button", name="Follow me", exact=True).wait_for(timeout=10000)
        assert lab.classroom.is_instructor(inst.view.client.client_id)
        # a student page cannot reach any instructor control, even knowing where it would be
        for s in (s1, s2):
            s.open_folder("Instructor", "Instructor code")
            assert _instructor_buttons_visible(s) == []
            assert s.page.get_by_text("Instructor panel", exact=True).count() == 0
        # a wrong code on a student page is refused
        s2.fill("Instructor code", "guess-0000")
        time.sleep(0.15)  # viser's 50 ms input throttle
        wrong = lab.classroom.stats["wrong_codes"]
        s2.button("Become instructor")
        wait_until(lambda: lab.classroom.stats["wrong_codes"] > wrong, 10, "the code checked")
        assert (
            not lab.classroom.is_instructor(s2.view.client.client_id)
            and _instructor_buttons_visible(s2) == []
        )
        # the instructor's demo: another lesson, a preset, playing
        inst.select("Lesson", _label("ellipsoid"))
        wait_until(lambda: inst.session.lesson.id == "ellipsoid", 10, "instructor lesson")
        preset = inst.session.lesson.presets[0].name
        inst.load(_label("ellipsoid"), preset)
        inst.tab("Controls")
        inst.page.get_by_text("pause at t_end").click()
        inst.button("Play")
        inst.button("Follow me")
        for s in (s1, s2):
            wait_until(lambda s=s: s.session is inst.session, 10, "following")
            wait_until(
                lambda s=s: s.input_for("Lesson").input_value() == _label("ellipsoid"),
                10,
                "the demo's lesson shown",
            )
            wait_until(
                lambda s=s: s.input_for("Preset").input_value() == preset,
                10,
                "the demo's preset shown",
            )
        wait_until(lambda: inst.session.frame.t > 0.3, 10, "the demo plays")
        s1.shot("classroom-student-following")
        # a parameter change of the instructor reaches both students' pages
        inst.fill("u3(t) =", "4")
        wait_until(lambda: inst.session.raw_values()["u3"] == "4", 5, "u3 on the instructor")
        for s in (s1, s2):
            s.tab("Controls")
            wait_until(
                lambda s=s: s.input_for("u3(t) =").input_value() == "4",
                10,
                "u3 shown to the student",
            )
        # a following student sees a persistent banner and read-only controls
        for s in (s1, s2):
            assert "Following the instructor" in s.page.locator(".al-following-banner").inner_text()
            assert s.input_for("u3(t) =").is_disabled()
        assert inst.page.locator(".al-following-banner").count() == 0
        inst.shot("classroom-instructor")
        # release: each student has an own session again, starting from the demo
        t_demo = inst.session.frame.t
        inst.button("Release")
        for s in (s1, s2):
            wait_until(lambda s=s: s.session is not inst.session, 10, "released")
            assert s.session.lesson.id == "ellipsoid" and s.session.preset == preset
            assert s.session.raw_values()["u3"] == "4" and s.session.frame.t >= t_demo - 1e-6
        assert s1.session is not s2.session
        wait_until(lambda: not s1.input_for("u3(t) =").is_disabled(), 10, "controls back")
        wait_until(lambda: s1.page.locator(".al-following-banner").count() == 0, 5, "banner gone")
        s1.fill("u3(t) =", "2")
        wait_until(lambda: s1.session.raw_values()["u3"] == "2", 5, "the student's own edit")
        assert inst.session.raw_values()["u3"] == "4" and s2.session.raw_values()["u3"] == "4"
        s1.shot("classroom-student-released")
        for p in (inst, s1, s2):
            assert p.errors == [], p.errors
    finally:
        for p in (inst, s1, s2):
            p.close()


def test_presenter_mode_bookmarks(lab: Any, browser: Any) -> None:
    p = Page(lab, browser)
    try:
        p.load(_label("sphere"), "(defaults)")
        p.open_folder("Presenter", "Presenter mode")
        small = p.page.evaluate("parseFloat(getComputedStyle(document.documentElement).fontSize)")
        p.page.get_by_text("Presenter mode", exact=True).click()
        wait_until(
            lambda: (
                p.page.evaluate("parseFloat(getComputedStyle(document.documentElement).fontSize)")
                > small * 1.3
            ),
            10,
            "large fonts",
        )
        names = [q.name for q in p.session.lesson.presets]
        p.button("Next ▶")
        wait_until(lambda: p.session.preset == names[0], 5, "first bookmark")
        p.button("Next ▶")
        wait_until(lambda: p.session.preset == names[1], 5, "second bookmark")
        p.button("◀ Previous")
        wait_until(lambda: p.session.preset == names[0], 5, "back to the first")
        # keyboard: PageDown (a presentation clicker) steps forward through viser's hotkeys
        p.page.evaluate("document.activeElement && document.activeElement.blur()")
        p.page.keyboard.press("PageDown")
        wait_until(lambda: p.session.preset == names[1], 5, "PageDown")
        p.page.keyboard.press("PageUp")
        wait_until(lambda: p.session.preset == names[0], 5, "PageUp")
        wait_until(
            lambda: p.page.locator(".al-bookmark.al-current").count() == 1,
            5,
            "current bookmark marked",
        )
        p.shot("presenter-mode")
        assert p.errors == [], p.errors
    finally:
        p.close()


def _sign_in(p: Page) -> None:
    p.open_folder("Instructor", "Instructor code")
    p.fill("Instructor code", CODE)
    time.sleep(0.15)  # viser's 50 ms input throttle
    p.button("Become instructor")
    p.page.get_by_role("button", name="Follow me", exact=True).wait_for(timeout=10000)


def test_the_instructor_role_survives_a_reload_of_the_same_page(lab: Any, browser: Any) -> None:
    p = Page(lab, browser)
    other = Page(lab, browser)
    try:
        _sign_in(p)
        # a demo the class follows
        p.button("Follow me")
        room = lab.classroom
        wait_until(lambda: room.is_following(other.view.client.client_id), 10, "following")
        demo = room.demo
        before = set(lab.views)
        p.page.reload()
        p.label("Lesson").wait_for(timeout=30000)
        new = wait_until(lambda: set(lab.views) - before, 20, "the reloaded page's session")
        p.view = lab.views[max(new)]
        wait_until(lambda: lab.classroom.is_instructor(p.view.client.client_id), 10, "role back")
        p.page.get_by_role("button", name="Follow me", exact=True).wait_for(timeout=10000)
        # the token lives in that page's own storage: another page does not get the role
        assert not lab.classroom.is_instructor(other.view.client.client_id)
        # the class went on following the same demo, and the reloaded page took it over
        wait_until(lambda: room.broadcaster == p.view.client.client_id, 10, "the demo taken over")
        assert room.demo is demo and p.view.session is demo
        assert room.is_following(other.view.client.client_id) and room.away_until is None
        p.button("Release")
        wait_until(lambda: not room.is_following(other.view.client.client_id), 10, "released")
        assert p.errors == [] and other.errors == [], (p.errors, other.errors)
    finally:
        p.close()
        other.close()


@pytest.mark.parametrize("size", [(1280, 720), (1920, 1080)], ids=["720p", "1080p"])
def test_presenter_mode_gives_the_scene_the_projector(
    lab: Any, browser: Any, size: tuple[int, int]
) -> None:
    w, h = size
    p = Page(lab, browser, browser.new_context(viewport={"width": w, "height": h}))
    try:
        _sign_in(p)
        assert p.page.get_by_text("Assignments (class)", exact=True).count() == 1
        p.open_folder("Presenter", "Presenter mode")
        p.page.get_by_text("Presenter mode", exact=True).click()
        nxt = p.page.get_by_role("button", name="Next ▶", exact=True)
        nxt.wait_for(timeout=10000)
        # the panel leaves the scene at least 60 % of the width
        panel = p.page.locator("text=Analyzer Lab").first.locator(
            "xpath=ancestor::div[contains(@class,'Paper') or contains(@class,'paper')][1]"
        )
        box = panel.bounding_box() if panel.count() else None
        width = box["width"] if box else 440.0
        assert width <= 0.4 * w, (width, w)
        # Previous/Next and the readout at the top, above the lesson picker
        top_next = nxt.bounding_box()["y"]
        readout = p.page.locator(".al-readout").first.bounding_box()["y"]
        lesson = p.label("Lesson").bounding_box()["y"]
        assert top_next < lesson and readout < lesson
        # the instructor panel is not projected to the class, nor the class's table of
        # names and results unless the instructor asks for it
        wait_until(
            lambda: p.page.get_by_role("button", name="Follow me", exact=True).count() == 0,
            5,
            "instructor panel hidden",
        )
        table = p.page.get_by_text("Assignments (class)", exact=True)
        wait_until(lambda: table.count() == 0, 5, "the class table hidden")
        p.shot(f"presenter-{w}x{h}")
        p.page.get_by_text("Show the class table", exact=True).click()
        wait_until(lambda: table.count() == 1, 5, "the class table shown on request")
        p.page.get_by_text("Show the class table", exact=True).click()
        wait_until(lambda: table.count() == 0, 5, "the class table hidden again")
        nxt.click()
        wait_until(lambda: p.session.preset == p.session.lesson.presets[0].name, 5, "bookmark")
        assert p.errors == [], p.errors
    finally:
        p.close()
