"""The paper's shear-rotation claims decided per seed (docs/verdict_statistics.md).

Every seed is a replicate of the whole study ([`seed_replicate`][suspension_fabric.evaluation.claims.seed_replicate]):
its own steady state (<nn>_12^ss,s normalises its curves), its own model fits and its own model predictions. The
functionals of the curves ([`deficit`][suspension_fabric.evaluation.claims.deficit],
[`transverse_effect`][suspension_fabric.evaluation.claims.transverse_effect],
[`overshoot_excess`][suspension_fabric.evaluation.claims.overshoot_excess],
[`suspension_fabric.evaluation.model_benchmark.mean_square`][]) are computed per seed and angle
([`angle_statistics`][suspension_fabric.evaluation.claims.angle_statistics]); each claim (`CLAIMS`) turns them into a
decision statistic T per seed and angle whose sign is the claim, effect size included
([`claim_values`][suspension_fabric.evaluation.claims.claim_values]); a claim's T per seed is the mean over its angles
within the seed, and the seeds give the t-interval and the verdict
([`suspension_fabric.analysis.seed_statistics`][suspension_fabric.analysis.seed_statistics]).

The claims compare two fabric models ([`Compared`][suspension_fabric.evaluation.claims.Compared], the config's
``verdicts.models``): the *reference* (the paper's G-W) and the *challenger* (the paper's modified model). Tables name
the two by role (``D12_reference``, ``MSE12_challenger``, ...) and record which models filled them.

Choices ([`Choice`][suspension_fabric.evaluation.claims.Choice],
[`study_choices`][suspension_fabric.evaluation.claims.study_choices]): the models' state at the rotation ("own": their
own startup state, rotated; "simulated": the seed's simulated fabric at the rotation; "steady": their own steady state,
rotated), the strain window W, the fit ("steady": each model's steady components, <nn>_12 for G-W, <nn>_11 and <nn>_12
for the modified model, as in the paper; "startup": least squares on the seed's whole startup curve of the same
components; "paper": the parameters the models' source printed, beta 10.9 and (9.4, 42.4) for the paper's models, left
out when a compared model has none) and the baseline of the <nn>'_12 deficit ("steady": 1;
"continuation": the same seed's theta = 0 curve).

Tables are tidy: ``angle_statistics`` has one row per (seed, theta) with the quantities of the
simulation and of both models; ``claim_values`` one row per (claim, seed, theta) with T.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
import pandas as pd

from suspension_fabric.analysis import tables
from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.analysis.frames import rotation_about_gradient, simple_shear_gradient, to_basis
from suspension_fabric.analysis.seed_statistics import LEVEL, decide, seeds_needed, t_interval, variance_pseudo_values
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.evaluation.model_benchmark import mean_square
from suspension_fabric.models import fabric_models
from suspension_fabric.models.fabric_models import FabricModel

__all__ = [
    "Compared",
    "ROLES",
    "Choice",
    "study_choices",
    "Claim",
    "CLAIMS",
    "EFFECT",
    "seed_replicate",
    "SeedReplicate",
    "deficit",
    "transverse_effect",
    "overshoot_excess",
    "angle_statistics",
    "claim_values",
    "claim_angles",
    "range_interval",
    "claim_text",
    "claim_table",
    "per_angle_table",
    "range_edge_table",
    "study_claim_values",
    "choices_table",
]

#: The two models' roles in the claims, in the order of [`Compared`][suspension_fabric.evaluation.claims.Compared].
ROLES = ("reference", "challenger")
STATES = ("own", "simulated", "steady")
FITS = ("steady", "startup", "paper")
BASELINES = ("steady", "continuation")
#: Effect sizes, named before looking (docs/verdict_statistics.md, Sec. 3).
EFFECT = {"factor": 1.25, "mse_reduction": 0.2, "overshoot_share": 0.25, "overshoot_margin": 0.05}
_ANGLE_TOL = 1e-9
#: r12 must exceed its baseline by more than this to count as inside the overshoot window.
OVERSHOOT_FLOOR = 1e-9


class Compared(NamedTuple):
    """The two fabric models the claims compare (config ``verdicts.models``)."""

    reference: FabricModel
    challenger: FabricModel

    @classmethod
    def from_specs(cls, specs: dict[str, str]) -> Compared:
        """From {role: config entry} (the entries of models.fabric that verdicts.models names)."""
        return cls(*(fabric_models.load_model(specs[role]) for role in ROLES))

    @property
    def by_role(self) -> dict[str, FabricModel]:
        return dict(zip(ROLES, self))

    @property
    def labels(self) -> dict[str, str]:
        """{role: the model's label}, for the claims' texts."""
        return {role: model.label for role, model in self.by_role.items()}


# ----------------------------------------------------------------------------- choices
@dataclass(frozen=True)
class Choice:
    """One way of setting up the comparison; ``name`` labels its column."""

    name: str
    window: float
    state: str = "own"
    fit: str = "steady"
    baseline: str = "steady"

    def __post_init__(self):
        for key, allowed in (("state", STATES), ("fit", FITS), ("baseline", BASELINES)):
            if getattr(self, key) not in allowed:
                raise ValueError(f"Choice.{key} must be one of {allowed}, got {getattr(self, key)!r}")
        if not self.window > 0:
            raise ValueError(f"Choice.window must be positive, got {self.window}")


def study_choices(window: float, rotation_strain: float, published: bool = True) -> list[Choice]:
    """The primary choice, then one change at a time (docs/verdict_statistics.md, Sec. 6): the
    models' state (simulated, steady), the window (1; and 3 when the runs reach it), the fit on the
    startup curve or (``published``: both compared models have printed parameters) the printed
    parameters, the theta = 0 continuation baseline."""
    primary = Choice("primary", window)
    choices = [
        primary,
        replace(primary, name="state: simulated", state="simulated"),
        replace(primary, name="state: model steady", state="steady"),
    ]
    choices += [
        replace(primary, name=f"window {other:g}", window=other)
        for other in (1.0, 2.0, 3.0)
        if other != window and other <= rotation_strain + _ANGLE_TOL
    ]
    choices += [
        replace(primary, name="fit: startup curve", fit="startup"),
        *([replace(primary, name="fit: paper's values", fit="paper")] if published else []),
        replace(primary, name="baseline: theta = 0", baseline="continuation"),
    ]
    return choices


# ----------------------------------------------------------------------------- replicates
class SeedReplicate(NamedTuple):
    """One seed's curves after the rotation, normalised by its own <nn>_12^ss: ``sim`` and
    ``models[role]`` map "r12", "r23" to arrays (angles, strains); ``params[role]`` is the
    model's {name: value}."""

    seed: int
    n12_ss: float
    params: dict
    thetas: np.ndarray
    strain: np.ndarray
    sim: dict
    models: dict


def _fit(startup: pd.DataFrame, steady: pd.DataFrame, phi: float, fabric0, how: str, compared: Compared) -> dict:
    """Each compared model's parameters for one seed (``steady``: its steady-state table) under the
    fit choice, by role."""
    out = {}
    for role, fabric_model in compared.by_role.items():
        if how == "paper":
            if fabric_model.published is None:
                raise ValueError(f"model {fabric_model.key} has no published parameters for the fit choice 'paper'")
            out[role] = fabric_model.check(fabric_model.published)
            continue
        targets = {name[1:]: float(steady.loc[steady["quantity"] == name, "mean"].iloc[0]) for name in COMPONENTS}
        fitted = fabric_models.fit_steady(fabric_model, targets, phi)
        if how == "startup":
            strains = startup["strain"].to_numpy(dtype=float)
            observed = {c: startup[f"n{c}"].to_numpy(dtype=float) for c in fabric_model.steady_targets}
            fitted = fabric_models.fit_startup_curve(fabric_model, strains, observed, phi, fabric0, fitted)
        out[role] = fitted
    return out


def seed_replicate(
    startup: pd.DataFrame,
    rotation: pd.DataFrame,
    phi: float,
    steady_window,
    startup_strain: float,
    choice: Choice,
    compared: Compared,
) -> SeedReplicate:
    """One seed's simulated and the ``compared`` models' post-rotation curves under ``choice``.

    ``startup`` and ``rotation`` are that seed's rows of the startup and rotation run tables
    ([`suspension_fabric.analysis.tables`][suspension_fabric.analysis.tables]); every angle must share the post-rotation
    strains, which must reach ``choice.window`` (else ``ValueError`` naming the seed). Only strains up to the
    window are kept.
    """
    seeds = set(startup["seed"]) | set(rotation["seed"])
    if len(seeds) != 1:
        raise ValueError(f"seed_replicate needs one seed's rows, got seeds {sorted(seeds)}")
    seed = int(seeds.pop())
    startup = startup.sort_values("strain")
    steady = tables.steady_state(startup, *steady_window)
    n12_ss = float(steady.loc[steady["quantity"] == "n12", "mean"].iloc[0])
    fabric0 = fabric_tensors(startup.iloc[0])
    params = _fit(startup, steady, phi, fabric0, choice.fit, compared)

    thetas = np.array(sorted(rotation["theta"].unique()), dtype=float)
    curves, strain = {}, None
    for theta in thetas:
        rows = rotation[np.isclose(rotation["theta"], theta)].sort_values("strain")
        grid = rows["strain"].to_numpy(dtype=float)
        if strain is None:
            strain = grid
        elif len(grid) != len(strain) or not np.allclose(grid, strain, rtol=1e-9, atol=1e-9):
            raise ValueError(
                f"seed {seed}: the post-rotation strains at theta = {theta:g} differ from those at "
                f"theta = {thetas[0]:g}"
            )
        curves[theta] = rows
    if strain[-1] < choice.window - 1e-9:
        raise ValueError(
            f"seed {seed}: the rotation runs reach strain {strain[-1]:g}, below the window "
            f"{choice.window:g} of choice '{choice.name}'"
        )
    keep = strain <= choice.window + 1e-9
    strain = strain[keep]
    simulated = np.stack([fabric_tensors(curves[t])[keep] for t in thetas])  # (angles, strains, 3, 3)
    sim = {"r12": simulated[..., 0, 1] / n12_ss, "r23": simulated[..., 1, 2] / n12_ss}

    models = {}
    for role, fabric_model in compared.by_role.items():
        if choice.state == "own":
            predicted = fabric_models.shear_rotation(
                fabric_model, np.radians(thetas), strain, params[role], phi, startup_strain, fabric0
            )
        else:
            before = (
                simulated[:, 0]
                if choice.state == "simulated"
                else to_basis(
                    fabric_models.steady_state(fabric_model, params[role], phi),
                    rotation_about_gradient(np.radians(thetas)),
                )
            )
            predicted = fabric_models.integrate(
                fabric_model, before, simple_shear_gradient(), strain, params[role], phi
            )
        models[role] = {"r12": predicted[..., 0, 1] / n12_ss, "r23": predicted[..., 1, 2] / n12_ss}
    return SeedReplicate(seed, n12_ss, params, thetas, strain, sim, models)


# ----------------------------------------------------------------------------- functionals
def _integral(values, strain) -> np.ndarray:
    return np.trapezoid(values, strain, axis=-1)


def deficit(r12, strain, baseline=None) -> np.ndarray:
    """D12 = integral of (baseline - r12) over the strains (last axis); baseline 1 (steady) unless a
    curve (the theta = 0 continuation) is given."""
    r12 = np.asarray(r12, dtype=float)
    return _integral((1.0 if baseline is None else baseline) - r12, strain)


def transverse_effect(r23, strain, thetas_deg) -> np.ndarray:
    """E23 = sign(theta) x integral of r23 (angles on the axis before the strains)."""
    return np.sign(np.asarray(thetas_deg, dtype=float)) * _integral(r23, strain)


def overshoot_excess(r12, strain, inside, baseline=None) -> np.ndarray:
    """X12 = integral of (r12 - baseline) over the strains flagged ``inside`` (the modified model's
    overshoot window: where its own r12 exceeds its baseline); baseline 1 unless a curve is given."""
    difference = np.asarray(r12, dtype=float) - (1.0 if baseline is None else baseline)
    return _integral(np.where(inside, difference, 0.0), strain)


def angle_statistics(replicates: list[SeedReplicate], choice: Choice) -> pd.DataFrame:
    """Per (seed, theta): D12, E23, X12 of the simulation and both models (by role), the models'
    mean-square errors on r12 and r23, the challenger's overshoot max(r12) - 1, and the noise floors
    ``s2_12``, ``s2_23``: the between-seed variance (ddof 1) of the simulated curve averaged over
    the strains of (0, W], as each seed's jackknife pseudo-value
    ([`variance_pseudo_values`][suspension_fabric.analysis.seed_statistics.variance_pseudo_values]), so that
    their mean over seeds is the variance and an interval over seeds carries the floor's own error
    (0 for a single seed, whose interval is infinite anyway)."""
    strain, thetas = replicates[0].strain, replicates[0].thetas
    for rep in replicates[1:]:
        if len(rep.strain) != len(strain) or not np.allclose(rep.strain, strain) or not np.allclose(rep.thetas, thetas):
            raise ValueError(f"seed {rep.seed}: angles or strains differ from seed {replicates[0].seed}'s")
    zero = np.flatnonzero(np.abs(thetas) < _ANGLE_TOL)
    if choice.baseline == "continuation" and not len(zero):
        raise ValueError("the theta = 0 continuation baseline needs a theta = 0 run")
    after = strain > 0.0
    sim12 = np.stack([rep.sim["r12"] for rep in replicates])
    sim23 = np.stack([rep.sim["r23"] for rep in replicates])
    s2 = {c: variance_pseudo_values(x)[..., after].mean(axis=-1) for c, x in (("12", sim12), ("23", sim23))}

    def base(curve):
        return curve[zero[0]][None, :] if choice.baseline == "continuation" else None

    rows = []
    for index, rep in enumerate(replicates):
        curves = {"sim": rep.sim, **rep.models}
        window = rep.models["challenger"]["r12"]
        window_base = base(window)
        # a model at its own steady state (theta = 0, state "steady") has r12 = 1 to round-off: no window
        inside = window > (1.0 if window_base is None else window_base) + OVERSHOOT_FLOOR
        values = {"seed": rep.seed, "theta": thetas}
        for source, c in curves.items():
            values[f"D12_{source}"] = deficit(c["r12"], strain, base(c["r12"]))
            values[f"E23_{source}"] = transverse_effect(c["r23"], strain, thetas)
            values[f"X12_{source}"] = overshoot_excess(c["r12"], strain, inside, base(c["r12"]))
        for role in ROLES:
            for comp in ("12", "23"):
                values[f"MSE{comp}_{role}"] = mean_square(rep.models[role][f"r{comp}"], rep.sim[f"r{comp}"], strain)
        values["O12_challenger"] = window.max(axis=-1) - 1.0
        values["s2_12"], values["s2_23"] = s2["12"][index], s2["23"][index]
        values["n12_ss"] = rep.n12_ss
        rows.append(pd.DataFrame(values))
    return pd.concat(rows, ignore_index=True)


# ----------------------------------------------------------------------------- claims
class Claim(NamedTuple):
    """A claim of the paper: its angle range (|theta| in degrees, inclusive), whether angles
    where both models are exact by symmetry (0, 180) are left out, and T per seed and angle."""

    key: str
    text: str
    angles: tuple[float, float]
    skip_symmetric: bool
    statistic: str

    def values(self, stats: pd.DataFrame) -> np.ndarray:
        f, share, cut = EFFECT["factor"], 1.0 - EFFECT["mse_reduction"], EFFECT["mse_reduction"]
        s = stats
        formulas = {
            "C1": lambda: s["D12_reference"] - f * s["D12_sim"],
            "C2": lambda: s["E23_sim"] - f * s["E23_reference"],
            "C3": lambda: share * s["MSE12_reference"] - s["MSE12_challenger"] + cut * s["s2_12"],
            "C4": lambda: share * s["MSE23_reference"] - s["MSE23_challenger"] + cut * s["s2_23"],
            "C5": lambda: s["O12_challenger"] - EFFECT["overshoot_margin"],
            "C6": lambda: EFFECT["overshoot_share"] * s["X12_challenger"] - s["X12_sim"],
        }
        return formulas[self.statistic]().to_numpy(dtype=float)


#: The paper's claims; {reference} and {challenger} stand for the compared models' labels
#: (G-W and the modified model in the paper).
CLAIMS: tuple[Claim, ...] = (
    Claim(
        "C1",
        "{reference} overestimates the effect of a rotation on <nn>_12 for pi/4 <~ |theta| <~ 3pi/4",
        (45.0, 135.0),
        False,
        "C1",
    ),
    Claim(
        "C2",
        "{reference} underestimates the effect on <nn>_23 for pi/2 <~ |theta| <~ pi (recovers much faster)",
        (90.0, 180.0),
        True,
        "C2",
    ),
    Claim(
        "C3",
        "{challenger} significantly better than {reference} on <nn>'_12 at intermediate angles",
        (45.0, 135.0),
        False,
        "C3",
    ),
    Claim(
        "C4",
        "{challenger} significantly better than {reference} on <nn>'_23 at large angles",
        (90.0, 180.0),
        True,
        "C4",
    ),
    Claim(
        "C3'",
        "{challenger} significantly better than {reference} on <nn>'_12 over all angles",
        (0.0, 180.0),
        False,
        "C3",
    ),
    Claim(
        "C4'",
        "{challenger} significantly better than {reference} on <nn>'_23 over all angles",
        (0.0, 180.0),
        True,
        "C4",
    ),
    Claim("C5", "{challenger} overshoots <nn>_12 near pi/2", (75.0, 105.0), False, "C5"),
    Claim("C6", "... and the simulations do not", (75.0, 105.0), False, "C6"),
)
#: What T is, per statistic (for the tables; ref: the reference model, chal: the challenger).
DECISION_STATISTIC = {
    "C1": "D12(ref) - 1.25 D12(sim)",
    "C2": "E23(sim) - 1.25 E23(ref)",
    "C3": "0.8 (MSE12 ref - s2) - (MSE12 chal - s2)",
    "C4": "0.8 (MSE23 ref - s2) - (MSE23 chal - s2)",
    "C5": "max r12(chal) - 1 - 0.05",
    "C6": "0.25 X12(chal) - X12(sim)",
}
#: Role names of the claims' texts when no labels are given.
ROLE_TEXT = {"reference": "the reference model", "challenger": "the challenger model"}


def _symmetric(thetas) -> np.ndarray:
    a = np.abs(np.asarray(thetas, dtype=float))
    return (a < _ANGLE_TOL) | (np.abs(a - 180.0) < _ANGLE_TOL)


def claim_angles(claim: Claim, thetas) -> np.ndarray:
    """The simulated angles a claim averages over (sorted by |theta|)."""
    thetas = np.unique(np.asarray(thetas, dtype=float))
    a = np.abs(thetas)
    inside = (a >= claim.angles[0] - _ANGLE_TOL) & (a <= claim.angles[1] + _ANGLE_TOL)
    if claim.skip_symmetric:
        inside &= ~_symmetric(thetas)
    return thetas[inside]


def claim_values(stats: pd.DataFrame) -> pd.DataFrame:
    """T per (claim, seed, theta) for every claim and every angle (the range is applied later),
    angles where both models are exact by symmetry left out of the <nn>_23 claims."""
    blocks = []
    for claim in CLAIMS:
        rows = stats if not claim.skip_symmetric else stats[~_symmetric(stats["theta"])]
        blocks.append(
            pd.DataFrame(
                {
                    "claim": claim.key,
                    "seed": rows["seed"].to_numpy(),
                    "theta": rows["theta"].to_numpy(),
                    "T": claim.values(rows),
                }
            )
        )
    return pd.concat(blocks, ignore_index=True)


def _seed_by_angle(values: pd.DataFrame) -> dict[str, pd.DataFrame]:
    """T of every claim as a (seed x theta) table, keyed by claim."""
    wide = values.set_index(["claim", "seed", "theta"])["T"].unstack("theta")
    return {claim: rows.droplevel("claim").dropna(axis=1, how="all") for claim, rows in wide.groupby(level="claim")}


def range_interval(values: pd.DataFrame, claim: str, thetas, level: float = LEVEL, tables: dict | None = None):
    """t-interval over seeds of T averaged over ``thetas`` within each seed (None if no angle);
    ``tables`` is `_seed_by_angle` of ``values`` when the caller has it already."""
    table = (_seed_by_angle(values) if tables is None else tables).get(claim)
    if table is None:
        return None
    columns = table.columns.to_numpy(dtype=float)
    chosen = np.isclose(columns[:, None], np.asarray(thetas, dtype=float)[None, :]).any(axis=1)
    if not chosen.any():
        return None
    return t_interval(table.to_numpy()[:, chosen].mean(axis=1), level)


def _row(interval, **keys) -> dict:
    if interval is None:
        return {
            **keys,
            "mean": np.nan,
            "low": np.nan,
            "high": np.nan,
            "se": np.nan,
            "n_seeds": 0,
            "verdict": "no angle in range",
            "seeds_needed": np.nan,
        }
    verdict = decide(interval)
    return {
        **keys,
        "mean": interval.mean,
        "low": interval.low,
        "high": interval.high,
        "se": interval.se,
        "n_seeds": interval.n,
        "verdict": verdict,
        "seeds_needed": seeds_needed(interval) if verdict == "undecided" else np.nan,
    }


def _angle_text(thetas) -> str:
    return ", ".join(f"{t:g}" for t in thetas) if len(thetas) else "none"


def claim_text(claim: Claim, labels: dict[str, str] | None = None) -> str:
    """The claim's text with the compared models' ``labels`` ({role: label}; default the roles)."""
    return claim.text.format(**(labels or ROLE_TEXT))


def claim_table(values: pd.DataFrame, level: float = LEVEL, labels: dict[str, str] | None = None) -> pd.DataFrame:
    """One row per claim: its text (models named by ``labels``,
    [`claim_text`][suspension_fabric.evaluation.claims.claim_text]), angles, T's mean and interval over seeds, the
    verdict and, if undecided, the seeds that would decide it."""
    thetas, tables = values["theta"].unique(), _seed_by_angle(values)
    rows = []
    for claim in CLAIMS:
        inside = claim_angles(claim, thetas)
        rows.append(
            _row(
                range_interval(values, claim.key, inside, level, tables),
                claim=claim.key,
                text=claim_text(claim, labels),
                statistic=DECISION_STATISTIC[claim.statistic],
                angles=_angle_text(inside),
                level=level,
            )
        )
    return pd.DataFrame(rows)


def per_angle_table(values: pd.DataFrame, stats: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """T per claim and angle with its interval and verdict, with the seed means of the
    underlying quantities (simulation and models) for reading."""
    quantities = {
        "C1": ("D12", ("sim", *ROLES)),
        "C2": ("E23", ("sim", *ROLES)),
        "C3": ("MSE12", ROLES),
        "C4": ("MSE23", ROLES),
        "C5": ("O12", ("challenger",)),
        "C6": ("X12", ("sim", *ROLES)),
    }
    means = stats.groupby("theta").mean(numeric_only=True)
    tables = _seed_by_angle(values)
    rows = []
    for claim in CLAIMS:
        if claim.key.endswith("'"):
            continue  # the same T per angle as its ranged claim
        for theta in np.unique(values[values["claim"] == claim.key]["theta"]):
            row = _row(
                range_interval(values, claim.key, [theta], level, tables), claim=claim.key, theta=theta, level=level
            )
            quantity, sources = quantities[claim.statistic]
            row["quantity"] = quantity
            for source in sources:
                row[source] = means.loc[theta, f"{quantity}_{source}"]
            rows.append(row)
    return pd.DataFrame(rows)


def range_edge_table(values: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """Each ranged claim with its range moved by one simulated angle at either edge (inward or
    outward): does the verdict change?"""
    grid = np.unique(np.abs(values["theta"].to_numpy()))
    tables = _seed_by_angle(values)
    rows = []
    for claim in CLAIMS:
        if claim.angles == (0.0, 180.0):
            continue
        eligible = grid[~_symmetric(grid)] if claim.skip_symmetric else grid
        inside = np.abs(claim_angles(claim, grid))
        if not len(inside):
            continue
        lo, hi = np.flatnonzero(np.isin(eligible, inside))[[0, -1]]
        variants = {
            "as stated": (lo, hi),
            "low edge out": (lo - 1, hi),
            "low edge in": (lo + 1, hi),
            "high edge in": (lo, hi - 1),
            "high edge out": (lo, hi + 1),
        }
        for name, (a, b) in variants.items():
            if a < 0 or b >= len(eligible) or a > b:
                continue
            chosen = eligible[a : b + 1]
            thetas = values["theta"].unique()
            selected = thetas[np.isin(np.abs(thetas), chosen)]
            rows.append(
                _row(
                    range_interval(values, claim.key, selected, level, tables),
                    claim=claim.key,
                    edges=name,
                    angles=_angle_text(selected),
                    level=level,
                )
            )
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- studies
def study_claim_values(
    startup_runs: pd.DataFrame,
    rotation_runs: pd.DataFrame,
    phi: float,
    steady_window,
    startup_strain: float,
    choice: Choice,
    compared: Compared,
) -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame]:
    """A study's per-angle statistics, T values and the compared models' parameters per seed
    (columns ``<role>_<parameter>``) under ``choice``; the statistics and the parameters name the
    models (``reference``, ``challenger``: their keys; the statistics' ``<role>_label``: labels)."""
    seeds = sorted(set(startup_runs["seed"]))
    missing = sorted(set(seeds) ^ set(rotation_runs["seed"]))
    if missing:
        raise ValueError(f"seeds {missing} have startup or rotation runs but not both")
    replicates = [
        seed_replicate(
            startup_runs[startup_runs["seed"] == s],
            rotation_runs[rotation_runs["seed"] == s],
            phi,
            steady_window,
            startup_strain,
            choice,
            compared,
        )
        for s in seeds
    ]
    stats = angle_statistics(replicates, choice)
    keys = {role: model.key for role, model in compared.by_role.items()}
    labels = {f"{role}_label": label for role, label in compared.labels.items()}
    params = pd.DataFrame(
        [
            {
                "seed": r.seed,
                "n12_ss": r.n12_ss,
                **{f"{role}_{name}": value for role in ROLES for name, value in r.params[role].items()},
                **keys,
            }
            for r in replicates
        ]
    )
    return stats.assign(**keys, **labels), claim_values(stats), params


def choices_table(
    values_by_choice: dict[str, pd.DataFrame], level: float = LEVEL, labels: dict[str, str] | None = None
) -> pd.DataFrame:
    """Claims by rows, choices by columns (long format: one row per claim and choice) and a
    ``robust`` column per claim: the verdict if every choice gives it, else the choices that differ."""
    rows = []
    for choice, values in values_by_choice.items():
        for row in claim_table(values, level, labels).to_dict("records"):
            rows.append({"choice": choice, **row})
    table = pd.DataFrame(rows)
    robust = {}
    for claim, group in table.groupby("claim", sort=False):
        verdicts = group.set_index("choice")["verdict"]
        primary = verdicts.iloc[0]
        flips = [c for c, v in verdicts.items() if v != primary]
        robust[claim] = primary if not flips else f"{primary} (primary); differs under: {', '.join(flips)}"
    table["robust"] = table["claim"].map(robust)
    return table


def evaluate_study(
    startup_runs: pd.DataFrame,
    rotation_runs: pd.DataFrame,
    *,
    phi: float,
    steady_window,
    startup_strain: float,
    rotation_strain: float,
    window: float,
    compared: Compared,
) -> dict[str, pd.DataFrame]:
    """Every choice of [`study_choices`][suspension_fabric.evaluation.claims.study_choices] on one study: ``statistics``
    (per seed and angle), ``values`` (T per claim, seed and angle) and ``fits`` (per-seed parameters), each with a
    ``choice`` column. The theta = 0 baseline is left out when the study has no theta = 0 run,
    the published parameters when a compared model has none."""
    has_zero = bool(np.any(np.abs(rotation_runs["theta"].to_numpy(dtype=float)) < _ANGLE_TOL))
    published = all(model.published is not None for model in compared)
    out = {"statistics": [], "values": [], "fits": []}
    for choice in study_choices(window, rotation_strain, published):
        if choice.baseline == "continuation" and not has_zero:
            continue
        results = study_claim_values(startup_runs, rotation_runs, phi, steady_window, startup_strain, choice, compared)
        for key, table in zip(("statistics", "values", "fits"), results):
            out[key].append(table.assign(choice=choice.name))
    return {key: pd.concat(blocks, ignore_index=True) for key, blocks in out.items()}


def evaluate_dataset(folder, window: float, compared: Compared) -> pd.DataFrame:
    """T per claim, seed and angle of a reference dataset under the primary choices (its own phi,
    steady window and startup strain; ``window`` after the rotation), comparing ``compared``."""
    from suspension_fabric.study.dataset import read_fabric_runs  # the dataset module needs the simulation stack

    record, startup, rotation = read_fabric_runs(folder)
    config = record["config"]
    if config["run"]["rotation_strain"] < window - 1e-9:
        raise ValueError(
            f"the dataset {folder} runs {config['run']['rotation_strain']:g} strain after each rotation, "
            f"less than the window verdicts.window = {window:g}"
        )
    _, values, _ = study_claim_values(
        startup,
        rotation,
        config["particles"]["phi"],
        config["analysis"]["steady_window"],
        config["run"]["startup_strain"],
        Choice("primary", window),
        compared,
    )
    return values
