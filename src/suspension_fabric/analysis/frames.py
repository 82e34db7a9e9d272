"""Frames and rotations shared by the models and the simulation analysis, and the 6-vector
storage of symmetric tensors.

Paper frame: e1 flow, e2 gradient, e3 = e1 x e2 vorticity.
Simulation frame: LAMMPS box axes x, y, z with z the gradient direction; a shear
with flow direction (cos t, sin t, 0) has paper frame
    e1 = (cos t, sin t, 0),  e2 = (0, 0, 1),  e3 = e1 x e2 = (sin t, -cos t, 0).
At t = 0 this is e1 = x, e2 = z, e3 = -y.

Shear rotation by theta turns e1 and e3 about e2, right-handed:
    e1' = cos(theta) e1 - sin(theta) e3,   e3' = sin(theta) e1 + cos(theta) e3,
which in the simulation frame is the flow direction t = theta.

A basis is stored as a 3x3 array whose ROWS are the basis vectors written in the
old frame, so that the components of a tensor T in the new basis are
``B @ T @ B.T`` and those of a vector v are ``B @ v``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "VECTOR_ORDER",
    "sym_to_vec",
    "vec_to_sym",
    "SYMMETRIC_BASIS",
    "map_matrix",
    "rotation_about_gradient",
    "paper_basis_in_simulation_frame",
    "to_basis",
    "simulation_to_paper",
    "paper_to_simulation",
    "simple_shear_gradient",
]


#: Order of the independent components of a symmetric tensor in the 6-vectors of
#: [`sym_to_vec`][suspension_fabric.analysis.frames.sym_to_vec] and
#: [`vec_to_sym`][suspension_fabric.analysis.frames.vec_to_sym] (the names of the fabric components in tables are
#: `suspension_fabric.analysis.fabric.COMPONENTS`).
VECTOR_ORDER = ("11", "22", "33", "12", "13", "23")
_ROWS = np.array([0, 1, 2, 0, 0, 1])
_COLS = np.array([0, 1, 2, 1, 2, 2])


def sym_to_vec(tensor) -> np.ndarray:
    """Symmetric tensor(s) (..., 3, 3) -> 6-vectors (..., 6) in `VECTOR_ORDER` order."""
    tensor = np.asarray(tensor, dtype=float)
    return tensor[..., _ROWS, _COLS]


def vec_to_sym(vec) -> np.ndarray:
    """6-vectors (..., 6) -> symmetric tensors (..., 3, 3)."""
    vec = np.asarray(vec, dtype=float)
    out = np.empty(vec.shape[:-1] + (3, 3))
    out[..., _ROWS, _COLS] = vec
    out[..., _COLS, _ROWS] = vec
    return out


#: The symmetric tensors whose 6-vectors are the unit vectors, (6, 3, 3): a tensor X is
#: sum_k v_k SYMMETRIC_BASIS[k] with v = sym_to_vec(X).
SYMMETRIC_BASIS = vec_to_sym(np.eye(6))
SYMMETRIC_BASIS.setflags(write=False)


def map_matrix(images) -> np.ndarray:
    """The matrix (..., 6, 6) on 6-vectors of a linear map of symmetric tensors to symmetric
    tensors, from its images (..., 6, 3, 3) of `SYMMETRIC_BASIS`: column k is the image of
    basis tensor k."""
    return np.swapaxes(sym_to_vec(images), -1, -2)


def rotation_about_gradient(theta) -> np.ndarray:
    """Basis (e1', e2, e3') of a shear rotated by ``theta`` (radians), in paper components.

    Rows are e1' = (cos, 0, -sin), e2 = (0, 1, 0), e3' = (sin, 0, cos). Accepts an
    array of angles and returns shape ``theta.shape + (3, 3)``.
    """
    theta = np.asarray(theta, dtype=float)
    c, s = np.cos(theta), np.sin(theta)
    zero, one = np.zeros_like(theta), np.ones_like(theta)
    return np.stack(
        [
            np.stack([c, zero, -s], axis=-1),
            np.stack([zero, one, zero], axis=-1),
            np.stack([s, zero, c], axis=-1),
        ],
        axis=-2,
    )


def paper_basis_in_simulation_frame(flow_angle=0.0) -> np.ndarray:
    """Paper basis (e1, e2, e3) of a shear with flow (cos t, sin t, 0), in simulation components.

    ``flow_angle`` t is in radians; t = theta after a shear rotation by theta.
    """
    t = np.asarray(flow_angle, dtype=float)
    c, s = np.cos(t), np.sin(t)
    zero, one = np.zeros_like(t), np.ones_like(t)
    return np.stack(
        [
            np.stack([c, s, zero], axis=-1),
            np.stack([zero, zero, one], axis=-1),
            np.stack([s, -c, zero], axis=-1),
        ],
        axis=-2,
    )


def to_basis(tensor, basis) -> np.ndarray:
    """Components ``B T B^T`` of second-rank tensor(s) ``T`` in basis ``B`` (broadcasts)."""
    tensor = np.asarray(tensor, dtype=float)
    basis = np.asarray(basis, dtype=float)
    return basis @ tensor @ np.swapaxes(basis, -1, -2)


def simulation_to_paper(tensor_sim, flow_angle=0.0) -> np.ndarray:
    """Tensor(s) from simulation components (gradient z) to the paper frame of flow angle t."""
    return to_basis(tensor_sim, paper_basis_in_simulation_frame(flow_angle))


def paper_to_simulation(tensor_paper, flow_angle=0.0) -> np.ndarray:
    """Inverse of [`simulation_to_paper`][suspension_fabric.analysis.frames.simulation_to_paper]."""
    basis = paper_basis_in_simulation_frame(flow_angle)
    return to_basis(tensor_paper, np.swapaxes(basis, -1, -2))


def simple_shear_gradient(shear_rate: float = 1.0) -> np.ndarray:
    """Velocity gradient L = gammadot e1 e2 of simple shear in the paper frame."""
    grad = np.zeros((3, 3))
    grad[0, 1] = shear_rate
    return grad
