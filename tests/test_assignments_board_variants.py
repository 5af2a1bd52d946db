"""The assignments board hands each student their variant: real pages (viser's protocol
over a websocket, :class:`tests.support.client.ProtoClient`) against an in-process server."""

from __future__ import annotations

import asyncio
import copy
import json
from collections.abc import Callable
from typing import Any

import pytest
from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
from analyzer_lab.lessons.assignments import AssignmentError, parse_assignment

from tests.support.client import ProtoClient
from tests.support.waiting import until

pytestmark = pytest.mark.timeout(300)
TASK = "sphere-equator"


@pytest.fixture(scope="module")
def lab(make_lab: Callable[..., Any]) -> Any:
    return make_lab(lessons=[SPHERE], lesson="sphere", warm_up=False, restore=False)


async def page(lab: Any) -> tuple[ProtoClient, Any]:
    before = set(lab.views)
    c = await ProtoClient(lab.url).start()
    await c.wait_for("Run")
    new = await until(lambda: set(lab.views) - before, 10, "the view")
    return c, lab.views[max(new)]


def _panel(lab: Any, view: Any) -> Any:
    return lab.classroom.board.students[view.client.client_id]


def _task(c: ProtoClient) -> str:
    return next((h for h in c.html.values() if "al-assignment-task" in h), "")


def _verdict(c: ProtoClient) -> str:
    return next((h for h in c.html.values() if "al-assignment-result" in h), "")


def test_each_student_sees_their_variant_and_the_same_again(lab: Any) -> None:
    board = lab.classroom.board
    ann = board.variant(TASK, board.class_id, "Ann")
    bob = next(
        n
        for n in (f"Bob {k}" for k in range(50))
        if board.variant(TASK, board.class_id, n).index != ann.index
    )
    bob_v = board.variant(TASK, board.class_id, bob)

    async def go() -> None:
        (c1, v1), (c2, v2), (c3, v3) = [await page(lab) for _ in range(3)]
        for c, name in ((c1, "Ann"), (c2, bob), (c3, "Ann")):
            await c.set("Assignment", TASK, 0.2)
            await c.set("Your name", name, 0.1)
        for c, v, want in ((c1, v1, ann), (c2, v2, bob_v), (c3, v3, ann)):
            await until(
                lambda v=v, want=want: (
                    _panel(lab, v).variant is not None
                    and _panel(lab, v).variant.index == want.index
                ),
                30,
                "the student's variant",
            )
            s = want.values["s"]
            await until(lambda c=c, s=s: f"Your numbers: s = {s:g}" in _task(c), 15, "numbers")
            assert f"at the speed {s:g} m/s" in _task(c)
        assert _panel(lab, v1).variant.values == _panel(lab, v3).variant.values
        assert _panel(lab, v1).variant.values != _panel(lab, v2).variant.values
        # Ann answers her own numbers (right), Bob answers Ann's (wrong for him)
        u1 = "u1(t) ="
        for c, v in ((c1, v1), (c2, v2)):
            await c.set("u2(t) =", "0", 0.1)
            await c.set("u3(t) =", "0", 0.1)
            await c.set(u1, ann.assignment.answers["correct"]["u1"], 0.2)
            await until(
                lambda v=v: (
                    v.session.raw_values()["u1"] == ann.assignment.answers["correct"]["u1"]
                    and v.session.raw_values()["u3"] == "0"
                ),
                10,
                "the answer's value",
            )
            await c.click("Check my answer", 0.1)
        await until(lambda: "al-check" in _verdict(c1), 20, "Ann's verdict")
        await until(lambda: "al-check" in _verdict(c2), 20, "Bob's verdict")
        assert "All checks pass." in _verdict(c1)
        bad = _verdict(c2)
        assert "data-check='speed' data-pass='no'" in bad and "misses the tolerance" in bad
        assert "al-check-feedback" in bad and "the speed along the equator is |u1|" in bad
        board.refresh()
        rows = board.progress.rows(None)
        assert {(r.name, r.passed) for r in rows} >= {("Ann", True), (bob, False)}
        for c in (c1, c2, c3):
            await c.close()

    asyncio.run(go())


def test_a_broken_variant_space_is_not_pushed(lab: Any) -> None:
    board = lab.classroom.board
    data = copy.deepcopy(board.assignments[TASK].data)
    data["id"] = "broken-equator"
    data["answers"]["correct"]["u1"] = "{2}"  # right only for s = 2
    broken = parse_assignment(json.loads(json.dumps(data)), "broken.json")
    board.assignments["broken-equator"] = broken
    try:
        pushed = board.pushed
        with pytest.raises(AssignmentError) as exc:
            board.push("broken-equator")
        assert "variant 0 (s = 1): the reference answer fails check speed" in str(exc.value)
        assert board.pushed == pushed
    finally:
        del board.assignments["broken-equator"]
