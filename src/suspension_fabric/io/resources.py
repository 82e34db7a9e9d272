"""Where the project's non-Python files live: the config schema, the LAMMPS scripts, the plugin.

Every path the package needs outside its Python code is defined here and only here (the
Snakefile imports the plugin's from this module too). The engine's files are package data of
``suspension_fabric.simulation.lammps``: the LAMMPS inputs in its ``inputs/`` folder, the plugin's
C++ sources in ``plugin_source/``, found with importlib.resources in any install. The config schema
and the engine rule's pressure over the map live in the repository (``config/schema.yaml``,
``config/engine_pressure_law.json``) and are found

- in a regular install (``pip install .``, a wheel): as package data, which pyproject.toml
  maps into ``suspension_fabric/_data/``;
- in an editable install (``pip install -e .``, as ``envs/bootstrap.sh`` does): in the
  checkout the package was installed from, recorded by pip in the distribution's
  ``direct_url.json`` (PEP 610), so edits there take effect at once.

The plugin library is built into ``<checkout>/build/plugin`` for an editable install and
into ``./build/plugin`` (the workflow's working directory) otherwise;
``SUSPENSION_FABRIC_BUILD_DIR`` overrides both.
"""

from __future__ import annotations

import functools
import importlib.metadata
import importlib.resources
import json
import os
from pathlib import Path
from urllib.parse import unquote, urlparse

__all__ = [
    "SCHEMA_PATH",
    "ENGINE_PRESSURE_LAW_PATH",
    "LAMMPS_SCRIPTS_DIR",
    "PLUGIN_SOURCE_DIR",
    "PLUGIN_BUILD_DIR",
    "PLUGIN_LIBRARY_NAME",
    "editable_checkout",
]

PLUGIN_LIBRARY_NAME = "libsuspension_fabric_lammps.so"


@functools.cache
def editable_checkout() -> Path | None:
    """The source checkout of an editable install (pip's direct_url.json), else None."""
    # the first installed distribution on the path is the one imported; a stray build's
    # egg-info (no direct_url.json) does not count
    for distribution in importlib.metadata.distributions(name="suspension_fabric"):
        text = distribution.read_text("direct_url.json")
        if not text:
            continue
        record = json.loads(text)
        if not record.get("dir_info", {}).get("editable"):
            return None
        url = urlparse(record["url"])
        return Path(unquote(url.path)) if url.scheme == "file" else None
    return None


def _located(packaged: str, in_checkout: str) -> Path:
    """A data folder or file: the checkout's (editable install) or the packaged copy."""
    checkout = editable_checkout()
    if checkout is not None and (checkout / in_checkout).exists():
        return checkout / in_checkout
    path = Path(str(importlib.resources.files("suspension_fabric") / "_data" / packaged))
    if not path.exists():
        raise FileNotFoundError(
            f"suspension_fabric data '{in_checkout}' not found: neither an editable checkout nor "
            f"packaged at {path}; reinstall the package (envs/bootstrap.sh)"
        )
    return path


SCHEMA_PATH = _located("config/schema.yaml", "config/schema.yaml")
#: the pressure over the map that the engine's rule reads (suspension_fabric.simulation.engine_rule)
ENGINE_PRESSURE_LAW_PATH = _located("config/engine_pressure_law.json", "config/engine_pressure_law.json")
_ENGINE = Path(str(importlib.resources.files("suspension_fabric") / "simulation" / "lammps"))
LAMMPS_SCRIPTS_DIR = _ENGINE / "inputs"
PLUGIN_SOURCE_DIR = _ENGINE / "plugin_source"
PLUGIN_BUILD_DIR = Path(
    os.environ.get("SUSPENSION_FABRIC_BUILD_DIR") or ((editable_checkout() or Path.cwd()) / "build" / "plugin")
).resolve()
