"""Closures of <nnnn> in terms of <nn> (suspension_fabric.models.closures) against the distributions
each is exact for, and the measured fourth moment of the same directions
(suspension_fabric.analysis.fabric.direction_moments)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from suspension_fabric.analysis.fabric import FOURTH_MOMENT_COMPONENTS, direction_moments
from suspension_fabric.models.closures import (
    CLOSURES,
    contract_hybrid,
    hybrid_closure,
    linear_closure,
    quadratic_closure,
)
from suspension_fabric.models.gillissen_wilson import hinch_leal_closure


def full(components) -> np.ndarray:
    """The symmetric 3x3x3x3 tensor of the 15 named components of direction_moments."""
    by_name = dict(zip(FOURTH_MOMENT_COMPONENTS, components))
    tensor = np.empty((3, 3, 3, 3))
    for index in itertools.product(range(3), repeat=4):
        tensor[index] = by_name["n" + "".join(str(i + 1) for i in sorted(index))]
    return tensor


def sphere_quadrature(n_polar: int = 24, n_azimuth: int = 48):
    """Directions and weights (summing to 1) integrating polynomials of degree < 2 n_polar exactly
    over the unit sphere: Gauss-Legendre in cos(polar), the trapezoidal rule in the azimuth."""
    cosines, weights = np.polynomial.legendre.leggauss(n_polar)
    azimuths = np.arange(n_azimuth) * 2.0 * np.pi / n_azimuth
    sines = np.sqrt(1.0 - cosines**2)
    directions = np.stack(
        np.broadcast_arrays(
            sines[:, None] * np.cos(azimuths), sines[:, None] * np.sin(azimuths), cosines[:, None] + 0 * azimuths
        ),
        axis=-1,
    ).reshape(-1, 3)
    return directions, (weights[:, None] / 2.0 / n_azimuth * np.ones(n_azimuth)).ravel()


def weighted_moments(directions, weights, scale: float):
    """<nn> and <nnnn> of a distribution given by weighted directions (total weight ``scale``)."""
    second = scale * np.einsum("p,pa,pb->ab", weights, directions, directions)
    fourth = scale * np.einsum("p,pa,pb,pc,pd->abcd", weights, directions, directions, directions, directions)
    return second, fourth


def test_the_linear_closure_is_the_papers():
    """The paper's closure is linear in <nn>: Tr<nn> A_linear(<nn>/Tr<nn>) = hinch_leal_closure(<nn>)."""
    rng = np.random.default_rng(3)
    vectors = rng.normal(size=(50, 3))
    fabric = vectors.T @ vectors / 30.0
    np.testing.assert_allclose(linear_closure(fabric), hinch_leal_closure(fabric), rtol=1e-13, atol=1e-15)


def test_the_linear_and_hybrid_closures_are_exact_for_an_isotropic_distribution():
    """Isotropic directions (total weight Z/2 = 1.75): <nnnn> = (1.75/15)(d_ij d_kl + d_ik d_jl + d_il d_jk),
    which the linear closure gives and, since det(a) = 1/27 there (f = 0), the hybrid one too; the
    quadratic one gives (1.75/9) d_ij d_kl instead."""
    directions, weights = sphere_quadrature()
    second, fourth = weighted_moments(directions, weights, 1.75)
    eye = np.eye(3)
    isotropic = (
        np.einsum("ij,kl->ijkl", eye, eye) + np.einsum("ik,jl->ijkl", eye, eye) + np.einsum("il,jk->ijkl", eye, eye)
    )
    np.testing.assert_allclose(fourth, 1.75 / 15.0 * isotropic, atol=1e-13)
    np.testing.assert_allclose(linear_closure(second), fourth, atol=1e-13)
    np.testing.assert_allclose(hybrid_closure(second), fourth, atol=1e-12)
    np.testing.assert_allclose(quadratic_closure(second), 1.75 / 9.0 * np.einsum("ij,kl->ijkl", eye, eye), atol=1e-13)


def test_the_quadratic_and_hybrid_closures_are_exact_for_perfect_alignment():
    """Every near contact along one direction e (4 pairs, N = 2): <nn> = 2 e e and <nnnn> = 2 eeee, the
    quadratic closure's value, and the hybrid one's (det(a) = 0, f = 1); measured by direction_moments."""
    e = np.array([1.0, 2.0, -2.0]) / 3.0
    second, fourth, _ = direction_moments(np.tile(e, (4, 1)), 2)
    measured = full(fourth)
    np.testing.assert_allclose(measured, 2.0 * np.einsum("i,j,k,l->ijkl", e, e, e, e), atol=1e-15)
    np.testing.assert_allclose(quadratic_closure(second), measured, atol=1e-14)
    np.testing.assert_allclose(hybrid_closure(second), measured, atol=1e-14)
    assert np.abs(linear_closure(second) - measured).max() > 0.1


@pytest.mark.parametrize("name", list(CLOSURES))
def test_every_closure_keeps_the_trace_identity(name):
    """A_ijkk = <nn>_ij for a sheared-like fabric (contraction over the last index pair), and every
    closure is symmetric in (ij) and in (kl); a fabric without contacts closes to zero."""
    rng = np.random.default_rng(7)
    vectors = rng.normal(size=(200, 3)) * np.array([1.3, 1.0, 0.8])
    fabric = vectors.T @ vectors / 110.0
    closed = CLOSURES[name](fabric)
    np.testing.assert_allclose(np.einsum("ijkk->ij", closed), fabric, atol=1e-14)
    np.testing.assert_allclose(closed, np.swapaxes(closed, 0, 1), atol=1e-15)
    np.testing.assert_allclose(closed, np.swapaxes(closed, 2, 3), atol=1e-15)
    np.testing.assert_array_equal(CLOSURES[name](np.zeros((3, 3))), np.zeros((3, 3, 3, 3)))


def test_the_contracted_hybrid_closure_equals_the_contraction_of_the_formed_tensor():
    """contract_hybrid(T, X)_ij = T_kl <nnnn>_ijkl of hybrid_closure(X), for random symmetric
    fabrics (one without contacts) and strain-rate-like symmetric T, broadcast over a batch."""
    rng = np.random.default_rng(11)
    half = rng.normal(size=(5, 3, 3))
    fabrics = np.einsum("...ik,...jk->...ij", half, half) / 10.0
    fabrics[0] = 0.0
    drive = rng.normal(size=(5, 3, 3))
    drive = drive + np.swapaxes(drive, -1, -2)
    formed = np.einsum("...kl,...ijkl->...ij", drive, hybrid_closure(fabrics))
    np.testing.assert_allclose(contract_hybrid(drive, fabrics), formed, rtol=1e-12, atol=1e-14)
