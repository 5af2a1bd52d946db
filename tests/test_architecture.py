"""The house's rules, read from the code's imports (every import: at the top, inside
functions and under ``TYPE_CHECKING``).

The layers, from the bottom: the model (``analyzer_lab.lessons``: the kit, then each
domain's machinery, its pages, the catalog, the assignments), then the view's own layers
(``limits``, ``viser_boundary``, ``session``, ``view``, ``classroom``, ``serve``, and the
package's face). An import may point down or sideways within a layer, never up; no
import circle anywhere; no page imports another page; no domain imports another; only
``viser_boundary`` touches viser's private names.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import tomllib

ROOT = Path(__file__).resolve().parent.parent
#: Source folders and the package each one is.
FOLDERS = {"app": "analyzer_lab", "lessons": "analyzer_lab.lessons"}
LESSONS = "analyzer_lab.lessons"
#: The domains of the model: pages stand directly in them (or are their ``__init__``).
DOMAINS = ("analyzers", "mechanics", "vibration", "servo", "laser5")
#: The view's layers, bottom first (a module's layer is its first package below analyzer_lab).
APP_LAYERS = (
    "token_bucket",
    "limits",
    "text_numbers",
    "pseudo",
    "i18n",
    "lesson_texts",
    "viser_boundary",
    "session",
    "view",
    "classroom",
    "serve",
    "api",
    "__init__",
    "__main__",
)
#: viser's private names the boundary uses: nothing else in the lab may touch them.
VISER_PRIVATE = re.compile(
    r"\._(websock_server|websock_connection|impl|thread_executor|queue_update|queue_scene_message"
    r"|background_event_loop|live_connections|viser_server|scene_lifecycle_lock|connected_clients"
    r"|prop_hints|message_consumer|assignable_props_api|scene_api|messages|infra)\b"
)


@dataclass(frozen=True)
class Module:
    name: str
    path: Path
    is_package: bool


def modules() -> dict[str, Module]:
    found: dict[str, Module] = {}
    for folder, package in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT / folder).with_suffix("").parts
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            name = ".".join((package, *parts))
            if name.startswith(LESSONS) and folder == "app":
                continue  # app/ holds no lessons
            found[name] = Module(name, path, is_package)
    return found


MODULES = modules()


def imports(module: Module) -> Iterator[tuple[str, tuple[str, ...], int]]:
    """(imported module, names taken from it, line) for every import in the file."""
    tree = ast.parse(module.path.read_text(encoding="utf-8"))
    package = module.name if module.is_package else module.name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, (), node.lineno
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            names = tuple(a.name for a in node.names)
            yield base, names, node.lineno


def edges(module: Module) -> Iterator[tuple[str, int]]:
    """The lab's modules this one imports (``from pkg import mod`` counts as ``pkg.mod``)."""
    for base, names, line in imports(module):
        if not base.startswith("analyzer_lab"):
            continue
        taken = [f"{base}.{n}" for n in names if f"{base}.{n}" in MODULES]
        if taken:
            yield from ((t, line) for t in taken)
        if base in MODULES and len(taken) < len(names) or (not names and base in MODULES):
            yield base, line


GRAPH = {name: sorted({t for t, _ in edges(m) if t != name}) for name, m in MODULES.items()}


def circles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in GRAPH:
        if v not in index:
            visit(v)
    return found


def is_page(name: str) -> bool:
    """A page stands directly in a domain, or is a domain that is one page."""
    parts = name.split(".")
    if len(parts) < 3 or parts[:2] != ["analyzer_lab", "lessons"] or parts[2] not in DOMAINS:
        return False
    domain = MODULES[".".join(parts[:3])].path.read_text(encoding="utf-8")
    domain_is_page = "\nLESSON = " in domain
    if len(parts) == 3:
        return domain_is_page
    return len(parts) == 4 and not MODULES[name].is_package and not domain_is_page


def lesson_rank(name: str) -> int:
    """The model's layers: kit 0, machinery 1, pages 2, catalog 3, assignments 4."""
    parts = name.split(".")
    if len(parts) == 2:
        return 5
    if parts[2] == "kit":
        return 0
    if parts[2] == "catalog":
        return 3
    if parts[2] == "assignments":
        return 4
    return 2 if is_page(name) else 1


def app_rank(name: str) -> int:
    parts = name.split(".")
    return APP_LAYERS.index(parts[1] if len(parts) > 1 else "__init__")


def test_the_graph_is_read() -> None:
    assert len(MODULES) > 140
    assert "analyzer_lab.lessons.kit.contract" in GRAPH["analyzer_lab.lessons.analyzers.sphere"]
    assert sum(len(v) for v in GRAPH.values()) > 350


def test_no_import_circles() -> None:
    assert circles() == []


def test_the_model_never_imports_the_view() -> None:
    bad = [
        f"{m} imports {t}"
        for m, targets in GRAPH.items()
        if m.startswith(LESSONS)
        for t in targets
        if not t.startswith(LESSONS) and t != "analyzer_lab"
    ]
    assert bad == []


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_point_down_or_sideways(module: str) -> None:
    bad = []
    for target in GRAPH[module]:
        if module.startswith(LESSONS) and target.startswith(LESSONS):
            if lesson_rank(target) > lesson_rank(module) and lesson_rank(module) != 5:
                bad.append(f"{target} (a higher layer of the model)")
            mine, theirs = module.split("."), target.split(".")
            if (
                len(mine) > 2
                and len(theirs) > 2
                and mine[2] in DOMAINS
                and theirs[2] in DOMAINS
                and mine[2] != theirs[2]
            ):
                bad.append(f"{target} (another domain)")
            if is_page(module) and is_page(target):
                bad.append(f"{target} (another page)")
        elif not module.startswith(LESSONS) and not target.startswith(LESSONS):
            if app_rank(target) > app_rank(module):
                bad.append(f"{target} (a higher layer of the view)")
    assert bad == [], f"{module} imports " + "; ".join(bad)


def test_no_private_name_crosses_a_module() -> None:
    bad = []
    for name, module in MODULES.items():
        for base, names, line in imports(module):
            if not base.startswith("analyzer_lab"):
                continue
            own_package = name if module.is_package else name.rpartition(".")[0]
            private_module = any(p.startswith("_") and p != "__main__" for p in base.split("."))
            if private_module and not base.startswith(own_package):
                bad.append(f"{module.path.relative_to(ROOT)}:{line} imports {base}")
            for n in names:
                if n.startswith("_") and f"{base}.{n}" not in MODULES:
                    bad.append(f"{module.path.relative_to(ROOT)}:{line} takes {n} from {base}")
    assert bad == []


def test_only_the_boundary_touches_viser_internals() -> None:
    bad = []
    for name, module in MODULES.items():
        if name.startswith("analyzer_lab.viser_boundary"):
            continue
        for base, names, line in imports(module):
            if base.startswith("viser") and (
                any(p.startswith("_") for p in base.split("."))
                or any(n.startswith("_") for n in names)
                or base.startswith("viser.infra")
            ):
                bad.append(f"{module.path.relative_to(ROOT)}:{line} imports {base} {names}")
        for k, text in enumerate(module.path.read_text(encoding="utf-8").splitlines(), 1):
            if VISER_PRIVATE.search(text):
                bad.append(f"{module.path.relative_to(ROOT)}:{k}: {text.strip()}")
    assert bad == []


def test_the_boundary_is_used_through_its_face() -> None:
    """The rest of the lab imports ``analyzer_lab.viser_boundary`` itself, never a private
    module of it; the check finds the boundary's own uses (so it can fail)."""
    inside = [
        t
        for m, targets in GRAPH.items()
        if m.startswith("analyzer_lab.viser_boundary")
        for t in targets
        if t.startswith("analyzer_lab.viser_boundary._")
    ]
    assert inside, "the boundary's private modules should be found"
    outside = [
        f"{m} imports {t}"
        for m, targets in GRAPH.items()
        if not m.startswith("analyzer_lab.viser_boundary")
        for t in targets
        if t.startswith("analyzer_lab.viser_boundary._")
    ]
    assert outside == []


def test_no_formatter_exclusions() -> None:
    bad = [
        f"{m.path.relative_to(ROOT)}:{k}"
        for m in MODULES.values()
        for k, line in enumerate(m.path.read_text(encoding="utf-8").splitlines(), 1)
        if re.search(r"#\s*fmt:\s*(skip|off)", line)
    ]
    assert bad == []


def test_no_generic_top_level_imports() -> None:
    """Nothing imports ``app`` or ``lessons`` as top-level names: they are folders, and the
    installed distribution claims only ``analyzer_lab``."""
    files = [*(m.path for m in MODULES.values()), *ROOT.joinpath("tests").rglob("*.py")]
    files += list(ROOT.joinpath("benchmarks").rglob("*.py"))
    bad = []
    for path in files:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module or ""]
            bad += [
                f"{path.relative_to(ROOT)}:{node.lineno} {n}"
                for n in names
                if n.split(".")[0] in ("app", "lessons")
            ]
    assert bad == []


def test_every_package_is_shipped() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    shipped = set(config["tool"]["setuptools"]["packages"])
    found = {m.name for m in MODULES.values() if m.is_package}
    assert found == shipped
    assert config["tool"]["setuptools"]["package-dir"] == {
        "analyzer_lab": "app",
        "analyzer_lab.lessons": "lessons",
    }
