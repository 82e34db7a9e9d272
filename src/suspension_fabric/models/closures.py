r"""Closures: the fourth moment $\langle nnnn\rangle$ written in terms of the second, $\langle nn\rangle$.

Every closure here is defined in the fibre-suspension literature for the unit-trace orientation
tensor $a = \langle nn\rangle/\operatorname{Tr}\langle nn\rangle$; the near-contact fabric's trace
is $Z/2$, not 1, so each is applied to $a$ and scaled back:

$$
\langle n_in_jn_kn_l\rangle \approx \operatorname{Tr}\langle nn\rangle\,A_{ijkl}(a).
$$

All take (..., 3, 3) and return (..., 3, 3, 3, 3). With $\delta_{ij}$ the Kronecker delta:

linear (the paper's, [`suspension_fabric.models.gillissen_wilson.hinch_leal_closure`][]), exact
for an isotropic distribution (Hand, J. Fluid Mech. 13, 1962; Hinch and Leal, J. Fluid Mech. 76,
1976):

$$
\begin{split}
A^{\mathrm{lin}}_{ijkl} ={}&
-\frac{1}{35}\left(\delta_{ij}\delta_{kl} + \delta_{ik}\delta_{jl} + \delta_{il}\delta_{jk}\right) \\
&+ \frac{1}{7}\left(\delta_{ij}a_{kl} + \delta_{ik}a_{jl} + \delta_{il}a_{jk}
+ a_{ij}\delta_{kl} + a_{ik}\delta_{jl} + a_{il}\delta_{jk}\right);
\end{split}
$$

quadratic, exact for perfect alignment, $a = ee$ (Doi, J. Polym. Sci. 19, 1981):

$$
A^{\mathrm{quad}}_{ijkl} = a_{ij}\,a_{kl};
$$

hybrid, with $f$ 0 for isotropy and 1 for perfect alignment (Advani and Tucker, J. Rheol. 31,
1987):

$$
A^{\mathrm{hyb}} = (1 - f)\,A^{\mathrm{lin}} + f\,A^{\mathrm{quad}}, \qquad f = 1 - 27\det a.
$$

Each keeps the trace identity $A_{ijkk} = a_{ij}$ (the linear and hybrid ones over every index
pair, the quadratic one over the last pair: $a_{ij}a_{kl}$ is symmetric in $(ij)$ and in $(kl)$
only).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .gillissen_wilson import contract_closure, hinch_leal_closure

__all__ = ["CLOSURES", "linear_closure", "quadratic_closure", "hybrid_closure", "contract_hybrid", "normalised"]


def normalised(fabric) -> tuple[np.ndarray, np.ndarray]:
    """(a, Tr<nn>): the unit-trace orientation tensor of fabric(s) (..., 3, 3) and the trace
    (..., 1, 1, 1, 1) that scales a closure's A(a) back to <nnnn>; a fabric without contacts
    (trace 0) gives a = I/3, whose closures all vanish after scaling."""
    fabric = np.asarray(fabric, dtype=float)
    trace = np.trace(fabric, axis1=-2, axis2=-1)
    safe = np.where(trace > 0.0, trace, 1.0)[..., None, None]
    a = np.where(trace[..., None, None] > 0.0, fabric / safe, np.eye(3) / 3.0)
    return a, trace[..., None, None, None, None]


def _unit_linear(a) -> np.ndarray:
    return hinch_leal_closure(a)  # linear in a: the paper's closure at unit trace


def _unit_quadratic(a) -> np.ndarray:
    return np.einsum("...ij,...kl->...ijkl", a, a)


def _unit_hybrid(a) -> np.ndarray:
    f = (1.0 - 27.0 * np.linalg.det(a))[..., None, None, None, None]
    return (1.0 - f) * _unit_linear(a) + f * _unit_quadratic(a)


def _scaled(unit: Callable) -> Callable:
    def closure(fabric) -> np.ndarray:
        a, trace = normalised(fabric)
        return trace * unit(a)

    closure.__doc__ = f"<nnnn> ~ Tr<nn> A(<nn>/Tr<nn>) with the {unit.__name__[6:]} closure (module docstring)."
    return closure


linear_closure = _scaled(_unit_linear)
quadratic_closure = _scaled(_unit_quadratic)
hybrid_closure = _scaled(_unit_hybrid)


def contract_hybrid(tensor, fabric) -> np.ndarray:
    """(T:<nnnn>)_ij = T_kl <n_i n_j n_k n_l> with the hybrid closure, without forming it (the
    models' right-hand sides need only this): Tr<nn> [(1 - f) T:A_linear(a) + f a (T:a)], the
    linear part by [`suspension_fabric.models.gillissen_wilson.contract_closure`][]."""
    a, trace = normalised(fabric)
    f = (1.0 - 27.0 * np.linalg.det(a))[..., None, None]
    t_dot_a = np.einsum("...kl,...kl->...", np.asarray(tensor, dtype=float), a)[..., None, None]
    return trace[..., 0, 0] * ((1.0 - f) * contract_closure(tensor, a) + f * a * t_dot_a)


#: The closures by name.
CLOSURES: dict[str, Callable] = {
    "linear": linear_closure,
    "quadratic": quadratic_closure,
    "hybrid": hybrid_closure,
}
