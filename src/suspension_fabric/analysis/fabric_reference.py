"""Brute-force O(N^2) near-contact search, independent of MDAnalysis' neighbour search.

Used in production and as a reference. Production: the overlap check of every finished
shear run ([`suspension_fabric.simulation.lammps.checks.max_overlap_in_dump`][]) falls back to it
for boxes too small for the neighbour search of
[`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric]. Reference: the tests and
benchmarks/bench_fabric.py check [`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric] against it.

Every pair i < j is tested; the minimum image is found by explicit search over the
27 neighbouring images of the separation after wrapping its fractional components
into [-1/2, 1/2) (exact for a box whose tilts do not exceed half the box lengths,
which LAMMPS keeps with ``flip yes``). The box is given directly by its LAMMPS
edge vectors, so no conversion through MDAnalysis' lengths-and-angles form is used.
"""

from __future__ import annotations

import numpy as np

__all__ = ["brute_force_near_contacts", "brute_force_fabric_tensor"]

_SHIFTS = np.array([(i, j, k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)], dtype=float)


def brute_force_near_contacts(positions, radii, box_rows, eps: float = 0.01, chunk: int = 64):
    """Near-contact pairs by testing all pairs and all 27 images.

    ``box_rows`` holds the edge vectors a, b, c as rows. Returns ``(pairs, separations)``:
    pairs (M, 2) with i < j sorted lexicographically, and the minimum-image vectors
    from i to j. Near contact: |r_ij| - a_i - a_j < eps * 2 * min(a_i, a_j).
    """
    positions = np.asarray(positions, dtype=float)
    radii = np.asarray(radii, dtype=float)
    box_rows = np.asarray(box_rows, dtype=float)
    inverse = np.linalg.inv(box_rows)
    image_offsets = _SHIFTS @ box_rows
    n = len(positions)
    found_pairs, found_vectors = [], []
    for start in range(0, n, chunk):
        rows = np.arange(start, min(start + chunk, n))
        delta = positions[None, :, :] - positions[rows, None, :]  # (chunk, n, 3): i -> j
        fractional = delta @ inverse
        fractional -= np.floor(fractional + 0.5)
        wrapped = fractional @ box_rows
        images = wrapped[:, :, None, :] + image_offsets[None, None, :, :]
        squared = np.einsum("abkx,abkx->abk", images, images)
        best = np.argmin(squared, axis=2)
        shortest = np.take_along_axis(images, best[:, :, None, None], axis=2)[:, :, 0, :]
        distance = np.sqrt(np.take_along_axis(squared, best[:, :, None], axis=2)[:, :, 0])
        gap = distance - radii[rows, None] - radii[None, :]
        threshold = eps * 2.0 * np.minimum(radii[rows, None], radii[None, :])
        upper = np.arange(n)[None, :] > rows[:, None]
        i_local, j = np.nonzero((gap < threshold) & upper)
        found_pairs.append(np.column_stack([rows[i_local], j]))
        found_vectors.append(shortest[i_local, j])
    pairs = np.concatenate(found_pairs) if found_pairs else np.zeros((0, 2), dtype=int)
    vectors = np.concatenate(found_vectors) if found_vectors else np.zeros((0, 3))
    order = np.lexsort((pairs[:, 1], pairs[:, 0]))
    return pairs[order], vectors[order]


def brute_force_fabric_tensor(positions, radii, box_rows, eps: float = 0.01):
    """(1/N) sum over brute-force near contacts of n n, and the number of pairs."""
    pairs, vectors = brute_force_near_contacts(positions, radii, box_rows, eps)
    if len(pairs) == 0:
        return np.zeros((3, 3)), 0
    normals = vectors / np.linalg.norm(vectors, axis=1)[:, None]
    return normals.T @ normals / len(positions), len(pairs)
