"""Time scales of the force model, in units of the inverse shear rate (time = strain).

The stiff, rate-independent limit the paper simulates needs every contact to unload much
faster than the flow turns it: an overlap o pushes a pair apart with kn o, resisted by the
lubrication squeeze at contact, X = 6 pi eta_f a*^2 / h_r (a* = a_i a_j / (a_i + a_j),
h_r = (a_i + a_j) delta / 2, the regularised gap of workflow/plugin), and by the two Stokes
drags c = 3 pi eta_f d in series. Without inertia do/dt = -o / tau with
    tau = (X + c_i c_j / (c_i + c_j)) / kn.
At the paper's printed values (eta_f = 223, kn = 1.25e5) and delta = 1e-3, tau = 4.2 strain
for two small spheres: contacts formed on the compression axis survive into the extension
quadrant and the near-contact fabric loses its anisotropy (BENCHMARKS.md, stiffness study).
"""

from __future__ import annotations

import math


def contact_relaxation_time(d_i: float, d_j: float, eta_f: float, delta: float, kn: float) -> float:
    """Relaxation time tau of the overlap of a pair of diameters d_i, d_j (see module doc)."""
    if min(d_i, d_j, eta_f, delta, kn) <= 0:
        raise ValueError("diameters, eta_f, delta and kn must be positive")
    a_i, a_j = 0.5 * d_i, 0.5 * d_j
    reduced_radius = a_i * a_j / (a_i + a_j)
    squeeze = 6.0 * math.pi * eta_f * reduced_radius**2 / (0.5 * (a_i + a_j) * delta)
    drag_i, drag_j = 3.0 * math.pi * eta_f * d_i, 3.0 * math.pi * eta_f * d_j
    return (squeeze + drag_i * drag_j / (drag_i + drag_j)) / kn


def contact_period(d_i: float, d_j: float, kn: float, density: float = 1.0) -> float:
    """Period 2 pi sqrt(m* / kn) of the contact spring, m* = m_i m_j / (m_i + m_j).

    An explicit integrator resolves the contact only with many steps per period; the
    project asks for at least 30 (config validation).
    """
    if min(d_i, d_j, kn, density) <= 0:
        raise ValueError("diameters, kn and density must be positive")
    m_i, m_j = (density * math.pi / 6.0 * d**3 for d in (d_i, d_j))
    return 2.0 * math.pi * math.sqrt(m_i * m_j / (m_i + m_j) / kn)
