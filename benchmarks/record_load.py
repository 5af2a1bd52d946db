"""The course record under a class: attempts written into one SQLite file by two worker
processes while 50 pages play on a two-worker server.

    python -m benchmarks.record_load [--pages 50] [--writers 2] [--seconds 15]

Starts its own ``redis-server`` and ``python -m analyzer_lab serve --workers 2 --data DIR``
(the course record: the SQLite file in DIR, WAL mode), opens ``--pages`` pages through the
front door, each playing the sphere's Example 1.1, and, while they play, ``--writers``
processes record graded attempts of ``sphere-equator`` into the same class as fast as they
can, each through the record's own :class:`~analyzer_lab.classroom.course.Course` (as a
worker records a student's check).  Reports attempts written per second (all writers
together), the attempts the database holds afterwards, the pages' updates/s (mean, min)
and CPU.
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing
import os
import statistics
import subprocess
import tempfile
import time
from typing import Any

from benchmarks.cluster_load import (
    CPU,
    page_url,
    start_front_door,
    start_redis,
    status,
    stop_front_door,
)
from tests.support.load import LabClient, count_window, page_plan
from tests.support.servers import free_port

CLASS = "record-bench"
JOIN = "BENCH42"
ASSIGNMENT = "sphere-equator"


def _writer(data: str, k: int, seconds: float, go: Any, out: Any) -> None:
    """One writer: join as a student, then record the same graded attempt until time."""
    from analyzer_lab.lessons.assignments import grade, ready_assignments
    from analyzer_lab.serve.course_record import open_course, resolve

    a = next(x for x in ready_assignments() if x.id == ASSIGNMENT)
    values = dict(a.answers["correct"])
    g = grade(a, values, "answer")
    course = open_course(resolve(data, None, CLASS), create=False)
    student = course.join(JOIN, f"writer {k}")
    go.wait()
    n, end = 0, time.monotonic() + seconds
    while time.monotonic() < end:
        course.record(student, g, values)
        n += 1
    out.put(n)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.record_load", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--pages", type=int, default=50)
    ap.add_argument("--writers", type=int, default=2)
    ap.add_argument("--seconds", type=float, default=15.0)
    args = ap.parse_args(argv)
    data = tempfile.mkdtemp(prefix="analyzer-lab-record-")
    rport, port = free_port(), free_port()
    redis_proc = start_redis(rport)
    extra = ("--data", data, "--class", CLASS, "--join-code", JOIN)
    door = start_front_door(port, 2, f"redis://127.0.0.1:{rport}", subprocess.DEVNULL, extra)
    ctx = multiprocessing.get_context("spawn")
    go, out = ctx.Event(), ctx.Queue()
    writers = [
        ctx.Process(target=_writer, args=(data, k, args.seconds, go, out), daemon=True)
        for k in range(args.writers)
    ]
    try:
        pids = [w["pid"] for w in status(port)["workers"]]
        cpu = CPU(door.pid, pids)
        print(f"workers warmed up in {cpu.settle():.0f} s; {os.cpu_count()} cores", flush=True)
        for w in writers:
            w.start()
        time.sleep(8.0)  # the writers have imported and joined
        urls = [page_url(port) for _ in range(args.pages)]
        clients = [LabClient(u, page_plan("sphere", "example-1.1")) for u in urls]

        def start() -> None:
            cpu.start()
            go.set()

        dt, (door_cpu, workers_cpu, machine) = asyncio.run(
            count_window(clients, args.seconds, 3.0, start, cpu.read, ready_timeout=90.0)
        )
        written = [out.get(timeout=120) for _ in writers]
        rate = sum(written) / args.seconds
        from analyzer_lab.serve.course_record import open_course, resolve

        held = len(open_course(resolve(data, None, CLASS), create=False).attempts())
        ups = [c.stats.updates / dt for c in clients if not c.stats.error] or [0.0]
        errors = sum(1 for c in clients if c.stats.error)
        print(
            f"{args.writers} writers into one SQLite file (WAL): {sum(written)} attempts in "
            f"{args.seconds:g} s = {rate:.0f} attempts/s ({', '.join(map(str, written))}; the "
            f"record holds {held}); "
            f"{args.pages} pages on 2 workers meanwhile: updates/s per page mean "
            f"{statistics.mean(ups):.1f}, min {min(ups):.1f}, errors {errors}; server CPU per "
            f"worker {', '.join(f'{c:.0f}%' for c in workers_cpu)}, machine {machine:.0f}%",
            flush=True,
        )
    finally:
        for w in writers:
            w.join(timeout=5)
            if w.is_alive():
                w.kill()
        stop_front_door(door, redis_proc)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
