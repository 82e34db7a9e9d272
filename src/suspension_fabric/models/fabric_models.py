r"""Fabric models as plug-ins: any model of $\mathrm{d}\langle nn\rangle/\mathrm{d}\gamma$ runs
through the same integration, steady state and fits.

A fabric model is a [`FabricModel`][suspension_fabric.models.fabric_interface.FabricModel]: a key (its name in
tables), a display label, its parameters with bounds
([`Parameter`][suspension_fabric.models.fabric_interface.Parameter]), the components of the steady simple-shear fabric
that the paper-style fit matches (one per parameter), and the right-hand side

$$
\frac{\mathrm{d}\langle nn\rangle}{\mathrm{d}\gamma} =
\mathrm{rhs}(\langle nn\rangle, \mathrm{flow}, \mathrm{params}, \phi)
$$

in the paper frame, where ``flow`` is the normalised kinematics of the velocity gradient $L$
([`Flow`][suspension_fabric.models.fabric_interface.Flow]: $\hat{L} = L/\dot\gamma$,
$\hat{E} = (\hat{L} + \hat{L}^{\mathsf{T}})/2$, its extensional part $\hat{E}_e$ and compressional part $\hat{E}_c$, as
in [`suspension_fabric.models.gillissen_wilson.split_strain_rate`][]), ``params`` maps parameter
names to values and $\phi$ is the volume fraction. A model may also give a closed-form steady
state in simple shear and its own exact steady fit.
The interface is defined in
[`suspension_fabric.models.fabric_interface`][suspension_fabric.models.fabric_interface] (its names importable from here
too), below this module and the sparse-regression model whose files
[`load_model`][suspension_fabric.models.fabric_models.load_model] reads
([`suspension_fabric.models.sparse_fabric`][suspension_fabric.models.sparse_fabric]).

Integration ([`integrate`][suspension_fabric.models.fabric_models.integrate]): if the model declares itself ``affine``
(its right-hand side is affine in $\langle nn\rangle$ for a fixed flow, as G-W and the modified model are), the 6-vector
system $\mathrm{d}v/\mathrm{d}\gamma = Mv + b$ is built from the right-hand side itself
(b = rhs(0), column k of M = rhs(basis_k) - b), checked once on a random fabric, and propagated
exactly, $v(\gamma) = v_{\mathrm{ss}} + e^{M\gamma}(v_0 - v_{\mathrm{ss}})$; otherwise scipy's
``solve_ivp`` integrates it.

G-W (Eq. 1), the modified model (Eq. 2) and the separate-rates refinement are the built-in
instances (`BUILT_IN`), with rates of breaking in extension $b_e$, of directed formation in
compression $b_c$ and of isotropic formation $a$:

$$
\begin{split}
\frac{\mathrm{d}\langle nn\rangle}{\mathrm{d}\gamma} ={}&
\hat{L}\cdot\langle nn\rangle + \langle nn\rangle\cdot\hat{L}^{\mathsf{T}}
- 2\,\hat{L}:\langle nnnn\rangle \\
&- b_e\,\hat{E}_e:\langle nnnn\rangle
- b_c\,\frac{\phi}{15}\,2\hat{E}_c
- a\,\frac{\phi}{15}\operatorname{Tr}(\hat{E}_c)\,I,
\end{split}
$$

$(b_e, b_c, a) = (\beta, \beta, \beta)$ for G-W, $(\beta, \beta, A)$ for the modified model and
$(\beta_e, \beta_c, A)$ for separate rates, $\langle nnnn\rangle$ by the paper's closure
([`suspension_fabric.models.gillissen_wilson.hinch_leal_closure`][]; `GW_HYBRID` is G-W
with the hybrid closure of [`suspension_fabric.models.closures`][suspension_fabric.models.closures]). Reference:
the paper, Acharya and Mari, arXiv:2506.05222, Eqs. 1 and 2 (the Gillissen-Wilson model as it
writes it). A user's model is named in the config as ``module:attribute`` or
``path/to/file.py:attribute`` ([`load_model`][suspension_fabric.models.fabric_models.load_model]).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import partial

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
from suspension_fabric.io.protocols import Protocol

from . import gillissen_wilson as paper_models
from .closures import contract_hybrid

# the model interface, its names importable from here as before it had a module of its own
from .fabric_interface import (
    FabricModel,
    Flow,
    ModelError,
    Parameter,
    check_parameters,
    common_flow,
    flow_of,
    newton_steady,
)
from .gillissen_wilson import as_strains, closure_model_rhs, solve_affine
from .plugins import load_plugin, resolve_plugins
from .sparse_fabric import read_model_file

__all__ = [
    "Parameter",
    "Flow",
    "flow_of",
    "FabricModel",
    "GW",
    "MODIFIED",
    "SEPARATE_RATES",
    "GW_HYBRID",
    "newton_steady",
    "BUILT_IN",
    "load_model",
    "resolve_models",
    "check_parameters",
    "affine_system",
    "vector_rhs",
    "common_flow",
    "integrate",
    "steady_state",
    "fit_steady",
    "fit_startup_curve",
    "startup_shear",
    "shear_rotation",
    "rotated_shear",
    "integrate_segment",
    "protocol_fabric",
    "ModelError",
]

#: Strain to which a model that is not affine is integrated in search of its steady state.
STEADY_STRAIN = 200.0


# --------------------------------------------------------------------------- built-in models
def _closure_model_rhs(fabric, flow: Flow, rate_break: float, rate_form: float, rate_iso: float, phi: float):
    """[`suspension_fabric.models.gillissen_wilson.closure_model_rhs`][] on a
    [`Flow`][suspension_fabric.models.fabric_interface.Flow]."""
    return closure_model_rhs(
        np.asarray(fabric, dtype=float), flow.grad_hat, flow.e_ext, flow.e_comp, rate_break, rate_form, rate_iso, phi
    )


_BETA = Parameter("beta", 1e-3, 1e4, 10.0)


def _gw_fit(targets, phi):
    return {"beta": paper_models.fit_gw(targets["12"], phi)}


def _modified_fit(targets, phi):
    beta, A = paper_models.fit_modified(targets["11"], targets["12"], phi)
    return {"beta": beta, "A": A}


#: Gillissen-Wilson (paper Eq. 1): one rate beta for breaking, formation and the isotropic term.
GW = FabricModel(
    key="gw",
    label="G-W (Eq. 1)",
    parameters=(_BETA,),
    steady_targets=("12",),
    affine=True,
    rhs=lambda fabric, flow, p, phi: _closure_model_rhs(fabric, flow, p["beta"], p["beta"], p["beta"], phi),
    steady=lambda p, phi: paper_models.steady_state(p["beta"], None, phi),
    fit=_gw_fit,
    published={"beta": 10.9},  # the paper's fit (its Sec. 3)
    description="d<nn>/dgamma = Lh.<nn> + <nn>.Lh^T - 2 Lh:<nnnn> - beta (Eh_e:<nnnn> + (phi/15)(2 Eh_c + Tr(Eh_c) I))",
)

#: The paper's modified model (Eq. 2): the isotropic creation term has its own rate A.
MODIFIED = FabricModel(
    key="modified",
    label="modified G-W (Eq. 2)",
    parameters=(_BETA, Parameter("A", 0.0, 1e5, 40.0)),
    steady_targets=("11", "12"),
    affine=True,
    rhs=lambda fabric, flow, p, phi: _closure_model_rhs(fabric, flow, p["beta"], p["beta"], p["A"], phi),
    steady=lambda p, phi: paper_models.steady_state(p["beta"], p["A"], phi),
    fit=_modified_fit,
    published={"beta": 9.4, "A": 42.4},  # the paper's fit (its Sec. 3)
    description="Eq. 1 with the isotropic term's rate A: ... - A (phi/15) Tr(Eh_c) I",
)


def _separate_rates_fit(targets, phi):
    """Exact steady fit of the separate-rates model to <nn>_11, <nn>_33, <nn>_12.

    M depends on beta_e only and b is linear in (beta_c, A), so for fixed beta_e the steady
    fabric is phi (beta_c x_form + A x_iso)
    ([`gillissen_wilson.shear_steady_parts`][suspension_fabric.models.gillissen_wilson.shear_steady_parts]): <nn>_11 and
    <nn>_12 give (beta_c, A) and <nn>_33 leaves one equation in beta_e, whose roots on a fine grid of [1e-3, 1e4] are
    refined; roots with a negative rate, an unstable fixed point or a fabric that is not positive semi-definite are
    dropped; of several, the one whose <nn>_22 is closest to ``targets["22"]`` (when given) is kept; exactly one must
    remain."""
    wanted = np.array([targets["11"], targets["12"], targets["33"]], dtype=float) / phi

    def rates(beta_e):
        beta_e = np.asarray(beta_e, dtype=float)
        parts = np.stack(paper_models.shear_steady_parts(beta_e), axis=-1)  # (..., 6, 2): x_form, x_iso
        coefficients = np.linalg.solve(
            parts[..., [0, 3], :], np.broadcast_to(wanted[:2], beta_e.shape + (2,))[..., None]
        )[..., 0]
        return coefficients, np.einsum("...k,...k->...", parts[..., 2, :], coefficients) - wanted[2]

    found = []
    for beta_e in paper_models.roots_on_grid(lambda x: rates(x)[1], paper_models.RATE_GRID):
        (beta_c, A), miss = rates(np.array(beta_e))
        x_form, x_iso = paper_models.shear_steady_parts(beta_e)
        steady = vec_to_sym(phi * (beta_c * x_form + A * x_iso))
        if (
            beta_c >= 0
            and A >= 0
            and abs(miss) < 1e-8 * max(1.0, abs(wanted[2]))
            and paper_models.is_stable(beta_e)
            and np.linalg.eigvalsh(steady).min() >= -1e-12
        ):
            found.append(({"beta_e": float(beta_e), "beta_c": float(beta_c), "A": float(A)}, steady[1, 1]))
    if len(found) > 1 and "22" in targets:
        # several exact solutions: the steady component not fitted, <nn>_22, decides
        found = [min(found, key=lambda solution: abs(solution[1] - targets["22"]))]
    if len(found) != 1:
        raise ModelError(
            f"separate_rates: {len(found)} stable, physical solutions (rates >= 0) reproduce the steady "
            f"<nn>_11, <nn>_33, <nn>_12 = {targets['11']:.6g}, {targets['33']:.6g}, {targets['12']:.6g} "
            f"at phi = {phi}: {[solution for solution, _ in found]}"
        )
    return found[0][0]


#: Refinement aimed at the modified model's overshoot: breaking in extension (beta_e), directed
#: formation in compression (beta_c) and isotropic formation (A) at separate rates.
SEPARATE_RATES = FabricModel(
    key="separate_rates",
    label="separate rates",
    parameters=(
        Parameter("beta_e", 1e-3, 1e4, 10.0),
        Parameter("beta_c", 0.0, 1e4, 10.0),
        Parameter("A", 0.0, 1e5, 40.0),
    ),
    steady_targets=("11", "33", "12"),
    affine=True,
    rhs=lambda fabric, flow, p, phi: _closure_model_rhs(fabric, flow, p["beta_e"], p["beta_c"], p["A"], phi),
    fit=_separate_rates_fit,
    description=(
        "d<nn>/dgamma = Lh.<nn> + <nn>.Lh^T - 2 Lh:<nnnn> - beta_e Eh_e:<nnnn> - beta_c (phi/15) 2 Eh_c"
        " - A (phi/15) Tr(Eh_c) I"
    ),
)


def _hybrid_rhs(fabric, flow: Flow, params, phi):
    """G-W (Eq. 1) with the hybrid closure of Advani and Tucker in place of the paper's."""
    fabric = np.asarray(fabric, dtype=float)
    beta = params["beta"]
    drive = 2.0 * flow.e_hat + beta * flow.e_ext
    convective = flow.grad_hat @ fabric + fabric @ np.swapaxes(flow.grad_hat, -1, -2)
    creation = paper_models.source_part(flow.e_comp, beta, beta, phi)
    return convective - contract_hybrid(drive, fabric) + creation


def _hybrid_vector_form(flow: Flow, params, phi):
    """`_hybrid_rhs` on 6-vectors: with X' = Tr X a (X' = X for Tr X > 0, Tr X I/3 otherwise, as
    [`suspension_fabric.models.closures.normalised`][] has it) and D the drive, D:<nnnn> =
    (1 - f) C(X') + f X' (D:X') / Tr X, C the linear closure's contraction, a matrix for the fixed flow."""
    flow = common_flow(flow) or flow
    beta = params["beta"]
    drive = 2.0 * flow.e_hat + beta * flow.e_ext
    convective = map_matrix(
        flow.grad_hat[..., None, :, :] @ SYMMETRIC_BASIS
        + SYMMETRIC_BASIS @ np.swapaxes(flow.grad_hat, -1, -2)[..., None, :, :]
    )
    closure = map_matrix(paper_models.contract_closure(drive[..., None, :, :], SYMMETRIC_BASIS))
    creation = sym_to_vec(paper_models.source_part(flow.e_comp, beta, beta, phi))
    drive_weights = sym_to_vec(drive) * _OFF_DIAGONALS_TWICE  # D:X = drive_weights . v
    convective, closure, drive_weights = _applied(convective), _applied(closure), _applied(drive_weights[..., None, :])

    def rhs(v):
        x11, x22, x33, x12, x13, x23 = (v[..., k] for k in range(6))
        trace = x11 + x22 + x33
        det = x11 * (x22 * x33 - x23 * x23) - x12 * (x12 * x33 - x23 * x13) + x13 * (x12 * x23 - x22 * x13)
        if np.all(trace > 0.0):
            f = (1.0 - 27.0 * det / trace**3)[..., None]
            scaled, ratio = v, drive_weights(v) / trace[..., None]
        else:  # no contacts (the start of a startup): a = I/3, f = 0
            positive = trace > 0.0
            safe = np.where(positive, trace, 1.0)
            f = np.where(positive, 1.0 - 27.0 * det / safe**3, 0.0)[..., None]
            scaled = np.where(positive[..., None], v, trace[..., None] * _ISOTROPIC_THIRD)
            ratio = np.where(positive[..., None], drive_weights(v) / safe[..., None], 0.0)
        return convective(v) - (1.0 - f) * closure(scaled) - f * scaled * ratio + creation

    return rhs


#: Weights of the 6-vector components in a double contraction A:X of symmetric tensors.
_OFF_DIAGONALS_TWICE = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])
#: The 6-vector of I/3.
_ISOTROPIC_THIRD = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0]) / 3.0


def _applied(matrix) -> Callable:
    """v -> matrix v for 6-vectors v (..., 6) and a matrix (6 or m, 6), or one per batch entry
    (..., m, 6)."""
    if matrix.ndim == 2:
        transposed = np.ascontiguousarray(matrix.T)
        return lambda v: v @ transposed
    return lambda v: (matrix @ v[..., None])[..., 0]


#: G-W with the closure that tested best against the measured fourth moment (the hybrid closure,
#: [`suspension_fabric.models.closures`][suspension_fabric.models.closures]); its steady state by Newton's method from
#: G-W's.
GW_HYBRID = FabricModel(
    key="gw_hybrid",
    label="G-W, hybrid closure",
    parameters=(_BETA,),
    steady_targets=("12",),
    rhs=_hybrid_rhs,
    vector_form=_hybrid_vector_form,
    steady=lambda p, phi: newton_steady(GW_HYBRID, p, phi, paper_models.steady_state(p["beta"], None, phi)),
    description="Eq. 1 with <nnnn> = Tr<nn> [(1 - f) A_linear(a) + f a a], a = <nn>/Tr<nn>, f = 1 - 27 det(a)",
)

#: Built-in models by key.
BUILT_IN = {m.key: m for m in (GW, MODIFIED, SEPARATE_RATES, GW_HYBRID)}


# --------------------------------------------------------------------------- loading
def load_model(spec: str) -> FabricModel:
    """A model from its config entry: a built-in key, ``package.module:attribute``,
    ``path/to/file.py:attribute`` (the attribute a
    [`FabricModel`][suspension_fabric.models.fabric_interface.FabricModel]) or a model file ``path/to/model.json``
    written by the project (a sparse-regression model,
    [`suspension_fabric.models.sparse_fabric.read_model_file`][])."""
    if spec.endswith(".json"):
        return read_model_file(spec)
    return load_plugin(spec, BUILT_IN, FabricModel, ModelError, "model")


def resolve_models(specs) -> dict[str, FabricModel]:
    """Models of a config's list of entries, by key (keys must be distinct)."""
    return resolve_plugins(specs, load_model, ModelError, "models.fabric")


# --------------------------------------------------------------------------- dynamics
def _rhs_vec(fabric_model: FabricModel, vectors, flow: Flow, params, phi):
    return sym_to_vec(fabric_model.rhs(vec_to_sym(vectors), flow, params, phi))


def vector_rhs(fabric_model: FabricModel, flow: Flow, params, phi) -> Callable:
    """v -> dv/dgamma on 6-vectors (..., 6) under a fixed flow: the model's ``vector_form`` where it
    has one for this flow, else its ``rhs`` between tensors and 6-vectors."""
    fast = None if fabric_model.vector_form is None else fabric_model.vector_form(flow, params, phi)
    return fast if fast is not None else partial(_rhs_vec, fabric_model, flow=flow, params=params, phi=phi)


def affine_system(fabric_model: FabricModel, flow: Flow, params, phi):
    """(M, b) of dv/dgamma = M v + b for an affine model, from its right-hand side; raises
    [`ModelError`][suspension_fabric.models.fabric_interface.ModelError] if the model is not affine in <nn> (checked
    on a random fabric)."""
    if not fabric_model.affine:
        raise ModelError(f"model {fabric_model.key} is not declared affine")
    lead = flow.grad_hat.shape[:-2]
    expand = Flow(*(t[..., None, :, :] for t in flow))
    b = _rhs_vec(fabric_model, np.zeros(lead + (6,)), flow, params, phi)
    columns = _rhs_vec(fabric_model, np.broadcast_to(np.eye(6), lead + (6, 6)), expand, params, phi)
    M = np.swapaxes(columns - b[..., None, :], -1, -2)
    probe = np.random.default_rng(0).normal(size=6) * 0.1
    direct = _rhs_vec(fabric_model, np.broadcast_to(probe, lead + (6,)), flow, params, phi)
    if not np.allclose(direct, M @ probe + b, rtol=1e-8, atol=1e-10):
        raise ModelError(f"model {fabric_model.key} is declared affine but its right-hand side is not affine in <nn>")
    return M, b


def integrate(
    fabric_model: FabricModel, fabric0, velocity_gradient, strains, params, phi, rtol=1e-10, atol=1e-12
) -> np.ndarray:
    """<nn>(gamma) from ``fabric0`` under a constant velocity gradient, shape
    ``batch + (len(strains), 3, 3)`` (``fabric0`` and the gradient broadcast): exact propagation
    for an affine model, ``solve_ivp`` (DOP853) on the whole batch as one system otherwise."""
    params = fabric_model.check(params)
    strains = as_strains(strains)
    flow = flow_of(velocity_gradient)
    fabric0 = np.asarray(fabric0, dtype=float)
    if fabric_model.affine:
        M, b = affine_system(fabric_model, flow, params, phi)
        return vec_to_sym(solve_affine(M, b, sym_to_vec(fabric0), strains))
    # the whole batch as one system: the right-hand side broadcasts over it
    batch = np.broadcast_shapes(fabric0.shape[:-2], flow.grad_hat.shape[:-2])
    starts = sym_to_vec(np.broadcast_to(fabric0, batch + (3, 3)).reshape(-1, 3, 3))
    flows = Flow(*(np.broadcast_to(t, batch + (3, 3)).reshape(-1, 3, 3) for t in flow))

    step = vector_rhs(fabric_model, flows, params, phi)

    def rhs(v):
        return step(v.reshape(-1, 6)).ravel()

    solved = _solve_ode(fabric_model, rhs, starts.ravel(), strains, rtol, atol)  # (strains, batch * 6)
    out = vec_to_sym(solved.reshape(len(strains), -1, 6).swapaxes(0, 1))
    return out.reshape(batch + (len(strains), 3, 3))


def _solve_ode(fabric_model: FabricModel, rhs, start, strains, rtol, atol) -> np.ndarray:
    """The 6-vectors (len(strains), 6) of dv/dgamma = rhs(v) from ``start`` (DOP853)."""
    from scipy.integrate import solve_ivp

    solution = solve_ivp(
        lambda _g, v: rhs(v),
        (0.0, float(strains.max(initial=0.0))),
        start,
        t_eval=strains,
        method="DOP853",
        rtol=rtol,
        atol=atol,
    )
    if not solution.success:
        raise ModelError(f"model {fabric_model.key}: integration failed ({solution.message})")
    return solution.y.T


def steady_state(fabric_model: FabricModel, params, phi) -> np.ndarray:
    """Steady fabric in simple shear L = e1 e2: the model's closed form if it has one, the fixed
    point -M^-1 b if affine (and attracting), else the fabric after `STEADY_STRAIN` strain
    from no contacts, if it has stopped changing there."""
    params = fabric_model.check(params)
    if fabric_model.steady is not None:
        return np.asarray(fabric_model.steady(params, phi), dtype=float)
    flow = flow_of(simple_shear_gradient())
    if fabric_model.affine:
        M, b = affine_system(fabric_model, flow, params, phi)
        if not np.all(np.linalg.eigvals(M).real < 0):
            raise ModelError(f"model {fabric_model.key}: the steady state at {params} does not attract")
        return vec_to_sym(-np.linalg.solve(M, b))
    end = integrate(fabric_model, np.zeros((3, 3)), simple_shear_gradient(), [STEADY_STRAIN], params, phi)[0]
    drift = _rhs_vec(fabric_model, sym_to_vec(end), flow, params, phi)
    if np.abs(drift).max() > 1e-8 * max(1.0, np.abs(end).max()):
        raise ModelError(f"model {fabric_model.key}: no steady state by strain {STEADY_STRAIN} at {params}")
    return end


def fit_steady(fabric_model: FabricModel, targets: Mapping[str, float], phi) -> dict[str, float]:
    """Parameters whose steady simple-shear fabric matches ``targets`` (a value for each of the
    model's ``steady_targets``): the model's own exact fit if it has one, else bounded least
    squares from the parameters' starts, accepted only if it matches to 1e-8 relative."""
    missing = set(fabric_model.steady_targets) - set(targets)
    if missing:
        raise ModelError(f"model {fabric_model.key}: steady targets {sorted(missing)} not given")
    if fabric_model.fit is not None:
        return fabric_model.check(fabric_model.fit(targets, phi))
    index = [VECTOR_ORDER.index(c) for c in fabric_model.steady_targets]
    wanted = np.array([targets[c] for c in fabric_model.steady_targets], dtype=float)
    scale = np.abs(wanted).max()

    def residual(x):
        try:
            fabric = steady_state(fabric_model, dict(zip(fabric_model.names, x)), phi)
        except ModelError:
            return np.full(len(x), 1e3)
        return (sym_to_vec(fabric)[index] - wanted) / scale

    start = [p.start for p in fabric_model.parameters]
    bounds = ([p.lower for p in fabric_model.parameters], [p.upper for p in fabric_model.parameters])
    from scipy.optimize import least_squares

    result = least_squares(residual, start, bounds=bounds, x_scale="jac", xtol=1e-14, ftol=1e-14, gtol=1e-14)
    if np.abs(result.fun).max() > 1e-8:
        raise ModelError(
            f"model {fabric_model.key}: no parameters reproduce the steady "
            f"{dict(zip(fabric_model.steady_targets, wanted))} at phi = {phi} "
            f"(best relative residual {np.abs(result.fun).max():.2g})"
        )
    return fabric_model.check(dict(zip(fabric_model.names, result.x)))


def fit_startup_curve(
    fabric_model: FabricModel, strains, observed: Mapping[str, np.ndarray], phi, fabric0, start: Mapping[str, float]
) -> dict[str, float]:
    """Parameters minimising the squared distance of
    [`startup_shear`][suspension_fabric.models.fabric_models.startup_shear] from ``fabric0`` to an observed startup
    curve, summed over the strains and the components of ``observed`` ({"12": values, ...}, each aligned with
    ``strains``): bounded least squares within the parameters' bounds from ``start`` (e.g. the steady fit);
    ``ModelError`` if the solver fails."""
    strains = as_strains(strains)
    unknown = set(observed) - set(VECTOR_ORDER)
    if not observed or unknown:
        raise ModelError(
            f"model {fabric_model.key}: observed components must be among {VECTOR_ORDER}, got {sorted(observed)}"
        )
    index = [VECTOR_ORDER.index(name) for name in observed]
    target = np.stack([np.asarray(values, dtype=float) for values in observed.values()], axis=-1)
    if target.shape[0] != len(strains) or not np.all(np.isfinite(target)):
        raise ModelError(f"model {fabric_model.key}: the observed curves need {len(strains)} finite points each")

    def residual(x):
        fabric = startup_shear(fabric_model, strains, dict(zip(fabric_model.names, x)), phi, fabric0)
        return (sym_to_vec(fabric)[:, index] - target).ravel()

    x0 = [fabric_model.check(start)[name] for name in fabric_model.names]
    bounds = ([p.lower for p in fabric_model.parameters], [p.upper for p in fabric_model.parameters])
    from scipy.optimize import least_squares

    result = least_squares(residual, x0, bounds=bounds, x_scale="jac", xtol=1e-12, ftol=1e-12)
    if not result.success:
        raise ModelError(f"model {fabric_model.key}: the startup-curve fit failed ({result.message})")
    return fabric_model.check(dict(zip(fabric_model.names, map(float, result.x))))


def startup_shear(fabric_model: FabricModel, strains, params, phi, fabric0=None) -> np.ndarray:
    """Fabric in startup simple shear L = e1 e2 from ``fabric0`` (default none), (len(strains), 3, 3)."""
    fabric0 = np.zeros((3, 3)) if fabric0 is None else fabric0
    return integrate(fabric_model, fabric0, simple_shear_gradient(), strains, params, phi)


def shear_rotation(
    fabric_model: FabricModel, theta, strains, params, phi, startup_strain=5.0, fabric0=None
) -> np.ndarray:
    """Startup shear to ``startup_strain``, then the shear turned by ``theta`` (radians, scalar or
    1-D) about e2: <nn> in the rotated frame at the post-rotation ``strains``, shape
    theta.shape + (len(strains), 3, 3) (as [`suspension_fabric.models.gillissen_wilson.shear_rotation`][])."""
    before = startup_shear(fabric_model, [startup_strain], params, phi, fabric0)[0]
    return rotated_shear(fabric_model, before, theta, strains, params, phi)


def rotated_shear(fabric_model: FabricModel, before, theta, strains, params, phi) -> np.ndarray:
    """The fabric ``before`` (3, 3), the shear then turned by ``theta`` (radians, scalar or 1-D)
    about e2 and continued: <nn> in the rotated frame at ``strains``, shape theta.shape +
    (len(strains), 3, 3) (the second half of
    [`shear_rotation`][suspension_fabric.models.fabric_models.shear_rotation])."""
    rotated = to_basis(np.asarray(before, dtype=float), rotation_about_gradient(np.asarray(theta, dtype=float)))
    return integrate(fabric_model, rotated, simple_shear_gradient(), strains, params, phi)


#: d B / d t of the basis B(t) = rotation_about_gradient(t) at t = 0: the generator of turning
#: the flow direction about e2 (e1' = cos t e1 - sin t e3).
_TURN_GENERATOR = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])


def _spin_matrix(turning_rad: float) -> np.ndarray:
    """(6, 6) matrix of X -> K X - X K on 6-vectors, K = turning x generator: the rate of change
    of the components of a fixed tensor seen from a frame turning at ``turning_rad`` per strain."""
    K = turning_rad * _TURN_GENERATOR
    return map_matrix(K @ SYMMETRIC_BASIS - SYMMETRIC_BASIS @ K)


def integrate_segment(
    fabric_model: FabricModel,
    fabric0,
    strains,
    params,
    phi,
    turning_deg_per_strain: float = 0.0,
    rtol=1e-10,
    atol=1e-12,
) -> np.ndarray:
    """<nn> in the frame of the current flow along one segment of simple shear whose flow direction
    turns about e2 at ``turning_deg_per_strain``, from ``fabric0`` (same frame, strain 0), at
    ``strains`` since the segment started: (len(strains), 3, 3).

    In the turning frame the velocity gradient is the constant simple shear L = e1 e2, and the
    components of the fabric change also because the frame turns: d<nn>/dgamma = rhs(<nn>, L) +
    K <nn> - <nn> K, K = w dB/dt (B the frame's basis, w the turning rate in radians per strain).
    This holds for any model whose right-hand side is frame indifferent, as every model that is
    rotated with the flow in a shear rotation must be. Exact propagation for an affine model,
    ``solve_ivp`` otherwise; a fixed direction is [`integrate`][suspension_fabric.models.fabric_models.integrate]."""
    if turning_deg_per_strain == 0.0:
        return integrate(fabric_model, fabric0, simple_shear_gradient(), strains, params, phi, rtol, atol)
    params = fabric_model.check(params)
    strains = as_strains(strains)
    flow = flow_of(simple_shear_gradient())
    spin = _spin_matrix(np.radians(turning_deg_per_strain))
    start = sym_to_vec(np.asarray(fabric0, dtype=float))
    if fabric_model.affine:
        M, b = affine_system(fabric_model, flow, params, phi)
        return vec_to_sym(solve_affine(M + spin, b, start, strains))
    rhs = vector_rhs(fabric_model, flow, params, phi)
    return vec_to_sym(_solve_ode(fabric_model, lambda v: rhs(v) + spin @ v, start, strains, rtol, atol))


def protocol_fabric(
    fabric_model: FabricModel, protocol: Protocol, segment_strains, params, phi, fabric0=None
) -> list[np.ndarray]:
    """<nn> along a protocol, in the frame of the current flow: one array (len(strains_k), 3, 3)
    per segment at its ``segment_strains[k]`` (strain since the segment started), from
    ``fabric0`` (default none) at rest. At each change of flow angle the fabric is carried over
    and seen in the new flow's frame (a shear rotation turns the frame, not the microstructure)."""
    if len(segment_strains) != len(protocol.segments):
        raise ValueError(
            f"protocol {protocol.name}: {len(segment_strains)} strain grids for {len(protocol.segments)} segments"
        )
    fabric = np.zeros((3, 3)) if fabric0 is None else np.asarray(fabric0, dtype=float)
    angle = protocol.segments[0].flow_angle_deg
    out = []
    for segment, strains in zip(protocol.segments, segment_strains):
        fabric = to_basis(fabric, rotation_about_gradient(np.radians(segment.flow_angle_deg - angle)))
        strains = as_strains(strains)
        if strains.size and strains.max() > segment.strain * (1.0 + 1e-9):
            raise ValueError(
                f"protocol {protocol.name}: strains up to {strains.max():g} asked of a segment of {segment.strain:g}"
            )
        grid = np.union1d(strains, [segment.strain])
        along = integrate_segment(fabric_model, fabric, grid, params, phi, segment.turning_deg_per_strain)
        out.append(along[np.searchsorted(grid, strains)])
        fabric, angle = along[np.searchsorted(grid, segment.strain)], segment.end_angle_deg
    return out
