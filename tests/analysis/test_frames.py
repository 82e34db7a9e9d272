"""Tests of the frame conventions (suspension_fabric.analysis.frames), as stated in the package
docstring (src/suspension_fabric/__init__.py)."""

import numpy as np
import pytest

from suspension_fabric.analysis import frames

ANGLES = np.deg2rad([0.0, 30.0, 90.0, 135.0, -60.0])


def test_startup_mapping():
    """At flow angle 0: e1 = x, e2 = z, e3 = -y."""
    np.testing.assert_allclose(
        frames.paper_basis_in_simulation_frame(0.0), [[1, 0, 0], [0, 0, 1], [0, -1, 0]], atol=1e-15
    )


@pytest.mark.parametrize("t", ANGLES)
def test_bases_are_right_handed_orthonormal(t):
    """Rows form a proper rotation (B B^T = 1, det B = 1) and e3 = e1 x e2."""
    for basis in (frames.paper_basis_in_simulation_frame(t), frames.rotation_about_gradient(t)):
        np.testing.assert_allclose(basis @ basis.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(basis) == pytest.approx(1.0)
        np.testing.assert_allclose(np.cross(basis[0], basis[1]), basis[2], atol=1e-14)


@pytest.mark.parametrize("theta", ANGLES)
def test_rotation_by_theta_is_flow_angle_theta(theta):
    """e1' = cos e1 - sin e3, e3' = sin e1 + cos e3 is, in simulation components, flow (cos, sin, 0)."""
    rotated_in_sim = frames.rotation_about_gradient(theta) @ frames.paper_basis_in_simulation_frame(0.0)
    np.testing.assert_allclose(rotated_in_sim, frames.paper_basis_in_simulation_frame(theta), atol=1e-14)
    np.testing.assert_allclose(rotated_in_sim[0], [np.cos(theta), np.sin(theta), 0.0], atol=1e-14)


def test_shear_component_after_rotation():
    """A fabric with only a 12 component reads <nn>'_12 = cos(theta) n12 and <nn>'_23 = sin(theta) n12."""
    fabric = np.zeros((3, 3))
    fabric[0, 1] = fabric[1, 0] = -0.1
    rotated = frames.to_basis(fabric, frames.rotation_about_gradient(ANGLES))
    np.testing.assert_allclose(rotated[:, 0, 1], -0.1 * np.cos(ANGLES), atol=1e-15)
    np.testing.assert_allclose(rotated[:, 1, 2], -0.1 * np.sin(ANGLES), atol=1e-15)


def test_simulation_paper_round_trip_and_shear_gradient():
    """paper_to_simulation inverts simulation_to_paper; L = e1 e2 maps to du_x/dz = 1 at t = 0."""
    tensor = np.random.default_rng(1).normal(size=(3, 3))
    for t in ANGLES:
        np.testing.assert_allclose(
            frames.paper_to_simulation(frames.simulation_to_paper(tensor, t), t), tensor, atol=1e-14
        )
    grad_sim = frames.paper_to_simulation(frames.simple_shear_gradient(), 0.0)
    expected = np.zeros((3, 3))
    expected[0, 2] = 1.0  # xz erate 1: v_x = z
    np.testing.assert_allclose(grad_sim, expected, atol=1e-15)
