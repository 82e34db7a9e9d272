"""Critical-load friction (fix hydro/implicit/sf ... critical_load F_CL; contact.h) with two spheres
and a short sheared packing, real LAMMPS through the Python module.

The law (Mari, Seto, Morris and Denn, J. Rheol. 58, 1693, 2014, as LF_DEM implements it): a contact
with normal force F_n = kn o is frictional only while F_n > F_CL, with the Coulomb bound
|F_t| <= mu (F_n - F_CL); at F_n <= F_CL it is frictionless, F_t = 0, and its tangential spring is
reset, so a contact that loses its friction forgets its stretch.

Units: d_small = 1, rho = 1, strain rate 1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from test_lammps_implicit import IMPLICIT_PAIR, atom_array
from test_lammps_plugin import ETA_F, make_system

from suspension_fabric.simulation.lammps import (
    ForceModel,
    ShearSettings,
    iter_dump_frames,
    pack,
    read_stress_table,
    run_startup,
)
from suspension_fabric.simulation.lammps.plugin import plugin_path
from suspension_fabric.simulation.scales import critical_load_force
from suspension_fabric.study.config import ConfigError, validate_config

pytestmark = pytest.mark.lammps

KN = 1.25e9
KT = 2.0 / 7.0 * KN
MU = 0.5
OVERLAP = 1e-4
DT = 1e-5
# the fix's global vector (fix_hydro_implicit_sf.h, HydroVector), counted from 0 here
CONTACT_XX, CONTACT_XY, CONTACTS, FRICTIONAL_CONTACTS = 3, 6, 19, 30


def pressed_pair(critical_load):
    """Two unit spheres along x overlapping by OVERLAP, with the fix's contacts and critical load."""
    return make_system(
        [(5.0, 5.0, 5.0, 1.0, (0, 0, 0), (0, 0, 0)), (6.0 - OVERLAP, 5.0, 5.0, 1.0, (0, 0, 0), (0, 0, 0))],
        pair=IMPLICIT_PAIR,
        extra="group left id 1\ngroup right id 2\n"
        f"fix integrate all hydro/implicit/sf tol 1e-12 contacts {KN} {KT} {MU} critical_load {critical_load}\n"
        f"timestep {DT}\n",
    )


def push(lmp, normal, tangential):
    """Press the pair together with +-normal along x and shear it with +-tangential along y."""
    lmp.command("unfix push_left" if lmp.has_id("fix", "push_left") else "print ''")
    lmp.command("unfix push_right" if lmp.has_id("fix", "push_right") else "print ''")
    lmp.command(f"fix push_left left addforce {normal} {-tangential} 0")
    lmp.command(f"fix push_right right addforce {-normal} {tangential} 0")
    lmp.command("fix_modify integrate virial yes")


def step(lmp):
    """One step; the contact force on sphere 1 from the fix's contact virial W = (x_1 - x_2) (x) F_1
    (motion in the xy plane), split into its normal and tangential parts, the start-of-step spring
    force kn o, and the fix's counts of contacts and frictional contacts."""
    lmp.command("run 1 post no")
    separation = atom_array(lmp, "x")[0] - atom_array(lmp, "x")[1]
    w_xx = lmp.numpy.extract_fix("integrate", 0, 1, CONTACT_XX)
    w_xy = lmp.numpy.extract_fix("integrate", 0, 1, CONTACT_XY)
    force = np.array([w_xx, w_xy, 0.0]) / separation[0]
    n = separation / np.linalg.norm(separation)
    tangential = np.linalg.norm(force - (force @ n) * n)
    spring = KN * (1.0 - np.linalg.norm(separation))
    counts = tuple(int(lmp.numpy.extract_fix("integrate", 0, 1, k)) for k in (CONTACTS, FRICTIONAL_CONTACTS))
    return tangential, spring, counts


def test_a_contact_below_the_critical_load_is_frictionless():
    """Pressed by kn o0 with F_CL = 2 kn o0 and sheared by 0.2 mu kn o0 (a push a constant-mu contact
    holds by sticking), the contact carries no tangential force at any step (|F_t| < 1e-9 kn o0) and
    the fix counts one contact, none of it frictional."""
    normal = KN * OVERLAP
    lmp = pressed_pair(2.0 * normal)
    push(lmp, normal, 0.2 * MU * normal)
    records = [step(lmp) for _ in range(30)]
    lmp.close()
    for tangential, spring, counts in records:
        assert spring < 2.0 * normal
        assert tangential < 1e-9 * normal
        assert counts == (1, 0)


def test_above_the_critical_load_the_bound_is_mu_times_the_excess_load():
    """Pressed by kn o0 with F_CL = 0.5 kn o0 and sheared by 2 mu kn o0 (above any bound), the
    tangential force stays within mu (kn o - F_CL), o the step's overlap, and sits at it once the
    contact slides: half the constant-mu bound mu kn o here. One contact, frictional."""
    normal = KN * OVERLAP
    critical = 0.5 * normal
    lmp = pressed_pair(critical)
    push(lmp, normal, 2.0 * MU * normal)
    records = [step(lmp) for _ in range(40)]
    lmp.close()
    for tangential, spring, counts in records:
        assert tangential <= MU * (spring - critical) * (1 + 1e-9)
        assert counts == (1, 1)
    last_tangential, last_spring, _ = records[-1]
    assert last_tangential == pytest.approx(MU * (last_spring - critical), rel=1e-9)
    assert last_tangential < 0.6 * MU * last_spring


def test_a_contact_that_drops_below_the_critical_load_forgets_its_spring():
    """The spring's memory across a switch. (1) Pressed by kn o0 with F_CL = 0.5 kn o0 and sheared
    by 0.1 mu (kn o0 - F_CL), the contact sticks below its bound and its spring carries over half
    the push (the pair also turns). (2) With the
    shear removed and the normal push lowered to 0.25 kn o0, the overlap relaxes (time
    X(delta)/kn = 4.2e-4, 42 steps) until kn o <= F_CL; from then on F_t = 0 (to the round-off of
    the virial, 1e-9 kn o0) and no contact is frictional. (3) Pressed
    by kn o0 again, with no shear: had the spring kept its stretch, the contact would at once push
    back with the stored force; reset, it carries less than 1e-6 of it."""
    normal = KN * OVERLAP
    critical = 0.5 * normal
    lmp = pressed_pair(critical)
    held = 0.1 * MU * (normal - critical)
    push(lmp, normal, held)
    loaded = [step(lmp) for _ in range(300)]
    push(lmp, 0.25 * normal, 0.0)
    unloaded = [step(lmp) for _ in range(300)]
    push(lmp, normal, 0.0)
    reloaded = [step(lmp) for _ in range(5)]
    lmp.close()
    stored = loaded[-1][0]
    assert 0.5 * held < stored < MU * (loaded[-1][1] - critical)
    assert loaded[-1][2] == (1, 1)
    below = [(tangential, counts) for tangential, spring, counts in unloaded if spring <= critical]
    assert len(below) > 100
    for tangential, counts in below:
        assert tangential < 1e-9 * normal  # zero but for the round-off of F from W / (x_1 - x_2)
        assert counts == (1, 0)
    assert max(tangential for tangential, _, _ in reloaded) < 1e-6 * stored


def test_the_critical_load_of_a_config_is_the_rate_ratio_formula():
    """F_CL = 6 pi eta_f a^2 gammadot / (gammadot / gammadot_0), a = d_small / 2: at eta_f = 223,
    d_small = 1, gammadot = 1 and gammadot / gammadot_0 = 0.5 it is 3 pi 223 = 2101.7;
    ForceModel.from_config passes it to LAMMPS, and a config without the key keeps F_CL = 0."""
    config = validate_config({"study": "t", "seeds": [1, 2], "angles_deg": [0, 90]})
    assert ForceModel.from_config(config).critical_load == 0.0
    config = validate_config(
        {"study": "t", "seeds": [1, 2], "angles_deg": [0, 90], "forces": {"critical_load_rate": 0.5}}
    )
    model = ForceModel.from_config(config, plugin=plugin_path())
    assert model.critical_load == pytest.approx(3.0 * math.pi * ETA_F, rel=1e-12)
    assert critical_load_force(0.5, ETA_F, 1.0) == model.critical_load
    assert float(model.variables()["critical_load"]) == pytest.approx(model.critical_load, rel=1e-12)


@pytest.mark.parametrize(
    "forces, run, named",
    [
        ({"critical_load_rate": 0}, {}, "forces.critical_load_rate"),
        ({"critical_load_rate": 1.0, "mu": 0.0}, {}, "forces.critical_load_rate"),
        ({"critical_load_rate": 1.0}, {"contact_springs": "explicit", "dt": 1e-5}, "forces.critical_load_rate"),
    ],
)
def test_critical_load_settings_that_cannot_work_are_refused(forces, run, named):
    """A critical load of zero, one with mu = 0 (it would change nothing) and one with pair
    granular's explicit contacts (which have no critical load) are refused before any job,
    naming the key."""
    config = {"study": "t", "seeds": [1, 2], "angles_deg": [0, 90], "forces": forces, "run": run}
    with pytest.raises(ConfigError, match=named.replace(".", r"\.")):
        validate_config(config)


def test_a_critical_load_above_every_contact_force_is_frictionless_shear(tmp_path):
    """Through the runner and forces_sf.lmp: a touching N = 60 packing (phi = 0.45) sheared 0.01
    strain with mu = 0.5 and F_CL = 1e9 (above every contact force, ~1e3 here) moves exactly as with
    mu = 0 (every Coulomb bound is 0 in both), and differently from mu = 0.5 without a critical
    load (positions after the run differ by more than 1e-9 d). The stress table counts the same
    contacts in all three, none of them frictional with the critical load or mu = 0, all without."""
    packing = pack(tmp_path / "packing", 60, phi=0.45, seed=11, gap_margin=0.0)
    settings = ShearSettings(
        dt=1e-5, dump_strain=0.005, table_strain=0.001, thermo_strain=0.001, restart_strain=0.01, max_stress_jitter=None
    )

    def last_positions(name, **forces):
        run = run_startup(
            tmp_path / name,
            packing.data_file,
            0.01,
            settings=settings,
            progress=None,
            force_model=ForceModel(plugin=plugin_path(), kn=KN, solver_tol=1e-8, **forces),
        )
        table = read_stress_table(run.table_file)
        return list(iter_dump_frames(run.dump_file))[-1].positions, table["contacts"], table["frictional_contacts"]

    critical, contacts, critical_frictional = last_positions("critical", mu=0.5, critical_load=1e9)
    frictionless, _, frictionless_frictional = last_positions("frictionless", mu=0.0)
    frictional, frictional_contacts, all_frictional = last_positions("frictional", mu=0.5)
    assert np.abs(critical - frictionless).max() < 1e-12
    assert np.abs(critical - frictional).max() > 1e-9
    assert contacts.max() >= 3
    assert not critical_frictional.any() and not frictionless_frictional.any()
    np.testing.assert_array_equal(all_frictional, frictional_contacts)
