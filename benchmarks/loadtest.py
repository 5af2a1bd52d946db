"""Load test: N simultaneous sessions, each a real websocket client speaking viser's protocol.

    python -m benchmarks.loadtest --sessions 1 10 30 50 [--seconds 10] [--lesson sphere] [--preset P]
    python -m benchmarks.loadtest --all-lessons --sessions 50 [--seconds 10]

The server runs as a subprocess (``python -m analyzer_lab serve``).  Each client connects
with viser's subprotocol, sends a camera message (which makes it a connected client),
selects the lesson and its preset (the lesson's first unless ``--preset``) in the
page's pickers, unticks "pause at t_end" and presses Play through GUI update messages,
then counts what it receives: websocket frames that carry an update of the lesson's
live scene (any node under :data:`analyzer_lab.view.scene.LIVE_ROOT`: moving points, trails,
vectors, posed bodies), once per frame (updates/s), and bytes (MB/s).  Server CPU
comes from psutil on the server process.  ``--all-lessons`` measures every lesson of
the catalog in turn, each on a fresh server, and prints one markdown table.

The clients and the counting are :mod:`tests.support.load` (the tests measure with them
too); the wire format is :mod:`tests.support.wire`.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from tests.support.load import MARKDOWN_HEAD, measure, page_plan
from tests.support.servers import ServeProcess, free_port, start_server, stop_process


def all_lessons_table(
    sessions: Sequence[int], seconds: float, settle: float, fps: float | None, log: Any
) -> None:
    """Every lesson of the catalog with its first preset, each on a fresh server: one
    markdown table (a row per lesson and number of pages)."""
    from analyzer_lab.lessons.catalog import all_lessons

    extra = ("--fps", str(fps)) if fps else ()
    print(f"{os.cpu_count()} cores; {seconds:g} s per run" + (f"; {fps:g} frames/s" if fps else ""))
    print(MARKDOWN_HEAD, flush=True)
    for lesson in all_lessons():
        plan = page_plan(lesson.id)
        port = free_port()
        proc = start_server(port, lesson.id, log, extra_args=extra)
        try:
            for n in sessions:
                fig = asyncio.run(
                    measure(f"ws://127.0.0.1:{port}/", n, seconds, plan, proc.pid, settle)
                )
                print(fig.markdown_row(), flush=True)
                for e in fig.errors[:3]:
                    print("   ", e, file=sys.stderr)
                time.sleep(1.0)
        finally:
            stop_process(proc)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.loadtest", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--sessions", type=int, nargs="+", default=[1, 10, 30, 50])
    ap.add_argument("--seconds", type=float, default=10.0, help="measuring window per run")
    ap.add_argument(
        "--settle", type=float, default=3.0, help="seconds after the last client started playing"
    )
    ap.add_argument("--lesson", default="sphere")
    ap.add_argument("--preset", default=None, help="default: the lesson's first preset")
    ap.add_argument(
        "--all-lessons",
        action="store_true",
        help="every lesson in turn (its first preset), a fresh server each; one markdown table",
    )
    ap.add_argument(
        "--fps",
        type=float,
        default=None,
        help="the server's frame rate (serve --fps; default: its own)",
    )
    ap.add_argument(
        "--server-log", default="", help="file for the server's stderr (loop figures every 5 s)"
    )
    ap.add_argument(
        "--clients-only",
        type=int,
        default=0,
        metavar="PORT",
        help="measure a server already running on this port (with --server-pid for its CPU)",
    )
    ap.add_argument("--server-pid", type=int, default=0)
    args = ap.parse_args(argv)
    if args.all_lessons:
        log = open(args.server_log, "w") if args.server_log else subprocess.DEVNULL
        all_lessons_table(args.sessions, args.seconds, args.settle, args.fps, log)
        return 0
    plan = page_plan(args.lesson, args.preset)
    if args.clients_only:
        for n in args.sessions:
            fig = asyncio.run(
                measure(
                    f"ws://127.0.0.1:{args.clients_only}/",
                    n,
                    args.seconds,
                    plan,
                    args.server_pid or os.getpid(),
                    args.settle,
                )
            )
            print(fig.row(), flush=True)
            print(sorted(round(u, 1) for u in fig.updates_per_s))
        return 0
    log_path = Path(args.server_log or tempfile.mkstemp(prefix="analyzer-lab-load-")[1])
    server = ServeProcess.start(args.lesson, ("--fps", str(args.fps)) if args.fps else (), log_path)
    # measured once every lesson is warmed up: the warm-up's CPU is not the pages'
    server.wait_warm()
    proc, port = server.proc, server.port
    url = f"ws://127.0.0.1:{port}/"
    print(
        f"server pid {proc.pid} on port {port}; lesson {plan.lesson}, preset {plan.preset}; "
        f"{os.cpu_count()} cores" + (f"; server at {args.fps:g} frames/s" if args.fps else "")
    )
    print(
        f"{'sessions':>8} {'updates/s':>10} {'min':>9} {'MB/s/client':>12} {'max MB/s':>11} "
        f"{'server CPU':>10} {'clients':>10} {'machine':>9}  errors  server RSS"
    )
    print(
        f"{'':>8} {'(mean)':>10} {'':>9} {'(mean)':>12} {'':>11} {'(1 core=100%)':>10} {'CPU':>10} {'(all cores)':>9}"
    )
    try:
        for n in args.sessions:
            fig = asyncio.run(measure(url, n, args.seconds, plan, proc.pid, args.settle))
            print(fig.row(), flush=True)
            for e in fig.errors[:3]:
                print("   ", e)
            time.sleep(1.0)
    finally:
        stop_process(proc)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
