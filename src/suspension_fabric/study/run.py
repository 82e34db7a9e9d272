"""``python -m suspension_fabric.study.run [snakemake arguments]``: Snakemake, after the checks it cannot make.

Snakemake reads ``--configfile`` and ``--config`` before the Snakefile runs, so two mistakes stop it
with messages that name neither file nor key: a YAML syntax error in a config file, and a dotted key
(``--config run.startup_strain=0.5``, "must start with a valid identifier"). This entry point reads
every ``--configfile`` as the workflow will (errors name the file, line and column), turns dotted
``--config`` keys into the nested form Snakemake merges (``run={startup_strain: 0.5}``), and then runs
Snakemake with the rest of the arguments unchanged.
"""

from __future__ import annotations

import json
import os
import shutil
import sys
from pathlib import Path

from .config import ConfigError, read_config_file

__all__ = ["nested_config_args", "snakemake_arguments", "main"]

_OPTIONS_WITH_FILES = ("--configfile", "--configfiles")
_OPTIONS_WITH_SETTINGS = ("--config", "-C")


def _values_after(args: list[str], index: int) -> int:
    """Index of the first argument after ``args[index]`` that is an option (or the end)."""
    end = index + 1
    while end < len(args) and not args[end].startswith("-"):
        end += 1
    return end


def _value(text: str, yaml):
    """A --config value as Snakemake parses it: an int, a float (1e-4 included), else YAML."""
    for parse in (int, float):
        try:
            return parse(text)
        except ValueError:
            pass
    return yaml.safe_load(text) if text else text


def nested_config_args(settings: list[str]) -> list[str]:
    """``--config`` entries with dotted keys merged into one nested entry per top-level key
    (``a.b=1``, ``a.c=2`` -> ``a={"b": 1, "c": 2}``); the values are kept as text for Snakemake to
    parse, so ``seeds=[1,2]`` and ``run.startup_strain=0.5`` read as they would without dots."""
    import yaml

    plain, nested = [], {}
    for setting in settings:
        key, equals, value = setting.partition("=")
        if not equals or "." not in key:
            plain.append(setting)
            continue
        parts = key.split(".")
        if any(not part for part in parts):
            raise ConfigError(f"--config {setting}: empty part in the key {key!r}")
        node = nested.setdefault(parts[0], {})
        for part in parts[1:-1]:
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                raise ConfigError(f"--config {setting}: {key!r} sets a key under a value given before")
        node[parts[-1]] = _value(value, yaml)
    return plain + [f"{top}={json.dumps(tree)}" for top, tree in nested.items()]


def snakemake_arguments(args: list[str]) -> list[str]:
    """The arguments with every ``--configfile`` checked (ConfigError naming the file and line) and
    the ``--config`` entries nested."""
    args, index = list(args), 0
    while index < len(args):
        end = _values_after(args, index)
        if args[index] in _OPTIONS_WITH_FILES:
            for path in args[index + 1 : end]:
                read_config_file(path)
        elif args[index] in _OPTIONS_WITH_SETTINGS:
            args[index + 1 : end] = nested_config_args(args[index + 1 : end])
            end = _values_after(args, index)
        index = end if end > index + 1 else index + 1
    return args


def main(argv: list[str] | None = None) -> int:
    args = sys.argv[1:] if argv is None else argv
    try:
        args = snakemake_arguments(args)
    except ConfigError as err:
        print(err, file=sys.stderr)
        return 1
    snakemake = shutil.which("snakemake") or str(Path(sys.executable).with_name("snakemake"))
    os.execv(snakemake, [snakemake, *args])
    return 0  # not reached: execv replaces this process


if __name__ == "__main__":
    sys.exit(main())
