"""A real PostgreSQL cluster (Debian's binaries) in a temporary folder on a free loopback
port, made, started, stopped and removed by a test.  initdb refuses to run as root: as
root the cluster belongs to the unprivileged user ``nobody``."""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

from tests.support.servers import free_port


def postgres_bin() -> Path | None:
    """The newest installed PostgreSQL's bin folder (Debian: /usr/lib/postgresql/N/bin)."""
    found = sorted(
        glob.glob("/usr/lib/postgresql/*/bin/initdb"),
        key=lambda p: (
            int(Path(p).parent.parent.name) if Path(p).parent.parent.name.isdigit() else 0
        ),
    )
    if found:
        return Path(found[-1]).parent
    initdb = shutil.which("initdb")
    return Path(initdb).parent if initdb else None


def require_postgres() -> Path:
    """The bin folder; skip without one (fail under CI=true)."""
    path = postgres_bin()
    if path is None:
        missing = "PostgreSQL not found; install it with `apt-get install postgresql`"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(missing + " (CI=true: the PostgreSQL tests must run)")
        pytest.skip(missing)
    assert path is not None
    return path


class PostgresCluster:
    """A throw-away cluster: trust authentication on 127.0.0.1 only, database ``lab``."""

    def __init__(self) -> None:
        self.bin = require_postgres()
        self.root = Path(tempfile.mkdtemp(prefix="analyzer-lab-pg-"))
        self.data = self.root / "data"
        self.port = free_port()
        self.url = f"postgresql://postgres@127.0.0.1:{self.port}/lab"
        self.as_root = os.geteuid() == 0

    def _run(self, *args: str, check: bool = True) -> subprocess.CompletedProcess:
        cmd = list(args)
        if self.as_root:
            cmd = ["runuser", "-u", "nobody", "--", *cmd]
        return subprocess.run(
            cmd, check=check, capture_output=True, text=True, timeout=60, cwd=self.root
        )

    def create(self) -> PostgresCluster:
        self.root.chmod(0o755)
        if self.as_root:
            shutil.chown(self.root, "nobody")
        self._run(
            str(self.bin / "initdb"),
            "-D",
            str(self.data),
            "-U",
            "postgres",
            "--auth=trust",
            "-E",
            "UTF8",
            "--no-sync",
        )
        return self.start()

    def start(self) -> PostgresCluster:
        """Start it (again); returns when it accepts connections."""
        self._run(
            str(self.bin / "pg_ctl"),
            "-D",
            str(self.data),
            "-l",
            str(self.root / "log"),
            "-w",
            "-t",
            "60",
            "-o",
            f"-p {self.port} -c listen_addresses=127.0.0.1 -k {self.root} -c fsync=off",
            "start",
        )
        if not getattr(self, "made", False):
            self._run(
                str(self.bin / "psql"),
                "-h",
                "127.0.0.1",
                "-p",
                str(self.port),
                "-U",
                "postgres",
                "-c",
                "CREATE DATABASE lab",
                "postgres",
            )
            self.made = True
        return self

    def stop(self, mode: str = "fast") -> None:
        self._run(
            str(self.bin / "pg_ctl"), "-D", str(self.data), "-m", mode, "-w", "stop", check=False
        )

    def remove(self) -> None:
        self.stop("immediate")
        deadline = time.monotonic() + 10
        while (self.data / "postmaster.pid").exists() and time.monotonic() < deadline:
            time.sleep(0.1)
        shutil.rmtree(self.root, ignore_errors=True)


__all__ = ["PostgresCluster", "postgres_bin", "require_postgres"]
