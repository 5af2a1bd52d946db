"""Assignments in a real browser: the instructor pushes one, two students answer (one
right, one wrong) and the instructor's live table shows exactly that; screenshots of the
assignment view (Playwright + Debian's Chromium, like tests/test_classroom_browser.py)."""

from __future__ import annotations

import csv
import io
import json
import time
from collections.abc import Callable
from typing import Any

import pytest

from tests.support.browser import Page
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]
CODE = "assign-4826-class"
TASK = "circle-speed-10"


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    from analyzer_lab.lessons.catalog import get_lesson

    return make_lab(
        lesson="sphere",
        lessons=[get_lesson("sphere"), get_lesson("circle")],
        instructor_code=CODE,
        warm_up=False,
    )


def _sign_in(p: Page) -> None:
    p.open_folder("Instructor", "Instructor code")
    p.fill("Instructor code", CODE)
    time.sleep(0.15)  # viser's 50 ms input throttle
    p.button("Become instructor")
    p.page.get_by_role("button", name="Push assignment to all", exact=True).wait_for(timeout=10000)


def _panel(lab: Any, p: Page) -> Any:
    return lab.classroom.board.students[p.view.client.client_id]


def _answer(p: Page, name: str, u: str | None) -> None:
    """Answer as ``name`` (typed the first time: then the page knows its student)."""
    if p.input_for("Your name").is_visible():
        p.fill("Your name", name)
    if u is not None:
        p.tab("Controls")
        p.fill("u(t) =", u)
        wait_until(lambda: p.session.raw_values()["u"] == u, 5, "the answer's value")
    p.button("Check my answer")


def test_push_two_students_right_and_wrong_live_table(lab: Any, browser: Any) -> None:
    inst, s1, s2 = Page(lab, browser), Page(lab, browser), Page(lab, browser)
    try:
        _sign_in(inst)
        inst.select("Assignment for all", TASK)
        inst.button("Push assignment to all")
        for s in (s1, s2):
            wait_until(lambda s=s: s.session.lesson.id == "circle", 15, "the pushed lesson")
            wait_until(lambda s=s: (_panel(lab, s).active or None) is not None, 10, "opened")
            assert _panel(lab, s).active.id == TASK
            s.page.locator(".al-assignment-task").first.wait_for(timeout=10000)
            assert "speed stays at 10" in s.page.locator(".al-assignment-task").inner_text()
        # the locked fields are read-only, the unlocked one is not
        s1.tab("Controls")
        wait_until(lambda: s1.input_for("x0").is_disabled(), 10, "x0 locked")
        assert not s1.input_for("u(t) =").is_disabled()
        # one right answer (u = 2), one wrong (u left at 1); a name is user text
        _answer(s1, "Ann <b>bold</b>", "2")
        _answer(s2, "Bob", None)
        wait_until(lambda: len(s2.page.locator(".al-check").all()) == 1, 15, "s2 verdict")
        wait_until(lambda: len(s1.page.locator(".al-check").all()) == 1, 15, "s1 verdict")
        ok = s1.page.locator(".al-check").first
        bad = s2.page.locator(".al-check").first
        assert ok.get_attribute("data-pass") == "yes"
        assert bad.get_attribute("data-pass") == "no" and bad.get_attribute("data-check") == "speed"
        assert "misses the tolerance 1e-06 by 5" in bad.inner_text()
        # the instructor's table: exactly these two rows
        rows = inst.page.locator(".al-roster-row")
        wait_until(lambda: rows.count() == 2, 15, "two rows in the instructor's table")
        cells = [[c.strip() for c in r.locator("td").all_inner_texts()] for r in rows.all()]
        assert cells[0][:3] == ["Ann <b>bold</b>", "1", "yes"]
        assert float(cells[0][3]) >= 0
        assert cells[1] == ["Bob", "1", "no", ""]
        assert inst.page.locator(".al-roster b").count() == 0  # the name stayed text
        # a second, now right, attempt of Bob updates his row live
        _answer(s2, "Bob", "2")
        wait_until(lambda: s2.session.raw_values()["u"] == "2", 10, "Bob's new value")
        roster = lab.classroom.board.progress
        wait_until(lambda: roster.rows(TASK)[-1].attempts == 2, 15, "Bob's second attempt")
        wait_until(
            lambda: (
                [c.strip() for c in rows.nth(1).locator("td").all_inner_texts()][1:3]
                == ["2", "yes"]
            ),
            15,
            "Bob's row after the second attempt",
        )
        # CSV export of the table
        inst.page.get_by_text("Download results (CSV)", exact=True).scroll_into_view_if_needed()
        with inst.page.expect_download(timeout=15000) as dl:
            inst.button("Download results (CSV)")
        table = list(csv.reader(io.StringIO(open(dl.value.path(), encoding="utf-8").read())))
        assert table[0][:4] == ["student", "assignment", "attempts", "passed"]
        assert [r[:4] for r in table[1:]] == [
            ["Ann <b>bold</b>", TASK, "1", "yes"],
            ["Bob", TASK, "2", "yes"],
        ]
        inst.shot("assignment-instructor-table")
        # a locked field refuses input from the page
        before = s1.session.raw_values()["x0"]
        assert s1.input_for("x0").is_disabled()
        for p in (inst, s1, s2):
            assert p.errors == [], p.errors
        assert s1.session.raw_values()["x0"] == before
    finally:
        for p in (inst, s1, s2):
            p.close()


def test_student_opens_from_list_and_sees_refusal_next_to_button(lab: Any, browser: Any) -> None:
    p = Page(lab, browser)
    try:
        p.select("Assignment", "circle-radius-2")
        wait_until(lambda: p.session.lesson.id == "circle", 10, "the assignment's lesson")
        p.button("Check my answer")
        err = p.page.locator(".al-assignment-error").first
        err.wait_for(timeout=10000)
        assert "type your name first" in err.inner_text()
        assert p.errors == [], p.errors
    finally:
        p.close()


def test_instructor_authors_an_assignment_from_the_state(lab: Any, browser: Any) -> None:
    from analyzer_lab.lessons.assignments import grade, parse_assignment

    inst = Page(lab, browser)
    try:
        _sign_in(inst)
        inst.open_folder("Author from this state", "Unlocked")
        inst.fill("Unlocked", "u1, warp")
        inst.button("Download assignment")
        err = inst.page.locator(".al-assignment-error").first
        err.wait_for(timeout=10000)
        assert "unlocked[1]" in err.inner_text() and "warp" in err.inner_text()
        inst.fill("Unlocked", "u1, u2, u3")
        inst.fill("Series to check", "speed")
        inst.fill("Metrics to check", "v2_max")
        inst.fill("Id", "class-sphere")
        with inst.page.expect_download(timeout=15000) as dl:
            inst.button("Download assignment")
        data = json.loads(open(dl.value.path(), encoding="utf-8").read())
        a = parse_assignment(data, "downloaded")
        assert a.id == "class-sphere" and a.lesson == "sphere" and a.unlocked == ("u1", "u2", "u3")
        assert {"speed-end", "speed-size", "v2-max-max", "v2-max-min"} == {c.id for c in a.checks}
        assert grade(a, a.answers["correct"]).passed
        assert inst.errors == [], inst.errors
    finally:
        inst.close()


@pytest.mark.parametrize("size", [(1400, 900), (1280, 720)], ids=["1400x900", "1280x720"])
def test_assignment_view_screenshots(lab: Any, browser: Any, size: tuple[int, int]) -> None:
    w, h = size
    p = Page(lab, browser, browser.new_context(viewport={"width": w, "height": h}))
    try:
        p.select("Assignment", "sphere-circle-plane")
        wait_until(lambda: _panel(lab, p).active is not None, 10, "opened")
        p.fill("Your name", "Student")
        p.button("Check my answer")
        wait_until(lambda: p.page.locator(".al-check").count() == 2, 15, "verdict")
        task = p.page.locator(".al-assignment-task").first.bounding_box()
        assert task is not None and task["width"] > 200 and task["y"] + 40 < h
        assert p.input_for("Lesson").is_disabled()  # leave the assignment first
        p.page.locator(".al-assignment-result").first.scroll_into_view_if_needed()
        p.shot(f"assignment-view-{w}x{h}")
        assert p.errors == [], p.errors
    finally:
        p.close()


def test_a_follower_gets_the_pushed_assignment_on_release(lab: Any, browser: Any) -> None:
    inst, s1 = Page(lab, browser), Page(lab, browser)
    try:
        _sign_in(inst)
        inst.button("Follow me")
        wait_until(lambda: s1.session is inst.session, 10, "following")
        inst.select("Assignment for all", "circle-radius-2")
        inst.button("Push assignment to all")
        wait_until(lambda: _panel(lab, s1).pending == "circle-radius-2", 10, "pending")
        assert _panel(lab, s1).active is None and inst.session.lesson.id == "sphere"
        inst.button("Release")
        wait_until(lambda: s1.session is not inst.session, 10, "released")
        wait_until(lambda: _panel(lab, s1).active is not None, 10, "opened on release")
        assert s1.session.lesson.id == "circle" and inst.session.lesson.id == "sphere"
        s1.tab("Controls")
        wait_until(lambda: s1.input_for("u(t) =").is_disabled(), 10, "u locked")
        assert not s1.input_for("x0").is_disabled()
        assert s1.input_for("Lesson").is_disabled()
        for p in (inst, s1):
            assert p.errors == [], p.errors
    finally:
        for p in (inst, s1):
            p.close()
