"""Time scales of the force model, in units of the inverse shear rate (time = strain), and the
step strides of the output.

Contact relaxation: an overlap o pushes a pair apart with kn o, resisted by the lubrication
squeeze at contact, X = 6 pi eta_f a*^2 / h_r (a* = a_i a_j / (a_i + a_j),
h_r = (a_i + a_j) delta / 2, the regularised gap of simulation/lammps/plugin_source), and by the two Stokes
drags c = 3 pi eta_f d in series. Without inertia do/dt = -o / tau with
    tau = (X + c_i c_j / (c_i + c_j)) / kn.
What tau means for the choice of kn: simulation/lammps/plugin_source/README.md, "Contact stiffness".
"""

from __future__ import annotations

import math

from suspension_fabric.analysis.constants import EINSTEIN_COEFFICIENT


def _mass(d: float, density: float) -> float:
    return density * math.pi / 6.0 * d**3


def _squeeze_at_contact(d_i: float, d_j: float, eta_f: float, delta: float) -> float:
    """X(delta) of the pair, the squeeze resistance at the regularised gap (see module doc)."""
    a_i, a_j = 0.5 * d_i, 0.5 * d_j
    return 6.0 * math.pi * eta_f * (a_i * a_j / (a_i + a_j)) ** 2 / (0.5 * (a_i + a_j) * delta)


def contact_relaxation_time(d_i: float, d_j: float, eta_f: float, delta: float, kn: float) -> float:
    """Relaxation time tau of the overlap of a pair of diameters d_i, d_j (see module doc)."""
    if min(d_i, d_j, eta_f, delta, kn) <= 0:
        raise ValueError("diameters, eta_f, delta and kn must be positive")
    squeeze = _squeeze_at_contact(d_i, d_j, eta_f, delta)
    drag_i, drag_j = 3.0 * math.pi * eta_f * d_i, 3.0 * math.pi * eta_f * d_j
    return (squeeze + drag_i * drag_j / (drag_i + drag_j)) / kn


def contact_period(d_i: float, d_j: float, kn: float, density: float = 1.0) -> float:
    """Period 2 pi sqrt(m* / kn) of the contact spring, m* = m_i m_j / (m_i + m_j).

    Velocity Verlet (the explicit integrator) resolves the contact only with many steps per
    period (the config asks for 30); with stiff contacts ``max_dt_explicit`` is far stricter.
    """
    if min(d_i, d_j, kn, density) <= 0:
        raise ValueError("diameters, kn and density must be positive")
    m_i, m_j = _mass(d_i, density), _mass(d_j, density)
    return 2.0 * math.pi * math.sqrt(m_i * m_j / (m_i + m_j) / kn)


# Measured with the explicit plugin at N = 500, phi = 0.45, eta_f = 223, delta = 1e-3:
# dt X(delta) (1/m_i + 1/m_j) = 0.4 (dt = 2e-7) is smooth, 1.0 (5e-7) rings intermittently,
# 2.0 (1e-6) rings at once (BENCHMARKS.md); a particle shares its mass among several near contacts.
EXPLICIT_SQUEEZE_LIMIT = 0.5


def max_dt_explicit(d: float, eta_f: float, delta: float, density: float = 1.0) -> float:
    """Largest dt of the explicit (velocity-Verlet) integration of the lubrication squeeze:
    dt X(delta) (2/m) <= EXPLICIT_SQUEEZE_LIMIT for two spheres of the smallest diameter d.
    2.5e-7 at d = 1, eta_f = 223, delta = 1e-3."""
    if min(d, eta_f, delta, density) <= 0:
        raise ValueError("d, eta_f, delta and density must be positive")
    return EXPLICIT_SQUEEZE_LIMIT / (_squeeze_at_contact(d, d, eta_f, delta) * 2.0 / _mass(d, density))


def max_dt_implicit(d: float, eta_f: float, delta: float, kt: float, density: float = 1.0) -> float:
    """Largest dt of the implicit-hydrodynamics integration (fix hydro/implicit/sf) for one
    sticking tangential contact between two spheres of the smallest diameter d.

    The contact spring is explicit (symplectic Euler) and its damping implicit; for
    m x'' = -k x - c x' that scheme is stable iff k dt^2 < 4 m + 2 c dt, i.e.
    dt < (c + sqrt(c^2 + 4 k m)) / k. The tangential spring is the binding one: its
    damping is only the log-singular shear resistance c = Y_A(delta) =
    pi eta_f d log(1/delta) / 2 (equal spheres; the drags are left out, a conservative
    choice), and the contact point moves with m = (2/7) m*, m* = m/2 the reduced mass, as
    rotation adds 5/2 to each 1/m (solid spheres, I = m d^2 / 10). 3.7e-5 at d = 1,
    eta_f = 223, delta = 1e-3, kt = 2/7 x 1.25e9. The normal spring, damped by X(delta),
    allows ~20x more.
    """
    if min(d, eta_f, delta, kt, density) <= 0:
        raise ValueError("d, eta_f, delta, kt and density must be positive")
    if delta >= 1.0:
        raise ValueError("delta must be < 1 (log(1/delta) > 0)")
    damping = math.pi * eta_f * d * math.log(1.0 / delta) / 2.0
    mass = (2.0 / 7.0) * 0.5 * _mass(d, density)
    return (damping + math.sqrt(damping**2 + 4.0 * kt * mass)) / kt


def critical_load_force(rate_ratio: float, eta_f: float, d_small: float, shear_rate: float = 1.0) -> float:
    """The critical load F_CL that puts a shear rate at ``rate_ratio`` = gammadot / gammadot_0, with
    gammadot_0 = F_CL / (6 pi eta_f a^2) the rate at which the Stokes force on a small sphere
    (radius a = d_small / 2) moving at a gammadot reaches F_CL (Mari et al. 2014): F_CL =
    6 pi eta_f a^2 gammadot / rate_ratio. 1051 at eta_f = 223, d_small = 1, gammadot = 1 and
    rate_ratio = 1."""
    if min(rate_ratio, eta_f, d_small, shear_rate) <= 0:
        raise ValueError("rate_ratio, eta_f, d_small and shear_rate must be positive")
    return 6.0 * math.pi * eta_f * (0.5 * d_small) ** 2 * shear_rate / rate_ratio


def background_viscosity(eta_f: float, phi: float) -> float:
    """eta_f (1 + 2.5 phi): the shear stress per unit rate of the solvent and the Einstein term, which
    the stress tables add to the particles' forces (suspension_fabric.analysis.stress) and stress
    control adds to the stress it holds (forces.critical_load_stress)."""
    if not (eta_f > 0 and 0 <= phi < 1):
        raise ValueError(f"eta_f must be > 0 and phi in [0, 1), got {eta_f}, {phi}")
    return eta_f * (1.0 + EINSTEIN_COEFFICIENT * phi)


def output_stride(strain: float, dt: float, rate: float = 1.0) -> int:
    """Steps between outputs every ``strain``, as shear_run.lmp computes them (at least 1;
    LAMMPS's round() takes halves away from zero, Python's to even)."""
    return max(1, math.floor(strain / (dt * rate) + 0.5))
