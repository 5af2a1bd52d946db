"""Attacks on the stepping, against ``python -m analyzer_lab serve`` in a subprocess with real
websocket clients speaking viser's protocol (the scenarios of
:mod:`tests.support.stepping_attacks`, which ``python -m benchmarks.attacks_stepping`` measures).

A normal page plays the sphere's Example 1.1; an attacker page, on the same server, sets
allowed values that make stepping expensive (attack 1: u1 = 5 sin t with the smallest
step h = 1e-5 at 8x, "pause at t_end" off; on the sphere and on the constant-speed
sphere) or non-finite (attack 7: u1 = sqrt(101 - t) past t = 101 s), and sends values of
the wrong type.  The normal page keeps >= 90 % of its own updates/s (baseline measured
first, in the same run) during and after the attack, the server's memory returns within
10 % of its baseline after the attacker leaves, the attacker's page is told, nothing of
the attacker's reaches the normal page, and the server prints no traceback.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Any

import pytest

from tests.support.servers import ServeProcess
from tests.support.stepping_attacks import NOT_FINITE, TINY_STEP, attack

pytestmark = pytest.mark.timeout(180)


@pytest.fixture(scope="module")
def server(serve: Callable[..., ServeProcess]) -> tuple[str, Any, str]:
    import psutil

    live = serve("sphere")
    return live.url, psutil.Process(live.pid), str(live.log_path)


def check(figures: dict[str, Any], log_path: str, name: str) -> None:
    print(
        f"{name}: baseline {figures['baseline']:.1f}/s during {figures['during']:.1f}/s"
        f" after {figures['after']:.1f}/s memory {figures['mem_before']:.0f} ->"
        f" {figures['mem_after']:.0f} MB"
    )
    assert figures["baseline"] > 20, figures
    assert figures["during"] >= 0.9 * figures["baseline"], figures
    assert figures["after"] >= 0.9 * figures["baseline"], figures
    assert figures["mem_after"] <= 1.1 * figures["mem_before"], figures
    assert figures["normal"] == [], figures["normal"]  # nothing of the attacker's arrived
    assert any("value refused" in s for s in figures["attacker"])
    assert not any("below the minimum" in s for s in figures["attacker"])
    with open(log_path, encoding="utf-8") as fh:
        fh.seek(figures["log_at"])
        log = fh.read()
    assert "Traceback" not in log, log[-3000:]
    assert log.count("refused GUI values") <= 1  # three refused values: one line at most


@pytest.mark.parametrize("lesson_id", ["sphere", "sphere-constant-speed"])
def test_a_tiny_step_at_8x_slows_only_the_attackers_clock(
    server: tuple[str, Any, str], lesson_id: str
) -> None:
    url, proc, log_path = server
    figures = asyncio.run(
        attack(url, proc, lesson_id, TINY_STEP, "the step is too small", log_path=log_path)
    )
    check(figures, log_path, f"attack 1 ({lesson_id})")
    assert any("the step is too small for live play" in s for s in figures["attacker"])


def test_a_non_finite_state_pauses_the_attackers_session(server: tuple[str, Any, str]) -> None:
    url, proc, log_path = server
    figures = asyncio.run(
        attack(url, proc, "sphere", NOT_FINITE, "is not finite", log_path=log_path)
    )
    check(figures, log_path, "attack 7 (NaN)")
    told = [s for s in figures["attacker"] if "is not finite" in s]
    assert any("at t = 101" in s and "playback paused" in s for s in told), told
