"""Start-up of ``analyzer-lab serve`` as a student meets it.

    python -m benchmarks.serve_startup [--repeats 5]

Each repeat starts ``analyzer-lab serve --no-browser`` on a free port with a fresh data
folder and measures, from the command's start: the first HTTP answer, the line saying
the lab is ready, and, in Debian's Chromium, how long a page opened then takes to show
its lesson picker (the seconds from ``page.goto`` to the visible "Lesson" field).  The
medians are printed as a Markdown table.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

from tests.support.browser import CHROMIUM, LAUNCH_ARGS
from tests.support.servers import free_port, stop_process

READY = "Analyzer Lab: http://"


def one_start(browser: object) -> dict[str, float]:
    """One start of the server: seconds to the first HTTP answer and to the ready line,
    and from opening a page (once ready) to its lesson picker."""
    port = free_port()
    with tempfile.TemporaryDirectory() as data:
        t0 = time.perf_counter()
        proc = subprocess.Popen(
            [sys.executable, "-m", "analyzer_lab", "serve", "--no-browser", "--port", str(port)]
            + ["--data", data],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        ready = threading.Event()
        at: dict[str, float] = {}

        def read() -> None:
            for line in proc.stdout or ():
                if READY in line and "ready" not in at:
                    at["ready"] = time.perf_counter() - t0
                    ready.set()

        threading.Thread(target=read, daemon=True).start()
        try:
            while "http" not in at:
                try:
                    urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1).read(64)
                    at["http"] = time.perf_counter() - t0
                except OSError:
                    time.sleep(0.01)
            ready.wait(120)
            context = browser.new_context(viewport={"width": 1400, "height": 900})  # type: ignore[attr-defined]
            page = context.new_page()
            opened = time.perf_counter()
            page.goto(f"http://127.0.0.1:{port}/")
            page.locator("label").filter(has_text="Lesson").first.wait_for(timeout=60_000)
            at["picker"] = time.perf_counter() - opened
            context.close()
        finally:
            stop_process(proc)
    return at


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=LAUNCH_ARGS)
        runs = [one_start(browser) for _ in range(args.repeats)]
        browser.close()
    print("| from the command's start | median | min | max |")
    print("|---|---:|---:|---:|")
    for key, label in (
        ("http", "first HTTP answer"),
        ("ready", "lab ready (lessons, course record, classroom)"),
        ("picker", "a page opened once ready: its lesson picker shown"),
    ):
        values = [r[key] for r in runs]
        print(
            f"| {label} | {statistics.median(values):.2f} s | {min(values):.2f} s "
            f"| {max(values):.2f} s |"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
