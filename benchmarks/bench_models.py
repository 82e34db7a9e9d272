"""Benchmark: cost of a 73-angle x 200-strain-point shear-rotation grid for both models.

Compares the project's exact propagation (``model.shear_rotation``: one batched
matrix exponential) with the obvious peer, scipy ``solve_ivp`` (DOP853, rtol 1e-8)
integrating each angle separately, in the same run, and reports the ratio of the
median times and the largest difference between the two. Single-threaded BLAS is
forced (by bench_fabric, imported first) so the figure is per core.

Run: OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_models.py [--angles 73]
"""

from __future__ import annotations

import argparse
import platform

import bench_fabric  # before numpy: it sets one thread for BLAS
import numpy as np

from suspension_fabric.analysis import frames
from suspension_fabric.models import gillissen_wilson as model

STRAINS = np.linspace(0.0, 5.0, 200)
MODELS = {"G-W (beta=10.9)": (10.9, None), "modified (beta=9.4, A=42.4)": (9.4, 42.4)}
PHI = 0.45


def solve_ivp_grid(thetas, beta, A):
    """Peer: startup to strain 5 then one solve_ivp per angle, in the rotated frame."""
    before = model.integrate_fabric_ode(
        np.zeros((3, 3)), frames.simple_shear_gradient(), np.array([0.0, 5.0]), beta, A, PHI, rtol=1e-8, atol=1e-10
    )[-1]
    out = np.empty((len(thetas), len(STRAINS), 3, 3))
    for k, basis in enumerate(frames.rotation_about_gradient(thetas)):
        out[k] = model.integrate_fabric_ode(
            frames.to_basis(before, basis), frames.simple_shear_gradient(), STRAINS, beta, A, PHI, rtol=1e-8, atol=1e-10
        )
    return out


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--angles", type=int, default=73, help="angles from -180 to 180 degrees (73: every 5)")
    thetas = np.deg2rad(np.linspace(-180.0, 180.0, parser.parse_args(argv).angles))
    print(f"# {platform.processor() or platform.machine()}, numpy {np.__version__}, 1 thread")
    print(f"# grid: {len(thetas)} angles x {len(STRAINS)} strain points, startup to strain 5, phi = {PHI}")
    print("| model | shear_rotation (expm) [ms] | solve_ivp per angle [ms] | speed-up | max abs diff |")
    print("|---|---|---|---|---|")
    for name, (beta, A) in MODELS.items():
        t_fast = bench_fabric.median_seconds(lambda: model.shear_rotation(thetas, STRAINS, beta, A, PHI), 20)
        t_peer = bench_fabric.median_seconds(lambda: solve_ivp_grid(thetas, beta, A), 2)
        difference = np.abs(model.shear_rotation(thetas, STRAINS, beta, A, PHI) - solve_ivp_grid(thetas, beta, A))
        print(f"| {name} | {1e3 * t_fast:.1f} | {1e3 * t_peer:.0f} | {t_peer / t_fast:.0f}x | {difference.max():.1e} |")


if __name__ == "__main__":
    main()
