"""Start-up of the command line, and ``al.run`` in a warm process against the command line.

    python -m benchmarks.startup [--runs 100] [--repeats 5] [--cli analyzer-lab]

Whole processes, wall time from start to exit (the median of ``--repeats`` runs):
``analyzer-lab run sphere --preset example-1.1``, a refused formula
(``run sphere --set u1=__import__(1)``) and ``analyzer-lab lessons``. Then ``--runs`` runs
of the sphere's Example 1.1: ``al.run`` in this process (warmed by one run first) against
as many ``analyzer-lab run ... --format json`` processes, one after the other. The numbers
are the same either way (``tests/test_api_same_numbers.py``).
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import time

COMMANDS = {
    "run sphere --preset example-1.1": ["run", "sphere", "--preset", "example-1.1"],
    "run sphere --set u1=__import__(1) (refused)": ["run", "sphere", "--set", "u1=__import__(1)"],
    "lessons": ["lessons"],
}


def wall(command: list[str]) -> float:
    """Seconds from the start of ``command`` to its exit (its output thrown away)."""
    start = time.perf_counter()
    subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    return time.perf_counter() - start


def command_line(cli: list[str], repeats: int) -> dict[str, float]:
    """The median wall time of each command."""
    out = {}
    for name, argv in COMMANDS.items():
        wall(cli + argv)  # warm the file cache
        out[name] = statistics.median(wall(cli + argv) for _ in range(repeats))
    return out


def warm_api_against_cli(cli: list[str], runs: int) -> tuple[float, float]:
    """Seconds for ``runs`` runs of Example 1.1: ``al.run`` in this process, the command line
    in a process each."""
    import analyzer_lab as al

    al.run("sphere", preset="example-1.1")  # the warm process: its lesson imported
    start = time.perf_counter()
    for _ in range(runs):
        al.run("sphere", preset="example-1.1")
    api = time.perf_counter() - start
    argv = cli + COMMANDS["run sphere --preset example-1.1"] + ["--format", "json"]
    start = time.perf_counter()
    for _ in range(runs):
        subprocess.run(argv, stdout=subprocess.DEVNULL, check=True)
    return api, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--cli", default=shutil.which("analyzer-lab") or "analyzer-lab")
    args = parser.parse_args()
    cli = [args.cli]
    print("| command | wall time (median) |\n|---|---:|")
    for name, seconds in command_line(cli, args.repeats).items():
        print(f"| `analyzer-lab {name}` | {seconds:.2f} s |")
    api, per_process = warm_api_against_cli(cli, args.runs)
    print(f"\n| {args.runs} runs of sphere Example 1.1 | total | per run |\n|---|---:|---:|")
    print(f"| `al.run` in a warm process | {api:.2f} s | {api / args.runs * 1e3:.1f} ms |")
    print(
        f"| `analyzer-lab run` (a process each) | {per_process:.2f} s"
        f" | {per_process / args.runs * 1e3:.0f} ms |"
    )
    sys.stdout.flush()


if __name__ == "__main__":
    main()
