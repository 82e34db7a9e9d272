"""Benchmark: cost of a 73-angle x 200-strain-point shear-rotation grid for both models.

Compares the project's exact propagation (``model.shear_rotation``: one batched
matrix exponential) with the obvious peer, scipy ``solve_ivp`` (DOP853, rtol 1e-8)
integrating each angle separately, in the same run, and reports the ratio and the
largest difference between the two. Single-threaded BLAS is forced so the figure is
per core.

Run: OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/bench_models.py
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import platform  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from suspension_fabric.analysis import frames  # noqa: E402
from suspension_fabric.models import gillissen_wilson as model  # noqa: E402

THETAS = np.deg2rad(np.linspace(-180.0, 180.0, 73))  # every 5 degrees
STRAINS = np.linspace(0.0, 5.0, 200)
MODELS = {"G-W (beta=10.9)": (10.9, None), "modified (beta=9.4, A=42.4)": (9.4, 42.4)}
PHI = 0.45


def best_time(func, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = func()
        times.append(time.perf_counter() - start)
    return min(times), result


def solve_ivp_grid(beta, A):
    """Peer: startup to strain 5 then one solve_ivp per angle, in the rotated frame."""
    before = model.integrate_fabric_ode(
        np.zeros((3, 3)), frames.simple_shear_gradient(), np.array([0.0, 5.0]), beta, A, PHI, rtol=1e-8, atol=1e-10
    )[-1]
    out = np.empty((len(THETAS), len(STRAINS), 3, 3))
    for k, basis in enumerate(frames.rotation_about_gradient(THETAS)):
        out[k] = model.integrate_fabric_ode(
            frames.to_basis(before, basis), frames.simple_shear_gradient(), STRAINS, beta, A, PHI, rtol=1e-8, atol=1e-10
        )
    return out


def main():
    print(f"# {platform.processor() or platform.machine()}, numpy {np.__version__}, 1 thread")
    print(f"# grid: {len(THETAS)} angles x {len(STRAINS)} strain points, startup to strain 5, phi = {PHI}")
    print("| model | shear_rotation (expm) [ms] | solve_ivp per angle [ms] | speed-up | max abs diff |")
    print("|---|---|---|---|---|")
    for name, (beta, A) in MODELS.items():
        t_fast, fast = best_time(lambda: model.shear_rotation(THETAS, STRAINS, beta, A, PHI), 20)
        t_peer, peer = best_time(lambda: solve_ivp_grid(beta, A), 2)
        print(
            f"| {name} | {1e3 * t_fast:.1f} | {1e3 * t_peer:.0f} | {t_peer / t_fast:.0f}x "
            f"| {np.abs(fast - peer).max():.1e} |"
        )


if __name__ == "__main__":
    main()
