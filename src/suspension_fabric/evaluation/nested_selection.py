"""The sparse model's held-out error by nested cross-validation, with seeds held out as well as angles.

The discovery ([`suspension_fabric.evaluation.model_discovery`][suspension_fabric.evaluation.model_discovery]) chooses
its terms by the error on folds of angles; that error is then a selection score, not an estimate of
how the chosen model predicts data it has not seen: the candidate supports were found on every angle,
the choice was made on the same folds, and every fold shares its seeds with the training. Here every
step that looks at data is repeated inside each outer fold:

- **outer folds**: the seeds split into groups (scikit-learn's ``GroupKFold``, the seed its own
  group) crossed with the folds of angles
  ([`angle_folds`][suspension_fabric.evaluation.model_benchmark.angle_folds]); an outer fold trains
  on the startups and the rotations at the other angles of the other seeds, and is scored on the
  rotations of its own seeds at its own angles, which no step of its fit saw;
- **inside each outer fold**: the candidate supports found by thresholded least squares on the
  training data only ([`candidate_supports`][suspension_fabric.evaluation.model_discovery.candidate_supports]),
  after the terms the training design cannot tell apart are dropped
  ([`independent_terms`][suspension_fabric.evaluation.nested_selection.independent_terms]); the support chosen by
  the one-standard-error rule on an inner cross-validation of the same kind (seed groups of the training seeds
  crossed with folds of the training angles); its coefficients refitted on the whole training data;
- **the same protocol for every model**: G-W, its rate fitted on the training seeds' steady
  <nn>_12 (as the paper fits it), and the search restricted to terms of order 1 in <nn> (the
  models affine in <nn>, as G-W is), each predicting the same outer test data.

Every seed is scored once per angle by a model that saw neither; the per-seed errors (mean over
the angles, in units of (<nn>_12^ss)^2) are the units of the intervals, and the comparison with G-W
is the target table of the model benchmark
([`target_table`][suspension_fabric.evaluation.model_targets.target_table]).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import scipy.linalg

from suspension_fabric.analysis.seed_statistics import LEVEL, t_interval
from suspension_fabric.models import fabric_models
from suspension_fabric.models.gillissen_wilson import fit_gw
from suspension_fabric.models.sparse_fabric import LIBRARY, ORDER, sparse_model

from .model_benchmark import SeedCurves, angle_folds
from .model_discovery import (
    _fitted,
    _one_standard_error_choice,
    _predicted,
    _training_system,
    candidate_supports,
    run_curves,
)

__all__ = [
    "SEED_GROUPS",
    "COLLINEAR_TOLERANCE",
    "seed_splits",
    "independent_terms",
    "design_conditioning",
    "nested_errors",
    "nested_comparison",
    "summary_markdown",
]

#: Groups the seeds are split into, in the outer and in the inner cross-validation.
SEED_GROUPS = 2
#: A term is dropped when its unit-rms column's distance from the span of the terms kept before it
#: (pivoted QR) is below this fraction of the largest: the design cannot tell it apart.
COLLINEAR_TOLERANCE = 1e-3


def seed_splits(seeds, groups: int = SEED_GROUPS) -> list[tuple[np.ndarray, np.ndarray]]:
    """(training seeds, test seeds) per split of ``seeds`` into ``groups`` groups (scikit-learn's
    GroupKFold, each seed its own group, so a seed is never on both sides)."""
    from sklearn.model_selection import GroupKFold

    seeds = np.asarray(seeds, dtype=int)
    if len(seeds) < groups:
        raise ValueError(f"{len(seeds)} seeds cannot be split into {groups} groups")
    splitter = GroupKFold(n_splits=groups)
    return [(seeds[train], seeds[test]) for train, test in splitter.split(seeds, groups=seeds)]


def _unit_columns(A) -> np.ndarray:
    scale = np.sqrt(np.mean(A**2, axis=0))
    return A / np.where(scale > 0, scale, 1.0)


def independent_terms(A, names, tolerance: float = COLLINEAR_TOLERANCE) -> list[str]:
    """The terms of ``names`` (columns of A) kept by QR with column pivoting on the unit-rms columns:
    a term whose residual after the ones kept before it is below ``tolerance`` times the largest is
    dropped (the design cannot tell it apart from a combination of the others)."""
    _, R, order = scipy.linalg.qr(_unit_columns(A), mode="economic", pivoting=True)
    diagonal = np.abs(np.diag(R))
    kept = order[diagonal > tolerance * diagonal[0]]
    return [names[k] for k in sorted(kept)]


def design_conditioning(A) -> float:
    """The 2-norm condition number of the design with unit-rms columns."""
    return float(np.linalg.cond(_unit_columns(A)))


def _curves_of(curves: SeedCurves, seeds) -> SeedCurves:
    keep = np.isin(curves.seeds, np.asarray(seeds, dtype=int))
    return curves._replace(seeds=curves.seeds[keep], startup=curves.startup[keep], rotation=curves.rotation[keep])


def _errors(model, params, curves: SeedCurves, phi, startup_strain, thetas) -> np.ndarray:
    """(seeds, 6) errors at ``thetas``, each seed from its own start (model_discovery's predictions)."""
    return _predicted(model, curves, phi, startup_strain, thetas, params)[0]


def _steady_n12(curves: SeedCurves, seeds, steady_window) -> float:
    low, high = steady_window
    inside = (curves.startup_strains >= low - 1e-9) & (curves.startup_strains <= high + 1e-9)
    return float(_curves_of(curves, seeds).startup[:, inside, 0, 1].mean())


def _system(startup, rotation, seeds, thetas, names, steady_window, cache: dict):
    """model_discovery's training system, its weak-form blocks cached per set of terms."""
    blocks = cache.setdefault(tuple(names), {})
    return _training_system(startup, rotation, set(int(s) for s in seeds), thetas, names, steady_window, blocks)


def _select(startup, rotation, curves, seeds, thetas, names, phi, startup_strain, steady_window, cache, inner_folds):
    """Inside one outer fold: the training design's independent terms, the candidate supports on it,
    and the one chosen by the one-standard-error rule over an inner seed x angle cross-validation.
    Returns (kept names, chosen support, candidates table, condition numbers before and after)."""
    system = _system(startup, rotation, seeds, thetas, names, steady_window, cache)
    kept = independent_terms(system[0], names)
    columns = [names.index(name) for name in kept]
    A, y = system[0][:, columns], system[1]
    supports = candidate_supports(A, y)
    per_seed = np.zeros((len(supports), len(seeds)))
    for inner_train, inner_test in seed_splits(seeds):
        test_curves = _curves_of(curves, inner_test)
        rows = np.isin(seeds, inner_test)
        for held in angle_folds(thetas, inner_folds):
            train_thetas = thetas[~np.isin(thetas, held)]
            inner = _system(startup, rotation, inner_train, train_thetas, kept, steady_window, cache)
            for k, support in enumerate(supports):
                model = sparse_model(_fitted(inner, support, kept))
                errors = _errors(model, {"rate": 1.0}, test_curves, phi, startup_strain, held)
                per_seed[k, rows] += errors.sum(axis=1) * len(held) / len(thetas)
    table = []
    for support, errors in zip(supports, per_seed):
        total = t_interval(errors) if np.all(np.isfinite(errors)) else None
        table.append(
            {
                "n_terms": int(support.sum()),
                "held_out_error": np.inf if total is None else total.mean,
                "held_out_se": np.inf if total is None else total.se,
            }
        )
    table = pd.DataFrame(table)
    chosen = supports[_one_standard_error_choice(table)]
    final = _system(startup, rotation, seeds, thetas, kept, steady_window, cache)
    conditions = (design_conditioning(system[0]), design_conditioning(A))
    return kept, chosen, final, conditions


def nested_errors(
    startup_runs: pd.DataFrame,
    rotation_runs: pd.DataFrame,
    curves: SeedCurves,
    phi: float,
    startup_strain: float,
    folds: int,
    steady_window,
    max_orders=(1, 2),
) -> tuple[dict[str, np.ndarray], pd.DataFrame]:
    """({model: (seeds, 6) errors}, per outer fold and search: the chosen terms and the design's
    condition numbers). Models: ``gw`` and ``sparse_order<k>`` for each of ``max_orders``; each
    seed's errors are the mean over every angle, each predicted by the outer fold that held out
    that seed and that angle (module docstring)."""
    startup, rotation = run_curves(startup_runs), run_curves(rotation_runs)
    thetas = curves.thetas
    keys = ["gw", *(f"sparse_order{k}" for k in max_orders)]
    errors = {key: np.zeros((len(curves.seeds), 6)) for key in keys}
    rows, cache = [], {}
    inner_folds = max(2, folds - 1)
    for fold, (train_seeds, test_seeds) in enumerate(seed_splits(curves.seeds)):
        test_curves = _curves_of(curves, test_seeds)
        test_rows = np.isin(curves.seeds, test_seeds)
        for held in angle_folds(thetas, folds):
            train_thetas = thetas[~np.isin(thetas, held)]
            weight = len(held) / len(thetas)
            beta = fit_gw(_steady_n12(curves, train_seeds, steady_window), phi)
            gw = _errors(fabric_models.GW, {"beta": beta}, test_curves, phi, startup_strain, held)
            errors["gw"][test_rows] += gw * weight
            for order in max_orders:
                names = [name for name in LIBRARY if ORDER[name] <= order]
                kept, support, final, conditions = _select(
                    startup, rotation, curves, train_seeds, train_thetas, names, phi, startup_strain,
                    steady_window, cache, inner_folds,
                )  # fmt: skip
                model = sparse_model(_fitted(final, support, kept))
                found = _errors(model, {"rate": 1.0}, test_curves, phi, startup_strain, held)
                errors[f"sparse_order{order}"][test_rows] += found * weight
                rows.append(
                    {
                        "seed_split": fold,
                        "test_seeds": " ".join(str(s) for s in test_seeds),
                        "held_angles": " ".join(f"{t:g}" for t in held),
                        "search": f"order <= {order}",
                        "library_terms": len(names),
                        "independent_terms": len(kept),
                        "condition_number_all": conditions[0],
                        "condition_number_kept": conditions[1],
                        "n_terms": int(support.sum()),
                        "terms": "; ".join(name for name, k in zip(kept, support) if k),
                        "gw_beta": beta,
                    }
                )
    return errors, pd.DataFrame(rows)


def nested_comparison(errors: dict[str, np.ndarray], curves: SeedCurves, level: float = LEVEL) -> pd.DataFrame:
    """Each searched model against G-W under the same nested protocol: the model benchmark's target
    table per component (held-out errors net of the noise floor, their paired difference, the
    target statistic), one block per model; a model that diverges from some held-out seed's start
    is scored on the other seeds, counts those seeds (``diverged_seeds``) and misses the target."""
    from .model_targets import target_table

    tables = []
    for key, values in errors.items():
        if key == "gw":
            continue
        diverged = int((~np.isfinite(values).all(axis=1)).sum())
        if diverged:  # a model that cannot be integrated from a seed's start has no finite score there
            keep = np.isfinite(values).all(axis=1) & np.isfinite(errors["gw"]).all(axis=1)
            if keep.sum() < 2:
                continue
            scored = curves._replace(
                seeds=curves.seeds[keep], startup=curves.startup[keep], rotation=curves.rotation[keep]
            )
            table = target_table(values[keep], errors["gw"][keep], scored, level)
            table["target_met"] = False  # a model that diverges on any held-out seed misses the target
        else:
            table = target_table(values, errors["gw"], curves, level)
        tables.append(table.assign(model=key, diverged_seeds=diverged))
    return pd.concat(tables, ignore_index=True) if tables else pd.DataFrame()


def summary_markdown(comparison: pd.DataFrame, folds: pd.DataFrame) -> str:
    """The nested comparison as Markdown: per search, the shear components' held-out errors against
    G-W's under the same protocol and the target, and the terms each outer fold chose; every number
    from the tables."""
    from suspension_fabric.analysis.components import component_label

    if comparison.empty:
        return "No nested cross-validation on this study: it needs at least four seeds.\n"
    level = int(round(100 * comparison["level"].iloc[0]))
    share = comparison["share"].iloc[0]
    n_folds = folds.groupby("search").size().iloc[0]
    lines = [
        f"Nested cross-validation, {n_folds} outer folds (the seeds in {folds['seed_split'].nunique()} groups "
        f"crossed with {folds['held_angles'].nunique()} folds of angles): each seed and angle predicted by a model "
        "whose terms, choice and coefficients saw neither; G-W fitted on the training seeds' steady ⟨nn⟩₁₂. "
        f"Mean square error net of the seed-noise floor in units of (⟨nn⟩₁₂ˢˢ)², mean over seeds [{level}% "
        f"t-interval]; target: at most {share:g} of G-W's, met when T = {share:g} (G-W − floor) − (model − floor) "
        "has its interval above 0.",
        "",
        "| search | component | model | G-W | difference | T | target |",
        "|---|---|---|---|---|---|---|",
    ]
    for _, row in comparison[comparison["component"].isin(["n12", "n23"])].iterrows():
        search = folds.loc[folds["search"].str.endswith(row["model"][-1]), "search"].iloc[0]
        diverged = int(row.get("diverged_seeds", 0))
        met = "met" if row["target_met"] else (f"not met (diverged on {diverged} seeds)" if diverged else "not met")
        lines.append(
            f"| {search} | {component_label(row['component'])} | "
            f"{_text(row['candidate_net'], row['candidate_low'], row['candidate_high'])} | "
            f"{_text(row['reference_net'], row['reference_low'], row['reference_high'])} | "
            f"{_text(row['difference'], row['difference_low'], row['difference_high'])} | "
            f"{_text(row['target_statistic'], row['target_low'], row['target_high'])} | {met} |"
        )
    lines += [
        "",
        "| search | terms in the library | kept (not collinear) | condition number, all → kept "
        "| terms chosen per outer fold |",
        "|---|---|---|---|---|",
    ]
    for search, rows in folds.groupby("search", sort=False):
        lines.append(
            f"| {search} | {rows['library_terms'].iloc[0]} | {rows['independent_terms'].min()}-"
            f"{rows['independent_terms'].max()} | {rows['condition_number_all'].median():.2g} → "
            f"{rows['condition_number_kept'].median():.2g} (median) | "
            f"{', '.join(str(n) for n in rows['n_terms'])} |"
        )
    return "\n".join(lines) + "\n"


def _text(mean, low, high) -> str:
    return f"{mean:.3g} [{low:.3g}, {high:.3g}]"
