"""The README's picture, taken as a student sees the page.

    python -m docs.readme_picture [--out assets/sphere-example-1.2.png]

A lab on the sphere in this process, Debian's Chromium at 1400x900: Example 1.2 played
for 6 s at 1x, the Plots tab open, the page's notices closed (the software-rendering
notice of a machine without a GPU among them), then the screenshot.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from playwright.sync_api import sync_playwright

from tests.support.browser import CHROMIUM, DISMISS_JS, LAUNCH_ARGS, Page
from tests.support.waiting import wait_until

OUT = Path(__file__).resolve().parent.parent / "assets" / "sphere-example-1.2.png"


def main(argv: list[str] | None = None) -> int:
    from analyzer_lab.serve.server import LabServer

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)
    lab = LabServer(host="127.0.0.1", port=0, lesson="sphere", restore=False)
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=LAUNCH_ARGS)
            context = browser.new_context(viewport={"width": 1400, "height": 900})
            tab = Page(lab, browser, context)
            tab.load(tab.input_for("Lesson").input_value(), "example-1.2")
            tab.button("Play")
            wait_until(lambda: tab.session.frame.t >= 6.0, 60, "6 s of the run")
            tab.button("Pause")
            tab.tab("Plots")
            time.sleep(1.0)  # the plots drawn
            wait_until(lambda: tab.page.evaluate(DISMISS_JS) == 0, 10, "the notices closed")
            tab.page.screenshot(path=str(args.out))
            browser.close()
    finally:
        lab.stop()
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
