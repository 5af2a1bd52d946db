"""The busy processes the suite can run beside the quick subset (:mod:`tests.support.busy`)."""

from __future__ import annotations

import pytest

from tests.support.busy import BUSY_ENV, BusyProcesses, busy_count
from tests.support.waiting import wait_until


def test_the_count_is_read_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(BUSY_ENV, raising=False)
    assert busy_count() == 0
    monkeypatch.setenv(BUSY_ENV, "2")
    assert busy_count() == 2
    monkeypatch.setenv(BUSY_ENV, "two")
    with pytest.raises(ValueError, match="expected a number of processes"):
        busy_count()


def test_busy_processes_spin_until_stopped() -> None:
    psutil = pytest.importorskip("psutil")
    busy = BusyProcesses(2)
    busy.start()
    try:
        procs = [psutil.Process(pid) for pid in busy.pids]
        assert len(procs) == 2 and busy.running
        wait_until(lambda: all(sum(p.cpu_times()[:2]) > 0.2 for p in procs), timeout=30)
    finally:
        busy.stop()
    assert not busy.running
    assert not any(p.is_running() and p.status() != psutil.STATUS_ZOMBIE for p in procs)
