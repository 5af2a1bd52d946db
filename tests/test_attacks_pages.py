"""Attacks by pages from another address (127.0.0.2) against ``python -m analyzer_lab
serve`` in a subprocess, measured like :mod:`tests.test_attacks_transport` (a normal page's
updates/s before, during and after; the server's memory), on a server of their own: pages
that leave while their GUI is built.  (Pages that stop reading are held by
:mod:`tests.test_back_pressure`.)"""

from __future__ import annotations

import asyncio
import subprocess
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from tests.support.servers import ServeProcess
from tests.test_attacks_transport import _measured, attacked_server


@pytest.fixture(scope="module")
def server(serve: Callable[..., ServeProcess]) -> Iterator[tuple[str, subprocess.Popen]]:
    yield from attacked_server(serve)


def test_pages_leaving_mid_build_do_not_slow_the_class(server: Any) -> None:
    async def go() -> None:
        _, figures, _ = await _measured(server, "churn: 300 pages leave mid-build", 15.0)
        assert figures["aborted"] >= 300, figures

    asyncio.run(go())
