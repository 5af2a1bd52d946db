"""The server's math libraries run one thread per call (app/serve/threads.py)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import pytest
from analyzer_lab.serve.cli import main
from analyzer_lab.serve.threads import THREAD_VARIABLES

pytestmark = pytest.mark.quick

PROBE = textwrap.dedent(
    """
    import ctypes, glob, os, sys
    from analyzer_lab.serve.threads import one_math_thread
    print(one_math_thread())
    import numpy
    libs = glob.glob(os.path.join(os.path.dirname(numpy.__file__), os.pardir, "numpy.libs", "*openblas*"))
    count = None
    for lib in libs:
        for name in ("scipy_openblas_get_num_threads64_", "openblas_get_num_threads64_",
                     "openblas_get_num_threads"):
            f = getattr(ctypes.CDLL(lib), name, None)
            if f is not None:
                count = f()
                break
    print(count)
    print(os.environ["OPENBLAS_NUM_THREADS"])
    """
)


def _probe(env: dict[str, str]) -> list[str]:
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env=env, capture_output=True, text=True, timeout=60
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.split()


def _clean_env() -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k not in THREAD_VARIABLES}


def test_one_thread_before_numpy_loads() -> None:
    first, count, variable = _probe(_clean_env())
    assert first == "True" and variable == "1"
    if count != "None":  # numpy's own OpenBLAS answers how many threads it runs
        assert count == "1"


def test_a_setting_in_the_environment_is_kept() -> None:
    _, count, variable = _probe({**_clean_env(), "OPENBLAS_NUM_THREADS": "2"})
    assert variable == "2"
    if count != "None" and (os.cpu_count() or 1) >= 2:
        assert count == "2"


def test_serve_sets_it_first(monkeypatch: pytest.MonkeyPatch) -> None:
    for name in THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    assert main(["serve", "--workers", "0", "--no-browser"]) == 2  # refused after the setting
    assert all(os.environ[name] == "1" for name in THREAD_VARIABLES)
