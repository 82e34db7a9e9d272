"""Physics tests of fix hydro/implicit/sf (implicit drag + lubrication) and of the
lubrication neighbour list, with real LAMMPS through the Python module.

The explicit velocity-Verlet update of the squeeze resistance X between two spheres of mass
m is stable only for dt < 2 m / (2 X) (a few 1e-6 at the gaps below, eta_f = 223); every
implicit run here uses a time step 10-1000x above that.
Units: d_small = 1, rho = 1, strain rate 1.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_lammps_plugin import DELTA, ETA_F, H_OUT, make_system, random_spheres, reynolds_squeeze

pytestmark = pytest.mark.lammps

IMPLICIT_PAIR = f"lubricate/sf {ETA_F} {DELTA} {H_OUT} implicit"
SPHERE_MASS = np.pi / 6.0  # d = 1, rho = 1


def atom_array(lmp, name):
    nlocal = lmp.extract_global("nlocal")
    order = np.argsort(lmp.numpy.extract_atom("id")[:nlocal])
    return lmp.numpy.extract_atom(name)[:nlocal][order].copy()


@pytest.mark.parametrize("angle_deg", [0.0, 45.0, 90.0])
def test_free_sphere_relaxes_to_the_imposed_flow_at_a_large_step(angle_deg):
    """A sphere with random velocity and spin in the shear xz erate cos t, yz erate sin t,
    integrated at dt = 1e-2 (40x its drag relaxation time m/(3 pi eta d) = 2.5e-4, so
    explicit Euler or Verlet would diverge): backward Euler multiplies the velocity error by
    (m/dt)/(m/dt + 3 pi eta d) = 0.024 per step, so after 30 steps v = u_inf(x) =
    (z - zlo)(cos t, sin t, 0) and omega = (-sin t, cos t, 0)/2 to round-off (with a solver
    tolerance below that: the solver keeps the old velocity once it is within tol)."""
    t = np.radians(angle_deg)
    lmp = make_system(
        [(0.3, 0.4, 7.0, 1.0, (0, 0, 0), (0, 0, 0))],
        pair=IMPLICIT_PAIR,
        extra="fix integrate all hydro/implicit/sf tol 1e-13\n"
        f"fix shear all deform 1 xz erate {np.cos(t)} yz erate {np.sin(t)} remap v flip yes\n"
        "timestep 1e-2\n",
    )
    lmp.numpy.extract_atom("v")[0] = (0.3, -2.0, 1.0)
    lmp.numpy.extract_atom("omega")[0] = (1.0, 2.0, -3.0)
    lmp.command("run 30 post no")
    x, v, omega = (atom_array(lmp, name)[0] for name in ("x", "v", "omega"))
    zlo = lmp.extract_box()[0][2]
    np.testing.assert_allclose(v, (x[2] - zlo) * np.array([np.cos(t), np.sin(t), 0.0]), atol=1e-9)
    np.testing.assert_allclose(omega, 0.5 * np.array([-np.sin(t), np.cos(t), 0.0]), atol=1e-9)
    lmp.close()


def squeeze_ode_gap(force, gap0, duration):
    """Gap h(duration) of two spheres (d = 1) pushed together by +-force in still fluid:
    m dv/dt = F - (3 pi eta d + 2 X(h)) v, dh/dt = -2 v, X(h) = 6 pi eta a (1/4) / (2h + delta)
    (the squeeze resistance of lubricate/sf for equal spheres, reduced gap xi = 2h/(a_i + a_j)
    = 2h), solved by scipy to rtol 1e-11."""
    drag = 3.0 * np.pi * ETA_F

    def rhs(_, state):
        gap, speed = state
        squeeze = 6.0 * np.pi * ETA_F * 0.5 * 0.25 / (max(2.0 * gap, 0.0) + DELTA)
        return [-2.0 * speed, (force - (drag + 2.0 * squeeze) * speed) / SPHERE_MASS]

    solution = solve_ivp(rhs, (0.0, duration), [gap0, 0.0], method="Radau", rtol=1e-11, atol=1e-14)
    return solution.y[0, -1]


@pytest.mark.parametrize("dt", [1e-4, 1e-5])
def test_two_spheres_pushed_together_approach_at_the_squeeze_rate(dt):
    """Two spheres (d = 1) at surface gap 0.02 pushed together by +-F = 15000 close to gap
    7.7e-4 in 0.05 time. The implicit integration matches the exact solution of the equation
    of motion (squeeze_ode_gap) to 0.05% of the closed distance at dt = 1e-4, 40x the
    explicit stability limit 2 m / (2 X) = 2.5e-6 at the final gap, and to 0.005% at 1e-5:
    first order in dt (measured 1.3e-4 and 1.3e-5)."""
    force, gap0, duration = 15000.0, 0.02, 0.05
    centre = 5.0
    half = 0.5 + 0.5 * gap0
    lmp = make_system(
        [(centre - half, 5.0, 5.0, 1.0, (0, 0, 0), (0, 0, 0)), (centre + half, 5.0, 5.0, 1.0, (0, 0, 0), (0, 0, 0))],
        pair=IMPLICIT_PAIR,
        extra="group left id 1\ngroup right id 2\n"
        f"fix push_left left addforce {force} 0 0\nfix push_right right addforce {-force} 0 0\n"
        f"fix integrate all hydro/implicit/sf tol 1e-10\ntimestep {dt}\n",
    )
    lmp.command(f"run {round(duration / dt)} post no")
    x = atom_array(lmp, "x")
    gap = x[1, 0] - x[0, 0] - 1.0
    lmp.close()
    expected = squeeze_ode_gap(force, gap0, duration)
    assert 5e-4 < expected < 1e-3
    closed = gap0 - expected
    tolerance = 5e-4 if dt == 1e-4 else 5e-5
    assert abs(gap - expected) < tolerance * closed, (gap, expected)


def dense_sheared_system(newton, dt):
    box, tilt = 6.0, (0.0, 1.3, -0.7)
    shape = np.array([[box, tilt[0], tilt[1]], [0.0, box, tilt[2]], [0.0, 0.0, box]])
    atoms = random_spheres(150, shape, seed=1)
    return make_system(
        atoms,
        box=(box,) * 3,
        tilt=tilt,
        newton=newton,
        pair=IMPLICIT_PAIR,
        extra="fix integrate all hydro/implicit/sf tol 1e-10\n"
        "fix shear all deform 1 xz erate 0.6 yz erate 0.8 remap v\n"
        f"timestep {dt}\n",
    )


@pytest.mark.parametrize("newton", ["on", "off"])
def test_lubrication_forces_cancel_in_the_implicit_step(newton):
    """One implicit step (dt = 1e-3, ~1000x the explicit limit at the smallest gaps) of 150
    random bidisperse spheres with random velocities in a tilted, shearing box: the change of
    total momentum equals the total drag, sum_i m_i (v_i' - v_i)/dt = -sum_i 3 pi eta d_i
    (v_i' - u_inf(x_i')), because the pair lubrication forces cancel (images included);
    newton on and off give the same new velocities."""
    dt = 1e-3
    results = {}
    for setting in ("on", "off"):
        lmp = dense_sheared_system(setting, dt)
        v_old = atom_array(lmp, "v")
        x_old = atom_array(lmp, "x")
        lmp.command("run 1 post no")
        x, v = atom_array(lmp, "x"), atom_array(lmp, "v")
        assert np.abs(x - x_old - dt * v_old).max() < 1e-12  # no atom was wrapped (no velocity jump)
        boxlo = lmp.extract_box()[0]
        diameters = 2.0 * atom_array(lmp, "radius")
        iterations = lmp.extract_fix("integrate", 0, 1, 0)
        lmp.close()
        u_inf = np.outer(x[:, 2] - boxlo[2], [0.6, 0.8, 0.0])
        inertia = (SPHERE_MASS * diameters**3)[:, None] * (v - v_old) / dt
        drag = -3.0 * np.pi * ETA_F * diameters[:, None] * (v - u_inf)
        scale = np.abs(inertia).sum()
        assert scale > 0.0 and iterations >= 1
        np.testing.assert_allclose(inertia.sum(axis=0), drag.sum(axis=0), atol=1e-8 * scale)
        results[setting] = v
    np.testing.assert_allclose(results["on"], results["off"], rtol=1e-8, atol=1e-8)


def test_solver_that_does_not_converge_stops_the_run():
    """tol 1e-14 within maxiter 1 cannot be met: the run stops with a message that names the
    step, the error reached and what to change."""
    lmp = dense_sheared_system("on", 1e-3)
    lmp.command("fix integrate all hydro/implicit/sf tol 1e-14 maxiter 1")
    with pytest.raises(Exception, match=r"did not converge at step 1.*after 1 iterations; reduce dt or raise maxiter"):
        lmp.command("run 1 post no")
    lmp.close()


@pytest.mark.parametrize(
    "pair, fixes, message",
    [
        (f"lubricate/sf {ETA_F} {DELTA} {H_OUT}", "fix integrate all hydro/implicit/sf", "keyword 'implicit'"),
        (IMPLICIT_PAIR, "fix nve all nve/sphere", "needs fix hydro/implicit/sf"),
        (IMPLICIT_PAIR, f"fix integrate all hydro/implicit/sf\nfix drag all stokes/sf {ETA_F}", "remove fix stokes/sf"),
    ],
)
def test_inconsistent_setups_are_refused(pair, fixes, message):
    """The implicit fix and the pair style's 'implicit' keyword come together, and the drag
    is not applied twice."""
    lmp = make_system(
        [(3.0, 3.0, 3.0, 1.0, (0, 0, 0), (0, 0, 0)), (4.02, 3.0, 3.0, 1.0, (0, 0, 0), (0, 0, 0))],
        pair=pair,
        extra=fixes + "\n",
    )
    with pytest.raises(Exception, match=message):
        lmp.command("run 1 post no")
    lmp.close()


def test_pair_entering_the_lubrication_range_between_rebuilds_feels_the_squeeze():
    """Two spheres (d = 1) at surface gap 0.101, just outside a = a_i + a_j + skin (skin 0.1),
    approach at 0.49 each for 0.1 time (fix move): each moves 0.049 < skin/2, so the list is
    not rebuilt, and they end at gap 0.003 (reduced 0.006, inside h_out). The pair list of
    lubricate/sf covers the lubrication range plus the skin, so the pair is listed and the
    force is the squeeze force, not zero (a size list, r < a_i + a_j + skin, would miss it)."""
    speed, gap0 = 0.49, 0.101
    lmp = make_system(
        [(3.0, 3.0, 3.0, 1.0, (0, 0, 0), (0, 0, 0)), (4.0 + gap0, 3.0, 3.0, 1.0, (0, 0, 0), (0, 0, 0))],
        extra="neighbor 0.1 bin\nneigh_modify every 1 delay 0 check yes\n"
        "group left id 1\ngroup right id 2\n"
        f"fix move_left left move linear {speed} 0 0\n"
        f"fix move_right right move linear {-speed} 0 0\ntimestep 1e-3\n",
    )
    lmp.command("run 100 post no")
    x, f = atom_array(lmp, "x"), atom_array(lmp, "f")
    lmp.close()
    gap = x[1, 0] - x[0, 0] - 1.0
    assert gap == pytest.approx(0.003, abs=1e-9)
    expected = reynolds_squeeze(0.5, 0.5, gap, 2 * speed)
    assert expected > 1e4
    np.testing.assert_allclose(f[0], [-expected, 0.0, 0.0], rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(f[1], [expected, 0.0, 0.0], rtol=1e-9, atol=1e-6)
