"""Soak of a class in waves: pages join, play, have answers checked and leave, again and
again; the server's memory stays flat, no session outlives its page, no traceback.

    python -m benchmarks.class_waves [--pages 50] [--waves 6] [--lesson-minutes 60]
                                     [--speed 8] [--graders 10]

Runs ``python -m analyzer_lab serve --join-code ...`` as a subprocess.  Each wave, ``--pages``
pages (real websocket clients speaking viser's protocol, from five loopback addresses)
open, choose one of the sphere's examples, set the speed and play; ``--graders`` of them
choose an assignment, give the class's join code and a name, and press "Check my answer"
(checked by the grader's worker process) and wait for their verdict; those pages (at
least five) count the moving point's updates, the others read without decoding; at the wave's end
every page leaves.  The waves together play ``--lesson-minutes`` of lesson time at
``--speed`` (60 lesson minutes at 8x: 7.5 minutes of wall time).  After each wave the
script waits for the server's next ``[classroom]`` figures and reads its memory (RSS);
memory is compared between the end of the first wave (the server warmed up by a whole
class) and the end of the last.  It exits 1 when memory grew by more than 10%, a session
or view outlived the pages, or the server's log has a traceback.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Any

from benchmarks.soak import wait_report
from tests.support.client import ProtoClient
from tests.support.servers import free_port, start_server

#: The class's join code.
JOIN = "WAVES42"
#: The assignment the graders answer (a sphere task: its check runs a few seconds of the
#: lesson).
ASSIGNMENT = "sphere-equator"
PRESETS = ("example-1.1", "example-1.2", "example-1.3")
#: The loopback addresses the pages come from (a class is several machines).
SOURCES = tuple(f"127.0.0.{k}" for k in range(2, 7))


async def _player(url: str, k: int, speed: str, rng: random.Random, measured: bool) -> ProtoClient:
    """A page that plays; a page not ``measured`` then reads its socket without decoding
    it (the clients' own CPU stays off the server's machine)."""
    c = await ProtoClient(url, source=SOURCES[k % len(SOURCES)]).start()
    await c.wait_for("Run", 60)
    await c.set("Preset", rng.choice(PRESETS), 0.2)
    await c.set("Speed", speed, 0.05)
    await c.set("pause at t_end", False, 0.05)
    await c.set("Run", "Play", 0.05)
    c.measuring = measured
    c.skim = not measured
    return c


async def _check(c: ProtoClient, name: str, timeout: float) -> float:
    """Choose the assignment, give the join code and ``name``, press "Check my answer";
    seconds until the verdict (inf: none in ``timeout``)."""
    await c.wait_for("Check my answer", 60)
    await c.set("Assignment", ASSIGNMENT, 0.3)
    await c.set("Join code", JOIN, 0.1)
    await c.set("Your name", name, 0.1)
    t = time.monotonic()
    await c.click("Check my answer", 0.0)
    while time.monotonic() - t < timeout:
        if any("al-check" in h for h in c.html.values() if "al-assignment" in h):
            return time.monotonic() - t
        await asyncio.sleep(0.2)
    return float("inf")


async def wave(
    url: str, k: int, pages: int, graders: int, seconds: float, speed: str
) -> dict[str, Any]:
    """One wave: ``pages`` join and play, ``graders`` of them have an answer checked,
    all leave after ``seconds``."""
    rng = random.Random(k)
    t0 = time.monotonic()
    opened = await asyncio.gather(
        *(_player(url, j, speed, rng, measured=j < max(graders, 5)) for j in range(pages)),
        return_exceptions=True,
    )
    clients = [c for c in opened if isinstance(c, ProtoClient)]
    failed = [repr(c)[:120] for c in opened if not isinstance(c, ProtoClient)]
    joined = time.monotonic() - t0
    took = await asyncio.gather(
        *(
            _check(c, f"Wave {k} student {j:02d}", max(5.0, seconds - joined))
            for j, c in enumerate(clients[:graders])
        )
    )
    await asyncio.sleep(max(0.0, seconds - (time.monotonic() - t0)))
    played = time.monotonic() - t0 - joined
    rates = [c.point_updates / max(played, 1e-9) for c in clients if c.measuring]
    for c in clients:
        await c.close()
    return {
        "pages": len(clients),
        "failed": failed,
        "join_s": joined,
        "verdicts": sum(t < float("inf") for t in took),
        "slowest_verdict_s": max(took) if took else 0.0,
        "updates_per_s_mean": statistics.fmean(rates) if rates else 0.0,
        "updates_per_s_min": min(rates) if rates else 0.0,
    }


async def soak(
    url: str,
    pid: int,
    log_path: str,
    waves: int,
    pages: int,
    graders: int,
    seconds: float,
    speed: str,
    out: Any = sys.stdout,
) -> dict[str, Any]:
    import psutil

    proc = psutil.Process(pid)
    proc.cpu_percent(None)
    rows: list[dict[str, Any]] = []
    for k in range(1, waves + 1):
        row = await wave(url, k, pages, graders, seconds, speed)
        await asyncio.sleep(3.0)  # the pages' leaving is over; the heap is trimmed after 2 s
        row["report"] = await wait_report(log_path)
        row["rss_mb"] = proc.memory_info().rss / 1e6
        row["cpu_percent"] = proc.cpu_percent(None)  # over the wave
        rows.append(row)
        print(
            f"[waves] wave {k}: {row['pages']} pages (joined in {row['join_s']:.1f} s), "
            f"{row['verdicts']}/{graders} verdicts (slowest {row['slowest_verdict_s']:.1f} s), "
            f"{row['updates_per_s_mean']:.1f} / {row['updates_per_s_min']:.1f} updates/s "
            f"(mean / min), server CPU {row['cpu_percent']:.0f}%; "
            f"after it: RSS {row['rss_mb']:.1f} MB, {row['report']}",
            file=out,
            flush=True,
        )
    return {"waves": rows}


def tracebacks(log_path: str) -> int:
    with open(log_path, encoding="utf-8", errors="replace") as f:
        return f.read().count("Traceback")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.class_waves", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--pages", type=int, default=50, help="pages in each wave")
    ap.add_argument("--waves", type=int, default=6)
    ap.add_argument("--lesson-minutes", type=float, default=60.0)
    ap.add_argument("--speed", type=float, default=8.0, choices=[1.0, 2.0, 4.0, 8.0])
    ap.add_argument("--graders", type=int, default=10, help="pages of a wave that check")
    args = ap.parse_args(argv)
    seconds = args.lesson_minutes * 60.0 / args.speed / args.waves
    port = free_port()
    log_path = os.path.join(tempfile.mkdtemp(prefix="analyzer-lab-waves-"), "server.log")
    before = os.environ.get("ANALYZER_LAB_STATS")
    os.environ["ANALYZER_LAB_STATS"] = "10"
    try:
        with open(log_path, "w") as log:
            proc = start_server(port, "sphere", log, ("--join-code", JOIN), ready_within=180.0)
    finally:
        if before is None:
            os.environ.pop("ANALYZER_LAB_STATS", None)
        else:
            os.environ["ANALYZER_LAB_STATS"] = before
    speed = f"{args.speed:g}x"
    print(
        f"[waves] server pid {proc.pid}, log {log_path}; {args.waves} waves of {args.pages}"
        f" pages at {speed}, {seconds:.0f} s each ({args.lesson_minutes:g} lesson minutes),"
        f" {args.graders} checks a wave",
        flush=True,
    )
    try:
        r = asyncio.run(
            soak(
                f"ws://127.0.0.1:{port}/",
                proc.pid,
                log_path,
                args.waves,
                args.pages,
                args.graders,
                seconds,
                speed,
            )
        )
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
    rows = r["waves"]
    first, last = rows[0]["rss_mb"], rows[-1]["rss_mb"]
    growth = last / first - 1.0
    left = rows[-1]["report"]
    ok_sessions = bool(left) and left.get("views", 1) == 0 and left.get("sessions_alive", 1) == 0
    errors = tracebacks(log_path)
    verdicts = sum(w["verdicts"] for w in rows)
    print(
        f"[waves] RSS after the first wave {first:.1f} MB, after the last {last:.1f} MB"
        f" ({growth:+.1%}; limit 10%), largest after a wave"
        f" {max(w['rss_mb'] for w in rows):.1f} MB"
    )
    print(f"[waves] verdicts {verdicts} of {args.graders * args.waves}")
    print(f"[waves] after the last wave left: {left}")
    print(f"[waves] tracebacks in the server's log: {errors}")
    ok = abs(growth) <= 0.10 and ok_sessions and errors == 0
    print(f"[waves] {'OK' if ok else 'FAIL'}")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
