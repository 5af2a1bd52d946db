"""The classroom below the server: it never imports the server, no module of the app
imports itself through others, and the server and the classroom meet through the
protocols of :mod:`analyzer_lab.classroom.ports`.

Imports are read from the source (every ``import``, under ``TYPE_CHECKING`` and inside
functions too), not from what happens to be loaded."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import analyzer_lab
import pytest

APP = Path(analyzer_lab.__file__).resolve().parent


def app_modules() -> dict[str, Path]:
    """Every module of the app (the model, ``analyzer_lab.lessons``, left out) by name."""
    found = {}
    for path in sorted(APP.rglob("*.py")):
        parts = path.relative_to(APP).with_suffix("").parts
        if parts[0] == "lessons":
            continue
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(("analyzer_lab", *parts))] = path
    return found


def imported_names(name: str, path: Path) -> Iterator[str]:
    """Every module name ``path`` imports, wherever the import stands; ``from a import b``
    gives ``a`` and ``a.b``."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            yield base
            yield from (f"{base}.{alias.name}" for alias in node.names)


def import_graph() -> dict[str, set[str]]:
    modules = app_modules()
    return {
        name: {n for n in imported_names(name, path) if n in modules and n != name}
        for name, path in modules.items()
    }


def test_the_classroom_never_imports_the_server() -> None:
    modules = app_modules()
    classroom = [n for n in modules if n.startswith("analyzer_lab.classroom")]
    assert "analyzer_lab.classroom.room" in classroom
    wrong = sorted(
        (name, imported)
        for name in classroom
        for imported in imported_names(name, modules[name])
        if imported == "analyzer_lab.serve" or imported.startswith("analyzer_lab.serve.")
    )
    assert not wrong, wrong


def test_no_module_of_the_app_imports_itself_through_others() -> None:
    graph = import_graph()
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    cycles = []

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for other in sorted(graph[name]):
            if state.get(other) == 1:
                cycles.append(path[path.index(other) :] + [other])
            elif other not in state:
                visit(other, [*path, other])
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    assert not cycles, cycles


@pytest.mark.live
@pytest.mark.timeout(60)
def test_the_server_and_the_classroom_meet_through_the_ports() -> None:
    from analyzer_lab.classroom.ports import Lab, RoomForBoard, RoomForLink, RoomForPanels
    from analyzer_lab.lessons.analyzers.sphere import LESSON as SPHERE
    from analyzer_lab.serve.server import LabServer

    lab = LabServer(host="127.0.0.1", port=0, lessons=[SPHERE], warm_up=False, restore=False)
    try:
        assert isinstance(lab, Lab)
        room = lab.classroom
        for port in (RoomForLink, RoomForPanels, RoomForBoard):
            assert isinstance(room, port), port.__name__
        assert room.lab is lab and room.link.room is room and room.board.room is room
        assert lab.open_views() == []
    finally:
        lab.stop()
