"""Why the default engine's CG iterations grow with N (BENCHMARKS.md, "Iterations against N"):
the linear systems of consecutive steps, exported from runs at N = 500 and 4000, solved again
here with the fix's preconditioner (block DILU) and stopping rule (max |M^-1 r| <= tol, from the
old velocities), with and without a coarse space.

Export (a patch that writes each step's system; not part of the engine):

    git worktree add /tmp/dump HEAD && cd /tmp/dump && git apply benchmarks/solver_prototype/dump_operator.patch
    bash envs/bootstrap.sh && cd <checkout with results/mpi_scaling/n<N>/startup, from mpi_scaling.py prepare>
    SF_DUMP_STEP=10101 SF_DUMP_COUNT=12 SF_DUMP_PATH=<folder>/s<N> /tmp/dump/.venv/bin/python -c \\
        "import sys; sys.path.insert(0, 'benchmarks'); import mpi_scaling as m; m.continuation(<N>, 1, 0.015, 'dump')"

then

    .venv/bin/python benchmarks/solver_prototype/where_the_error_sits.py <folder> steps
    .venv/bin/python benchmarks/solver_prototype/where_the_error_sits.py <folder> coarse

`steps`: per step, the CG iterations and, before each, the largest |z| and the atoms above tol.
`coarse`: the iterations of the first 6 steps per N with an additive coarse correction
z = M^-1 r + V (V^T A V)^-1 V^T r for three coarse spaces: the longest Fourier modes of the box
(wave vectors in {-1, 0, 1}^3, each of the 6 velocity components), piecewise-rigid motions of a
5 x 5 x 5 grid of cells (6 per cell), and rigid motions of aggregates of strongly coupled atoms
(greedy, coupling > 0.3 of the diagonal geometric mean, at most 8 atoms; rotations about the
aggregate's centre, the box's tilt neglected).
"""

from __future__ import annotations

import glob
import sys
from pathlib import Path

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve_triangular

PHI = 0.45  # volume fraction of the prepared states (mpi_scaling.py prepare: the paper's point)


def load(path):
    with open(path, "rb") as f:
        n = int(np.fromfile(f, np.int32, 1)[0])
        tol = float(np.fromfile(f, np.float64, 1)[0])
        lam = np.fromfile(f, np.float64, 3 * n).reshape(n, 3)
        radii = np.fromfile(f, np.float64, n)
        b = np.fromfile(f, np.float64, 6 * n)
        x0 = np.fromfile(f, np.float64, 6 * n)
        nnz = int(np.fromfile(f, np.int64, 1)[0])
        starts = np.fromfile(f, np.int64, 6 * n + 1)
        rows = np.fromfile(f, np.int32, nnz)
        values = np.fromfile(f, np.float64, nnz)
    A = sp.csc_matrix((values, rows, starts), shape=(6 * n, 6 * n)).tocsr()
    # the cubic box holding the spheres at PHI
    box = float((np.sum(4.0 / 3.0 * np.pi * radii**3) / PHI) ** (1.0 / 3.0))
    return {"n": n, "tol": tol, "lam": lam, "box": box, "b": b, "x0": x0, "A": A}


class Dilu:
    """M = (D + L) D^-1 (D + L^T) over 6x6 blocks, D_k = A_kk - sum_{m<k} A_km D_m^-1 A_mk, applied
    as F F^T with F = C + L C^-T (C the blocks' Cholesky factors)."""

    def __init__(self, A):
        n = A.shape[0] // 6
        B = sp.bsr_matrix(A, blocksize=(6, 6))
        B.sort_indices()
        D = np.zeros((n, 6, 6))
        upper = [[] for _ in range(n)]
        for k in range(n):
            for q in range(B.indptr[k], B.indptr[k + 1]):
                m = B.indices[q]
                if m == k:
                    D[k] += B.data[q]
                elif m > k:
                    upper[k].append((m, B.data[q]))
        rows, cols, vals = [], [], []
        for k in range(n):
            C = la.cholesky(D[k], lower=True)
            inverse = la.cho_solve((C, True), np.eye(6))
            C_inv = la.solve_triangular(C, np.eye(6), lower=True)
            rows.append(k), cols.append(k), vals.append(C)
            for m, Akm in upper[k]:
                D[m] -= Akm.T @ inverse @ Akm
                rows.append(m), cols.append(k), vals.append(Akm.T @ C_inv.T)
        r = (6 * np.array(rows)[:, None, None] + np.arange(6)[None, :, None]).repeat(6, 2)
        c = (6 * np.array(cols)[:, None, None] + np.arange(6)[None, None, :]).repeat(6, 1)
        self.F = sp.csr_matrix((np.array(vals).ravel(), (r.ravel(), c.ravel())), shape=A.shape)
        self.F.eliminate_zeros()
        self.FT = self.F.T.tocsr()

    def __call__(self, r):
        return spsolve_triangular(self.FT, spsolve_triangular(self.F, r, lower=True), lower=False)


def pcg(d, M, coarse=None, trace=None):
    """The fix's CG: from the old velocities until max |z| <= tol; returns the iterations."""
    A, tol = d["A"], d["tol"]
    x = d["x0"].copy()
    r = d["b"] - A @ x

    def precondition(r):
        z = M(r)
        return z if coarse is None else z + coarse(r)

    z = precondition(r)
    rz, p, iterations = r @ z, z.copy(), 0
    while True:
        per_atom = np.abs(z).reshape(-1, 6).max(1)
        if trace is not None:
            trace.append((per_atom.max(), int((per_atom > tol).sum())))
        if per_atom.max() <= tol or iterations == 500:
            return iterations
        q = A @ p
        alpha = rz / (p @ q)
        x += alpha * p
        r -= alpha * q
        z = precondition(r)
        rz, rz_old = r @ z, rz
        p = z + rz / rz_old * p
        iterations += 1


def fourier_space(d):
    cols = []
    for k in [(a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]:
        if k < (0, 0, 0):
            continue
        phase = 2 * np.pi * d["lam"] @ np.array(k, float)
        for f in [np.cos(phase)] if k == (0, 0, 0) else [np.cos(phase), np.sin(phase)]:
            for component in range(6):
                v = np.zeros((d["n"], 6))
                v[:, component] = f
                cols.append(v.ravel())
    return sp.csc_matrix(np.array(cols).T)


def rigid_space(d, groups):
    cols, n = [], d["n"]
    for members in groups:
        rel = d["lam"][members] - d["lam"][members[0]]
        rel = (rel - np.round(rel)) * d["box"]
        rel -= rel.mean(0)
        for component in range(6):
            v = np.zeros((n, 6))
            v[members, component] = 1.0
            if component >= 3:
                w = np.zeros(3)
                w[component - 3] = 1.0
                v[members, :3] = np.cross(w, rel)
            cols.append(v.ravel())
    return sp.csc_matrix(np.array(cols).T)


def cells(d, per_side=5):
    index = np.floor(d["lam"] * per_side).astype(int) % per_side
    cell = (index[:, 0] * per_side + index[:, 1]) * per_side + index[:, 2]
    return [np.flatnonzero(cell == c) for c in range(per_side**3) if (cell == c).any()]


def aggregates(d, theta=0.3, largest=8):
    n = d["n"]
    B = sp.bsr_matrix(d["A"], blocksize=(6, 6))
    B.sort_indices()
    diagonal = np.array(
        [
            np.abs(B.data[q][:3, :3]).max()
            for k in range(n)
            for q in range(B.indptr[k], B.indptr[k + 1])
            if B.indices[q] == k
        ]
    )
    strong = [
        [
            B.indices[q]
            for q in range(B.indptr[k], B.indptr[k + 1])
            if B.indices[q] != k
            and np.abs(B.data[q][:3, :3]).max() > theta * np.sqrt(diagonal[k] * diagonal[B.indices[q]])
        ]
        for k in range(n)
    ]
    owner, groups = -np.ones(n, int), []
    for seed in np.argsort([-len(s) for s in strong], kind="stable"):
        if owner[seed] >= 0:
            continue
        members, front = [seed], [seed]
        owner[seed] = len(groups)
        while front and len(members) < largest:
            following = []
            for k in front:
                for m in strong[k]:
                    if owner[m] < 0 and len(members) < largest:
                        owner[m] = len(groups)
                        members.append(m)
                        following.append(m)
            front = following
        groups.append(np.array(members))
    return groups


def additive(d, V):
    factor = la.cho_factor((V.T @ (d["A"] @ V)).toarray())
    return lambda r: V @ la.cho_solve(factor, V.T @ r)


def main() -> None:
    folder, command = Path(sys.argv[1]), sys.argv[2]
    for n in (500, 4000):
        paths = sorted(glob.glob(str(folder / f"s{n}.*")))
        if command == "steps":
            for path in paths:
                d = load(path)
                trace = []
                iterations = pcg(d, Dilu(d["A"]), trace=trace)
                print(
                    f"N {n} step {path.rsplit('.', 1)[1]}: {iterations} iterations; (max |z|, atoms above tol):",
                    ", ".join(f"({m:.2g}, {c})" for m, c in trace),
                    flush=True,
                )
        else:
            totals = {"block DILU": [], "Fourier": [], "cells": [], "aggregates": []}
            for path in paths[:6]:
                d = load(path)
                M = Dilu(d["A"])
                totals["block DILU"].append(pcg(d, M))
                totals["Fourier"].append(pcg(d, M, additive(d, fourier_space(d))))
                totals["cells"].append(pcg(d, M, additive(d, rigid_space(d, cells(d)))))
                totals["aggregates"].append(pcg(d, M, additive(d, rigid_space(d, aggregates(d)))))
            print(f"N {n}: " + "; ".join(f"{name} {its}" for name, its in totals.items()), flush=True)


if __name__ == "__main__":
    main()
