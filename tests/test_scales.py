"""Force-model time scales (suspension_fabric.scales); the LAMMPS check of the same formula
is tests/test_lammps_plugin.py::test_overlap_relaxes_on_the_contact_relaxation_time."""

import math

import pytest

from suspension_fabric.scales import contact_period, contact_relaxation_time


def test_paper_values_give_four_strain_units_for_small_spheres():
    """d = 1, eta_f = 223, delta = 1e-3, kn = 1.25e5: X = 6 pi eta (1/4)^2 / (delta/2)
    = 0.75 pi eta / delta, drags in series 3 pi eta / 2, so
    tau = (0.75 pi 223 / 1e-3 + 1.5 pi 223) / 1.25e5 = 4.2119 strain units."""
    expected = (0.75 * math.pi * 223 / 1e-3 + 1.5 * math.pi * 223) / 1.25e5
    assert contact_relaxation_time(1.0, 1.0, 223.0, 1e-3, 1.25e5) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(4.2119, abs=1e-4)


def test_scaling_with_stiffness_viscosity_and_size():
    base = contact_relaxation_time(1.0, 1.4, 223.0, 1e-3, 1.25e7)
    assert contact_relaxation_time(1.0, 1.4, 223.0, 1e-3, 1.25e9) == pytest.approx(base / 100)
    assert contact_relaxation_time(1.0, 1.4, 22.3, 1e-3, 1.25e7) == pytest.approx(base / 10)
    # symmetric in the pair; larger spheres unload more slowly (X grows like a)
    assert contact_relaxation_time(1.4, 1.0, 223.0, 1e-3, 1.25e7) == pytest.approx(base)
    assert contact_relaxation_time(1.4, 1.4, 223.0, 1e-3, 1.25e7) > base


def test_rejects_non_positive_inputs():
    with pytest.raises(ValueError, match="positive"):
        contact_relaxation_time(1.0, 1.0, 223.0, 0.0, 1.25e5)


def test_contact_period_of_two_small_spheres():
    """m = pi/6 for d = 1, rho = 1; m* = m/2; T = 2 pi sqrt(m*/kn) = 9.09e-5 at kn = 1.25e9."""
    expected = 2 * math.pi * math.sqrt(math.pi / 12 / 1.25e9)
    assert contact_period(1.0, 1.0, 1.25e9) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(9.093e-5, rel=1e-3)
    assert contact_period(1.0, 1.0, 1.25e11) == pytest.approx(expected / 10)
