"""suspension_fabric.code_version: which files a script's code version covers, and which edits
change it. A small stand-in package in tmp_path (named suspension_fabric, as the real one) for the
rules, the real workflow scripts for what the rules' params cover; the workflow itself is run in
tests/workflow/test_workflow_code_reruns.py."""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import pytest

from suspension_fabric.code_version import CodeVersions, code_files, code_version, imported_modules

REPO = Path(__file__).resolve().parents[2]
SCRIPTS = REPO / "workflow" / "scripts"

PACKAGE = {
    "__init__.py": '"""The package."""\n',
    "a/__init__.py": "",
    "a/x.py": (
        '"""Module x."""\n\n'
        "from suspension_fabric.io import files\n\n\n"
        "def f(value):\n"
        '    """Twice the value."""\n'
        "    from .y import g  # lazy\n\n"
        "    return 2 * g(value)  # a comment\n"
    ),
    "a/y.py": "def g(value):\n    return value\n",
    "a/unused.py": "UNUSED = 1\n",
    "a/inputs/run.lmp": "variable x equal 1\n",
    "a/inputs/README.md": "notes\n",
    "io/__init__.py": "",
    "io/files.py": "NAME = 'files'\n",
    "study/__init__.py": "",
    "study/config.py": "from suspension_fabric.a import unused\n",
    "b/__init__.py": "from . import z\n",
    "b/z.py": "Z = 1\n",
}
SCRIPT = "from suspension_fabric.a.x import f\nfrom suspension_fabric.study.config import load\nimport numpy\n"


@pytest.fixture
def tree(tmp_path):
    root = tmp_path / "checkout" / "src" / "suspension_fabric"
    for name, text in PACKAGE.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    script = tmp_path / "checkout" / "scripts" / "job.py"
    script.parent.mkdir()
    script.write_text(SCRIPT)
    return root, script


def version(tree, ignore=()):
    root, script = tree
    return code_version(script, ignore, root=root)


def test_the_version_covers_the_modules_a_script_imports_and_their_data(tree):
    """Imports at any depth, lazy and relative ones included, with the packages' __init__ files and
    the data in non-package folders beside the modules; not other modules, not Markdown, not the
    config's validation (its results are the rules' params), not third-party packages."""
    root, script = tree
    assert imported_modules(script, root=root) == [
        "suspension_fabric",
        "suspension_fabric.a",
        "suspension_fabric.a.x",
        "suspension_fabric.a.y",
        "suspension_fabric.io",
        "suspension_fabric.io.files",
        "suspension_fabric.study",
    ]
    assert sorted(code_files(script, root=root)) == [
        "__init__.py",
        "a/__init__.py",
        "a/inputs/run.lmp",
        "a/x.py",
        "a/y.py",
        "io/__init__.py",
        "io/files.py",
        "script:job.py",
        "study/__init__.py",
    ]


def edit(path: Path, old: str, new: str):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))


UNCHANGED = {
    "a comment": ("a/x.py", "# a comment", "# another comment"),
    "a docstring": ("a/x.py", "Twice the value.", "The value doubled."),
    "the layout": ("a/x.py", "return 2 * g(value)", "return (2 *\n            g(value))"),
    "a module's docstring": ("__init__.py", "The package.", "The package, described."),
    "the README beside the data": ("a/inputs/README.md", "notes", "other notes"),
    "a module the script does not run": ("b/z.py", "Z = 1", "Z = 2"),
    "the config's validation": ("study/config.py", "import unused", "import unused as u"),
}
CHANGED = {
    "the code of an imported module": ("a/x.py", "2 * g(value)", "3 * g(value)"),
    "a lazily imported module": ("a/y.py", "return value", "return -value"),
    "a package's __init__": ("a/__init__.py", "", "FLAG = True\n"),
    "a data file": ("a/inputs/run.lmp", "equal 1", "equal 2"),
    "the script": ("../../scripts/job.py", "import numpy", "import numpy as np"),
}


@pytest.mark.parametrize("case", UNCHANGED)
def test_edits_that_change_no_code_keep_the_version(tree, case):
    name, old, new = UNCHANGED[case]
    before = version(tree)
    edit(tree[0] / name, old, new)
    assert version(tree) == before


@pytest.mark.parametrize("case", CHANGED)
def test_edits_of_the_code_that_runs_change_the_version(tree, case):
    name, old, new = CHANGED[case]
    before = version(tree)
    path = tree[0] / name
    if old:
        edit(path, old, new)
    else:
        path.write_text(path.read_text() + new)
    assert version(tree) != before


def test_added_code_changes_the_version(tree):
    """A new module imported by an imported one, or a new data file."""
    root, _ = tree
    before = version(tree)
    (root / "a" / "inputs" / "extra.lmp").write_text("# more\n")
    with_data = version(tree)
    assert with_data != before
    (root / "a" / "w.py").write_text("W = 1\n")
    edit(root / "a" / "y.py", "def g", "from .w import W\n\n\ndef g")
    assert version(tree) not in {before, with_data}


def test_the_version_depends_on_contents_not_on_paths_or_times(tree, tmp_path):
    """The package and script copied elsewhere, every file with a new time: the same version."""
    root, script = tree
    before = version(tree)
    moved = tmp_path / "elsewhere" / "deeper"
    shutil.copytree(tmp_path / "checkout", moved)
    for path in moved.rglob("*"):
        os.utime(path, (1e9, 1e9))
    assert code_version(moved / "scripts" / "job.py", root=moved / "src" / "suspension_fabric") == before


def test_ignored_modules_and_what_only_they_import_are_left_out(tree):
    """ignore names a module (or a package): it is not covered, nor what only it imports."""
    root, script = tree
    before = version(tree)
    ignored = code_files(script, ["suspension_fabric.a.y"], root=root)
    assert "a/y.py" not in ignored and "a/x.py" in ignored
    after = version(tree, ["suspension_fabric.a.y"])
    assert after != before
    edit(root / "a" / "y.py", "return value", "return -value")
    assert version(tree, ["suspension_fabric.a.y"]) == after
    assert "io/files.py" not in code_files(script, ["suspension_fabric.io"], root=root)


def test_one_instance_reads_each_file_once(tree):
    """CodeVersions caches what it parsed: an edit after the first version is not seen by it (the
    workflow makes one per run), and is by a new one."""
    root, script = tree
    versions = CodeVersions(root)
    before = versions.version(script)
    edit(root / "a" / "y.py", "return value", "return -value")
    assert versions.version(script) == before
    assert CodeVersions(root).version(script) != before


def test_the_parse_cache_file_gives_the_same_versions_and_sees_edits(tree, tmp_path):
    """With a cache file (the workflow keeps one in .snakemake/), a second load parses nothing it
    has seen and gives the same version; an edited file has new bytes, so it is parsed again."""
    root, script = tree
    cache = tmp_path / "cache" / "code_versions.json"
    first = CodeVersions(root, cache=cache).version(script)
    assert cache.is_file() and first == CodeVersions(root).version(script)
    assert CodeVersions(root, cache=cache).version(script) == first
    edit(root / "a" / "y.py", "return value", "return -value")
    assert CodeVersions(root, cache=cache).version(script) == CodeVersions(root).version(script) != first


# --- the real scripts


def rule_scripts():
    """(rule, script as in its `script:` line, its `code` param's text) of every rule of the workflow."""
    found = []
    for path in sorted((REPO / "workflow" / "rules").glob("*.smk")):
        for block in re.split(r"\n(?=\s*rule[\s\w]*:\n)", path.read_text()):
            match = re.match(r"\s*rule\s*(\w*):\n", block)
            script = re.search(r"\n\s*script:\n\s*\"([^\"]+)\"", block)
            if match and script:
                name = match.group(1) or re.search(r"name:\n\s*(.+)", block).group(1)
                code = re.search(r"\n\s*code=(.+),\n", block)
                found.append((name, script.group(1), code.group(1) if code else None))
    return found


def test_every_rule_carries_the_code_version_of_its_own_script():
    """Each rule's `code` param names the script of its `script:` line."""
    found = rule_scripts()
    assert len(found) > 30
    for rule, script, code in found:
        assert code is not None, f"rule {rule} has no code param"
        assert re.fullmatch(rf'code_version\("{re.escape(script)}"(, ignore=SIMULATION_CHECKS)?\)', code), (rule, code)
        assert ("ignore=" in code) == (rule in {"pack", "shear_segment"}), rule


SIMULATION_CHECKS = ["suspension_fabric.analysis.fabric", "suspension_fabric.analysis.fabric_reference"]


def test_the_simulations_cover_the_lammps_inputs_and_not_the_analysis():
    """What the simulation rules' params cover (as workflow/rules/common.smk computes them): the
    engine and its LAMMPS inputs, not the fabric analysis of their overlap check, the models, the
    config's validation or the plugin's sources (those reach them through the plugin library)."""
    versions = CodeVersions()
    for script in ("shear.py", "pack.py"):
        files = versions.files(SCRIPTS / script, SIMULATION_CHECKS)
        assert "simulation/lammps/runner.py" in files and "simulation/lammps/inputs/segment.lmp" in files
        assert not [name for name in files if name.startswith(("analysis/fabric", "models/", "study/config"))]
        assert not [name for name in files if "plugin_source" in name]
    fabric_table = versions.files(SCRIPTS / "fabric_table.py")
    assert "analysis/fabric.py" in fabric_table
    assert not [name for name in fabric_table if name.startswith("simulation/lammps")]
