"""The study schema (config/schema.yaml) and its defaults: the one source of every default.

The package's dataclasses (``lammps.runner.ForceModel``, ``lammps.runner.ShearSettings``)
take their defaults from here; the LAMMPS scripts' defaults are tested against it.
"""

from __future__ import annotations

import copy
import functools
import os
from pathlib import Path

import yaml

from .resources import SCHEMA_PATH

__all__ = ["load_schema", "read_schema", "schema_default"]

# libyaml's safe loader when PyYAML has it (the same safe YAML, ~15x faster): the schema is read
# by every Snakemake run and by every job that validates its study's config
_SAFE_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


@functools.cache
def _parsed(path: str, mtime_ns: int, size: int) -> dict:
    return yaml.load(Path(path).read_text(), Loader=_SAFE_LOADER)


def read_schema(path: str | os.PathLike = SCHEMA_PATH) -> dict:
    """The schema at ``path``, parsed once per process and version of the file; a copy the caller may change."""
    status = Path(path).stat()
    return copy.deepcopy(_parsed(str(Path(path).resolve()), status.st_mtime_ns, status.st_size))


@functools.cache
def load_schema() -> dict:
    """The parsed JSON schema of a study configuration (shared: do not change it)."""
    return read_schema(SCHEMA_PATH)


def schema_default(section: str, key: str):
    """Default value of ``<section>.<key>`` in the schema (e.g. ``schema_default("run", "dt")``)."""
    try:
        return load_schema()["properties"][section]["properties"][key]["default"]
    except KeyError:
        raise KeyError(f"the schema has no default for '{section}.{key}'") from None
