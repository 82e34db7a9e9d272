"""Where the project's non-Python files live: the config schema, the LAMMPS scripts, the plugin.

Every path the package needs outside Python code is defined here and only here; the
Snakefile imports the plugin paths from this module too. They are found relative to the
repository checkout the package is installed from (``pip install -e .``, as
``envs/bootstrap.sh`` does).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["REPOSITORY", "SCHEMA_PATH", "LAMMPS_SCRIPTS_DIR", "PLUGIN_SOURCE_DIR",
           "PLUGIN_BUILD_DIR", "PLUGIN_LIBRARY_NAME"]

REPOSITORY = Path(__file__).resolve().parents[2]
SCHEMA_PATH = REPOSITORY / "config" / "schema.yaml"
LAMMPS_SCRIPTS_DIR = REPOSITORY / "workflow" / "lammps"
PLUGIN_SOURCE_DIR = REPOSITORY / "workflow" / "plugin"
PLUGIN_BUILD_DIR = REPOSITORY / "build" / "plugin"
PLUGIN_LIBRARY_NAME = "libsuspension_fabric_lammps.so"
