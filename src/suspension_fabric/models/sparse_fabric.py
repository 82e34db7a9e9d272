r"""A fabric model found by sparse regression: $\mathrm{d}\langle nn\rangle/\mathrm{d}\gamma$ on a
library of frame-indifferent terms.

The right-hand side is the co-rotational derivative plus a linear combination of isotropic
tensor functions $\Theta_k$ of the fabric $X = \langle nn\rangle$ and the normalised strain rate's
extensional and compressional parts $\hat{E}_e$, $\hat{E}_c$
([`suspension_fabric.models.gillissen_wilson.split_strain_rate`][]):

$$
\frac{\mathrm{d}X}{\mathrm{d}\gamma} = \hat{W}\cdot X - X\cdot\hat{W} + r\sum_k c_k\,\Theta_k(X),
\qquad \hat{W} = \frac{\hat{L} - \hat{L}^{\mathsf{T}}}{2},
\tag{1}
$$

with $\hat{L} = L/\dot\gamma$ the normalised velocity gradient, coefficients $c_k$, a rate $r$ and
the library `LIBRARY` up to second order in $X$ (every term is symmetric and turns with the
flow, so (1) is frame indifferent; the co-rotational part is fixed at 1 for the same reason).
G-W with the paper's closure lies in the span of the terms of order <= 1. The coefficients $c_k$
come from a regression on simulated fabric curves in weak form
([`suspension_fabric.evaluation.model_discovery`][suspension_fabric.evaluation.model_discovery]; Messenger and Bortz, J.
Comput. Phys. 443, 110525 (2021), with the sequential thresholding of Brunton, Proctor and Kutz, PNAS 113, 3932
(2016)); the one parameter of the model, the rate $r$ (1 where it was fitted), is what a new state
point refits, on the steady $\langle nn\rangle_{12}$ as G-W refits $\beta$.
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from suspension_fabric.analysis.frames import SYMMETRIC_BASIS, map_matrix, sym_to_vec, vec_to_sym

from .fabric_interface import FabricModel, Flow, ModelError, Parameter, common_flow, newton_steady

__all__ = [
    "LIBRARY",
    "quadratic_form",
    "ORDER",
    "MODEL_FILE_FORMAT",
    "library_terms",
    "corotational",
    "sparse_model",
    "write_model_file",
    "read_model_file",
]

#: Format of a model file ([`write_model_file`][suspension_fabric.models.sparse_fabric.write_model_file]).
MODEL_FILE_FORMAT = 1


def _trace(x) -> np.ndarray:
    return np.trace(x, axis1=-2, axis2=-1)[..., None, None]


def _dot(a, b) -> np.ndarray:
    return np.einsum("...ij,...ij->...", a, b)[..., None, None]


def _sym(a, x) -> np.ndarray:
    return a @ x + x @ a


_I = np.eye(3)

#: The library: name -> Theta(X, flow), each broadcasting over leading axes of X.
LIBRARY: dict[str, Callable[[np.ndarray, Flow], np.ndarray]] = {
    # order 0: formation on the compressional axis, extensional drive, isotropic formation
    "Ec": lambda x, f: np.broadcast_to(f.e_comp, x.shape),
    "Ee": lambda x, f: np.broadcast_to(f.e_ext, x.shape),
    "tr(Ec) I": lambda x, f: np.broadcast_to(_trace(f.e_comp) * _I, x.shape),
    # order 1
    "X": lambda x, f: x,
    "tr(X) I": lambda x, f: _trace(x) * _I,
    "tr(X) Ec": lambda x, f: _trace(x) * f.e_comp,
    "tr(X) Ee": lambda x, f: _trace(x) * f.e_ext,
    "Ec.X + X.Ec": lambda x, f: _sym(f.e_comp, x),
    "Ee.X + X.Ee": lambda x, f: _sym(f.e_ext, x),
    "(Ec:X) I": lambda x, f: _dot(f.e_comp, x) * _I,
    "(Ee:X) I": lambda x, f: _dot(f.e_ext, x) * _I,
    # order 2
    "X.X": lambda x, f: x @ x,
    "tr(X) X": lambda x, f: _trace(x) * x,
    "(Ec:X) X": lambda x, f: _dot(f.e_comp, x) * x,
    "(Ee:X) X": lambda x, f: _dot(f.e_ext, x) * x,
    "X.Ec.X": lambda x, f: x @ f.e_comp @ x,
    "X.Ee.X": lambda x, f: x @ f.e_ext @ x,
    "(X:X) I": lambda x, f: _dot(x, x) * _I,
    "tr(X)^2 I": lambda x, f: _trace(x) ** 2 * _I,
    "tr(X) (Ec.X + X.Ec)": lambda x, f: _trace(x) * _sym(f.e_comp, x),
    "tr(X) (Ee.X + X.Ee)": lambda x, f: _trace(x) * _sym(f.e_ext, x),
    "tr(X) (Ec:X) I": lambda x, f: _trace(x) * _dot(f.e_comp, x) * _I,
    "tr(X) (Ee:X) I": lambda x, f: _trace(x) * _dot(f.e_ext, x) * _I,
}
#: Each term's order in X.
ORDER = {name: 0 if k < 3 else 1 if k < 11 else 2 for k, name in enumerate(LIBRARY)}


def corotational(fabric, flow: Flow) -> np.ndarray:
    """Wh.X - X.Wh: how the components of X change as the flow's vorticity turns it."""
    spin = 0.5 * (flow.grad_hat - np.swapaxes(flow.grad_hat, -1, -2))
    return spin @ fabric - fabric @ spin


def library_terms(fabric, flow: Flow, names=None) -> np.ndarray:
    """Theta_k(X) of the named terms (default all), stacked on a new axis -3: (..., K, 3, 3)."""
    fabric = np.asarray(fabric, dtype=float)
    names = list(LIBRARY) if names is None else list(names)
    return np.stack([np.broadcast_to(LIBRARY[name](fabric, flow), fabric.shape) for name in names], axis=-3)


def quadratic_form(function) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(b, M, T) with function(X) = b + M v + T(v, v) on 6-vectors v of X (T symmetric in its last
    two indices), for a function of symmetric tensors that is at most quadratic, as every
    combination of `LIBRARY` terms is: from its values at 0, +-e_j and e_j + e_k."""
    basis = np.eye(6)
    pairs = [(j, k) for j in range(6) for k in range(j + 1, 6)]
    points = np.concatenate([np.zeros((1, 6)), basis, -basis, [basis[j] + basis[k] for j, k in pairs]])
    values = sym_to_vec(function(vec_to_sym(points)))
    constant, plus, minus, mixed = values[0], values[1:7], values[7:13], values[13:]
    linear = ((plus - minus) / 2.0).T
    quadratic = np.zeros((6, 6, 6))
    for j in range(6):
        quadratic[:, j, j] = (plus[j] + minus[j]) / 2.0 - constant
    for (j, k), value in zip(pairs, mixed):
        quadratic[:, j, k] = quadratic[:, k, j] = (value - plus[j] - plus[k] + constant) / 2.0
    return constant, linear, quadratic


def sparse_model(
    coefficients: Mapping[str, float],
    key: str = "sparse",
    label: str = "sparse regression",
    steady_fabric=None,
) -> FabricModel:
    """The [`FabricModel`][suspension_fabric.models.fabric_interface.FabricModel] of (1) with the given
    {term: c_k} (terms of `LIBRARY`); its parameter is the rate r, fitted on the steady
    <nn>_12. ``steady_fabric``: the steady fabric the fit held at r = 1, from which the steady
    state at any r is found by Newton's method
    ([`newton_steady`][suspension_fabric.models.fabric_interface.newton_steady]; else by integration)."""
    unknown = set(coefficients) - set(LIBRARY)
    if unknown or not coefficients:
        raise ModelError(f"sparse model terms {sorted(unknown) or '(none)'}: expected terms of LIBRARY {list(LIBRARY)}")
    names = list(coefficients)
    values = np.array([float(coefficients[name]) for name in names])

    def combination(fabric, flow):
        return np.einsum("k,...kij->...ij", values, library_terms(fabric, flow, names))

    polynomials = {}

    def polynomial(single: Flow):
        key = single.grad_hat.tobytes()
        if key not in polynomials:
            polynomials.clear()
            polynomials[key] = quadratic_form(lambda x: combination(x, single))
        return polynomials[key]

    def rhs(fabric, flow, params, phi):
        fabric = np.asarray(fabric, dtype=float)
        single = common_flow(flow)
        if single is None:  # flows that differ across the batch: the terms themselves
            return corotational(fabric, flow) + params["rate"] * combination(fabric, flow)
        constant, linear, quadratic = polynomial(single)
        v = sym_to_vec(fabric)
        terms = constant + v @ linear.T + np.einsum("ijk,...j,...k->...i", quadratic, v, v)
        return corotational(fabric, single) + params["rate"] * vec_to_sym(terms)

    def vector_form(flow, params, phi):
        """rhs on 6-vectors, one polynomial: (W + r M) v + r (b + T(v, v)), W the corotation."""
        single = common_flow(flow)
        if single is None:
            return None
        constant, linear, quadratic = polynomial(single)
        rate = params["rate"]
        drift = np.ascontiguousarray((map_matrix(corotational(SYMMETRIC_BASIS, single)) + rate * linear).T)
        pairs = np.ascontiguousarray(rate * quadratic.reshape(6, 36).T)  # (v_j v_k) flattened -> components
        offset = rate * constant
        return lambda v: offset + v @ drift + (v[..., :, None] * v[..., None, :]).reshape(v.shape[:-1] + (36,)) @ pairs

    affine = all(ORDER[name] <= 1 for name in names)
    text = " + ".join(f"{value:+.4g} {name}" for name, value in zip(names, values))
    model = FabricModel(
        key=key,
        label=label,
        parameters=(Parameter("rate", 1e-3, 1e3, 1.0),),
        steady_targets=("12",),
        rhs=rhs,
        vector_form=vector_form,
        affine=affine,
        description=f"dX/dgamma = Wh.X - X.Wh + rate ({text})",
    )
    if steady_fabric is None or affine:
        return model
    anchor = np.asarray(steady_fabric, dtype=float)
    return dataclasses.replace(model, steady=lambda params, phi: newton_steady(model, params, phi, anchor))


def write_model_file(
    path, coefficients: Mapping[str, float], errors: Mapping[str, float], source: dict, steady_fabric=None
) -> Path:
    """A sparse model as a file a config names in ``models.fabric`` (``path/to/model.json``): its
    terms' coefficients and their errors, the steady fabric it holds (if any) and where they were
    fitted (``source``)."""
    record = {
        "format": MODEL_FILE_FORMAT,
        "kind": "sparse",
        "coefficients": {name: float(value) for name, value in coefficients.items()},
        "errors": {name: float(errors[name]) for name in coefficients},
        "steady_fabric": None if steady_fabric is None else np.asarray(steady_fabric, dtype=float).tolist(),
        "source": source,
    }
    path = Path(path)
    path.write_text(json.dumps(record, indent=1) + "\n")
    return path


def model_file_source(path) -> dict:
    """Where a model file's terms were chosen and fitted (its ``source``: study, seeds, ...)."""
    return json.loads(Path(path).read_text()).get("source") or {}


def read_model_file(path) -> FabricModel:
    """The model of a file of [`write_model_file`][suspension_fabric.models.sparse_fabric.write_model_file]; errors name
    the file."""
    path = Path(path)
    if not path.is_file():
        raise ModelError(f"model file {path} not found")
    try:
        record = json.loads(path.read_text())
    except json.JSONDecodeError as failure:
        raise ModelError(f"model file {path}: not JSON ({failure})") from failure
    if record.get("format") != MODEL_FILE_FORMAT or record.get("kind") != "sparse":
        raise ModelError(
            f"model file {path}: format {record.get('format')!r}, kind {record.get('kind')!r}; "
            f"expected format {MODEL_FILE_FORMAT}, kind 'sparse'"
        )
    try:
        return sparse_model(record["coefficients"], steady_fabric=record.get("steady_fabric"))
    except ModelError as failure:
        raise ModelError(f"model file {path}: {failure}") from failure
