"""The package is laid out by the workflow's stages, and no module imports a stage above its own.

Every import of the package (module level or inside a function, absolute or relative) is read
from the source with ``ast`` and resolved to the stage it lands in.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import suspension_fabric

PACKAGE_DIR = Path(suspension_fabric.__file__).parent

# What each stage may import besides itself (lowest first). simulation and models are siblings.
ALLOWED = {
    "io": set(),
    "analysis": {"io"},
    "simulation": {"io", "analysis"},
    "models": {"io", "analysis"},
    "study": {"io", "analysis", "simulation", "models"},
    "evaluation": {"io", "analysis", "simulation", "models", "study"},
    "reporting": {"io", "analysis", "simulation", "models", "study", "evaluation"},
    # the logging helper of the workflow's scripts sits above every stage
    "workflow_io": {"io", "analysis", "simulation", "models", "study", "evaluation", "reporting"},
    # the rules' code versions read the package's files, never import them
    "code_version": set(),
}


def module_name(path: Path, package_dir: Path = PACKAGE_DIR) -> str:
    parts = path.relative_to(package_dir).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported_modules(path: Path, package_dir: Path = PACKAGE_DIR) -> list[tuple[int, str]]:
    """(line, name inside the package) of every import of the package in a source file."""
    name = module_name(path, package_dir)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
            found += [
                (node.lineno, m.removeprefix("suspension_fabric."))
                for m in modules
                if m.startswith("suspension_fabric.")
            ]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                module = ".".join([*base, node.module] if node.module else base)
            elif node.module == "suspension_fabric" or (node.module or "").startswith("suspension_fabric."):
                module = node.module.removeprefix("suspension_fabric").lstrip(".")
            else:
                continue
            # "from <package> import <module>" imports that module
            found += [(node.lineno, f"{module}.{alias.name}" if module else alias.name) for alias in node.names]
    return found


def stage(module: str) -> str:
    return module.split(".")[0]


MODULES = sorted(p for p in PACKAGE_DIR.rglob("*.py") if "_data" not in p.parts)


def test_every_module_belongs_to_a_stage():
    """Only the package's own __init__ and the scripts' helper live outside the stage folders."""
    loose = [module_name(p) for p in MODULES if stage(module_name(p)) not in ALLOWED and module_name(p) != ""]
    assert loose == []
    assert {stage(module_name(p)) for p in MODULES} - {""} == set(ALLOWED)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: module_name(p) or "__init__")
def test_no_module_imports_a_stage_above_its_own(path):
    own = stage(module_name(path))
    allowed = ALLOWED.get(own, set(ALLOWED)) | {own}
    upward = [f"line {line}: {target}" for line, target in imported_modules(path) if stage(target) not in allowed]
    assert upward == [], f"{module_name(path)} ({own}) imports above its stage: {upward}"


def test_the_import_reader_sees_relative_absolute_and_lazy_imports(tmp_path):
    """The check itself: an upward import of each kind is found (so the test above can fail)."""
    fake = tmp_path / "suspension_fabric"
    (fake / "analysis").mkdir(parents=True)
    source = fake / "analysis" / "probe.py"
    source.write_text(
        "import numpy\n"
        "from ..models import fabric_models\n"
        "from suspension_fabric.study.config import load_config\n"
        "import suspension_fabric.reporting.figures\n"
        "def later():\n"
        "    from ..io import dumpio\n"
        "from . import tables\n"
    )
    targets = sorted(target for _, target in imported_modules(source, fake))
    assert targets == [
        "analysis.tables",
        "io.dumpio",
        "models.fabric_models",
        "reporting.figures",
        "study.config.load_config",
    ]
    assert {stage(t) for t in targets} - ALLOWED["analysis"] - {"analysis"} == {"models", "study", "reporting"}


def test_the_api_reference_documents_every_module():
    """docs/api.md has a ``::: suspension_fabric.<module>`` entry for every module of the package."""
    api = (Path(__file__).parents[2] / "docs" / "api.md").read_text()
    documented = {line.removeprefix("::: suspension_fabric.") for line in api.splitlines() if line.startswith(":::")}
    assert {module_name(p) for p in MODULES} - {""} <= documented


MODULE_NAMES = {module_name(p) for p in MODULES}


def imported_module(target: str, modules: set[str] = MODULE_NAMES) -> str:
    """The module an import lands in: ``models.fabric_models.FabricModel`` -> ``models.fabric_models``."""
    while target and target not in modules:
        target = target.rpartition(".")[0]
    return target


def import_graph(paths: list[Path] = MODULES, package_dir: Path = PACKAGE_DIR) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (module level or inside functions)."""
    modules = {module_name(p, package_dir) for p in paths}
    return {
        module_name(p, package_dir): {imported_module(t, modules) for _, t in imported_modules(p, package_dir)}
        - {module_name(p, package_dir)}
        for p in paths
    }


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One cycle (``[a, b, ..., a]``) through every strongly connected group of two or more modules."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[set[str]] = []

    def visit(node: str) -> None:  # Tarjan's strongly connected components
        index[node] = low[node] = len(index)
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            group = set()
            while True:
                member = stack.pop()
                group.add(member)
                if member == node:
                    break
            if len(group) > 1:
                groups.append(group)

    for node in sorted(graph):
        if node not in index:
            visit(node)

    cycles = []
    for group in groups:
        start = min(group)
        path, seen = [start], {start}
        while True:  # walk inside the group until a module repeats
            nxt = min(m for m in graph[path[-1]] if m in group)
            if nxt in seen:
                cycles.append(path[path.index(nxt) :] + [nxt])
                break
            path.append(nxt)
            seen.add(nxt)
    return sorted(cycles)


def test_no_import_cycle_between_modules():
    """No module imports itself through others, not even by an import inside a function."""
    cycles = [" -> ".join(m or "suspension_fabric" for m in cycle) for cycle in import_cycles(import_graph())]
    assert cycles == [], f"import cycles: {cycles}"


def test_the_cycle_check_finds_a_cycle_through_a_lazy_import(tmp_path):
    """The check itself: a cycle closed by an import inside a function is found (so the test above can fail)."""
    fake = tmp_path / "suspension_fabric"
    (fake / "models").mkdir(parents=True)
    (fake / "models" / "a.py").write_text("from .b import thing\n")
    (fake / "models" / "b.py").write_text("def thing():\n    from suspension_fabric.models import c\n")
    (fake / "models" / "c.py").write_text("import numpy\nfrom .a import other\n")
    (fake / "models" / "d.py").write_text("from . import a\n")
    graph = import_graph(sorted(fake.rglob("*.py")), fake)
    assert import_cycles(graph) == [["models.a", "models.b", "models.c", "models.a"]]
    assert import_cycles({**graph, "models.c": set()}) == []
