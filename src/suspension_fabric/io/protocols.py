"""Flow histories as data: a protocol is a list of segments of simple shear, and the protocols of a
study form a tree of runs that share their common prefixes.

- **Segment**: ``strain`` sheared at flow angle ``flow_angle_deg`` (degrees about the gradient
  axis e2, measured from the flow direction of the first segment, right-handed: the flow direction
  is e1' = cos(t) e1 - sin(t) e3 in the paper frame of the first segment, (cos t, sin t, 0) in the
  simulation frame), turning at ``turning_deg_per_strain`` (0: a fixed direction; w: rotary shear,
  t(gamma) = flow_angle_deg + w gamma with gamma the strain since the segment started). A change
  of angle between two segments is a shear rotation; 180 degrees is a reversal.
- **Protocol**: a name and its segments, the first one from rest (a packing). The paper's family
  is ``startup`` (one segment of ``run.startup_strain`` at angle 0) and, per angle theta of
  ``angles_deg``, ``rotation_theta<theta>`` (the startup, then ``run.rotation_strain`` at theta)
  ([`paper_protocols`][suspension_fabric.io.protocols.paper_protocols]).
- **Run tree**: every prefix of a protocol is one simulation run
  ([`run_tree`][suspension_fabric.io.protocols.run_tree]). Protocols with a common prefix share
  its runs; each run continues from the checkpoint of its parent, the run of the prefix one
  segment shorter. The paper's runs keep their names, ``startup`` and ``rotation_theta<theta>``
  ([`paper_run_names`][suspension_fabric.study.dataset.paper_run_names]); any other run is named
  by its parent's name and its own segment's label, ``<parent>_<label>``, or by the label alone
  from a packing: ``rotation_theta180_theta0for2`` reverses the shear back after a reversal,
  ``startup_theta0turn45for5`` is rotary shear turning at 45 degrees per unit strain after the
  startup. A name that would pass `RUN_NAME_MAX` characters (a long oscillation) is shortened to
  ``<first run>_seg<index>_<digest>_<label>``, the digest a hash of the whole history, so that it
  still names the history and nothing else. A run's tables hold the strain since its segment
  started and tensors in the frame of the current flow (e1 the flow direction at that strain, e2
  the gradient, e3 = e1 x e2).
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

__all__ = [
    "SEGMENT_KEYS",
    "ProtocolError",
    "Segment",
    "Protocol",
    "RunNode",
    "number_label",
    "PaperRunNames",
    "protocol_runs",
    "protocols_from_params",
    "parse_protocols",
    "paper_protocols",
    "run_tree",
    "PAPER_STARTUP",
    "RUN_NAME_MAX",
    "paper_rotation_name",
]

#: The keys of a segment in a config (``strain`` required).
SEGMENT_KEYS = ("strain", "flow_angle_deg", "turning_deg_per_strain")
#: Name of the paper's startup protocol.
PAPER_STARTUP = "startup"
#: Longest run name made by joining labels; longer ones are shortened (the module docstring), so
#: that the file names the workflow makes from a run name stay within 255 characters.
RUN_NAME_MAX = 160


class ProtocolError(ValueError):
    """A protocol that cannot be run; the message names the protocol and the key."""


def number_label(value: float) -> str:
    """Text of a number for names: 45 -> '45', 22.5 -> '22.5', -30 -> 'm30', 1e-05 -> '1em05'."""
    return f"{float(value):g}".replace("-", "m").replace("+", "")


@dataclass(frozen=True)
class Segment:
    """One segment of simple shear (see the module docstring)."""

    strain: float
    flow_angle_deg: float = 0.0
    turning_deg_per_strain: float = 0.0

    def __post_init__(self):
        for name in SEGMENT_KEYS:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ProtocolError(f"{name} must be a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.strain <= 0:
            raise ProtocolError(f"strain must be positive, got {self.strain:g}")

    @property
    def label(self) -> str:
        """``theta<angle>[turn<rate>]for<strain>``: unique for the segment's content."""
        turning = f"turn{number_label(self.turning_deg_per_strain)}" if self.turning_deg_per_strain else ""
        return f"theta{number_label(self.flow_angle_deg)}{turning}for{number_label(self.strain)}"

    def flow_angle_at(self, strain):
        """Flow angle in degrees at ``strain`` since the segment started (scalar or array)."""
        return self.flow_angle_deg + self.turning_deg_per_strain * strain

    @property
    def end_angle_deg(self) -> float:
        return float(self.flow_angle_at(self.strain))

    def as_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in SEGMENT_KEYS}


@dataclass(frozen=True)
class Protocol:
    """A named flow history: its segments, the first from rest."""

    name: str
    segments: tuple[Segment, ...]

    def __post_init__(self):
        if not self.segments:
            raise ProtocolError(f"protocol {self.name}: no segments")

    @property
    def histories(self) -> tuple[tuple[Segment, ...], ...]:
        """The flow history up to the end of each segment (the key of its run in a tree)."""
        return tuple(self.segments[: k + 1] for k in range(len(self.segments)))

    @property
    def start_strains(self) -> tuple[float, ...]:
        """Total strain at the start of each segment."""
        starts, total = [], 0.0
        for segment in self.segments:
            starts.append(total)
            total += segment.strain
        return tuple(starts)

    @property
    def total_strain(self) -> float:
        return sum(segment.strain for segment in self.segments)


@dataclass(frozen=True)
class RunNode:
    """One run of the tree: its id, the id of its parent run (None: from a packing), its last
    segment, the segment's index in the flow history and the whole history up to it."""

    run: str
    parent: str | None
    segment: Segment
    index: int
    history: tuple[Segment, ...]


def parse_protocols(section: Mapping, key: str = "protocols") -> dict[str, Protocol]:
    """Protocols from a config section {name: [segment, ...]} with segments as mappings of
    `SEGMENT_KEYS`; errors ([`ProtocolError`][suspension_fabric.io.protocols.ProtocolError]) name the config key."""
    if not isinstance(section, Mapping):
        raise ProtocolError(f"config key '{key}': expected a mapping of protocol names to segment lists")
    protocols = {}
    for name, entries in section.items():
        where = f"{key}.{name}"
        if not (isinstance(name, str) and name.isidentifier()):
            raise ProtocolError(f"config key '{where}': a protocol name must be an identifier")
        if not isinstance(entries, list) or not entries:
            raise ProtocolError(f"config key '{where}': expected a non-empty list of segments")
        segments = []
        for index, entry in enumerate(entries):
            here = f"{where}.{index}"
            if not isinstance(entry, Mapping):
                raise ProtocolError(f"config key '{here}': expected a mapping with keys {list(SEGMENT_KEYS)}")
            unknown = sorted(set(entry) - set(SEGMENT_KEYS))
            if unknown:
                raise ProtocolError(
                    f"config key '{here}': unknown key(s) {unknown}; a segment has {list(SEGMENT_KEYS)}"
                )
            if "strain" not in entry:
                raise ProtocolError(f"config key '{here}.strain': every segment needs its strain")
            try:
                segments.append(Segment(**entry))
            except ProtocolError as err:
                field = str(err).split(" ", 1)[0]
                raise ProtocolError(f"config key '{here}.{field}': {err}") from None
        protocols[name] = Protocol(name, tuple(segments))
    return protocols


def paper_rotation_name(theta_deg: float) -> str:
    """Name of the paper's protocol that rotates the shear by ``theta_deg`` after the startup."""
    return f"rotation_theta{number_label(theta_deg)}"


def paper_protocols(angles_deg: Iterable[float], startup_strain: float, rotation_strain: float) -> dict[str, Protocol]:
    """The paper's family: the startup, and the startup then ``rotation_strain`` at each angle."""
    startup = Segment(startup_strain)
    protocols = {PAPER_STARTUP: Protocol(PAPER_STARTUP, (startup,))}
    for theta in angles_deg:
        name = paper_rotation_name(theta)
        protocols[name] = Protocol(name, (startup, Segment(rotation_strain, theta)))
    return protocols


class PaperRunNames:
    """The names the paper's runs have always had: ``startup`` for the startup of
    ``startup_strain`` at angle 0 from rest, ``rotation_theta<theta>`` for it followed by
    ``rotation_strain`` at any angle theta (a [`run_tree`][suspension_fabric.io.protocols.run_tree] naming)."""

    def __init__(self, startup_strain: float, rotation_strain: float):
        self.startup = Segment(startup_strain)
        self.rotation_strain = float(rotation_strain)

    def __call__(self, history: tuple[Segment, ...]) -> str | None:
        if history[0] != self.startup:
            return None
        if len(history) == 1:
            return PAPER_STARTUP
        last = history[1]
        if len(history) == 2 and last.strain == self.rotation_strain and not last.turning_deg_per_strain:
            return paper_rotation_name(last.flow_angle_deg)
        return None


def run_tree(protocols: Iterable[Protocol], fixed_names=lambda history: None) -> dict[str, RunNode]:
    """Every run of the protocols once, parents before children, keyed by its name:
    ``fixed_names(history)`` where it gives one (e.g. [`PaperRunNames`][suspension_fabric.io.protocols.PaperRunNames]),
    else the parent's name and the segment's label joined by '_' (the label alone from a packing)."""
    nodes: dict[str, RunNode] = {}
    by_history: dict[tuple[Segment, ...], str] = {}
    for protocol in protocols:
        parent = None
        for index, history in enumerate(protocol.histories):
            name = by_history.get(history)
            if name is None:
                segment = history[-1]
                name = fixed_names(history) or (f"{parent}_{segment.label}" if parent else segment.label)
                if len(name) > RUN_NAME_MAX:
                    name = _short_run_name(by_history[history[:1]], history)
                if name in nodes:  # two histories, one name: only a naming that ignores content does this
                    raise ProtocolError(f"protocol {protocol.name}: run name {name} given to two flow histories")
                nodes[name] = RunNode(name, parent, segment, index, history)
                by_history[history] = name
            parent = name
    return nodes


def _short_run_name(first_run: str, history: tuple[Segment, ...]) -> str:
    """``<first run>_seg<index>_<digest>_<label>`` for a history whose joined labels are too long."""
    digest = hashlib.sha256("_".join(segment.label for segment in history).encode()).hexdigest()[:10]
    return f"{first_run}_seg{len(history) - 1}_{digest}_{history[-1].label}"


def protocol_runs(protocol: Protocol, tree: Mapping[str, RunNode]) -> tuple[str, ...]:
    """The names of a protocol's runs in ``tree``, one per segment."""
    by_history = {node.history: name for name, node in tree.items()}
    try:
        return tuple(by_history[history] for history in protocol.histories)
    except KeyError:
        raise ProtocolError(f"protocol {protocol.name} is not in the run tree") from None


def protocols_from_params(segments: Mapping[str, list]) -> dict[str, Protocol]:
    """Protocols from {name: [segment fields, ...]}, as the workflow passes them to its scripts."""
    return {name: Protocol(name, tuple(Segment(**fields) for fields in entries)) for name, entries in segments.items()}
