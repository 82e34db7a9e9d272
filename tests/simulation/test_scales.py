"""Force-model time scales (suspension_fabric.simulation.scales); the LAMMPS check of the same formula
is tests/simulation/test_lammps_plugin.py::test_overlap_relaxes_on_the_contact_relaxation_time."""

import math

import pytest

from suspension_fabric.simulation.scales import (
    contact_period,
    contact_relaxation_time,
    max_dt_explicit,
    max_dt_implicit,
)


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


def test_explicit_squeeze_limit():
    """dt X(delta) (2/m) = 0.5 for two small spheres: X = 0.75 pi eta / delta (d = 1), m = pi/6,
    so dt = 0.5 / (0.75 pi 223 / 1e-3 x 12/pi) = 2.491e-7; it scales as delta/eta_f."""
    expected = 0.5 / (0.75 * math.pi * 223 / 1e-3 * 12 / math.pi)
    assert max_dt_explicit(1.0, 223.0, 1e-3) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(2.491e-7, rel=1e-3)
    assert max_dt_explicit(1.0, 22.3, 1e-2) == pytest.approx(100 * expected)


def test_implicit_tangential_spring_limit():
    """dt < (c + sqrt(c^2 + 4 k m)) / k with c = pi eta d log(1/delta) / 2 (Y_A of equal
    spheres at the regularised gap), k = kt, m = (2/7)(m/2): 3.650e-5 at the defaults. A
    scheme check: for c = 0 it is the symplectic-Euler bound dt < 2/omega; for large c, 2c/k."""
    kt = 2.0 / 7.0 * 1.25e9
    c = math.pi * 223 * math.log(1e3) / 2
    m = (2.0 / 7.0) * (math.pi / 12)
    assert max_dt_implicit(1.0, 223.0, 1e-3, kt) == pytest.approx((c + math.sqrt(c * c + 4 * kt * m)) / kt, rel=1e-12)
    assert max_dt_implicit(1.0, 223.0, 1e-3, kt) == pytest.approx(3.650e-5, rel=1e-3)
    assert max_dt_implicit(1.0, 1e-9, 1e-3, kt) == pytest.approx(2.0 / math.sqrt(kt / m), rel=1e-6)
    assert max_dt_implicit(1.0, 1e6, 1e-3, kt) == pytest.approx(2.0 * math.pi * 1e6 * math.log(1e3) / 2 / kt, rel=1e-3)
