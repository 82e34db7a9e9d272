r"""What a fabric model is: the interface every model of $\mathrm{d}\langle nn\rangle/\mathrm{d}\gamma$
implements, and the helpers its author uses to write one.

A model is a [`FabricModel`][suspension_fabric.models.fabric_interface.FabricModel] with its parameters
([`Parameter`][suspension_fabric.models.fabric_interface.Parameter]) and a right-hand side on the normalised
kinematics of the flow ([`Flow`][suspension_fabric.models.fabric_interface.Flow], from
[`flow_of`][suspension_fabric.models.fabric_interface.flow_of]); a model that cannot be used as declared raises
[`ModelError`][suspension_fabric.models.fabric_interface.ModelError].
[`common_flow`][suspension_fabric.models.fabric_interface.common_flow] and
[`newton_steady`][suspension_fabric.models.fabric_interface.newton_steady] help write its ``vector_form`` and its
``steady`` state. The built-in models, their integration and their fits are in
[`suspension_fabric.models.fabric_models`][suspension_fabric.models.fabric_models] (which imports every name of this
module too); a model found by sparse regression is in
[`suspension_fabric.models.sparse_fabric`][suspension_fabric.models.sparse_fabric].
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from suspension_fabric.analysis.frames import VECTOR_ORDER, simple_shear_gradient, sym_to_vec, vec_to_sym

from .gillissen_wilson import split_strain_rate

__all__ = [
    "ModelError",
    "Parameter",
    "check_parameters",
    "Flow",
    "flow_of",
    "FabricModel",
    "common_flow",
    "newton_steady",
]


class ModelError(ValueError):
    """A fabric model that cannot be used as declared (bad parameters, not affine, no steady state)."""


@dataclass(frozen=True)
class Parameter:
    """A model parameter: its name, bounds (inclusive) and the start of the fits' search."""

    name: str
    lower: float
    upper: float
    start: float

    def __post_init__(self):
        if not self.name.isidentifier():
            raise ModelError(f"parameter name {self.name!r} must be an identifier")
        if not (self.lower <= self.start <= self.upper):
            raise ModelError(
                f"parameter {self.name}: start {self.start} outside its bounds [{self.lower}, {self.upper}]"
            )


def check_parameters(parameters, params: Mapping[str, float], owner: str, error: type[Exception]) -> dict[str, float]:
    """``params`` as {name: float} with every one of ``parameters``, finite and within its bounds;
    otherwise ``error`` naming ``owner`` (e.g. "model gw")."""
    names = [p.name for p in parameters]
    if set(params) != set(names):
        raise error(f"{owner}: parameters {sorted(params)} given, expected {names}")
    checked = {}
    for p in parameters:
        value = float(params[p.name])
        if not (math.isfinite(value) and p.lower <= value <= p.upper):
            raise error(f"{owner}: {p.name} = {value} outside [{p.lower}, {p.upper}]")
        checked[p.name] = value
    return checked


class Flow(NamedTuple):
    """Normalised kinematics of a velocity gradient L (paper frame): Lh = L/gammadot, Eh = sym(Lh),
    Eh_e and Eh_c its parts with positive and negative eigenvalues (shapes (..., 3, 3))."""

    grad_hat: np.ndarray
    e_hat: np.ndarray
    e_ext: np.ndarray
    e_comp: np.ndarray


def flow_of(velocity_gradient) -> Flow:
    """[`Flow`][suspension_fabric.models.fabric_interface.Flow] of a velocity gradient (only its direction matters)."""
    grad_hat, e_hat, e_ext, e_comp, _ = split_strain_rate(velocity_gradient)
    return Flow(grad_hat, e_hat, e_ext, e_comp)


@dataclass(frozen=True)
class FabricModel:
    """A fabric model (see the module docstring). ``rhs(fabric, flow, params, phi)`` broadcasts over
    leading axes of ``fabric`` and of the flow's tensors; ``steady`` (optional) returns the closed
    steady fabric in simple shear L = e1 e2 from (params, phi); ``fit`` (optional) returns the
    parameters whose steady state matches ``targets`` ({component: value}) exactly; ``published``
    (optional) holds the parameters its source printed, for comparison with the fits.

    ``vector_form`` (optional) is ``rhs`` again, in the form the ODE solver calls about 10^5 times
    per fit: ``vector_form(flow, params, phi)`` returns the function v -> dv/dgamma on 6-vectors
    (..., 6) under that fixed flow, with whatever depends on the flow alone computed once (or None
    for a flow it does not handle, where ``rhs`` is used). It must equal ``rhs`` to rounding
    (tests/models/test_fabric_models.py checks the built-in ones)."""

    key: str
    label: str
    parameters: tuple[Parameter, ...]
    steady_targets: tuple[str, ...]
    rhs: Callable
    affine: bool = False
    steady: Callable | None = None
    fit: Callable | None = None
    description: str = field(default="", compare=False)
    published: Mapping[str, float] | None = field(default=None, compare=False)
    vector_form: Callable | None = field(default=None, compare=False)

    def __post_init__(self):
        if not self.key.isidentifier():
            raise ModelError(f"model key {self.key!r} must be an identifier (it names table columns)")
        names = [p.name for p in self.parameters]
        if not names or len(set(names)) != len(names):
            raise ModelError(f"model {self.key}: parameter names {names} must be distinct and at least one")
        if self.published is not None and set(self.published) != set(names):
            raise ModelError(f"model {self.key}: published parameters {sorted(self.published)} must be {names}")
        unknown = set(self.steady_targets) - set(VECTOR_ORDER)
        if unknown or len(self.steady_targets) != len(names):
            raise ModelError(
                f"model {self.key}: steady_targets {self.steady_targets} must be {len(names)} "
                f"fabric components among {VECTOR_ORDER} (one per parameter)"
            )

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def check(self, params: Mapping[str, float]) -> dict[str, float]:
        """``params`` as a {name: float} dict with every parameter, finite and within its bounds."""
        return check_parameters(self.parameters, params, f"model {self.key}", ModelError)


def common_flow(flow: Flow) -> Flow | None:
    """The flow as one (3, 3) flow if every entry of a batch is the same, else None."""
    grad = np.asarray(flow.grad_hat)
    if grad.ndim == 2:
        return flow
    flat = grad.reshape(-1, 3, 3)
    if np.all(flat == flat[0]):
        return Flow(*(np.asarray(t).reshape(-1, 3, 3)[0] for t in flow))
    return None


def newton_steady(fabric_model: FabricModel, params, phi, start) -> np.ndarray:
    """The steady fabric of a model in simple shear as the root of its right-hand side nearest
    ``start`` (Powell's hybrid method), accepted only if it attracts (every eigenvalue of the
    Jacobian, by central differences, has a negative real part); else
    [`ModelError`][suspension_fabric.models.fabric_interface.ModelError]."""
    flow = flow_of(simple_shear_gradient())

    def residual(v):
        return sym_to_vec(fabric_model.rhs(vec_to_sym(v), flow, params, phi))

    from scipy.optimize import root  # scipy where used: table-only jobs start without it

    solution = root(residual, sym_to_vec(np.asarray(start, dtype=float)), method="hybr", tol=1e-13)
    if not solution.success or np.abs(residual(solution.x)).max() > 1e-10:
        raise ModelError(f"model {fabric_model.key}: no steady state near the start at {params} ({solution.message})")
    step = 1e-6
    jacobian = np.stack(
        [(residual(solution.x + step * e) - residual(solution.x - step * e)) / (2 * step) for e in np.eye(6)], axis=1
    )
    if not np.all(np.linalg.eigvals(jacobian).real < 0.0):
        raise ModelError(f"model {fabric_model.key}: the steady state at {params} does not attract")
    return vec_to_sym(solution.x)
