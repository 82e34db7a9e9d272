r"""Gillissen-Wilson (G-W) fabric model and its modification (paper Eqs. 1 and 2).

The fabric $\langle nn\rangle$ (the near-contact second moment per particle,
[`suspension_fabric.analysis.fabric`][suspension_fabric.analysis.fabric]) evolves in strain $\gamma$ under a velocity
gradient $L$ ($L_{ij} = \partial u_i/\partial x_j$) as (paper Eq. 2)

$$
\begin{split}
\frac{\mathrm{d}\langle nn\rangle}{\mathrm{d}\gamma} ={}&
\hat{L}\cdot\langle nn\rangle + \langle nn\rangle\cdot\hat{L}^{\mathsf{T}}
- 2\,\hat{L}:\langle nnnn\rangle \\
&- \beta\left(\hat{E}_e:\langle nnnn\rangle + \frac{\phi}{15}\,2\hat{E}_c\right)
- A\,\frac{\phi}{15}\operatorname{Tr}(\hat{E}_c)\,\delta,
\end{split}
$$

with $\hat{L} = L/\dot\gamma$, $\hat{E} = (\hat{L} + \hat{L}^{\mathsf{T}})/2$,
$\dot\gamma = \sqrt{2E:E}$ ($E$ the strain rate), and $\hat{E}$ split into its extensional part
$\hat{E}_e$ (positive eigenvalues) and compressional part $\hat{E}_c$ (negative eigenvalues)
with the same eigenvectors; $\phi$ is the volume fraction, $\delta$ the identity, $\beta$ the
rate of breaking and directed formation and $A$ that of isotropic formation. $A = \beta$ is the
original G-W model (Eq. 1). Contractions are
$(T:\langle nnnn\rangle)_{ij} = T_{kl}\langle n_i n_j n_k n_l\rangle$. The fourth moment is the
paper's (Hinch-Leal) closure, see [`hinch_leal_closure`][suspension_fabric.models.gillissen_wilson.hinch_leal_closure].

Reference: P. Acharya and R. Mari, "Modelling the evolution of flow-induced anisotropy of
concentrated suspensions", arXiv:2506.05222 (2025): its Eqs. 1 and 2, the Gillissen-Wilson model
as the paper writes it, are written above.

Frames: all tensors here are in the paper frame (e1 flow, e2 gradient, e3
vorticity) unless stated; simple shear is $L = \dot\gamma\,e_1e_2$. A shear rotation by
theta turns e1 and e3 about e2 (see [`suspension_fabric.analysis.frames`][suspension_fabric.analysis.frames]) and
results after it are reported in the rotated frame (e1', e2, e3').

Because the right-hand side is affine in $\langle nn\rangle$ for a fixed flow, a constant-$L$
interval is integrated exactly: with the 6-vector $v$ of independent components,
$\mathrm{d}v/\mathrm{d}\gamma = Mv + b$, so
$v(\gamma) = v_{\mathrm{ss}} + e^{M\gamma}(v_0 - v_{\mathrm{ss}})$ with
$v_{\mathrm{ss}} = -M^{-1}b$, evaluated as $V e^{\Lambda\gamma} V^{-1}$
([`propagate_affine`][suspension_fabric.models.gillissen_wilson.propagate_affine]).
[`integrate_fabric_ode`][suspension_fabric.models.gillissen_wilson.integrate_fabric_ode] integrates the same right-hand
side numerically (scipy ``solve_ivp``) as an independent reference.

Symmetric tensors are stored as 6-vectors in the order (11, 22, 33, 12, 13, 23)
(`suspension_fabric.analysis.frames.VECTOR_ORDER`).
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np

from suspension_fabric.analysis.frames import (
    SYMMETRIC_BASIS,
    VECTOR_ORDER,
    map_matrix,
    rotation_about_gradient,
    simple_shear_gradient,
    sym_to_vec,
    to_basis,
    vec_to_sym,
)

__all__ = [
    "hinch_leal_closure",
    "source_part",
    "contract_closure",
    "split_strain_rate",
    "fabric_rhs",
    "affine_rhs",
    "integrate_fabric",
    "propagate_affine",
    "solve_affine",
    "closure_model_rhs",
    "shear_steady_parts",
    "roots_on_grid",
    "RATE_GRID",
    "integrate_fabric_ode",
    "steady_state",
    "steady_state_ode",
    "is_stable",
    "fit_gw",
    "fit_modified",
    "ModifiedFit",
    "fit_startup_curve",
    "startup_shear",
    "shear_rotation",
]


# Bracket (and grid) for the rate root searches of the fits (beta is a strain-scale ratio of
# order 1-100 in the literature; outside this range the fabric is degenerate).
_BETA_SEARCH = (1e-3, 1e4)
RATE_GRID = np.geomspace(*_BETA_SEARCH, 4000)


def _check_finite(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


def _check_phi(phi) -> float:
    phi = float(_check_finite("phi", phi))
    if not 0.0 < phi < 1.0:
        raise ValueError(f"phi (volume fraction) must lie in (0, 1), got {phi}")
    return phi


def _check_params(beta, A, phi):
    beta = float(_check_finite("beta", beta))
    if beta <= 0.0:
        raise ValueError(f"beta must be positive, got {beta}")
    A = beta if A is None else float(_check_finite("A", A))
    return beta, A, _check_phi(phi)


def _check_gradient(velocity_gradient) -> np.ndarray:
    grad = _check_finite("velocity_gradient", velocity_gradient)
    if grad.shape[-2:] != (3, 3):
        raise ValueError(f"velocity_gradient must have shape (..., 3, 3), got {grad.shape}")
    return grad


def _check_fabric(name: str, fabric) -> np.ndarray:
    fabric = _check_finite(name, fabric)
    if fabric.shape[-2:] != (3, 3):
        raise ValueError(f"{name} must have shape (..., 3, 3), got {fabric.shape}")
    if not np.allclose(fabric, np.swapaxes(fabric, -1, -2), atol=1e-12):
        raise ValueError(f"{name} must be symmetric")
    return fabric


# ----------------------------------------------------------------------- closure
def hinch_leal_closure(fabric) -> np.ndarray:
    r"""Fourth moment $\langle n_i n_j n_k n_l\rangle$ from $\langle nn\rangle$ by the paper's closure.

    $$
    \begin{split}
    \langle n_in_jn_kn_l\rangle ={}& -\frac{1}{35}\langle n_mn_m\rangle
    \left(\delta_{ij}\delta_{kl} + \delta_{ik}\delta_{jl} + \delta_{il}\delta_{jk}\right) \\
    &+ \frac{1}{7}\left(\delta_{ij}\langle n_kn_l\rangle + \delta_{ik}\langle n_jn_l\rangle
    + \delta_{il}\langle n_jn_k\rangle\right. \\
    &\qquad \left. {}+ \langle n_in_j\rangle\delta_{kl} + \langle n_in_k\rangle\delta_{jl}
    + \langle n_in_l\rangle\delta_{jk}\right)
    \end{split}
    $$

    (Hinch and Leal, J. Fluid Mech. 76, 187 (1976); $\delta$ the Kronecker delta). It is fully
    symmetric and its contraction over any index pair returns $\langle nn\rangle$ (exact for an
    isotropic distribution). Shape (..., 3, 3) -> (..., 3, 3, 3, 3).
    """
    fabric = np.asarray(fabric, dtype=float)
    eye = np.eye(3)
    trace = np.trace(fabric, axis1=-2, axis2=-1)[..., None, None, None, None]
    iso = np.einsum("ij,kl->ijkl", eye, eye) + np.einsum("ik,jl->ijkl", eye, eye) + np.einsum("il,jk->ijkl", eye, eye)
    mixed = (
        np.einsum("ij,...kl->...ijkl", eye, fabric)
        + np.einsum("ik,...jl->...ijkl", eye, fabric)
        + np.einsum("il,...jk->...ijkl", eye, fabric)
        + np.einsum("...ij,kl->...ijkl", fabric, eye)
        + np.einsum("...ik,jl->...ijkl", fabric, eye)
        + np.einsum("...il,jk->...ijkl", fabric, eye)
    )
    return -trace * iso / 35.0 + mixed / 7.0


def contract_closure(tensor, fabric) -> np.ndarray:
    """(T:<nnnn>)_ij = T_kl <n_i n_j n_k n_l> with the closure, without forming it.

    Expanding the closure with symmetric fabric X gives
    T:<nnnn> = -(Tr X/35)(Tr T delta + T + T^T)
               + (1/7)((T:X) delta + (T + T^T) X + X (T + T^T) + Tr T X),
    so only the symmetric part of T matters. Broadcasts over leading axes.
    """
    tensor = np.asarray(tensor, dtype=float)
    fabric = np.asarray(fabric, dtype=float)
    sym2 = tensor + np.swapaxes(tensor, -1, -2)
    tr_t = np.trace(tensor, axis1=-2, axis2=-1)[..., None, None]
    tr_x = np.trace(fabric, axis1=-2, axis2=-1)[..., None, None]
    t_dot_x = np.einsum("...kl,...kl->...", tensor, fabric)[..., None, None]
    eye = np.eye(3)
    return -tr_x * (tr_t * eye + sym2) / 35.0 + (t_dot_x * eye + sym2 @ fabric + fabric @ sym2 + tr_t * fabric) / 7.0


# ------------------------------------------------------------------- kinematics
def split_strain_rate(velocity_gradient):
    """Normalised kinematics of a velocity gradient L.

    Returns ``(Lh, Eh, Eh_e, Eh_c, gammadot)`` with gammadot = sqrt(2 E:E),
    Lh = L/gammadot, Eh = (Lh + Lh^T)/2 = Eh_e + Eh_c, where Eh_e (Eh_c) keeps
    the positive (negative) eigenvalues of Eh with their eigenvectors. For simple
    shear the eigenvalues are +-1/2 and Eh_e = (1/2) v_e v_e, Eh_c = -(1/2) v_c v_c
    with v_e = (e1 + e2)/sqrt 2, v_c = (e1 - e2)/sqrt 2. Broadcasts over leading axes.
    """
    grad = _check_gradient(velocity_gradient)
    strain_rate = 0.5 * (grad + np.swapaxes(grad, -1, -2))
    gammadot = np.sqrt(2.0 * np.einsum("...ij,...ij->...", strain_rate, strain_rate))
    if np.any(gammadot <= 0.0):
        raise ValueError("velocity_gradient has no straining part (gammadot = 0): strain is undefined")
    grad_hat = grad / gammadot[..., None, None]
    e_hat = strain_rate / gammadot[..., None, None]
    eigval, eigvec = np.linalg.eigh(e_hat)
    e_ext = (eigvec * np.clip(eigval, 0.0, None)[..., None, :]) @ np.swapaxes(eigvec, -1, -2)
    e_comp = (eigvec * np.clip(eigval, None, 0.0)[..., None, :]) @ np.swapaxes(eigvec, -1, -2)
    return grad_hat, e_hat, e_ext, e_comp, gammadot


def _linear_part(fabric, grad_hat, e_ext, beta):
    """Part of the right-hand side that is linear in the fabric."""
    convective = grad_hat @ fabric + fabric @ np.swapaxes(grad_hat, -1, -2)
    return convective - contract_closure(2.0 * grad_hat + beta * e_ext, fabric)


def source_part(e_comp, beta, A, phi):
    """Fabric-independent contact creation by compression: -(phi/15)(2 beta Eh_c + A Tr(Eh_c) I)."""
    tr_c = np.trace(e_comp, axis1=-2, axis2=-1)[..., None, None]
    return -(phi / 15.0) * (2.0 * beta * e_comp + A * tr_c * np.eye(3))


def closure_model_rhs(fabric, grad_hat, e_ext, e_comp, rate_break, rate_form, rate_iso, phi) -> np.ndarray:
    """Lh.X + X.Lh^T - 2 Lh:<nnnn> - b_e Eh_e:<nnnn> - b_c (phi/15) 2 Eh_c - a (phi/15) Tr(Eh_c) delta
    with the paper's closure, for breaking, directed-formation and isotropic rates (b_e, b_c, a);
    paper Eq. 2 is (beta, beta, A). No argument checks (the kinematics of
    [`split_strain_rate`][suspension_fabric.models.gillissen_wilson.split_strain_rate])."""
    return _linear_part(fabric, grad_hat, e_ext, rate_break) + source_part(e_comp, rate_form, rate_iso, phi)


def fabric_rhs(fabric, velocity_gradient, beta, A=None, phi=0.45) -> np.ndarray:
    """Right-hand side d<nn>/dgamma of paper Eq. 2 (Eq. 1 when ``A`` is None or beta).

    ``fabric`` (..., 3, 3) and ``velocity_gradient`` (..., 3, 3) broadcast together;
    only the direction of L matters (the model is rate independent).
    """
    beta, A, phi = _check_params(beta, A, phi)
    fabric = _check_fabric("fabric", fabric)
    grad_hat, _, e_ext, e_comp, _ = split_strain_rate(velocity_gradient)
    return closure_model_rhs(fabric, grad_hat, e_ext, e_comp, beta, beta, A, phi)


def _affine_system(velocity_gradient, beta, A, phi):
    """(M, b) of dv/dgamma = M v + b without argument checks (internal)."""
    grad_hat, _, e_ext, e_comp, _ = split_strain_rate(velocity_gradient)
    M = map_matrix(_linear_part(SYMMETRIC_BASIS, grad_hat[..., None, :, :], e_ext[..., None, :, :], beta))
    b = sym_to_vec(source_part(e_comp, beta, A, phi))
    return M, b


def affine_rhs(velocity_gradient, beta, A=None, phi=0.45):
    """The right-hand side as dv/dgamma = M v + b on 6-vectors v = sym_to_vec(<nn>).

    Returns ``(M, b)`` with shapes (..., 6, 6) and (..., 6), built column by column
    from the linear part applied to the basis of symmetric tensors. M depends on
    beta only; b is linear in (beta, A) and in phi.
    """
    beta, A, phi = _check_params(beta, A, phi)
    return _affine_system(velocity_gradient, beta, A, phi)


def is_stable(beta, velocity_gradient=None) -> bool:
    """True if the fixed point under L (default simple shear) attracts: all Re(eig M) < 0."""
    grad = simple_shear_gradient() if velocity_gradient is None else velocity_gradient
    M, _ = _affine_system(grad, float(_check_finite("beta", beta)), 0.0, 0.0)
    return bool(np.all(np.linalg.eigvals(M).real < 0.0))


# ------------------------------------------------------------------ integration
def as_strains(strains) -> np.ndarray:
    strains = _check_finite("strains", strains)
    if strains.ndim != 1:
        raise ValueError(f"strains must be a 1-D array, got shape {strains.shape}")
    if np.any(strains < 0.0):
        raise ValueError("strains must be non-negative (strain counted from the initial fabric)")
    return strains


def propagate_affine(M, deviation, strains) -> np.ndarray:
    """expm(M gamma) deviation at every strain, shape batch + (strains, 6): by the eigenvectors of M,
    V exp(Lambda gamma) V^-1, when they are well conditioned (one decomposition for all strains),
    else by scipy's expm per strain."""
    eigenvalues, vectors = np.linalg.eig(M)
    if np.all(np.linalg.cond(vectors) < 1e8):
        coefficients = np.linalg.solve(vectors, np.asarray(deviation, dtype=complex)[..., None])[..., 0]
        growth = np.exp(eigenvalues[..., None, :] * strains[:, None])  # flow batch + (strains, 6)
        return np.einsum("...ij,...sj->...si", vectors, growth * coefficients[..., None, :]).real
    import scipy.linalg  # scipy where used: table-only jobs start without it

    propagators = scipy.linalg.expm(M[..., None, :, :] * strains[:, None, None])
    return np.einsum("...sij,...j->...si", propagators, deviation)


#: Above this condition number of M the fixed point -M^-1 b is not used (it may not exist: a
#: stability exchange of the flow) and the augmented exponential propagates v instead.
SINGULAR_CONDITION = 1e8


def solve_affine(M, b, v0, strains) -> np.ndarray:
    """v(gamma) of dv/dgamma = M v + b from v0 at every strain, shape batch + (strains, 6) (M, b,
    v0 broadcast): v_ss + expm(M gamma)(v0 - v_ss) with v_ss = -M^-1 b when M is well
    conditioned, else the exponential of the augmented matrix [[M, b], [0, 0]] applied to (v0, 1),
    which needs no inverse (exact for a singular M too)."""
    M, b, v0 = (np.asarray(x, dtype=float) for x in (M, b, v0))
    if np.all(np.linalg.cond(M) < SINGULAR_CONDITION):
        v_ss = -np.linalg.solve(M, b[..., None])[..., 0]
        # one decomposition per flow; fabrics sharing a flow share it (cheap angle grids)
        return v_ss[..., None, :] + propagate_affine(M, v0 - v_ss, strains)
    batch = np.broadcast_shapes(M.shape[:-2], b.shape[:-1])
    augmented = np.zeros(batch + (7, 7))
    augmented[..., :6, :6] = M
    augmented[..., :6, 6] = b
    start = np.concatenate([v0, np.ones(v0.shape[:-1] + (1,))], axis=-1)
    import scipy.linalg

    propagators = scipy.linalg.expm(augmented[..., None, :, :] * strains[:, None, None])
    return np.einsum("...sij,...j->...si", propagators, start)[..., :6]


def integrate_fabric(fabric0, velocity_gradient, strains, beta, A=None, phi=0.45) -> np.ndarray:
    """Exact fabric <nn>(gamma) under a constant velocity gradient.

    Uses v(gamma) = v_ss + expm(M gamma)(v0 - v_ss) for the affine system of
    [`affine_rhs`][suspension_fabric.models.gillissen_wilson.affine_rhs]
    ([`solve_affine`][suspension_fabric.models.gillissen_wilson.solve_affine], which also takes a singular M).
    ``fabric0`` (..., 3, 3) and ``velocity_gradient`` (..., 3, 3) broadcast; ``strains`` is 1-D (strain since the
    initial fabric). Returns an array of shape ``batch + (len(strains), 3, 3)``.
    """
    fabric0 = _check_fabric("fabric0", fabric0)
    strains = as_strains(strains)
    M, b = affine_rhs(velocity_gradient, beta, A, phi)
    return vec_to_sym(solve_affine(M, b, sym_to_vec(fabric0), strains))


def integrate_fabric_ode(fabric0, velocity_gradient, strains, beta, A=None, phi=0.45, rtol=1e-10, atol=1e-12):
    """Reference integration of [`fabric_rhs`][suspension_fabric.models.gillissen_wilson.fabric_rhs] with scipy
    ``solve_ivp`` (one fabric).

    ``velocity_gradient`` may be a constant (3, 3) array or a callable
    ``gamma -> (3, 3)`` for a time-dependent flow. Returns (len(strains), 3, 3).
    """
    fabric0 = _check_fabric("fabric0", fabric0)
    strains = as_strains(strains)
    gradient_at = velocity_gradient if callable(velocity_gradient) else (lambda _g: velocity_gradient)

    def rhs(gamma, v):
        return sym_to_vec(fabric_rhs(vec_to_sym(v), gradient_at(gamma), beta, A, phi))

    from scipy.integrate import solve_ivp

    sol = solve_ivp(
        rhs,
        (0.0, float(strains.max(initial=0.0))),
        sym_to_vec(fabric0),
        t_eval=strains,
        method="DOP853",
        rtol=rtol,
        atol=atol,
    )
    if not sol.success:
        raise RuntimeError(f"fabric ODE integration failed: {sol.message}")
    return vec_to_sym(sol.y.T)


# ------------------------------------------------------------------ steady state
def steady_state(beta, A=None, phi=0.45, as_printed=False) -> np.ndarray:
    """Closed-form steady fabric in simple shear L = e1 e2 (paper frame, 3x3).

    With D = 416 + 9 beta (6 + beta) the paper prints
      P11 = (9 beta (136 - 30 beta + 9 beta^2) + 8 A (254 + beta (-13 + 6 beta))) phi / (15 beta D)
      P22 = (A (1864 + 372 beta + 69 beta^2) + 6 beta (-174 + beta (32 + 3 beta))) phi / (15 beta D)
      P33 = (464 A + 440 beta + 92 A beta + 6 (53 + 8 A) beta^2 + 81 beta^3) phi / (15 beta D)
      P12 = -7 (A (-8 + beta) + beta (-4 + 3 beta)) phi / (5 D)
    as <nn>_11, _22, _33, _12, with <nn>_13 = <nn>_23 = 0; A = None means A = beta (G-W).

    The fixed point of the paper's own Eq. 2
    ([`steady_state_ode`][suspension_fabric.models.gillissen_wilson.steady_state_ode], the reference) agrees exactly
    with P11 and P12 but has <nn>_22 = P33 and <nn>_33 = P22: the printed 22 and 33 expressions are exchanged. The
    reason is visible in the equation: the convective term -2 Lh:<nnnn> feeds <nn>_22 by
    6|<nn>_12|/7 but <nn>_33 only by 2|<nn>_12|/7, so only the corrected labels are
    consistent with Eq. 2 (tests/models/test_model.py checks both statements). By default
    this function returns the corrected tensor; ``as_printed=True`` returns the
    expressions with the paper's labels, for the record.
    """
    beta, A, phi = _check_params(beta, A, phi)
    D = 416.0 + 9.0 * beta * (6.0 + beta)
    p11 = (9 * beta * (136 - 30 * beta + 9 * beta**2) + 8 * A * (254 + beta * (-13 + 6 * beta))) * phi / (15 * beta * D)
    p22 = (A * (1864 + 372 * beta + 69 * beta**2) + 6 * beta * (-174 + beta * (32 + 3 * beta))) * phi / (15 * beta * D)
    p33 = (464 * A + 440 * beta + 92 * A * beta + 6 * (53 + 8 * A) * beta**2 + 81 * beta**3) * phi / (15 * beta * D)
    p12 = -7 * (A * (-8 + beta) + beta * (-4 + 3 * beta)) * phi / (5 * D)
    if as_printed:
        return vec_to_sym([p11, p22, p33, p12, 0.0, 0.0])
    return vec_to_sym([p11, p33, p22, p12, 0.0, 0.0])


def steady_state_ode(beta, A=None, phi=0.45, velocity_gradient=None) -> np.ndarray:
    r"""Fixed point of the ODE, $v_{\mathrm{ss}} = -M^{-1}b$, under $L$ (default simple shear
    $L = \dot\gamma\,e_1e_2$)."""
    grad = simple_shear_gradient() if velocity_gradient is None else velocity_gradient
    M, b = affine_rhs(grad, beta, A, phi)
    return vec_to_sym(-np.linalg.solve(M, b[..., None])[..., 0])


# -------------------------------------------------------------------------- fits
def _simple_shear_pieces():
    """Simple-shear system split by parameter, per unit phi: M = M0 + beta M1, b = beta b1 + A b2."""
    grad = simple_shear_gradient()
    M0, _ = _affine_system(grad, 0.0, 0.0, 1.0)
    M_one, b1 = _affine_system(grad, 1.0, 0.0, 1.0)
    _, b_both = _affine_system(grad, 1.0, 1.0, 1.0)
    return M0, M_one - M0, b1, b_both - b1


_SHEAR_M0, _SHEAR_M1, _SHEAR_B1, _SHEAR_B2 = _simple_shear_pieces()


def shear_steady_parts(rate_break):
    """Steady simple-shear 6-vectors per unit phi of unit directed formation and of unit isotropic
    formation, for the breaking rate ``rate_break`` (may be an array): the fixed point of
    [`closure_model_rhs`][suspension_fabric.models.gillissen_wilson.closure_model_rhs] is rate_form x_form + rate_iso
    x_iso, since M depends on the breaking rate only (M = M0 + b_e M1) and the source is linear in the two formation
    rates."""
    if rate_break is RATE_GRID:
        return _rate_grid_steady_parts()
    return _solved_steady_parts(rate_break)


def _solved_steady_parts(rate_break):
    rate = np.asarray(rate_break, dtype=float)
    M = _SHEAR_M0 + rate[..., None, None] * _SHEAR_M1
    sol = np.linalg.solve(M, -np.stack([_SHEAR_B1, _SHEAR_B2], axis=-1))
    return sol[..., 0], sol[..., 1]


@functools.cache
def _rate_grid_steady_parts():
    """`shear_steady_parts` on `RATE_GRID`, solved once per process: every steady fit scans the grid."""
    parts = _solved_steady_parts(RATE_GRID)
    for part in parts:
        part.flags.writeable = False
    return parts


def _steady_parts(beta):
    """Steady simple-shear fabric per unit phi split as v = v_beta + A v_A (beta may be an array).

    The source is linear in A for fixed beta, so the fixed point is affine in A.
    """
    x_form, x_iso = shear_steady_parts(beta)
    return np.asarray(beta, dtype=float)[..., None] * x_form, x_iso


def _is_physical(beta, A, phi) -> bool:
    """Stable fixed point whose fabric is positive semi-definite (a sum of n n)."""
    if not is_stable(beta):
        return False
    eig = np.linalg.eigvalsh(steady_state_ode(beta, A, phi))
    return bool(eig.min() >= -1e-12 * max(1.0, abs(eig).max()))


def _reproduces(beta, A, phi, targets, tol=1e-9) -> bool:
    """True if the ODE fixed point matches ``targets`` {(i, j): value}; rejects poles of the residual."""
    fabric = steady_state_ode(beta, A, phi)
    return all(abs(fabric[ij] - value) <= tol * max(1.0, abs(value)) for ij, value in targets.items())


def roots_on_grid(func, grid):
    """All sign changes of a vectorised ``func`` on ``grid``, refined with brentq."""
    from scipy.optimize import brentq

    values = func(grid)
    roots = []  # may include poles (sign change through infinity); callers verify
    for i in np.flatnonzero(
        np.isfinite(values[:-1]) & np.isfinite(values[1:]) & (np.sign(values[:-1]) != np.sign(values[1:]))
    ):
        if values[i] == 0.0:
            roots.append(float(grid[i]))
        else:
            roots.append(brentq(lambda x: float(func(np.array(x))), grid[i], grid[i + 1], xtol=1e-14, rtol=1e-14))
    return roots


def _pick_unique(candidates, what, target_text):
    if not candidates:
        raise ValueError(
            f"{what}: no stable, physical (beta > 0, positive semi-definite fabric) solution "
            f"reproduces {target_text}; beta searched in {_BETA_SEARCH}"
        )
    if len(candidates) > 1:
        raise ValueError(f"{what}: several stable physical solutions {candidates} reproduce {target_text}")
    return candidates[0]


# Limit of the G-W steady <nn>_12 / phi for beta -> infinity (from the closed form).
_GW_N12_LIMIT = 28.0 / 45.0


def _check_shear_component(n12) -> float:
    n12 = float(_check_finite("n12", n12))
    if n12 >= 0.0:
        raise ValueError(
            f"steady <nn>_12 must be negative in the paper frame (L = e1 e2 puts contacts along the "
            f"compression axis e1 - e2), got {n12}; check the sign convention of the input"
        )
    return n12


def fit_gw(n12, phi) -> float:
    """G-W beta reproducing the steady simple-shear <nn>_12 at volume fraction phi.

    The steady state is the ODE fixed point (linear in phi). Every root of
    <nn>_12^ss(beta) = n12 with beta in [1e-3, 1e4] is found on a fine grid and
    refined; roots whose fixed point is unstable or not positive semi-definite are
    dropped. Raises ValueError when no (or more than one) root remains; a steady
    <nn>_12 must be negative in the paper frame (contacts along compression).
    """
    n12 = _check_shear_component(n12)
    phi = _check_phi(phi)
    if not -_GW_N12_LIMIT * phi < n12:
        raise ValueError(
            f"fit_gw: G-W can only reach -28 phi/45 = {-_GW_N12_LIMIT * phi:.6g} < <nn>_12 < 0 at "
            f"phi = {phi}; got <nn>_12 = {n12}"
        )

    def residual(beta):
        x_beta, x_A = _steady_parts(beta)
        return (x_beta[..., 3] + beta * x_A[..., 3]) * phi - n12

    roots = [
        b
        for b in roots_on_grid(residual, RATE_GRID)
        if _reproduces(b, b, phi, {(0, 1): n12}) and _is_physical(b, b, phi)
    ]
    return float(_pick_unique(roots, "fit_gw", f"<nn>_12 = {n12} at phi = {phi}"))


class ModifiedFit(NamedTuple):
    """Parameters of the modified G-W model fitted to a steady state; unpacks as (beta, A)."""

    beta: float
    A: float


def fit_modified(n11, n12, phi) -> ModifiedFit:
    """Modified-model (beta, A) reproducing steady <nn>_11 and <nn>_12 at phi.

    For fixed beta the steady state is affine in A, X = phi (X_beta + A X_A), so A
    follows from <nn>_12 and a scalar equation in beta remains for <nn>_11. All its
    roots in [1e-3, 1e4] are found on a grid and refined; solutions with A < 0, an
    unstable fixed point or a fabric that is not positive semi-definite are dropped.
    Raises ValueError when none (or several) remain. Returns ``ModifiedFit(beta, A)``,
    a named tuple: ``beta, A = fit_modified(...)``.
    """
    n11 = float(_check_finite("n11", n11))
    n12 = _check_shear_component(n12)
    phi = _check_phi(phi)
    if n11 <= 0.0:
        raise ValueError(f"fit_modified: <nn>_11 must be positive (a diagonal fabric component), got {n11}")

    def A_of(beta):
        x_beta, x_A = _steady_parts(beta)
        return (n12 / phi - x_beta[..., 3]) / x_A[..., 3]

    def residual(beta):
        x_beta, x_A = _steady_parts(beta)
        return (x_beta[..., 0] + A_of(beta) * x_A[..., 0]) * phi - n11

    candidates = []
    for beta in roots_on_grid(residual, RATE_GRID):
        A = A_of(beta)
        if (
            np.isfinite(A)
            and A >= 0.0
            and _reproduces(beta, A, phi, {(0, 0): n11, (0, 1): n12})
            and _is_physical(beta, A, phi)
        ):
            candidates.append((float(beta), float(A)))
    beta, A = _pick_unique(candidates, "fit_modified", f"<nn>_11 = {n11}, <nn>_12 = {n12} at phi = {phi}")
    return ModifiedFit(beta=beta, A=A)


def fit_startup_curve(strains, observed: dict, phi, fabric0=None, *, free_A: bool, start) -> ModifiedFit:
    """(beta, A) minimising the squared distance of
    [`startup_shear`][suspension_fabric.models.gillissen_wilson.startup_shear] from ``fabric0`` to an observed startup
    curve, summed over the strains and the components of ``observed`` ({"12": values, "11": values, ...}, each aligned
    with ``strains``).

    ``free_A=False`` fits G-W (A = beta, one parameter), ``True`` the modified model. ``start``
    is the initial (beta, A) (e.g. the steady-state fit). Bounds: beta in the fits' search range,
    A >= 0. Raises ValueError if the least-squares solver fails.
    """
    strains = as_strains(strains)
    phi = _check_phi(phi)
    unknown = set(observed) - set(VECTOR_ORDER)
    if not observed or unknown:
        raise ValueError(f"observed components must be among {VECTOR_ORDER}, got {sorted(observed)}")
    index = [VECTOR_ORDER.index(name) for name in observed]
    target = np.stack([_check_finite(f"observed[{name!r}]", values) for name, values in observed.items()], axis=-1)
    if target.shape[0] != len(strains):
        raise ValueError(f"observed curves have {target.shape[0]} points for {len(strains)} strains")

    def residual(p):
        beta, A = (p[0], p[1]) if free_A else (p[0], p[0])
        return (sym_to_vec(startup_shear(strains, beta, A, phi, fabric0))[:, index] - target).ravel()

    x0 = [start[0], start[1]] if free_A else [start[0]]
    lower = [_BETA_SEARCH[0], 0.0] if free_A else [_BETA_SEARCH[0]]
    upper = [_BETA_SEARCH[1], np.inf] if free_A else [_BETA_SEARCH[1]]
    from scipy.optimize import least_squares

    result = least_squares(residual, x0, bounds=(lower, upper), x_scale="jac", xtol=1e-12, ftol=1e-12)
    if not result.success:
        raise ValueError(f"fit_startup_curve: least squares failed ({result.message})")
    beta = float(result.x[0])
    return ModifiedFit(beta=beta, A=float(result.x[1]) if free_A else beta)


# ----------------------------------------------------------- flow protocols
def startup_shear(strains, beta, A=None, phi=0.45, fabric0=None) -> np.ndarray:
    """Fabric in startup simple shear L = e1 e2 from ``fabric0`` (default: no contacts).

    Returns (len(strains), 3, 3) in the paper frame.
    """
    fabric0 = np.zeros((3, 3)) if fabric0 is None else fabric0
    return integrate_fabric(fabric0, simple_shear_gradient(), strains, beta, A, phi)


def shear_rotation(theta, strains, beta, A=None, phi=0.45, startup_strain=5.0, fabric0=None) -> np.ndarray:
    """Model prediction for a shear rotation by ``theta`` (radians, scalar or 1-D array).

    Protocol: startup simple shear L = e1 e2 from ``fabric0`` (default no contacts)
    to ``startup_strain``; then the flow turns by theta about e2 (e1' = cos e1 -
    sin e3, e3' = sin e1 + cos e3) and shearing continues. Returns <nn> in the
    rotated frame (e1', e2, e3') at the post-rotation ``strains``, shape
    theta.shape + (len(strains), 3, 3).

    In the rotated frame the new flow is again simple shear e1' e2, so the rotated
    pre-rotation fabric Q <nn> Q^T (Q rows e1', e2, e3') is integrated under the
    standard L; [`integrate_fabric`][suspension_fabric.models.gillissen_wilson.integrate_fabric] with the rotated L
    gives the same (a test checks this frame indifference).
    """
    theta = _check_finite("theta", theta)
    if startup_strain < 0 or not np.isfinite(startup_strain):
        raise ValueError(f"startup_strain must be finite and non-negative, got {startup_strain}")
    before = startup_shear(np.array([startup_strain]), beta, A, phi, fabric0)[0]
    rotated0 = to_basis(before, rotation_about_gradient(theta))
    return integrate_fabric(rotated0, simple_shear_gradient(), strains, beta, A, phi)
