"""Physics checks of a finished shear run: largest overlap in the dump, stress-table jitter.

Their bounds are the study settings ``run.max_overlap`` and ``run.max_stress_jitter``
(config/schema.yaml explains the values).
"""

from __future__ import annotations

import os
from collections.abc import Mapping

import numpy as np

from suspension_fabric.io.dumpio import iter_dump_frames

__all__ = ["max_overlap_in_dump", "stress_jitter"]


def max_overlap_in_dump(path: str | os.PathLike) -> tuple[float, int]:
    """Largest overlap (a_i + a_j - r, in d, 0 if none) over all frames, and the number of frames."""
    from suspension_fabric.analysis.fabric import near_contact_pairs
    from suspension_fabric.analysis.fabric_reference import brute_force_near_contacts

    largest, frames = 0.0, 0
    for frame in iter_dump_frames(path):
        positions = frame.positions - np.asarray(frame.box.origin)
        try:
            contacts = near_contact_pairs(positions, frame.radii, frame.box.mdanalysis_dimensions(), eps=0.0)
            overlaps = -contacts.gaps
        except ValueError:  # box too small for the neighbour search: test all pairs and images
            pairs, vectors = brute_force_near_contacts(positions, frame.radii, frame.box.edge_vectors, eps=0.0)
            overlaps = frame.radii[pairs[:, 0]] + frame.radii[pairs[:, 1]] - np.linalg.norm(vectors, axis=1)
        if len(overlaps):
            largest = max(largest, float(overlaps.max()))
        frames += 1
    return largest, frames


def stress_jitter(
    table: Mapping[str, np.ndarray], window_rows: int = 50, skip_strain: float = 0.005
) -> tuple[float, float, float]:
    """Largest row-to-row jitter of the pressure tensor, and the strain window where it occurs.

    For consecutive windows of ``window_rows`` rows of a stress table: the 95th percentile
    of |P_(k+1) - P_k| (Frobenius norm of the six components) over the median |P_k|.
    Sampled every ~1e-3 strain, a stable run stays below ~0.03 (N = 500, phi = 0.45);
    an explicit time step too large for the lubrication squeeze resistance makes the
    lubrication stress flip between rows and gives values ~1. Returns (jitter, strain_lo,
    strain_hi); jitter 0 if no window has 20 rows. Rows before ``skip_strain``
    are ignored: the impulsive change of flow at a start or rotation makes one physical
    jump (velocities relax within ~m/(3 pi eta_f d) ~ 3e-4 strain).
    """
    keep = table["strain"] >= table["strain"][0] + skip_strain
    table = {name: values[keep] for name, values in table.items()}
    components = np.column_stack([table[k] for k in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")])
    strain = table["strain"]
    worst = (0.0, float("nan"), float("nan"))
    for start in range(0, len(strain), window_rows):
        rows = slice(start, min(start + window_rows, len(strain)))
        block = components[rows]
        if len(block) < 20:
            continue
        size = np.median(np.linalg.norm(block, axis=1))
        jumps = np.linalg.norm(np.diff(block, axis=0), axis=1)
        value = float(np.percentile(jumps, 95) / size) if size > 0 else 0.0
        if value > worst[0]:
            worst = (value, float(strain[rows][0]), float(strain[rows][-1]))
    return worst
