"""Soak test: a class that comes and goes for a long time; memory and sessions stay put.

    python -m benchmarks.soak --minutes 30 [--students 20] [--churn 3]

Runs ``python -m analyzer_lab serve`` as a subprocess.  An instructor page (a real websocket
client speaking viser's protocol) enters the code, plays a preset and alternates
"Follow me" and "Release" every 30 s, moving to the next preset each time (a
run that plays for ever keeps up to MAX_LOG samples for export, about 2 MB for the
sphere); about ``--students`` student pages play their
own sessions (or follow the demo), and every ``--churn`` seconds one student leaves
and a new one joins.  The server's memory (RSS) is sampled every 5 s; the server
prints its live session count (``[classroom]`` lines: views, sessions alive after a
garbage collection, followers).  At the end every student leaves, then the
instructor; the script prints memory after warm-up and at the end, the largest
memory seen, and the sessions left (all must be 0 once everybody left).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import re
import subprocess
import sys
import tempfile
import time
from typing import Any

from benchmarks.classroom_load import BENCH_CODE, start_server
from tests.support.client import ProtoClient
from tests.support.servers import free_port


def last_report(path: str) -> dict[str, int]:
    """The newest ``[classroom]`` line of the server log, as numbers."""
    try:
        text = open(path, encoding="utf-8", errors="replace").read()
    except OSError:
        return {}
    lines = [ln for ln in text.splitlines() if ln.startswith("[classroom]")]
    if not lines:
        return {}
    parts = lines[-1].split()[1:]
    return {
        parts[i]: int(parts[i + 1])
        for i in range(0, len(parts) - 1, 2)
        if re.fullmatch(r"-?\d+", parts[i + 1])
    }


def _count(path: str) -> int:
    try:
        return open(path, encoding="utf-8", errors="replace").read().count("[classroom]")
    except OSError:
        return 0


async def wait_report(path: str, timeout: float = 30.0) -> dict[str, int]:
    """Wait for the next ``[classroom]`` line of the server log (one every 10 s)."""
    before = _count(path)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and _count(path) <= before:
        await asyncio.sleep(0.5)
    return last_report(path)


async def soak(
    url: str,
    pid: int,
    log_path: str,
    seconds: float,
    students: int,
    churn: float,
    warmup: float,
    out: Any = sys.stdout,
) -> dict[str, Any]:
    import psutil

    proc = psutil.Process(pid)
    rng = random.Random(7)
    presets = ["example-1.1", "example-1.2", "example-1.3"]
    inst = await ProtoClient(url).start()
    await inst.become_instructor(BENCH_CODE)
    await inst.set("Preset", "example-1.1", 0.3)
    await inst.set("pause at t_end", False, 0.1)
    await inst.set("Run", "Play", 0.1)
    pool: list[ProtoClient] = []

    async def join() -> None:
        c = await ProtoClient(url).start()
        pool.append(c)
        try:
            await c.wait_for("Run", 20)
            await c.set("Preset", rng.choice(presets), 0.2)
            await c.set("Run", "Play", 0.05)
        except Exception:
            pass

    for _ in range(students):
        await join()
    t0 = time.monotonic()
    samples: list[tuple[float, float]] = []
    warm_rss = 0.0
    following = False
    next_toggle = t0 + 30.0
    next_sample = t0
    joined = left = toggles = 0
    while time.monotonic() - t0 < seconds:
        await asyncio.sleep(churn)
        # one leaves, one joins
        if pool:
            c = pool.pop(rng.randrange(len(pool)))
            await c.close()
            left += 1
        await join()
        joined += 1
        now = time.monotonic()
        if now >= next_toggle:
            # the instructor moves to the next bookmark (its run restarts) and switches mode
            toggles += 1
            await inst.set("Preset", presets[toggles % len(presets)], 0.2)
            await inst.set("Run", "Play", 0.05)
            await inst.click("Release" if following else "Follow me", 0.1)
            following = not following
            next_toggle = now + 30.0
        if now >= next_sample:
            rss = proc.memory_info().rss / 1e6
            samples.append((now - t0, rss))
            next_sample = now + 5.0
            if not warm_rss and now - t0 >= warmup:
                warm_rss = rss
                print(
                    f"[soak] t={now - t0:6.0f} s  warm-up done: server RSS {rss:.1f} MB",
                    file=out,
                    flush=True,
                )
            elif int(now - t0) % 60 < 5:
                print(
                    f"[soak] t={now - t0:6.0f} s  RSS {rss:.1f} MB  students {len(pool)}  joined {joined} left {left}",
                    file=out,
                    flush=True,
                )
    if following:
        await inst.click("Release", 0.5)
    end_rss = proc.memory_info().rss / 1e6
    during = await wait_report(log_path)
    for c in pool:
        await c.close()
    pool.clear()
    await asyncio.sleep(2.0)
    after_students = await wait_report(log_path)
    await inst.close()
    await asyncio.sleep(2.0)
    after_all = await wait_report(log_path)
    final_rss = proc.memory_info().rss / 1e6
    if not warm_rss:
        warm_rss = samples[0][1] if samples else end_rss
    peak = max([r for _, r in samples] + [end_rss])
    result = {
        "minutes": seconds / 60,
        "joined": joined + students,
        "left": left + students,
        "warm_rss_mb": warm_rss,
        "end_rss_mb": end_rss,
        "peak_rss_mb": peak,
        "final_rss_mb": final_rss,
        "end_vs_warm": end_rss / warm_rss - 1.0,
        "during": during,
        "after_students_left": after_students,
        "after_all_left": after_all,
    }
    return result


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.soak", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--minutes", type=float, default=30.0)
    ap.add_argument("--students", type=int, default=20, help="students connected at any time")
    ap.add_argument(
        "--churn",
        type=float,
        default=3.0,
        help="seconds between a student leaving and another joining",
    )
    ap.add_argument(
        "--warmup",
        type=float,
        default=None,
        help="seconds of warm-up (default 10%% of the run, 30..180 s)",
    )
    args = ap.parse_args(argv)
    seconds = args.minutes * 60.0
    warmup = args.warmup if args.warmup is not None else min(180.0, max(30.0, 0.1 * seconds))
    port = free_port()
    log_path = os.path.join(tempfile.mkdtemp(prefix="analyzer-lab-soak-"), "server.log")
    env_before = os.environ.get("ANALYZER_LAB_STATS")
    os.environ["ANALYZER_LAB_STATS"] = "10"
    log = open(log_path, "w")
    try:
        proc = start_server(port, log=log)
    finally:
        if env_before is None:
            os.environ.pop("ANALYZER_LAB_STATS", None)
        else:
            os.environ["ANALYZER_LAB_STATS"] = env_before
    print(
        f"[soak] server pid {proc.pid}, log {log_path}; {args.minutes:g} min, {args.students} students, "
        f"one leaves and one joins every {args.churn:g} s; warm-up {warmup:.0f} s",
        flush=True,
    )
    try:
        r = asyncio.run(
            soak(
                f"ws://127.0.0.1:{port}/",
                proc.pid,
                log_path,
                seconds,
                args.students,
                args.churn,
                warmup,
            )
        )
    finally:
        proc.terminate()
        try:
            proc.wait(5)
        except subprocess.TimeoutExpired:
            proc.kill()
    ok_mem = abs(r["end_vs_warm"]) <= 0.10
    left = r["after_all_left"]
    ok_sessions = (
        bool(left)
        and left.get("views", 1) == 0
        and left.get("sessions_alive", 1) == 0
        and left.get("followers", 1) == 0
    )
    print(f"[soak] students joined {r['joined']}, left {r['left']} in {r['minutes']:g} min")
    print(
        f"[soak] server RSS: after warm-up {r['warm_rss_mb']:.1f} MB, end {r['end_rss_mb']:.1f} MB "
        f"({r['end_vs_warm']:+.1%}), peak {r['peak_rss_mb']:.1f} MB, after everybody left {r['final_rss_mb']:.1f} MB"
        f" -> {'OK' if ok_mem else 'FAIL'} (limit 10%)"
    )
    print(f"[soak] sessions while running: {r['during']}")
    print(f"[soak] after the students left: {r['after_students_left']}")
    print(
        f"[soak] after everybody left: {left} -> "
        f"{'OK: no orphaned sessions' if ok_sessions else 'FAIL: orphaned sessions'}"
    )
    return 0 if ok_mem and ok_sessions else 1


if __name__ == "__main__":
    raise SystemExit(main())
