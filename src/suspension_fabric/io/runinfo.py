"""What the analysis needs to know of a finished shear run, read from its completion marker.

The runner ([`suspension_fabric.simulation.lammps.runner`][suspension_fabric.simulation.lammps.runner]) writes
``run_complete.json`` last into a finished run directory. Format 2 (`RUN_RECORD_FORMAT`) holds

- ``format``: 2;
- ``variables``: the LAMMPS variables of the run (strings, as passed with ``-var``: ``dt``,
  ``rate``, ``eta_f``, ...);
- ``flow_segment``: the segment this run sheared, ``index`` (its depth in the flow history, 0
  from a packing), ``strain``, ``flow_angle_deg``, ``turning_deg_per_strain``
  ([`suspension_fabric.io.protocols.Segment`][suspension_fabric.io.protocols.Segment]);
- ``flow_history``: every segment from rest up to and including this one;
- ``results``: its outcome (``first_step``, the step where this segment started, ...).

The strain of a frame at step s is (s - first_step) dt rate; its flow angle is
flow_angle_deg + turning_deg_per_strain x strain, and the fabric and stress of the frame are
reported in the frame of that flow ([`suspension_fabric.analysis.frames`][suspension_fabric.analysis.frames]).

Format 1 (records without ``format``, written by startup.lmp and rotate.lmp) is read through
[`upgrade_record`][suspension_fabric.io.runinfo.upgrade_record]: a startup (no ``variables.theta_deg``) is segment 0 at
angle 0, a rotation segment 1 at ``variables.theta_deg`` after a startup whose strain the record does not hold, so its
history holds the rotation's segment alone.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

from .protocols import Segment

__all__ = ["RUN_RECORD_FORMAT", "RunInfo", "read_run_info", "upgrade_record"]

#: Format of the completion markers the runner writes.
RUN_RECORD_FORMAT = 2


@dataclass(frozen=True)
class RunInfo:
    """Time step ``dt``, shear ``rate``, ``first_step`` of the segment, the segment itself and
    its ``index`` in the flow history, the ``history`` (segments from rest, this one last; only
    this one for a format-1 rotation) and the fluid viscosity ``eta_f`` (None in a record that
    lacks it)."""

    dt: float
    rate: float
    first_step: int
    segment: Segment
    index: int = 0
    history: tuple[Segment, ...] = ()
    eta_f: float | None = None
    #: False for a format-1 record without ``strain_total``: its segment's strain is a default.
    strain_recorded: bool = True

    @property
    def theta_deg(self) -> float:
        """Flow angle at the segment's start, degrees (the angle of a paper rotation)."""
        return self.segment.flow_angle_deg

    @property
    def turning(self) -> bool:
        return self.segment.turning_deg_per_strain != 0.0


def upgrade_record(content: dict, where: str) -> dict:
    """A format-1 record (no ``format`` key: startup.lmp or rotate.lmp) as format 2."""
    if "format" in content:
        return content
    variables = content.get("variables") if isinstance(content.get("variables"), dict) else {}
    rotated = str(content.get("script", "")).startswith("rotate")
    angle = variables.get("theta_deg")
    if angle is None and rotated:  # the startup's default 0 would be silently wrong
        raise ValueError(f"{where}: missing variables.theta_deg")
    index = 1 if angle is not None else 0
    angle = 0.0 if angle is None else angle
    try:
        segment = Segment(float(variables.get("strain_total", 1.0)), float(angle))
    except (TypeError, ValueError) as err:
        raise ValueError(f"{where}: variables.theta_deg or strain_total unreadable ({err})") from None
    return {
        **content,
        "format": RUN_RECORD_FORMAT,
        "flow_segment": {"index": index, **segment.as_dict()},
        "flow_history": [segment.as_dict()],
    }


def read_run_info(marker: str | os.PathLike) -> RunInfo:
    """The [`RunInfo`][suspension_fabric.io.runinfo.RunInfo] of the run whose completion marker (``run_complete.json``)
    is ``marker``.

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` naming the file and
    the key for unreadable JSON, a missing or malformed entry or an unknown format.
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
    strain_recorded = "format" in content or "strain_total" in (content.get("variables") or {})
    content = upgrade_record(content, str(path))
    if content["format"] != RUN_RECORD_FORMAT:
        raise ValueError(f"{path}: run record format {content['format']!r}, this code reads {RUN_RECORD_FORMAT}")

    def entry(section: str, key: str, convert, default=None):
        part = content.get(section)
        value = part.get(key) if isinstance(part, dict) else None
        if value is None:
            if default is not None:
                return default
            raise ValueError(f"{path}: missing {section}.{key}")
        try:
            return convert(value)
        except (TypeError, ValueError):
            raise ValueError(f"{path}: {section}.{key} = {value!r} is not a {convert.__name__}") from None

    def segment(fields, key: str) -> Segment:
        if not isinstance(fields, dict):
            raise ValueError(f"{path}: {key} is not a segment")
        try:
            return Segment(**{name: fields[name] for name in ("strain", "flow_angle_deg", "turning_deg_per_strain")})
        except (KeyError, TypeError, ValueError) as err:
            raise ValueError(f"{path}: {key} is not a segment ({err})") from None

    history = content.get("flow_history")
    if not isinstance(history, list) or not history:
        raise ValueError(f"{path}: missing flow_history")
    return RunInfo(
        dt=entry("variables", "dt", float),
        rate=entry("variables", "rate", float),
        first_step=entry("results", "first_step", int),
        segment=segment(content.get("flow_segment"), "flow_segment"),
        index=entry("flow_segment", "index", int),
        history=tuple(segment(item, f"flow_history.{k}") for k, item in enumerate(history)),
        eta_f=entry("variables", "eta_f", float) if "eta_f" in content.get("variables", {}) else None,
        strain_recorded=strain_recorded,
    )
