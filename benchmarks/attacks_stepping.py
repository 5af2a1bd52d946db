"""Attacks on the stepping (issue 14, attacks 1 and 7-10), measured as ratios in one run.

    python -m benchmarks.attacks_stepping [--window 4]

The server runs as a subprocess (``python -m analyzer_lab serve``); pages are real websocket
clients speaking viser's protocol.  A normal page plays the sphere's Example 1.1 and
counts the moving point's updates per second: its baseline, then while an attacker page
plays allowed but expensive values (attack 1: u1 = 5 sin t with the smallest step
h = 1e-5 at 8x, "pause at t_end" off, on the sphere and on the constant-speed sphere) or
values that turn non-finite (attack 7: u1 = sqrt(101 - t) past t = 101 s), then after
the attacker left; the server's memory (RSS) before and after.  The command line's attacks
(8-10) are timed with their peak memory.  Prints one README table row per attack.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import subprocess
import sys
import tempfile
import time
from typing import Any

from tests.support.servers import free_port, start_server
from tests.support.stepping_attacks import NOT_FINITE, TINY_STEP, WINDOW, attack

#: The command line's attacks: (row, arguments of ``analyzer-lab run``).
CLI_ATTACKS = [
    (
        "8: run sphere --set u1=exp(t) --t-end 1000",
        ("sphere", "--set", "u1=exp(t)", "--t-end", "1000"),
    ),
    (
        "9: run sphere --set h=1.1e-5 --t-end 100000",
        ("sphere", "--set", "h=1.1e-5", "--t-end", "100000"),
    ),
    (
        "9: run sphere --set family=24 --t-end 100000",
        ("sphere", "--set", "family=24", "--t-end", "100000"),
    ),
    (
        "9: run sphere DOP853 rtol 1e-14 --t-end 100000",
        ("sphere", "--set", "integrator=DOP853", "--set", "rtol=1e-14", "--t-end", "100000"),
    ),
    ("10: run sphere --set h=1e-5", ("sphere", "--set", "h=1e-5")),
]


def run_cli(args: tuple[str, ...]) -> tuple[int, float, float, str]:
    """``python -m analyzer_lab run ARGS``: exit code, seconds, peak RSS (MB), its last stderr line."""
    import psutil

    env = dict(os.environ)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    t0 = time.monotonic()
    proc = subprocess.Popen(
        [sys.executable, "-m", "analyzer_lab", "run", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=root,
    )
    ps = psutil.Process(proc.pid)
    peak = 0.0
    while proc.poll() is None:
        try:
            peak = max(peak, ps.memory_info().rss / 1e6)
        except psutil.Error:
            break
        time.sleep(0.05)
    err = proc.stderr.read() if proc.stderr else ""
    lines = err.strip().splitlines()
    return proc.wait(), time.monotonic() - t0, peak, lines[-1] if lines else ""


def start(log_path: str) -> tuple[str, Any, subprocess.Popen]:
    """The server (stderr to ``log_path``): its websocket URL, psutil process and process."""
    import psutil

    port = free_port()
    log = open(log_path, "w")
    proc = start_server(port, "sphere", log=log)
    return f"ws://127.0.0.1:{port}", psutil.Process(proc.pid), proc


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.attacks_stepping", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--window", type=float, default=WINDOW, help="seconds of each window")
    args = ap.parse_args(argv)
    log_path = os.path.join(tempfile.mkdtemp(prefix="analyzer-lab-attack-"), "server.log")
    url, ps, proc = start(log_path)
    print("| attack | baseline (updates/s) | during | after | memory before/after (MB) |")
    print("|---|---|---|---|---|")
    try:
        for row, lesson_id, moves, told in (
            ("1: h = 1e-5, u1 = 5 sin t, 8x, sphere", "sphere", TINY_STEP, "the step is too small"),
            (
                "1: the same on sphere-constant-speed",
                "sphere-constant-speed",
                TINY_STEP,
                "the step is too small",
            ),
            ("7: u1 = sqrt(101 - t), 8x, past t = 101 s", "sphere", NOT_FINITE, "is not finite"),
        ):
            f = asyncio.run(attack(url, ps, lesson_id, moves, told, args.window, log_path))
            print(
                f"| {row} | {f['baseline']:.1f} | {f['during']:.1f}"
                f" ({f['during'] / f['baseline']:.0%}) | {f['after']:.1f}"
                f" ({f['after'] / f['baseline']:.0%}) | {f['mem_before']:.0f} / {f['mem_after']:.0f} |",
                flush=True,
            )
    finally:
        proc.terminate()
        proc.wait(10)
    for row, cli_args in CLI_ATTACKS:
        code, seconds, peak, line = run_cli(cli_args)
        what = f"exit {code} in {seconds:.1f} s" + (f": {line[:90]}" if code else "")
        print(f"| {row} | command line: {what} | - | - | peak {peak:.0f} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
