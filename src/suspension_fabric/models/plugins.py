"""Loading a plug-in object (a fabric model, a stress relation) named in the config.

An entry is a built-in key, ``package.module:attribute`` or ``path/to/file.py:attribute``; the
attribute must be an instance of the expected class. Every failure is raised as the caller's
error class with the entry in the message.
"""

from __future__ import annotations

import importlib
import importlib.util
from pathlib import Path

__all__ = ["load_plugin", "resolve_plugins"]


def load_plugin(spec: str, built_in: dict, expected: type, error: type[Exception], what: str):
    """The object named by the config entry ``spec`` (module docstring); ``what`` names the kind
    in messages (e.g. "model")."""
    if spec in built_in:
        return built_in[spec]
    location, sep, attribute = spec.rpartition(":")
    if not sep or not location or not attribute:
        raise error(
            f"{what} {spec!r}: expected a built-in key {sorted(built_in)}, 'module:attribute' or 'file.py:attribute'"
        )
    if location.endswith(".py"):
        path = Path(location)
        if not path.is_file():
            raise error(f"{what} {spec!r}: file {path} not found")
        module_spec = importlib.util.spec_from_file_location(f"{what.replace(' ', '_')}_{path.stem}", path)
        module = importlib.util.module_from_spec(module_spec)
        try:
            module_spec.loader.exec_module(module)
        except Exception as failure:  # the user's file: report any failure with its name
            raise error(f"{what} {spec!r}: importing {path} failed: {failure!r}") from failure
    else:
        try:
            module = importlib.import_module(location)
        except ImportError as failure:
            raise error(f"{what} {spec!r}: cannot import {location} ({failure})") from failure
    found = getattr(module, attribute, None)
    if not isinstance(found, expected):
        raise error(
            f"{what} {spec!r}: {attribute} in {location} is {type(found).__name__}, "
            f"expected a {expected.__module__}.{expected.__name__}"
        )
    return found


def resolve_plugins(specs, load, error: type[Exception], config_key: str) -> dict:
    """The objects of a config list (``config_key``, e.g. "models.fabric") loaded with ``load``,
    by their ``key`` (keys must be distinct)."""
    found = {}
    for spec in specs:
        plugin = load(spec)
        if plugin.key in found:
            raise error(f"{config_key}: two entries have the key {plugin.key!r}")
        found[plugin.key] = plugin
    return found
