"""Batch grading: many answer files in one ``grade`` call against one call per file.

    python -m benchmarks.grade_batch [--files 200] [--assignment circle-radius-2]
                                     [--separate 200] [--cli analyzer-lab]

Writes ``--files`` answer files (right and wrong in turn) to a temporary folder, grades the
folder in one ``analyzer-lab grade`` process, then ``--separate`` of the files one process
each, one after the other, in the same run.  Reports wall time and the CPU time of the
grading processes (user + system, from ``getrusage``: on a shared machine the CPU time is
what the work costs, the wall time what a user waits), and checks that both ways give the
same verdict for every file.  Progress of the separate calls goes to stderr.
"""

from __future__ import annotations

import argparse
import json
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def children_cpu() -> float:
    """CPU seconds (user + system) of the finished child processes so far."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(argv: list[str]) -> tuple[float, float, subprocess.CompletedProcess]:
    """Wall and CPU seconds of one process, and its output."""
    cpu, start = children_cpu(), time.perf_counter()
    out = subprocess.run(argv, capture_output=True, text=True, check=False)
    return time.perf_counter() - start, children_cpu() - cpu, out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--files", type=int, default=200)
    ap.add_argument("--separate", type=int, default=None, help="default: --files")
    ap.add_argument("--assignment", default="circle-radius-2")
    ap.add_argument("--cli", default=shutil.which("analyzer-lab") or "analyzer-lab")
    args = ap.parse_args(argv)
    from analyzer_lab.lessons.assignments import ready_assignments

    a = next(x for x in ready_assignments() if x.id == args.assignment)
    separate = args.files if args.separate is None else min(args.separate, args.files)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        files = []
        for k in range(args.files):
            kind = "correct" if k % 2 == 0 else "wrong"
            p = folder / f"student-{k:04d}.json"
            p.write_text(json.dumps(dict(a.answers[kind])))
            files.append(p)
        wall_one, cpu_one, out = timed([args.cli, "grade", a.id, str(folder)])
        batch = {Path(d["file"]).name: d["pass"] for d in map(json.loads, out.stdout.splitlines())}
        if len(batch) != args.files or out.returncode != 1:
            print(
                f"batch call failed (exit {out.returncode}): {out.stderr[-500:]}", file=sys.stderr
            )
            return 2
        print(
            f"one call, {args.files} files: {wall_one:.1f} s wall, {cpu_one:.1f} s CPU",
            file=sys.stderr,
            flush=True,
        )
        wall_many = cpu_many = 0.0
        for k, p in enumerate(files[:separate]):
            w, c, one = timed([args.cli, "grade", a.id, str(p)])
            wall_many, cpu_many = wall_many + w, cpu_many + c
            if json.loads(one.stdout)["pass"] != batch[p.name]:
                print(f"{p.name}: the verdicts differ", file=sys.stderr)
                return 2
            print(
                f"separate {k + 1}/{separate}: {wall_many:.1f} s wall, {cpu_many:.1f} s CPU",
                file=sys.stderr,
                flush=True,
            )
    print(f"grade {a.id}: {args.files} answer files (half right, half wrong)")
    print(f"{'':28s} {'wall s':>9s} {'CPU s':>9s} {'wall/file':>10s} {'CPU/file':>9s}")
    print(
        f"{'one call, ' + str(args.files) + ' files':28s} {wall_one:9.1f} {cpu_one:9.1f}"
        f" {wall_one / args.files:10.3f} {cpu_one / args.files:9.3f}"
    )
    print(
        f"{str(separate) + ' separate calls':28s} {wall_many:9.1f} {cpu_many:9.1f}"
        f" {wall_many / separate:10.3f} {cpu_many / separate:9.3f}"
    )
    per_one, per_many = cpu_one / args.files, cpu_many / separate
    print(f"CPU per file: {per_many / per_one:.1f} times less in one call; same verdicts")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
