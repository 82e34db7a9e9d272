"""Benchmark: near-contact fabric per frame, fast kernel vs brute-force reference.

Usage:  .venv/bin/python benchmarks/bench_fabric.py [--sizes 500 2000] [--seed 0]

Configurations: bidisperse 50:50 by number, diameters 1 and 1.4, volume fraction 0.45,
in a triclinic box (xz = 0.3 L, yz = -0.2 L); random positions relaxed by pushing
overlapping pairs apart until the largest overlap is below 1e-3 d. Times are medians
over repeats on one thread. Rows:
  fabric_tensor          the kernel (MDAnalysis neighbour search + float64 test)
  brute force            O(N^2) all pairs x 27 images (fabric_reference)
  FabricAnalysis         whole per-frame analysis from a text dump, including
                         MDAnalysis' parsing of the frame
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from suspension_fabric.analysis.fabric import FabricAnalysis, fabric_tensor, near_contact_pairs  # noqa: E402
from suspension_fabric.analysis.fabric_reference import brute_force_fabric_tensor  # noqa: E402
from suspension_fabric.io.dumpio import DumpFrame, TriclinicBox, write_lammps_dump  # noqa: E402


def relaxed_configuration(n, phi=0.45, seed=0, max_overlap=1e-3, max_sweeps=500):
    """Bidisperse (d = 1, 1.4) random packing at volume fraction ``phi`` with overlaps < ``max_overlap``."""
    rng = np.random.default_rng(seed)
    radii = np.where(np.arange(n) < n // 2, 0.5, 0.7)
    volume = np.sum(4.0 / 3.0 * np.pi * radii**3) / phi
    length = volume ** (1.0 / 3.0)
    box = TriclinicBox(length, length, length, xz=0.3 * length, yz=-0.2 * length)
    dims = box.mdanalysis_dimensions()
    positions = rng.random((n, 3)) @ box.edge_vectors
    for _ in range(max_sweeps):
        overlaps = near_contact_pairs(positions, radii, dims, eps=0.0)
        if len(overlaps) == 0 or -overlaps.gaps.min() < max_overlap:
            break
        normals = overlaps.separations / np.linalg.norm(overlaps.separations, axis=1)[:, None]
        push = 0.55 * (-overlaps.gaps)[:, None] * normals
        displacement = np.zeros_like(positions)
        np.add.at(displacement, overlaps.pairs[:, 0], -push)
        np.add.at(displacement, overlaps.pairs[:, 1], push)
        positions += displacement
    return positions, radii, box


def median_seconds(function, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[500, 2000])
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)

    print(
        f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}, "
        f"numpy {np.__version__}, one thread"
    )
    print("| N | method | ms/frame | frames/s | pairs | Z | brute/kernel |")
    print("|---:|---|---:|---:|---:|---:|---:|")
    for n in args.sizes:
        positions, radii, box = relaxed_configuration(n, seed=args.seed)
        dims = box.mdanalysis_dimensions()
        fabric, pairs = fabric_tensor(positions, radii, dims)
        ref_fabric, ref_pairs = brute_force_fabric_tensor(positions, radii, box.edge_vectors)
        if pairs != ref_pairs or not np.allclose(fabric, ref_fabric, atol=1e-12):
            raise SystemExit(f"N={n}: kernel and brute force disagree ({pairs} vs {ref_pairs} pairs)")
        kernel = median_seconds(lambda: fabric_tensor(positions, radii, dims), 30 if n <= 500 else 15)
        brute = median_seconds(
            lambda: brute_force_fabric_tensor(positions, radii, box.edge_vectors), 5 if n <= 500 else 2
        )
        with tempfile.TemporaryDirectory() as tmp:
            frames = [DumpFrame(step, box, positions, radii) for step in range(0, 10 * 100, 100)]
            dump = write_lammps_dump(Path(tmp) / "bench.dump", frames, float_format="%.15g")
            analysis = FabricAnalysis.from_dump(dump, dt=1e-4)
            start = time.perf_counter()
            analysis.run()
            pipeline = (time.perf_counter() - start) / len(frames)
        z = 2 * pairs / n
        for name, seconds, ratio in (
            ("fabric_tensor", kernel, f"{brute / kernel:.0f}"),
            ("brute force (27 images)", brute, ""),
            ("FabricAnalysis (dump read + kernel)", pipeline, ""),
        ):
            print(f"| {n} | {name} | {1e3 * seconds:.2f} | {1.0 / seconds:.1f} | {pairs} | {z:.3f} | {ratio} |")


if __name__ == "__main__":
    main()
