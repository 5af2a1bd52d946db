"""The course record in a real browser (Playwright + Debian's Chromium): an instructor
opens a class with a 3-student roster and pushes a varied assignment; two students join
in their own browsers and answer on their own numbers (one right, one wrong); one reloads
and is still the same student with their attempt; the instructor's table shows exactly
that and the Moodle CSV downloads through the page."""

from __future__ import annotations

import csv
import io
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import pytest
from analyzer_lab.classroom.course import Course
from analyzer_lab.classroom.store.records import RosterEntry
from analyzer_lab.classroom.store.sql_store import SqlStore

from tests.support.browser import Page
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.browser, pytest.mark.timeout(600)]
CODE = "record-5130-browser"
JOIN = "MECH42"
TASK = "sphere-equator"  # varied: s from 1 to 4 in steps of 0.5
CLASS = "mech-browser"
ROSTER = [
    RosterEntry("s1", "Ann Lee", "ann@uni.example", "G1"),
    RosterEntry("s2", "Bob Marsh", "bob@uni.example", "G2"),
    RosterEntry("s3", "Chen Wei", "chen@uni.example", "G1"),
]


@pytest.fixture(scope="module")
def store(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SqlStore]:
    s = SqlStore(f"sqlite:///{Path(tmp_path_factory.mktemp('record')) / 'record.sqlite3'}")
    yield s
    s.close()


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any], store: SqlStore) -> Any:
    from analyzer_lab.lessons.catalog import get_lesson

    course = Course(store, store.open_class(CLASS, ROSTER, join_code=JOIN), b"b" * 32)
    return make_lab(
        lesson="sphere",
        lessons=[get_lesson("sphere")],
        instructor_code=CODE,
        warm_up=False,
        course=course,
    )


def _panel(lab: Any, p: Page) -> Any:
    return lab.classroom.board.students[p.view.client.client_id]


def _reload(lab: Any, p: Page) -> None:
    """Reload the tab (the same browser, its storage kept); ``p.view`` becomes the new
    page's view."""
    before = set(lab.views)
    p.page.reload()
    p.label("Lesson").wait_for(timeout=90000)
    new = wait_until(lambda: set(lab.views) - before, 30, "the reloaded page's session")
    p.view = lab.views[max(new)]


def _join_and_answer(lab: Any, p: Page, roster_id: str, answer: dict[str, str]) -> None:
    """Type the join code and the student id (once), then the answer, and check."""
    if p.input_for("Join code").is_visible():
        p.fill("Join code", JOIN)
        p.fill("Your name", roster_id)
    board = lab.classroom.board
    want = board.variant(TASK, board.class_id, roster_id)
    wait_until(
        lambda: (v := _panel(lab, p).variant) is not None and v.index == want.index,
        30,
        f"{roster_id}'s numbers",
    )
    p.tab("Controls")
    for name in ("u1", "u2", "u3"):
        p.fill(f"{name}(t) =", answer[name])
    wait_until(
        lambda: all(p.session.raw_values()[n] == answer[n] for n in ("u1", "u2", "u3")),
        20,
        "the answer's values",
    )
    p.button("Check my answer")


def _verdict(p: Page, checks: int) -> dict[str, str]:
    """Each check's verdict on the page, once the page shows ``checks`` of them."""
    items = p.page.locator(".al-check")
    wait_until(lambda: items.count() == checks, 60, "the verdict")
    return {
        str(c.get_attribute("data-check")): str(c.get_attribute("data-pass")) for c in items.all()
    }


def _who(p: Page) -> str:
    who = p.page.locator(".al-student-who")
    return str(who.first.inner_text()) if who.count() else ""


def _rows(inst: Page) -> list[list[str]]:
    rows = inst.page.locator(".al-roster-row")
    return [[c.strip() for c in r.locator("td").all_inner_texts()] for r in rows.all()]


def test_a_class_with_a_roster_joins_answers_reloads_and_downloads_grades(
    lab: Any, browser: Any, store: SqlStore
) -> None:
    board = lab.classroom.board
    ann_v = board.variant(TASK, CLASS, "s1")
    # the second student: the first roster id whose numbers differ from Ann's
    other = next(r for r in ("s2", "s3") if board.variant(TASK, CLASS, r).index != ann_v.index)
    other_v = board.variant(TASK, CLASS, other)
    other_name = next(e.name for e in ROSTER if e.roster_id == other)
    inst, ann, bob = Page(lab, browser), Page(lab, browser), Page(lab, browser)
    try:
        inst.open_folder("Instructor", "Instructor code")
        inst.fill("Instructor code", CODE)
        inst.button("Become instructor")
        inst.page.get_by_role("button", name="Push assignment to all", exact=True).wait_for(
            timeout=30000
        )
        assert JOIN in inst.page.locator(".al-join-code").first.inner_text()
        inst.select("Assignment for all", TASK)
        inst.button("Push assignment to all")
        for p in (ann, bob):
            wait_until(lambda p=p: _panel(lab, p).active is not None, 30, "the pushed task")
            p.page.locator(".al-assignment-task").first.wait_for(timeout=30000)
        # Ann answers her numbers right; the other student answers half the speed (wrong)
        _join_and_answer(lab, ann, "s1", ann_v.assignment.answers["correct"])
        _join_and_answer(lab, bob, other, other_v.assignment.answers["wrong"])
        assert _verdict(ann, 2) == {"equator": "yes", "speed": "yes"}
        assert _verdict(bob, 2) == {"equator": "yes", "speed": "no"}
        s_ann, s_other = ann_v.values["s"], other_v.values["s"]
        assert s_ann != s_other
        for p, s in ((ann, s_ann), (bob, s_other)):
            assert f"Your numbers: s = {s:g}" in p.page.locator(".al-variant").first.inner_text()
        wait_until(lambda: "Ann Lee (s1)" in _who(ann), 30, "Ann recorded as herself")
        # Ann reloads: the page brings her back from its token, on the same numbers
        _reload(lab, ann)
        ann.select("Assignment", TASK)
        wait_until(lambda: "Ann Lee (s1)" in _who(ann), 60, "Ann after the reload")
        assert not ann.input_for("Your name").is_visible()
        assert not ann.input_for("Join code").is_visible()
        wait_until(
            lambda: (v := _panel(lab, ann).variant) is not None and v.index == ann_v.index,
            30,
            "Ann's numbers after the reload",
        )
        # the instructor's table: exactly these two students, one attempt each
        wait_until(lambda: len(_rows(inst)) == 2, 30, "two rows in the instructor's table")
        rows = sorted(_rows(inst))
        assert [r[:3] for r in rows] == sorted(
            [["Ann Lee", "1", "yes"], [other_name, "1", "no"]]
        ), rows
        # the record holds the same: each attempt under its roster student and variant
        info = store.get_class(CLASS)
        assert info is not None
        ids = {s.id: s.roster_id for s in store.students(info.id)}
        got = sorted((ids[a.student_id], a.variant, a.passed) for a in store.attempts(info.id))
        assert got == sorted([("s1", ann_v.label, True), (other, other_v.label, False)])
        # the Moodle CSV, downloaded through the instructor's page
        btn = inst.page.get_by_role("button", name="Download grades (Moodle CSV)", exact=True)
        btn.scroll_into_view_if_needed()
        with inst.page.expect_download(timeout=30000) as dl:
            btn.click()
        assert dl.value.suggested_filename.startswith("grades-moodle-")
        text = Path(dl.value.path()).read_text(encoding="utf-8")
        table = list(csv.reader(io.StringIO(text)))
        score = {"s1": "1", other: "0"}
        assert table == [["ID number", "Email address", "Full name", TASK]] + [
            [e.roster_id, e.email, e.name, score.get(e.roster_id, "")] for e in ROSTER
        ]
        for p in (inst, ann, bob):
            assert p.errors == [], p.errors
    finally:
        for p in (inst, ann, bob):
            p.close()
