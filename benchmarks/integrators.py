"""Integrator benchmark: the default Gauss–Legendre integrator against scipy's ``solve_ivp``.

    python -m benchmarks.integrators [--t-end 100] [--quick]

For the same problems in one run: invariant drift max|F - F0| / scale, error along the
curve against a tight reference (max |r - r_ref| / max(1, |r_ref|) over samples every 0.1 s), CPU time
(the least of three runs),
right-hand-side evaluations (for the affine analyzer: steps, each one batched linear
solve), and the CPU-time ratio at equal accuracy along the curve (of the Gauss-Legendre
runs, 3 and 6 stages at several steps, whose error is at most DOP853's at
rtol = atol = 1e-12, the one of least CPU time).  The reference is DOP853 at
rtol = 2.5e-14, atol = 1e-15.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from analyzer_lab.lessons.analyzers.field.analyzer import AnalyzerModel
from analyzer_lab.lessons.analyzers.field.run import integrate

from tests.support.integrator_problems import problems


@dataclass
class BenchRow:
    problem: str
    method: str
    drift: float
    error: float
    seconds: float
    nfev: int
    note: str = ""


def _timed(model: AnalyzerModel, r0: np.ndarray, t_end: float, repeat: int = 3, **kw: object):
    """Run ``repeat`` times; the least CPU time of this process (the machine may be busy
    with other processes: their time does not count)."""
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        run = integrate(model, r0, t_end, **kw)  # type: ignore[arg-type]
        best = min(best, time.process_time() - t0)
    return run, best


def run_benchmark(t_end: float = 100.0, quick: bool = False) -> list[BenchRow]:
    if quick:
        t_end = min(t_end, 20.0)
    samples = int(round(t_end / 0.1)) + 1
    rows: list[BenchRow] = []
    for name, q, controls, r0 in problems():
        model = AnalyzerModel.of(q.coeffs(), controls)
        ref, _ = _timed(
            model, r0, t_end, repeat=1, method="DOP853", rtol=2.5e-14, atol=1e-15, samples=samples
        )
        # F's terms where the point goes (unbounded surfaces): round-off of F is ~1e-16 of it
        scale = float(max(q.scale, np.max(model.F_scale(ref.r))))

        def row(method: str, run, sec: float, note: str = "") -> BenchRow:
            if run.t.shape != ref.t.shape or np.max(np.abs(run.t - ref.t)) > 1e-9:
                raise ValueError(
                    f"{method}: samples do not line up with the reference (the step must divide 0.1)"
                )
            # relative to the size of r (trajectories on unbounded surfaces may run far)
            err = float(
                np.max(
                    np.abs(run.r - ref.r)
                    / np.maximum(1.0, np.linalg.norm(ref.r, axis=-1, keepdims=True))
                )
            )
            work = (
                int(run.nfev)
                if run.nfev
                else int(round(t_end / float(method.split("h=")[1].rstrip(")"))))
                if "h=" in method
                else 0
            )
            return BenchRow(name, method, float(run.drift.max() / scale), err, sec, work, note)

        rk45, s_rk45 = _timed(model, r0, t_end, method="RK45", samples=samples)
        rows.append(row("RK45 (default tol)", rk45, s_rk45))
        dop, s_dop = _timed(
            model, r0, t_end, method="DOP853", rtol=1e-12, atol=1e-12, samples=samples
        )
        dop_row = row("DOP853 (rtol=atol=1e-12)", dop, s_dop)
        rows.append(dop_row)
        # Gauss-Legendre of order 6 and 12 at several steps; the fair choice at equal
        # accuracy: the least CPU time of the rows whose error is at most DOP853's
        hs = (
            (0.05, 0.025, 0.0125, 0.00625)
            if controls.V is None
            else (0.05, 0.025, 0.02, 0.0125, 0.01)
        )
        runs = [(3, h) for h in hs] + [(6, h) for h in (0.1, 0.05)]
        gl_rows: list[BenchRow] = []
        for stages, h in runs:
            gl, s_gl = _timed(
                model, r0, t_end, method=f"gauss-legendre-{stages}", h=h, samples=samples
            )
            gl_rows.append(row(f"Gauss-Legendre {stages} (h={h:g})", gl, s_gl))
        rows.extend(gl_rows)
        accurate = [r for r in gl_rows if r.error <= dop_row.error]
        if accurate:
            chosen = min(accurate, key=lambda r: r.seconds)
            chosen.note = f"equal accuracy: {chosen.seconds / dop_row.seconds:.2f}x DOP853's time"
        else:
            rows[-1].note = "did not reach DOP853's accuracy at these steps"
    return rows


def format_table(rows: list[BenchRow]) -> str:
    head = (
        "| problem | method | max drift/scale | max error along curve | CPU s"
        " | RHS evals (GL affine: steps) | note |\n|---|---|---|---|---|---|---|"
    )
    body = [
        f"| {r.problem} | {r.method} | {r.drift:.2e} | {r.error:.2e} | {r.seconds:.3f}"
        f" | {r.nfev or '-'} | {r.note} |"
        for r in rows
    ]
    return "\n".join([head, *body])


def main(argv: list[str] | None = None) -> int:
    import argparse

    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.integrators", description=__doc__.split("\n\n")[0]
    )
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--quick", action="store_true", help="a shorter run")
    args = ap.parse_args(argv)
    print(format_table(run_benchmark(t_end=args.t_end, quick=args.quick)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
