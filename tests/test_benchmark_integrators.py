"""The integrator benchmark's table: same problems, all methods, sensible ordering."""

from benchmarks.integrators import format_table, run_benchmark


def test_quick_benchmark_rows_and_orders():
    rows = run_benchmark(t_end=5.0, quick=True)
    problems = {r.problem for r in rows}
    assert len(problems) == 3
    for p in problems:
        mine = [r for r in rows if r.problem == p]
        rk45 = next(r for r in mine if r.method.startswith("RK45"))
        gl = [r for r in mine if r.method.startswith("Gauss")]
        # the invariant: GL at round-off, RK45 at default tolerances far from it
        assert max(r.drift for r in gl) < 1e-14
        assert rk45.drift > 1e3 * max(r.drift for r in gl)
        assert min(r.error for r in gl) < 1e-9 < rk45.error
        # orders 6 and 12; the fair pick: least CPU time of those at most DOP853's error
        assert {r.method.split(" (")[0] for r in gl} == {"Gauss-Legendre 3", "Gauss-Legendre 6"}
        dop = next(r for r in mine if r.method.startswith("DOP853"))
        picked = [r for r in mine if "equal accuracy" in r.note]
        accurate = [r for r in gl if r.error <= dop.error]
        assert len(picked) == 1 and picked[0] in accurate
        assert picked[0].seconds == min(r.seconds for r in accurate)
    table = format_table(rows)
    assert table.count("\n") == len(rows) + 1 and "equal accuracy" in table
