"""What the analysis needs to know of a finished shear run, read from its completion marker.

The runner (:mod:`suspension_fabric.simulation.lammps.runner`) writes ``run_complete.json`` last into
a finished run directory: the LAMMPS variables of the run under ``variables`` (strings, as
passed with ``-var``: ``dt``, ``rate``, and ``theta_deg`` for a shear rotation) and its
outcome under ``results`` (``first_step``, the step where this shear started, ...). The
strain of a frame at step s is (s - first_step) dt rate; the fabric of a rotation by
theta is reported in its rotated frame (see :mod:`suspension_fabric.analysis.fabric`).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

__all__ = ["RunInfo", "read_run_info"]


@dataclass(frozen=True)
class RunInfo:
    """Time step ``dt``, shear ``rate``, ``first_step`` of the shear, its flow angle ``theta_deg``
    (degrees; 0 for startup shear, which records no angle) and the fluid viscosity ``eta_f``
    (None in a record that lacks it)."""

    dt: float
    rate: float
    first_step: int
    theta_deg: float = 0.0
    eta_f: float | None = None


def read_run_info(marker: str | os.PathLike) -> RunInfo:
    """The :class:`RunInfo` of the run whose completion marker (``run_complete.json``) is ``marker``.

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` naming the file and
    the key for unreadable JSON or a missing or malformed entry.
    """
    path = Path(marker)
    if not path.is_file():
        raise FileNotFoundError(f"run completion marker not found: {path}")
    try:
        content = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: not valid JSON ({err})") from None
    if not isinstance(content, dict):
        raise ValueError(f"{path}: expected a JSON object, got {type(content).__name__}")
    # a rotation's record must state its angle: the startup's default 0 would be silently wrong
    rotated = str(content.get("script", "")).startswith("rotate")

    def entry(section: str, key: str, convert, default=None):
        part = content.get(section) if isinstance(content, dict) else None
        value = part.get(key) if isinstance(part, dict) else None
        if value is None:
            if default is not None:
                return default
            raise ValueError(f"{path}: missing {section}.{key}")
        try:
            return convert(value)
        except (TypeError, ValueError):
            raise ValueError(f"{path}: {section}.{key} = {value!r} is not a {convert.__name__}") from None

    return RunInfo(
        dt=entry("variables", "dt", float),
        rate=entry("variables", "rate", float),
        first_step=entry("results", "first_step", int),
        theta_deg=entry("variables", "theta_deg", float, default=None if rotated else 0.0),
        eta_f=entry("variables", "eta_f", float) if "eta_f" in content.get("variables", {}) else None,
    )
