"""Derivations in child processes: the page's HTML, the time and size limits, one slow
derivation next to a quick one."""

from __future__ import annotations

import time
from typing import Any

import analyzer_lab.serve.derivation_jobs as dj
from analyzer_lab.lessons.catalog import all_lessons

SLOW = "(sin(t)+cos(t)+t)**64"


def _wait(jobs: dj.DerivationJobs, owners: list[str], limit: float) -> dict[str, tuple[float, str]]:
    t0 = time.monotonic()
    done: dict[str, tuple[float, str]] = {}
    while len(done) < len(owners) and time.monotonic() - t0 < limit:
        for o in owners:
            if o not in done:
                r = jobs.poll(o)
                if r is not None:
                    done[o] = (time.monotonic() - t0, r)
        time.sleep(0.02)
    return done


def test_a_slow_derivation_is_ended_and_does_not_delay_a_quick_one() -> None:
    jobs = dj.DerivationJobs(seconds=6.0)
    jobs.warm()
    try:
        jobs.start("slow", "sphere", {"u1": SLOW, "u2": SLOW, "u3": SLOW})
        time.sleep(0.3)  # the slow one has run 0.3 s when the quick one starts
        jobs.start("quick", "sphere", {"u1": "5*sin(t)"})
        assert jobs.busy("slow") and jobs.busy("quick")
        done = _wait(jobs, ["slow", "quick"], 60.0)
        took_quick, quick = done["quick"]
        took_slow, slow = done["slow"]
        # the quick one is shown while the slow one still runs (it runs beside it, not
        # after it): wall times compared with each other, so a busy machine slows both
        assert 'class="al-derivation"' in quick and took_quick < took_slow
        # the slow one is ended at its limit (measured from 0.3 s after its start)
        assert "too large to show: it takes longer than 6 s" in slow and took_slow > 5.6
        assert not jobs.jobs  # both ended and collected
    finally:
        jobs.stop()


def test_a_derivation_over_the_size_limit_is_replaced_by_a_message(monkeypatch: Any) -> None:
    monkeypatch.setattr(dj, "MAX_DERIVATION_BYTES", 1000)
    lesson = {x.id: x for x in all_lessons()}["sphere"]
    out = dj.build(lesson, {})
    assert out.startswith('<div class="al-error">The derivation is too large to show: ')
    assert "MB of formulas" in out


def test_only_catalog_lessons_run_in_a_child_and_jobs_are_capped() -> None:
    lesson = {x.id: x for x in all_lessons()}["sphere"]
    assert dj.DerivationJobs.can_run(lesson)
    assert not dj.DerivationJobs.can_run(object())
    jobs = dj.DerivationJobs(max_jobs=1)
    try:
        jobs.start("a", "sphere", {})
        assert jobs.full()
        jobs.cancel("a")
        assert not jobs.full() and jobs.poll("a") is None
    finally:
        jobs.stop()
