r"""Stress relations as plug-ins: the particle stress as a static function of the fabric.

A stress relation gives the particle stress $\sigma^p$ in simple shear $e_1e_2$ (paper frame of
the current shear), in units of the solvent viscosity $\eta_f$ times the shear rate
$\dot\gamma$, from the fabric $\langle nn\rangle$ as a hydrodynamic and a contact term,

$$
\frac{\sigma^p}{\eta_f\dot\gamma} = a_H\,H(\langle nn\rangle; q) + a_C\,C(\langle nn\rangle; q),
$$

with tensor forms $H$ and $C$ (``forms(fabric, q) -> (H, C)``, broadcasting over leading axes),
linear coefficients $a_H$, $a_C$ and optional shape parameters $q$
([`suspension_fabric.models.fabric_models.Parameter`][suspension_fabric.models.fabric_models.Parameter]). For any $q$,
$a_H$ and $a_C$ are fixed by the steady state of startup shear as for the paper's relation
([`suspension_fabric.evaluation.stress_model`][suspension_fabric.evaluation.stress_model]):
$a_H = \sigma^{\mathrm{lub}}_{12}/H_{12}(\langle nn\rangle^{\mathrm{ss}})$,
$a_C = \sigma^{\mathrm{con}}_{12}/C_{12}(\langle nn\rangle^{\mathrm{ss}})$
([`coefficients`][suspension_fabric.models.stress_relations.coefficients]). The total adds the solvent's 1 and the
Einstein $2.5\phi$ on $\sigma_{12}$, $\eta_r = 1 + 2.5\phi + \sigma^p_{12}/(\eta_f\dot\gamma)$
(docs/gw_stress_relation.md, section 2.5). Shape parameters are fitted on transients
([`suspension_fabric.evaluation.stress_benchmark`][suspension_fabric.evaluation.stress_benchmark]).

Built in (`BUILT_IN`), with $\hat{E}$ and $\hat{E}_c$ the normalised strain rate of simple
shear and its compressional part and $\langle nnnn\rangle$ the paper's closure:

- ``gw``: the Gillissen-Wilson relation,
  $H = \langle nnnn\rangle:\hat{E}$, $C = \langle nnnn\rangle:\hat{E}_c$; no shape parameter.
- ``gw_jamming``: the same with a contact coefficient that grows with the coordination $Z$ and
  diverges at a jamming coordination $Z_J$ (infinite for $Z \ge Z_J$):

    $$
    C = \frac{\langle nnnn\rangle:\hat{E}_c}{(1 - Z/Z_J)^2},
    \qquad Z = 2\operatorname{Tr}\langle nn\rangle.
    $$

    The form is this project's. Gillissen, Ness, Peterson, Wilson and Cates (Phys. Rev. Lett. 123,
    214504 (2019)) let the contact stress diverge at jamming through the microstructure; their
    exact expression could not be checked here, so this is not claimed to be theirs. $Z_J$ is
    fitted on the viscosity transients.

A user's relation is a [`StressRelation`][suspension_fabric.models.stress_relations.StressRelation] named in the config
(``models.stress``) as ``package.module:attribute`` or ``path/to/file.py:attribute``
([`load_relation`][suspension_fabric.models.stress_relations.load_relation]).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from suspension_fabric.analysis.constants import EINSTEIN_COEFFICIENT
from suspension_fabric.analysis.frames import simple_shear_gradient

from . import gillissen_wilson as model
from .fabric_models import Parameter, check_parameters
from .plugins import load_plugin, resolve_plugins

__all__ = [
    "RelationError",
    "StressRelation",
    "GW_RELATION",
    "GW_JAMMING",
    "BUILT_IN",
    "load_relation",
    "resolve_relations",
    "coefficients",
    "relation_stress",
    "stress_from_forms",
    "STRESS_QUANTITIES",
    "relation_terms",
]

#: What [`relation_stress`][suspension_fabric.models.stress_relations.relation_stress] returns per fabric, in units of
#: eta_f gammadot.
STRESS_QUANTITIES = (
    "eta_r",
    "N1",
    "N2",
    "Pi",
    "total_12",
    "total_23",
    "total_13",
    "contact_12",
    "contact_23",
    "lubrication_12",
    "lubrication_23",
)


class RelationError(ValueError):
    """A stress relation that cannot be used as declared."""


@dataclass(frozen=True)
class StressRelation:
    """A stress relation (module docstring): ``forms(fabric, params)`` returns (H, C) of shape
    ``fabric.shape`` for fabrics (..., 3, 3) and ``params`` {name: value} of its shape parameters."""

    key: str
    label: str
    forms: Callable
    parameters: tuple[Parameter, ...] = ()
    description: str = field(default="", compare=False)
    #: how messages name the two forms
    term_names: tuple[str, str] = ("H", "C")

    def __post_init__(self):
        if not self.key.isidentifier():
            raise RelationError(f"stress relation key {self.key!r} must be an identifier (it names table rows)")
        names = [p.name for p in self.parameters]
        if len(set(names)) != len(names) or {"a_H", "a_C"} & set(names):
            raise RelationError(
                f"stress relation {self.key}: shape parameter names {names} must be distinct "
                "and not a_H or a_C (the coefficients fitted on the steady state)"
            )

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.parameters)

    def check(self, params: Mapping[str, float]) -> dict[str, float]:
        """``params`` as {name: float} with every shape parameter, finite and within its bounds."""
        return check_parameters(self.parameters, params, f"stress relation {self.key}", RelationError)

    def start(self) -> dict[str, float]:
        return {p.name: p.start for p in self.parameters}


_E_HAT = model.split_strain_rate(simple_shear_gradient())


def relation_terms(fabric) -> tuple[np.ndarray, np.ndarray]:
    """(<nnnn>:E^, <nnnn>:E^_c) of simple shear e1 e2 for fabric(s) of shape (..., 3, 3)."""
    _, e_hat, _, e_comp, _ = _E_HAT
    fabric = np.asarray(fabric, dtype=float)
    return model.contract_closure(e_hat, fabric), model.contract_closure(e_comp, fabric)


def _gw_forms(fabric, params):
    return relation_terms(fabric)


def _jamming_forms(fabric, params):
    hydro, contact = relation_terms(fabric)
    z = 2.0 * np.trace(np.asarray(fabric, dtype=float), axis1=-2, axis2=-1)
    with np.errstate(divide="ignore"):
        growth = np.where(z < params["Z_J"], (1.0 - z / params["Z_J"]) ** -2.0, np.inf)
    return hydro, contact * growth[..., None, None]


GW_RELATION = StressRelation(
    key="gw",
    label="G-W stress relation",
    forms=_gw_forms,
    term_names=("<nnnn>:E^", "<nnnn>:E^_c"),
    description="sigma^p = a_H <nnnn>:E^ + a_C <nnnn>:E^_c (Gillissen and Wilson 2018)",
)
GW_JAMMING = StressRelation(
    key="gw_jamming",
    label="G-W, contact coefficient diverging at Z_J",
    forms=_jamming_forms,
    parameters=(Parameter("Z_J", 2.0, 12.0, 6.0),),
    description="sigma^p = a_H <nnnn>:E^ + a_C <nnnn>:E^_c / (1 - Z/Z_J)^2, Z = 2 Tr<nn> (this project's form)",
)

#: Built-in relations by key.
BUILT_IN = {r.key: r for r in (GW_RELATION, GW_JAMMING)}


def load_relation(spec: str) -> StressRelation:
    """A relation from its config entry: a built-in key, ``package.module:attribute`` or
    ``path/to/file.py:attribute`` (the attribute a
    [`StressRelation`][suspension_fabric.models.stress_relations.StressRelation])."""
    return load_plugin(spec, BUILT_IN, StressRelation, RelationError, "stress relation")


def resolve_relations(specs) -> dict[str, StressRelation]:
    """Relations of a config's list of entries, by key (keys must be distinct)."""
    return resolve_plugins(specs, load_relation, RelationError, "models.stress")


def coefficients(
    relation: StressRelation,
    steady_fabric,
    lubrication_12: float,
    contact_12: float,
    params: Mapping[str, float],
    lubrication_12_sem: float = np.nan,
    contact_12_sem: float = np.nan,
) -> dict[str, float]:
    """a_H and a_C that reproduce the steady lubrication and contact sigma_12 at the steady fabric,
    with the errors the targets' standard errors give them (a_H_err, a_C_err)."""
    hydro, contact = relation.forms(np.asarray(steady_fabric, dtype=float), relation.check(params))
    h12, c12 = float(hydro[0, 1]), float(contact[0, 1])
    if not (0.0 < h12 < math.inf and 0.0 < c12 < math.inf):
        raise RelationError(
            f"stress relation {relation.key} at {dict(params)}: the steady fabric gives "
            f"({relation.term_names[0]})_12 = {h12:.4g} and ({relation.term_names[1]})_12 = {c12:.4g}; both must "
            "be positive and finite"
        )
    return {
        "a_H": lubrication_12 / h12,
        "a_H_err": lubrication_12_sem / h12,
        "a_C": contact_12 / c12,
        "a_C_err": contact_12_sem / c12,
    }


def relation_stress(
    relation: StressRelation, fabric, coefficient: Mapping[str, float], params: Mapping[str, float], phi: float
) -> dict[str, np.ndarray]:
    """`STRESS_QUANTITIES` for fabrics (..., 3, 3), each of shape (...): eta_r (= total_12,
    with the solvent and Einstein terms), the normal stress differences, the particle pressure
    and the shear components of the total and of both terms."""
    hydro, contact = relation.forms(np.asarray(fabric, dtype=float), relation.check(params))
    return stress_from_forms(hydro, contact, coefficient, phi)


def stress_from_forms(hydro, contact, coefficient: Mapping[str, float], phi: float) -> dict[str, np.ndarray]:
    """[`relation_stress`][suspension_fabric.models.stress_relations.relation_stress] from the forms (H, C) themselves
    (..., 3, 3), e.g. the G-W forms <nnnn>:E^ and <nnnn>:E^_c of a measured <nnnn>."""
    lubrication, contacts = coefficient["a_H"] * hydro, coefficient["a_C"] * contact
    particle = lubrication + contacts
    eta = particle[..., 0, 1] + 1.0 + EINSTEIN_COEFFICIENT * phi
    return {
        "eta_r": eta,
        "N1": particle[..., 0, 0] - particle[..., 1, 1],
        "N2": particle[..., 1, 1] - particle[..., 2, 2],
        "Pi": -np.trace(particle, axis1=-2, axis2=-1) / 3.0,
        "total_12": eta,
        "total_23": particle[..., 1, 2],
        "total_13": particle[..., 0, 2],
        "contact_12": contacts[..., 0, 1],
        "contact_23": contacts[..., 1, 2],
        "lubrication_12": lubrication[..., 0, 1],
        "lubrication_23": lubrication[..., 1, 2],
    }
