"""A regular (non-editable) install works: the package finds its schema, LAMMPS scripts and
plugin sources as package data (pyproject.toml: the engine files of simulation/lammps and config/schema.yaml), builds
the plugin from them and runs a simulation, with no repository checkout on its path."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.lammps

PROBE = """
import importlib, json, pkgutil
import suspension_fabric
modules = sorted(m.name for m in pkgutil.walk_packages(suspension_fabric.__path__, "suspension_fabric."))
for name in modules:
    importlib.import_module(name)
from suspension_fabric.io import resources
from suspension_fabric.simulation.lammps import ShearSettings, pack, run_startup
from suspension_fabric.simulation.lammps.plugin import plugin_path
packing = pack("packing", 20, seed=1)
run = run_startup("startup", packing.data_file, 0.002, progress=None,
                  settings=ShearSettings(dump_strain=0.001, table_strain=0.001, thermo_strain=0.001,
                                         restart_strain=0.001))
print(json.dumps({"checkout": str(resources.editable_checkout()), "schema": str(resources.SCHEMA_PATH),
                  "scripts": str(resources.LAMMPS_SCRIPTS_DIR), "sources": str(resources.PLUGIN_SOURCE_DIR),
                  "plugin": str(plugin_path()), "strain": run.strain, "modules": modules}))
"""


def test_a_regular_install_runs_without_the_checkout(tmp_path):
    source = tmp_path / "source"  # a copy, so the in-tree build leaves the checkout clean
    source.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(REPO / name, source / name)
    for name in ("src", "config", "workflow"):
        shutil.copytree(REPO / name, source / name, ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    target = tmp_path / "site"
    install = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--target", str(target), str(source)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert install.returncode == 0, install.stderr[-3000:]
    work = tmp_path / "work"
    work.mkdir()
    env = dict(os.environ, PYTHONPATH=str(target), SUSPENSION_FABRIC_BUILD_DIR=str(tmp_path / "plugin"))
    result = subprocess.run(
        [sys.executable, "-c", PROBE], cwd=work, env=env, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stderr[-3000:]
    found = json.loads(result.stdout.strip().splitlines()[-1])
    assert found["checkout"] == "None"
    data = target / "suspension_fabric" / "_data"
    assert found["schema"] == str(data / "config" / "schema.yaml")
    engine = target / "suspension_fabric" / "simulation" / "lammps"
    assert found["scripts"] == str(engine / "inputs") and found["sources"] == str(engine / "plugin_source")
    assert found["plugin"] == str(tmp_path / "plugin" / "libsuspension_fabric_lammps.so")
    assert found["strain"] == pytest.approx(0.002)
    # every module of the source tree is installed and imports (a package left out of pyproject.toml's
    # list would be missing from a cluster's install)
    tree = REPO / "src"
    in_source = sorted(
        ".".join(path.relative_to(tree).with_suffix("").parts).removesuffix(".__init__")
        for path in (tree / "suspension_fabric").rglob("*.py")
        if "plugin_source" not in path.parts
    )
    assert sorted(set(found["modules"]) | {"suspension_fabric"}) == in_source
