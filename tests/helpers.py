"""Small helpers shared by the tests that drive a live server."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from typing import Any


async def until(cond: Callable[[], Any], timeout: float = 10.0, what: str = "condition") -> Any:
    """Poll ``cond`` every 50 ms until it is truthy (returned) or ``timeout`` seconds pass."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = cond()
        if value:
            return value
        await asyncio.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")


REDIS_SERVER = "/usr/bin/redis-server"


def require_redis() -> str:
    """The path of Debian's redis-server; skip without it (fail under CI=true)."""
    import os
    import shutil

    import pytest

    path = REDIS_SERVER if os.path.exists(REDIS_SERVER) else shutil.which("redis-server")
    missing = None
    if path is None:
        missing = "redis-server not found; install it with `apt-get install redis-server`"
    else:
        try:
            import redis  # noqa: F401
        except ImportError:
            missing = "the python package `redis` is missing (pip install redis)"
    if missing:
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(missing + " (CI=true: the Redis tests must run)")
        pytest.skip(missing)
    assert path is not None
    return path


class RedisServer:
    """A real redis-server on a free loopback port (no persistence), started and stopped here."""

    def __init__(self, port: int | None = None) -> None:
        from benchmarks.loadtest import free_port

        self.path = require_redis()
        self.port = port or free_port()
        self.url = f"redis://127.0.0.1:{self.port}"
        self.proc: Any = None

    def start(self) -> RedisServer:
        import subprocess

        import redis

        self.proc = subprocess.Popen(
            [self.path, "--port", str(self.port), "--bind", "127.0.0.1", "--save", ""]
            + ["--appendonly", "no", "--protected-mode", "yes"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        client = redis.Redis(host="127.0.0.1", port=self.port, socket_connect_timeout=0.5)
        deadline = time.monotonic() + 10
        while True:
            try:
                client.ping()
                break
            except Exception:
                if time.monotonic() > deadline or self.proc.poll() is not None:
                    raise RuntimeError("redis-server did not start") from None
                time.sleep(0.05)
        client.close()
        return self

    def stop(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(5)
        self.proc = None


def start_worker(
    port: int, bus: str, name: str, code: str, log: Any, lesson: str = "sphere"
) -> Any:
    """``python -m app serve --bus BUS --worker-name NAME`` in a subprocess (stderr to ``log``)."""
    from benchmarks.loadtest import start_server

    return start_server(
        port,
        lesson,
        log,
        ("--bus", bus, "--worker-name", name, "--instructor-code", code),
    )


def stop_process(proc: Any) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(5)
        except Exception:
            proc.kill()
            proc.wait(5)
