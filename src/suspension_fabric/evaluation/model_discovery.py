"""A fabric model found in the data: sparse regression of d<nn>/dgamma, terms chosen by held-out error.

The model is [`suspension_fabric.models.sparse_fabric`][suspension_fabric.models.sparse_fabric] (1): the co-rotational
derivative plus sum_k c_k Theta_k(X) over a library of frame-indifferent terms up to second order in X = <nn>.

Regression in weak form ([`weak_form_system`][suspension_fabric.evaluation.model_discovery.weak_form_system]):
derivatives of noisy curves are not taken. Over consecutive windows of `WINDOW_FRAMES` frames of every seed's curve (the
startup and each training rotation, the whole run; neighbouring windows share their end frame),
X(gamma_b) - X(gamma_a) - int (Wh.X - X.Wh) = sum_k c_k int Theta_k(X), the integrals by
Simpson's rule over the frames; all six components of every window and seed are the rows of one
least-squares problem.

Sparsity ([`stlsq`][suspension_fabric.evaluation.model_discovery.stlsq]): sequentially thresholded least squares
(Brunton, Proctor and Kutz, PNAS 113, 3932 (2016)) on columns scaled to unit rms: terms whose scaled coefficient falls
below a threshold times the largest are dropped and the rest refitted, until the support stops
changing. A grid of thresholds gives supports of decreasing size
([`candidate_supports`][suspension_fabric.evaluation.model_discovery.candidate_supports]).

Held-out choice ([`held_out_support_errors`][suspension_fabric.evaluation.model_discovery.held_out_support_errors]): the
angles are split into folds as in the model benchmark ([`suspension_fabric.evaluation.model_benchmark.angle_folds`][]);
for each support, the coefficients are refitted on the startup and the other folds and the held-out angles are
predicted from the model's own state (each seed's startup from that seed's fabric at strain 0,
then the rotation; a candidate that diverges from any seed's start is out), scored per seed as
the benchmark scores ([`seed_errors`][suspension_fabric.evaluation.model_benchmark.seed_errors]).
Of the supports whose held-out error summed over the six components is within one standard error
(over seeds) of the least, the one with the fewest terms is chosen; its coefficients are then
fitted on every angle, with a jackknife over seeds (leave one seed out, refit) for their errors.

Every fit is constrained to hold the seeds' mean steady fabric of the startup exactly (the
right-hand side vanishes there on 11, 22, 33 and 12,
[`steady_constraint`][suspension_fabric.evaluation.model_discovery.steady_constraint]; linear in the coefficients, so
the constrained least squares is exact,
[`constrained_least_squares`][suspension_fabric.evaluation.model_discovery.constrained_least_squares]).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.components import component_label
from suspension_fabric.analysis.frames import VECTOR_ORDER, simple_shear_gradient, sym_to_vec
from suspension_fabric.analysis.seed_statistics import LEVEL, jackknife, t_interval
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.models import fabric_models
from suspension_fabric.models.sparse_fabric import LIBRARY, ORDER, corotational, library_terms, sparse_model

from .model_benchmark import SeedCurves, angle_folds, model_curves, seed_errors
from .model_targets import overshoot_sentence, percent, steady_rows

__all__ = [
    "WINDOW_FRAMES",
    "THRESHOLDS",
    "run_curves",
    "weak_form_system",
    "stlsq",
    "candidate_supports",
    "held_out_support_errors",
    "discover",
    "STEADY_COMPONENTS",
    "steady_constraint",
    "constrained_least_squares",
    "held_out_support",
    "steady_table",
    "coefficient_table",
    "summary_markdown",
]

#: Frames per window of the weak form (0.08 strain at the datasets' 0.02 between frames; an odd
#: number, so that Simpson's rule applies).
WINDOW_FRAMES = 5
#: Thresholds of the sequentially thresholded least squares (fractions of the largest scaled
#: coefficient); each gives one support.
THRESHOLDS = tuple(np.geomspace(1e-4, 0.5, 40))

_FLOW = fabric_models.flow_of(simple_shear_gradient())


def run_curves(runs: pd.DataFrame) -> dict[tuple[int, float], tuple[np.ndarray, np.ndarray]]:
    """{(seed, theta): (strains, fabrics (S, 3, 3))} of a per-seed run table (startup_runs.csv or
    rotation_runs.csv), each sorted by strain."""
    curves = {}
    for (seed, theta), rows in runs.groupby(["seed", "theta"]):
        rows = rows.sort_values("strain")
        curves[(int(seed), float(theta))] = (rows["strain"].to_numpy(dtype=float), fabric_tensors(rows))
    return curves


def _window_integrals(values, strains, ends) -> np.ndarray:
    """Integral of ``values`` (S, ...) over each window [ends[i], ends[i+1]] (windows of equal
    length): composite Simpson where a window has an even number of equal steps (exact for
    cubics), else the trapezoidal rule."""
    length = ends[1] - ends[0]
    index = ends[:-1, None] + np.arange(length + 1)  # (W, frames)
    steps = np.diff(strains[index], axis=1)  # (W, length)
    trapezoid = 0.5 * (np.pad(steps, ((0, 0), (0, 1))) + np.pad(steps, ((0, 0), (1, 0))))
    simpson = np.ones(length + 1)
    simpson[1:-1:2], simpson[2:-1:2] = 4.0, 2.0
    uniform = np.all(np.abs(steps - steps[:, :1]) <= 1e-6 * np.abs(steps[:, :1]), axis=1) & (length % 2 == 0)
    weights = np.where(uniform[:, None], simpson[None, :] * steps[:, :1] / 3.0, trapezoid)
    return np.einsum("wf,wf...->w...", weights, values[index])


def weak_form_system(curves, names=None, window: int = WINDOW_FRAMES) -> tuple[np.ndarray, np.ndarray]:
    """(A, y) of the weak form over the curves [(strains, fabrics), ...]: one row per window and
    component, one column per library term (``names``, default all)."""
    names = list(LIBRARY) if names is None else list(names)
    rows_a, rows_y = [], []
    for strains, fabrics in curves:
        ends = np.arange(0, len(strains), window - 1)
        if len(ends) < 2:
            continue
        terms = sym_to_vec(library_terms(fabrics, _FLOW, names))  # (S, K, 6)
        spin = sym_to_vec(corotational(fabrics, _FLOW))  # (S, 6)
        change = np.diff(sym_to_vec(fabrics)[ends], axis=0) - _window_integrals(spin, strains, ends)
        rows_y.append(change.ravel())  # (windows * 6)
        rows_a.append(_window_integrals(terms, strains, ends).transpose(0, 2, 1).reshape(-1, len(names)))
    if not rows_y:
        raise ValueError(f"no curve has {window} frames: nothing to regress")
    return np.concatenate(rows_a), np.concatenate(rows_y)


def stlsq(A, y, threshold: float, max_iterations: int = 50) -> np.ndarray:
    """The support (bool mask) of sequentially thresholded least squares at ``threshold`` (a
    fraction of the largest coefficient of the unit-rms columns), solved on the normal equations."""
    scale = np.sqrt(np.mean(A**2, axis=0))
    scale = np.where(scale > 0, scale, 1.0)
    gram, moment = (A.T @ A) / np.outer(scale, scale), (A.T @ y) / scale
    support = np.ones(A.shape[1], dtype=bool)
    for _ in range(max_iterations):
        coefficients = np.zeros(A.shape[1])
        coefficients[support] = np.linalg.lstsq(gram[np.ix_(support, support)], moment[support], rcond=None)[0]
        coefficients = np.abs(coefficients)
        kept = coefficients >= threshold * coefficients.max()
        if np.array_equal(kept, support):
            break
        support = kept
    return support


def candidate_supports(A, y, thresholds=THRESHOLDS) -> list[np.ndarray]:
    """The distinct supports of [`stlsq`][suspension_fabric.evaluation.model_discovery.stlsq] over ``thresholds``,
    largest first."""
    found = {}
    for threshold in thresholds:
        support = stlsq(A, y, threshold)
        found.setdefault(tuple(support), support)
    return sorted(found.values(), key=lambda s: -int(s.sum()))


#: Components of the steady state the fitted model must hold exactly (13 and 23 vanish by symmetry).
STEADY_COMPONENTS = ("11", "22", "33", "12")


def steady_constraint(fabric, names=None) -> tuple[np.ndarray, np.ndarray]:
    """(C, d) with C c = d saying that the right-hand side of (1) vanishes at the steady fabric
    ``fabric`` in simple shear, on `STEADY_COMPONENTS` (linear in the coefficients c)."""
    names = list(LIBRARY) if names is None else list(names)
    index = [VECTOR_ORDER.index(c) for c in STEADY_COMPONENTS]
    terms = sym_to_vec(library_terms(fabric, _FLOW, names))[:, index]  # (K, 4)
    return terms.T, -sym_to_vec(corotational(fabric, _FLOW))[index]


def constrained_least_squares(A, y, support, constraint) -> np.ndarray:
    """Coefficients (0 outside ``support``) minimising |A c - y|^2 subject to C c = d, from the
    normal equations bordered by the constraint (Lagrange multipliers)."""
    C, d = constraint
    A, C = A[:, support], C[:, support]
    k, m = A.shape[1], C.shape[0]
    system = np.zeros((k + m, k + m))
    system[:k, :k], system[:k, k:], system[k:, :k] = A.T @ A, C.T, C
    solution = np.linalg.lstsq(system, np.concatenate([A.T @ y, d]), rcond=None)[0]
    coefficients = np.zeros(len(support))
    coefficients[support] = solution[:k]
    return coefficients


def _fitted(system, support, names) -> dict[str, float]:
    A, y, (C, d, _) = system
    coefficients = constrained_least_squares(A, y, support, (C, d))
    return {name: float(c) for name, c, kept in zip(names, coefficients, support) if kept}


def _training_system(startup, rotation, seeds, thetas, names, steady_window, blocks: dict):
    """(A, y, (C, d, X_ss)): the weak form over the seeds' startups and rotations at ``thetas``, and
    the constraint that the model holds the seeds' mean steady fabric X_ss over ``steady_window``.
    ``blocks`` keeps each curve's rows of the weak form, made once."""
    keys = [("startup", key) for key in startup if key[0] in seeds]
    low, high = steady_window
    steady = np.concatenate(
        [
            fabrics[(strains >= low - 1e-9) & (strains <= high + 1e-9)]
            for strains, fabrics in (startup[k] for _, k in keys)
        ]
    ).mean(axis=0)
    keys += [("rotation", key) for key in rotation if key[0] in seeds and np.any(np.isclose(key[1], thetas))]
    for kind, key in keys:
        if (kind, key) not in blocks:
            blocks[(kind, key)] = weak_form_system([(startup if kind == "startup" else rotation)[key]], names)
    A = np.concatenate([blocks[k][0] for k in keys])
    y = np.concatenate([blocks[k][1] for k in keys])
    return A, y, (*steady_constraint(steady, names), steady)


def _predicted(model, curves: SeedCurves, phi, startup_strain, thetas, params=None) -> tuple[np.ndarray, np.ndarray]:
    """Per seed and component the model's errors at ``thetas`` and its predictions there (seeds,
    angles, R, 3, 3), each seed predicted from its own fabric at strain 0 of its startup (a model
    that diverges from any seed's start scores inf); ``params`` default the found model's rate 1."""
    params = {"rate": 1.0} if params is None else params
    errors = np.empty((len(curves.seeds), 6))
    predicted = np.full((len(curves.seeds), len(thetas), len(curves.rotation_strains), 3, 3), np.nan)
    for i in range(len(curves.seeds)):
        own = curves._replace(fabric0=curves.startup[i, 0])
        try:
            _, rotation = model_curves(model, params, phi, own, startup_strain, thetas)
        except (fabric_models.ModelError, ValueError, np.linalg.LinAlgError, FloatingPointError):
            return np.full((len(curves.seeds), 6), np.inf), predicted
        if not np.all(np.isfinite(rotation)):
            return np.full((len(curves.seeds), 6), np.inf), predicted
        errors[i] = seed_errors(rotation, curves, thetas)[i]
        predicted[i] = rotation
    return errors, predicted


def held_out_support(
    startup,
    rotation,
    curves: SeedCurves,
    support,
    phi: float,
    startup_strain: float,
    folds: int,
    steady_window,
    names=None,
    blocks=None,
) -> tuple[np.ndarray, np.ndarray]:
    """One support's (a mask over ``names``, default the whole library) (seeds, 6) errors of every
    angle predicted by a fit on the startup and the other folds of angles (all seeds), and those
    predictions (seeds, angles, R, 3, 3); ``startup`` and ``rotation`` are
    [`run_curves`][suspension_fabric.evaluation.model_discovery.run_curves], ``blocks`` a cache of weak-form blocks
    shared between calls."""
    names = list(LIBRARY) if names is None else list(names)
    blocks = {} if blocks is None else blocks
    seeds = set(int(s) for s in curves.seeds)
    total = np.zeros((len(curves.seeds), 6))
    predicted = np.empty((len(curves.seeds), len(curves.thetas), len(curves.rotation_strains), 3, 3))
    for held in angle_folds(curves.thetas, folds):
        train = curves.thetas[~np.isin(curves.thetas, held)]
        system = _training_system(startup, rotation, seeds, train, names, steady_window, blocks)
        errors, fold = _predicted(sparse_model(_fitted(system, support, names)), curves, phi, startup_strain, held)
        total += errors * len(held)
        predicted[:, np.isin(curves.thetas, held)] = fold  # both in ascending order of angle
    return total / len(curves.thetas), predicted


def held_out_support_errors(
    startup,
    rotation,
    curves: SeedCurves,
    supports,
    phi: float,
    startup_strain: float,
    folds: int,
    steady_window,
    names=None,
) -> list[np.ndarray]:
    """Per support, [`held_out_support`][suspension_fabric.evaluation.model_discovery.held_out_support]'s (seeds, 6)
    errors."""
    blocks, common = {}, (phi, startup_strain, folds, steady_window, names)
    return [held_out_support(startup, rotation, curves, support, *common, blocks)[0] for support in supports]


def _one_standard_error_choice(table: pd.DataFrame) -> int:
    """Row of the fewest terms whose held-out error is within one standard error of the least
    (the one-standard-error rule: Hastie, Tibshirani and Friedman, The Elements of Statistical
    Learning, Sec. 7.10)."""
    errors = table["held_out_error"].to_numpy()
    best = int(np.argmin(errors))
    if not np.isfinite(errors[best]):
        raise ValueError("no candidate support of the sparse model could be integrated on the held-out angles")
    within = errors <= errors[best] + table["held_out_se"].iloc[best]
    return int(table.index[within][np.argmin(table["n_terms"].to_numpy()[within])])


def discover(
    startup_runs: pd.DataFrame,
    rotation_runs: pd.DataFrame,
    curves: SeedCurves,
    phi: float,
    startup_strain: float,
    folds: int,
    steady_window,
    level: float = LEVEL,
    max_order: int = 2,
) -> dict:
    """The sparse model of a study: every candidate support with its held-out error (mean over
    seeds of the six components' sum, with its t-interval), the chosen support's coefficients
    fitted on every angle with their seed jackknife errors, and its per-seed held-out errors
    (seeds, 6) and predictions (seeds, angles, R, 3, 3) for the comparison with other models.
    ``max_order``: the library's terms up to this order in <nn> only (1: models affine in <nn>, as G-W is)."""
    names = [name for name in LIBRARY if ORDER[name] <= max_order]
    startup, rotation = run_curves(startup_runs), run_curves(rotation_runs)
    seeds = [int(s) for s in curves.seeds]
    blocks = {}
    system = _training_system(startup, rotation, set(seeds), curves.thetas, names, steady_window, blocks)
    supports = candidate_supports(*system[:2])
    errors = held_out_support_errors(
        startup, rotation, curves, supports, phi, startup_strain, folds, steady_window, names
    )
    table = []
    for support, error in zip(supports, errors):
        total = t_interval(error.sum(axis=1), level) if np.all(np.isfinite(error)) else None
        table.append(
            {
                "n_terms": int(support.sum()),
                "terms": "; ".join(name for name, kept in zip(names, support) if kept),
                "max_order": max(ORDER[name] for name, kept in zip(names, support) if kept),
                "held_out_error": np.inf if total is None else total.mean,
                "held_out_se": np.inf if total is None else total.se,
                "held_out_low": np.inf if total is None else total.low,
                "held_out_high": np.inf if total is None else total.high,
            }
        )
    table = pd.DataFrame(table).assign(level=level)
    best = _one_standard_error_choice(table)
    support = supports[best]
    coefficients = _fitted(system, support, names)
    _, predicted = held_out_support(
        startup, rotation, curves, support, phi, startup_strain, folds, steady_window, names, blocks
    )

    def coefficient(subset, name):
        key = tuple(subset)
        if key not in cache:
            cache[key] = _fitted(
                _training_system(startup, rotation, set(subset), curves.thetas, names, steady_window, blocks),
                support,
                names,
            )
        return cache[key][name]

    cache = {}

    errors_jackknife = {name: jackknife(lambda s, name=name: coefficient(s, name), seeds)[1] for name in coefficients}
    return {
        "library": names,
        "steady_fabric": system[2][2],
        "window_frames": WINDOW_FRAMES,
        "folds": folds,
        "supports": table,
        "chosen": best,
        "coefficients": coefficients,
        "errors": errors_jackknife,
        "held_out": errors[best],
        "held_out_predicted": predicted,
    }


# ----------------------------------------------------------------------------- the target
def steady_table(model, curves: SeedCurves, targets: dict, phi: float) -> pd.DataFrame:
    """The model's steady fabric against the simulated steady components (fits.json's
    ``targets``), at the rate it was found with (1) and at the rate refitted on the steady
    <nn>_12 (as a new state point refits it): relative difference and whether it is within
    `STEADY_TOLERANCE`; NaN where the model,
    integrated from no contacts, reaches no steady state or no rate reproduces <nn>_12."""
    rates = {"as found": {"rate": 1.0}}
    try:
        rates["rate fitted on <nn>_12"] = fabric_models.fit_steady(model, {"12": targets["n12"]["mean"]}, phi)
    except fabric_models.ModelError as failure:
        print(f"no steady fit of the rate: {failure}")
        rates["rate fitted on <nn>_12"] = {"rate": np.nan}
    rows = []
    for fit, params in rates.items():
        try:
            steady = fabric_models.steady_state(model, params, phi)
        except fabric_models.ModelError as failure:  # from no contacts it reaches no steady state
            print(f"{fit}: {failure}")
            steady = np.full((3, 3), np.nan)
        rows += [{"fit": fit, "rate": params["rate"], **row} for row in steady_rows(steady, targets)]
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- tables


def coefficient_table(found: dict) -> pd.DataFrame:
    """The chosen terms with their order, coefficient and seed-jackknife error."""
    return pd.DataFrame(
        [
            {"term": name, "order": ORDER[name], "coefficient": value, "error": found["errors"][name]}
            for name, value in found["coefficients"].items()
        ]
    )


def _interval(mean, low, high) -> str:
    return f"{mean:.3g} [{low:.3g}, {high:.3g}]"


def summary_markdown(
    found: dict, target: pd.DataFrame, overshoot: dict, steady: pd.DataFrame, reference_label: str
) -> str:
    """The discovered model as Markdown: its equation's terms with errors, the held-out comparison
    with the reference model and the target, the overshoot after rotation
    ([`overshoot_table`][suspension_fabric.evaluation.model_targets.overshoot_table]), the steady state; every
    number from the tables."""
    level = int(round(100 * target["level"].iloc[0]))
    chosen = found["supports"].iloc[found["chosen"]]
    lines = [
        f"Terms chosen by held-out error: {int(chosen['n_terms'])} of {len(found['library'])} "
        f"(candidates {', '.join(str(n) for n in found['supports']['n_terms'])} terms; held-out error of the chosen "
        f"{chosen['held_out_error']:.3g}, the least {found['supports']['held_out_error'].min():.3g}, in units of "
        "(⟨nn⟩₁₂ˢˢ)² summed over the six components). Coefficients fitted on every angle, "
        "errors a jackknife over seeds:",
        "",
        "| term | order in X | coefficient |",
        "|---|---|---|",
    ]
    for name, value in found["coefficients"].items():
        lines.append(f"| {name} | {ORDER[name]} | {value:.4g} ± {found['errors'][name]:.2g} |")
    share = target["share"].iloc[0]
    lines += [
        "",
        f"Held out (each fold of angles predicted by a fit on the startup and the other folds; {reference_label} "
        f"fitted on the steady state), mean square error net of the seed-noise floor in units of (⟨nn⟩₁₂ˢˢ)², "
        f"mean over {len(found['held_out'])} seeds [{level}% t-interval]; target: at most {share:g} of "
        f"{reference_label}'s, decided when T = {share:g} (reference − floor) − (model − floor) "
        "has its interval above 0.",
        "",
        f"| component | sparse model | {reference_label} | difference | T | target |",
        "|---|---|---|---|---|---|",
    ]
    for _, row in target.iterrows():
        lines.append(
            f"| {component_label(row['component'])} | "
            f"{_interval(row['candidate_net'], row['candidate_low'], row['candidate_high'])} | "
            f"{_interval(row['reference_net'], row['reference_low'], row['reference_high'])} | "
            f"{_interval(row['difference'], row['difference_low'], row['difference_high'])} | "
            f"{_interval(row['target_statistic'], row['target_low'], row['target_high'])} | "
            f"{'met' if row['target_met'] else 'not met'} |"
        )
    lines += ["", overshoot_sentence(overshoot)]
    lines += [
        "",
        "| steady component | rate | model | simulation | relative difference | tolerance |",
        "|---|---|---|---|---|---|",
    ]
    for _, row in steady.iterrows():
        lines.append(
            f"| {component_label(row['component'])} | {row['rate']:.4g} ({row['fit'].replace('<nn>_12', '⟨nn⟩₁₂')}) | "
            f"{row['model']:.4g} | {row['simulated']:.4g} | {percent(row['relative_difference'])} | "
            f"{row['tolerance']:.0%} ({'within' if row['within'] else 'outside'}) |"
        )
    shear = target.set_index("component")
    met = [c for c in ("n12", "n23") if shear.loc[c, "target_met"]]
    lines += [
        "",
        "Reading, plainly: the target on ⟨nn⟩₁₂ and ⟨nn⟩₂₃ is "
        + (
            "met on both."
            if len(met) == 2
            else f"met on {', '.join(component_label(c) for c in met) or 'neither'}, not on both."
        )
        + " Steady state, "
        + "; ".join(
            f"{fit.replace('<nn>_12', '⟨nn⟩₁₂')}: "
            + (
                "every component within its tolerance"
                if rows["within"].all()
                else "not every component within its tolerance"
            )
            for fit, rows in steady.groupby("fit", sort=False)
        )
        + ".",
    ]
    return "\n".join(lines) + "\n"
