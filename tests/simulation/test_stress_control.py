"""Stress control (fix hydro/implicit/sf ... critical_load_stress S a eta_b; forces.critical_load_stress)
with a short sheared packing, real LAMMPS through the runner and forces_sf.lmp.

The law: at a shear rate of 1 (time = strain) a change of the physical rate changes no force but the
critical load, so holding sigma / sigma_0 = S (sigma_0 = F_CL / a^2) is letting the critical load
follow the stress, F_CL(step n) = a^2 sigma(step n - 1) / S, with sigma the shear stress along the
flow, eta_b gammadot plus the particles' contact (symmetrised) and lubrication stress, eta_b =
eta_f (1 + 2.5 phi). The physical stress of step n is then S sigma_n / sigma_{n-1}.

Units: d_small = 1, rho = 1, strain rate 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from suspension_fabric.simulation.lammps import (
    ForceModel,
    ShearSettings,
    pack,
    read_stress_table,
    run_rotation,
    run_startup,
)
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.scales import background_viscosity
from suspension_fabric.study.config import ConfigError, validate_config

pytestmark = pytest.mark.lammps

ETA_F = 223.0
PHI = 0.55
STRESS = 0.05  # sigma / sigma_0
RADIUS = 0.5


def table_shear_stress(table) -> np.ndarray:
    """sigma along the flow (x, gradient z) of each row: eta_b minus the xz particle pressure, the
    contact part made symmetric with the summed torque (xz + T_y / 2 ... with LAMMPS's sum dx_a F_b:
    suspension_fabric.analysis.stress.symmetric_contact_pressure adds -T_y / (2 V))."""
    contact_xz = table["contact_pxz"] - 0.5 * table["contact_torque_y"] / table["vol"]
    return background_viscosity(ETA_F, PHI) - (contact_xz + table["lubrication_pxz"])


def stress_controlled_startup(tmp_path, strain):
    """A stress-controlled startup of N = 60 (phi = 0.55, touching), mu = 0.5, kn = 1.25e9, a
    stress-table row every step; returns the run, its settings and force model."""
    packing = pack(tmp_path / "packing", 60, phi=PHI, seed=11, gap_margin=0.0)
    dt = 1e-5
    settings = ShearSettings(
        dt=dt, dump_strain=0.002, table_strain=dt, thermo_strain=0.001, restart_strain=0.01, max_stress_jitter=None
    )
    model = ForceModel(
        plugin=plugin_path(),
        kn=1.25e9,
        mu=0.5,
        solver_tol=1e-8,
        critical_load_stress=STRESS,
        critical_load_radius=RADIUS,
        background_viscosity=background_viscosity(ETA_F, PHI),
    )
    run = run_startup(tmp_path / "run", packing.data_file, strain, settings=settings, progress=None, force_model=model)
    return run, settings, model


def test_a_reversal_at_controlled_stress_follows_the_law_with_its_floor(tmp_path):
    """Reversed after 0.01 strain, each step's load is a^2 max(sigma, eta_b gammadot) / S of the step
    before, sigma now along the reversed flow: where the contacts built by the old flow push against
    the new one hard enough to bring sigma below the solvent's stress, which no finite rate could hold,
    the load is the solvent's (this small, lubrication-dominated system stays above it: the first
    steps' stress jumps up as the particles' old velocities meet the reversed flow; a thickened
    reversal at phi = 0.54 fell below it and stopped the engine before the floor existed). The reversal
    runs to its end."""
    startup, settings, model = stress_controlled_startup(tmp_path, 0.01)
    reversal = run_rotation(
        tmp_path / "reversal",
        startup.checkpoint_file,
        180.0,
        0.002,
        settings=settings,
        progress=None,
        force_model=model,
    )
    table = read_stress_table(reversal.table_file)
    sigma = -table_shear_stress(table) + 2.0 * background_viscosity(ETA_F, PHI)  # along the reversed flow
    load = table["critical_load"]
    floor = RADIUS**2 * background_viscosity(ETA_F, PHI) / STRESS
    expected = RADIUS**2 * np.maximum(sigma[:-1], background_viscosity(ETA_F, PHI)) / STRESS
    np.testing.assert_allclose(load[1:], expected, rtol=1e-6)
    assert (load[1:] >= floor * (1 - 1e-9)).all()
    assert table["strain"][-1] == pytest.approx(0.002)


def test_the_critical_load_follows_the_stress_of_the_step_before(tmp_path):
    """N = 60 (phi = 0.55, touching), mu = 0.5, kn = 1.25e9, sheared 0.01 strain from rest with a
    stress-table row every step: each step's critical load is a^2 sigma / S of the row before (to
    1e-6: the table prints 12 digits). The physical stress S sigma_n / sigma_{n-1} then moves from S only
    by the stress's change over one step: past the start from rest (strain 0.002) within 5% at every
    step and 1e-3 at the median (measured: 2e-2 at the 99th percentile, 5e-5 at the median). Some
    contacts are frictional at the end and some not."""
    run, _, _ = stress_controlled_startup(tmp_path, 0.01)
    table = read_stress_table(run.table_file)
    sigma = table_shear_stress(table)
    load = table["critical_load"]
    np.testing.assert_allclose(load[1:], RADIUS**2 * sigma[:-1] / STRESS, rtol=1e-6)
    held = (RADIUS**2 * sigma[1:] / (load[1:] * STRESS))[table["strain"][1:] > 0.002]
    assert np.abs(held - 1.0).max() < 0.05 and np.median(np.abs(held - 1.0)) < 1e-3, np.abs(held - 1.0).max()
    assert 0 < table["frictional_contacts"][-1] < table["contacts"][-1]


def test_a_stress_of_a_config_reaches_the_force_model():
    """forces.critical_load_stress S gives the force model S, a = d_small / 2 and eta_b = eta_f (1 + 2.5 phi)
    (here 223 x 2.375 at phi = 0.55), passed to LAMMPS; without it the rate is imposed (S = 0)."""
    base = {"study": "t", "seeds": [1, 2], "angles_deg": [0, 90], "particles": {"phi": PHI}}
    assert ForceModel.from_config(validate_config(base)).critical_load_stress == 0.0
    config = validate_config({**base, "forces": {"critical_load_stress": STRESS}})
    model = ForceModel.from_config(config, plugin=plugin_path())
    assert (model.critical_load_stress, model.critical_load_radius) == (STRESS, 0.5)
    assert model.background_viscosity == pytest.approx(223.0 * 2.375, rel=1e-12)
    assert model.critical_load == 0.0
    variables = model.variables()
    assert float(variables["critical_load_stress"]) == STRESS
    assert float(variables["background_viscosity"]) == pytest.approx(model.background_viscosity, rel=1e-12)


@pytest.mark.parametrize(
    "forces, run, named",
    [
        ({"critical_load_stress": 0}, {}, "forces.critical_load_stress"),
        ({"critical_load_stress": 0.1, "mu": 0.0}, {}, "forces.critical_load_stress"),
        ({"critical_load_stress": 0.1}, {"contact_springs": "explicit", "dt": 1e-5}, "forces.critical_load_stress"),
        ({"critical_load_stress": 0.1, "critical_load_rate": 0.1}, {}, "forces.critical_load_rate"),
    ],
)
def test_stress_control_that_cannot_work_is_refused(forces, run, named):
    """A target stress of zero, one with mu = 0 (nothing to control), one with pair granular's explicit
    contacts (no critical load) and one beside an imposed rate are refused before any job, naming
    the key."""
    config = {"study": "t", "seeds": [1, 2], "angles_deg": [0, 90], "forces": forces, "run": run}
    with pytest.raises(ConfigError, match=named.replace(".", r"\.")):
        validate_config(config)


def test_the_force_model_refuses_rate_and_stress_together():
    with pytest.raises(ValueError, match="exclude each other"):
        ForceModel(critical_load=10.0, critical_load_stress=0.1, background_viscosity=1.0, plugin="x").variables()
