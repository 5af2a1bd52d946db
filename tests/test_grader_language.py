"""The grader's words to a student in the page's language: each refusal and each reason a
check has no grade is a message a Russian page shows in Russian."""

from __future__ import annotations

import asyncio
import threading
from typing import Any

import pytest
from analyzer_lab.classroom.grader import GradeOutcome, Grader, GraderBusy
from analyzer_lab.i18n import language_of
from analyzer_lab.lessons.assignments import ready_assignments

from tests.support.client import open_page
from tests.support.waiting import until

READY = {a.id: a for a in ready_assignments()}
CHEAP = READY["sphere-equator"]
COSTLY = READY["table-6dof-feedforward"]
pytestmark = pytest.mark.timeout(300)
RU = language_of("ru")
EN = language_of("en")


def _refusal(g: Grader, key: str = "ann") -> GraderBusy:
    with pytest.raises(GraderBusy) as caught:
        g.submit(key, CHEAP, dict(CHEAP.answers["correct"]), lambda o: None, lambda k: None)
    return caught.value


def test_a_stopping_server_refuses_in_the_page_language() -> None:
    g = Grader()
    g.close()
    busy = _refusal(g)
    assert "the server is stopping" in str(busy)  # logs and the API keep the English
    assert RU.message(busy) == "сервер останавливается: проверьте ответ, когда он снова заработает"
    assert EN.message(busy) == str(busy)


def test_a_full_line_refuses_in_the_page_language() -> None:
    g = Grader(max_waiting=0)
    try:
        shown = RU.message(_refusal(g))
        assert shown == "ответов класса в очереди на проверку: 0; проверьте снова через минуту"
    finally:
        g.close()


def test_a_check_over_its_cpu_time_is_told_in_russian_with_its_decimal_comma() -> None:
    g = Grader(cpu_seconds=0.3)
    done = threading.Event()
    told: list[GradeOutcome] = []
    try:
        g.submit(
            "fay",
            COSTLY,
            dict(COSTLY.answers["correct"]),
            lambda o: (told.append(o), done.set()),
            lambda k: None,
        )
        assert done.wait(300), "the verdict"
    finally:
        g.close()
    error = told[0].error
    assert told[0].grade is None and "more than 0.3 s of computing" in error
    shown = RU.message(error)
    assert "больше 0,3 с вычислений" in shown and "computing" not in shown


def test_a_russian_page_shows_the_grader_refusal_in_russian(labs: dict[str, Any]) -> None:
    lab = labs["ru"]
    grader = lab.classroom.board.grader
    full = grader.max_waiting

    async def go() -> None:
        c, _ = await open_page(lab, "Движение")
        try:
            await c.wait_for("Проверить мой ответ")
            await c.set("Задание", CHEAP.id, 0.2)
            await c.set("Ваше имя", "Аня", 0.1)
            await until(lambda: "Ваши числа" in _html(c, "al-assignment-task"), 30, "the task")
            grader.max_waiting = 0
            await c.click("Проверить мой ответ", 0.1)
            shown = await until(
                lambda: (
                    "очереди" in _html(c, "al-assignment-error") and _html(c, "al-assignment-error")
                ),
                30,
                "the refusal",
            )
            assert "ответов класса в очереди на проверку: 0" in shown
            assert "waiting to be checked" not in shown
        finally:
            grader.max_waiting = full
            await c.close()

    asyncio.run(go())


def _html(c: Any, cls: str) -> str:
    return next((h for h in c.html.values() if cls in h), "")


def test_an_answer_the_worker_refuses_is_told_in_the_page_language() -> None:
    """A refusal from the worker process comes back as its message: English in the
    outcome's text (logs, API), Russian on a Russian page."""
    g = Grader()
    done = threading.Event()
    told: list[GradeOutcome] = []
    try:
        g.submit(
            "gus",
            CHEAP,
            {"u1": 1, "zz": 0},
            lambda o: (told.append(o), done.set()),
            lambda k: None,
        )
        assert done.wait(120), "the verdict"
    finally:
        g.close()
    outcome = told[0]
    assert outcome.grade is None and outcome.field == "zz"
    assert str(outcome.error) == (
        "your answer: field zz: is not a parameter (you may set u1, u2, u3)"
    )
    assert RU.message(outcome.error) == (
        "ваш ответ: поле zz: не является параметром (можно задать u1, u2, u3)"
    )
