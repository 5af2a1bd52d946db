"""Grading cannot slow the class (Hardening, round 3, finding 1): twelve students from
another address each press "Check my answer" once on the costliest assignment, against
``python -m analyzer_lab serve`` in a subprocess, measured like
:mod:`tests.test_attacks_transport` (a normal page's updates/s before, during and after;
the server's memory), on a server of its own.  The answers are checked in the grader's
worker process, one after another; each page is told its place in line."""

from __future__ import annotations

import asyncio
import subprocess
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.support.servers import ServeProcess
from tests.test_attacks_transport import JOIN, _measured, attacked_server


@pytest.fixture(scope="module")
def server(serve: Callable[..., ServeProcess]) -> Iterator[tuple[str, subprocess.Popen]]:
    yield from attacked_server(serve, "--join-code", JOIN)


def test_a_class_checking_costly_answers_does_not_slow_the_others(server: Any) -> None:
    async def go() -> None:
        _, figures, _ = await _measured(
            server, "grading: 12 checks of table-6dof-feedforward", 60.0
        )
        assert figures["verdicts"] == 12, figures
        assert figures["told_their_place"] >= 6, figures  # most waited in line, and were told

    asyncio.run(go())
