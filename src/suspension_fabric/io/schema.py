"""The study schema (config/schema.yaml) and its defaults: the one source of every default.

The package's dataclasses (``lammps.runner.ForceModel``, ``lammps.runner.ShearSettings``)
take their defaults from here; the LAMMPS scripts' defaults are tested against it.
"""

from __future__ import annotations

import functools

import yaml

from .resources import SCHEMA_PATH

__all__ = ["load_schema", "schema_default"]


@functools.cache
def load_schema() -> dict:
    """The parsed JSON schema of a study configuration."""
    return yaml.safe_load(SCHEMA_PATH.read_text())


def schema_default(section: str, key: str):
    """Default value of ``<section>.<key>`` in the schema (e.g. ``schema_default("run", "dt")``)."""
    try:
        return load_schema()["properties"][section]["properties"][key]["default"]
    except KeyError:
        raise KeyError(f"the schema has no default for '{section}.{key}'") from None
