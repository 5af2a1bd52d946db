"""A real redis-server (Debian's) on a free loopback port, started and stopped by a test."""

from __future__ import annotations

import os
import shutil
import subprocess
import time

import pytest

from tests.support.servers import free_port

REDIS_SERVER = "/usr/bin/redis-server"


def require_redis() -> str:
    """The path of Debian's redis-server; skip without it (fail under CI=true)."""
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
        self.path = require_redis()
        self.port = port or free_port()
        self.url = f"redis://127.0.0.1:{self.port}"
        self.proc: subprocess.Popen | None = None

    def start(self) -> RedisServer:
        """Start it (again, on the same port); returns when it answers a ping."""
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
            except (redis.exceptions.ConnectionError, redis.exceptions.TimeoutError):
                if time.monotonic() > deadline or self.proc.poll() is not None:
                    raise RuntimeError("redis-server did not start") from None
                time.sleep(0.05)
        client.close()
        return self

    def subscribers(self, channel: str) -> int:
        """How many connections listen on ``channel`` now."""
        import redis

        client = redis.Redis(host="127.0.0.1", port=self.port, socket_connect_timeout=0.5)
        try:
            return int(dict(client.pubsub_numsub(channel)).get(channel.encode(), 0))
        finally:
            client.close()

    def stop(self) -> None:
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(5)
        self.proc = None
