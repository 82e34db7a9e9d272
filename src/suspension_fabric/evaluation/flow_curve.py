r"""Flow curves under critical-load friction: one row per campaign point (phi, mu, rate ratio) with its
steady stress, contacts and frictional fraction, and the onset stress of the Wyart-Cates form.

The critical load F_CL sets a rate and a stress scale (Mari, Seto, Morris and Denn, J. Rheol. 58,
1693, 2014): $\dot\gamma_0 = F_{CL} / (6\pi\eta_f a^2)$ and $\sigma_0 = F_{CL} / a^2$, $a$ the small
radius. A point runs at $\Gamma = \dot\gamma / \dot\gamma_0$ (config key
``forces.critical_load_rate``), so its shear stress in units of $\sigma_0$ is

$$
\frac{\sigma}{\sigma_0} = \frac{\eta_r \eta_f \dot\gamma\, a^2}{F_{CL}} = \frac{\eta_r \Gamma}{6\pi},
$$

with $\eta_r$ the relative viscosity (solvent and Einstein parts included, as everywhere in the
project). A point at controlled stress (``forces.critical_load_stress``: $\sigma/\sigma_0 = S$ held) has
its rate measured instead: the runs' clock is the strain, and the critical load follows the stress,
$F_{CL} = a^2\sigma/S$, so the physical rate at each step is
$\dot\gamma/\dot\gamma_0 = 6\pi\eta_f a^2/F_{CL}$ and its mean over time is $6\pi\eta_f a^2$ over the
mean of $F_{CL}$ over strain (a step of strain lasts a time proportional to $F_{CL}$). Its $\eta_r$,
the mean over strain, is then the viscosity of the mean rate, $6\pi S$ over that rate.

Per seed, every quantity is the mean over the startup frames in the steady window; the table gives
the mean over seeds with its t-interval (``level``), the seeds the independent units.

Onset stress. Wyart and Cates (Phys. Rev. Lett. 112, 098302, 2014) take the fraction of frictional
contacts as $f(\sigma) = \exp(-\sigma^*/\sigma)$. The simulation counts that fraction, so the form is
tested directly: $-\ln f = \sigma^*/\sigma$ is linear in $1/\sigma$ through the origin. Per seed,
$\sigma^*$ is the least-squares slope of $-\ln f$ against $\sigma_0/\sigma$ over that seed's points with
$0 < f < 1$ (``onset_stress``), and its t-interval over seeds is reported with the spread of the
per-point estimates $-\ln f \cdot \sigma/\sigma_0$ (equal for every point if the form holds). The fit
through the origin weights each point by $(\sigma_0/\sigma)^2$, so the lowest-stress point with $f > 0$
sets most of the slope. Beside it, with every point weighted alike, the per-seed geometric mean of the
per-point estimates (``sigma_star_equal_weights``), and the two's paired difference per seed
(``weighting_difference``, weighted alike minus the fit): 0 if the form holds.
``onset_differences`` compares the curves' $\sigma^*$ by Welch's interval.

Thickening exponent. Between neighbouring imposed values of one curve, per seed, the secant
$\beta = \Delta\ln\eta_r / \Delta\ln\sigma$ (``thickening_exponents``): 0 on a Newtonian plateau.
$\beta > 1$ is a rate that falls while the stress rises, the S-shaped curve of discontinuous
thickening. Under rate control $\beta = x/(x + r)$ with $x = \Delta\ln\eta_r$ and
$r = \Delta\ln\dot\gamma > 0$, below 1 whenever the stress rises, even across a jump: there it
only describes the steepness, and the test is the stress-controlled curve's.

Shape. Over the points of a curve inside a window of imposed values (``campaign.shape_window``), per
seed, with $y = \ln(\dot\gamma/\dot\gamma_0)$ and $x = \ln(\sigma/\sigma_0)$, the least-squares
slope $b$ of $y$ on $x$ and the quadratic coefficient $c$ of the least-squares quadratic
(``curve_shape``): linear statistics of the seed's points, so their t-intervals over seeds are exact
for normal seed errors. $b = 0$ is a vertical curve (a viscosity exponent $1 - b$ of 1), $b < 0$ a
turn-back on average, $c > 0$ a dip and recovery of the rate. For three points equally spaced by $h$
in $x$, $c = (y_0 - 2y_1 + y_2)/(2h^2)$.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import LEVEL, t_interval, welch_interval

__all__ = [
    "FLOW_CURVE_QUANTITIES",
    "DERIVED_QUANTITIES",
    "stress_over_sigma0",
    "measured_rate_ratio",
    "CONTROLS",
    "seed_steady_means",
    "per_seed_table",
    "flow_curve_table",
    "onset_stress",
    "onset_differences",
    "thickening_exponents",
    "SHAPE_STATISTICS",
    "SLOPE_EFFECT",
    "curve_shape",
    "WYART_CATES_PARAMETERS",
    "wyart_cates_viscosity",
    "frictionless_steady",
    "wyart_cates_fit",
]

#: Steady quantities of the flow curve (stress table columns)
FLOW_CURVE_QUANTITIES = ("eta_r", "N1", "N2", "Pi", "Z_touching", "Z_frictional")
#: Per seed beside them: the frictional fraction Z_frictional / Z_touching (of the window means),
#: sigma / sigma_0 and gammadot / gammadot_0 (one of the two imposed, the other measured)
DERIVED_QUANTITIES = ("frictional_fraction", "sigma", "rate_ratio")
#: What a point imposes: its shear rate (forces.critical_load_rate) or its shear stress
#: (forces.critical_load_stress); ``target`` is that imposed value
CONTROLS = ("rate", "stress")


def stress_over_sigma0(eta_r, rate_ratio: float):
    """sigma / sigma_0 = eta_r Gamma / (6 pi) (module docstring)."""
    if not rate_ratio > 0:
        raise ValueError(f"the rate ratio gammadot / gammadot_0 must be > 0, got {rate_ratio}")
    return np.asarray(eta_r, dtype=float) * rate_ratio / (6.0 * math.pi)


def measured_rate_ratio(critical_load, eta_f: float, d_small: float):
    """gammadot / gammadot_0 = 6 pi eta_f a^2 / F_CL at a shear rate of 1 (module docstring), a = d_small / 2,
    from the critical load's mean over strain (stress control)."""
    load = np.asarray(critical_load, dtype=float)
    if np.any(~(load > 0)):
        raise ValueError(f"a point at controlled stress needs the critical load its runs recorded (> 0), got {load}")
    return 6.0 * math.pi * eta_f * (0.5 * d_small) ** 2 / load


def seed_steady_means(runs: pd.DataFrame, window, quantities=FLOW_CURVE_QUANTITIES) -> pd.DataFrame:
    """Per seed (index) the mean of each quantity over the frames with strain in ``window``, and the
    frictional fraction of those means; a seed without a frame there is an error naming it."""
    low, high = window
    inside = runs[(runs["strain"] >= low - 1e-9) & (runs["strain"] <= high + 1e-9)]
    means = inside.groupby("seed")[list(quantities)].mean()
    missing = sorted(set(runs["seed"]) - set(means.index))
    if missing:
        raise ValueError(f"seeds {missing} have no frame in the steady window {list(window)}")
    if {"Z_touching", "Z_frictional"} <= set(means.columns):
        means["frictional_fraction"] = means["Z_frictional"] / means["Z_touching"]
    return means


def per_seed_table(points: dict[str, dict], window) -> pd.DataFrame:
    """One row per point and seed: ``points`` maps a point name to {"phi", "mu", "rate_ratio",
    "stress_ratio", "eta_f", "d_small", "runs"}, one of the two ratios given (the other None), ``runs``
    its startup stress table over seeds. Columns: point, phi, mu, control ("rate" or "stress"), target
    (the imposed ratio), seed, the steady means of ``FLOW_CURVE_QUANTITIES`` and ``DERIVED_QUANTITIES``."""
    frames = []
    for name, point in points.items():
        quantities = FLOW_CURVE_QUANTITIES
        stress_ratio = point.get("stress_ratio")
        if stress_ratio is not None:
            quantities = (*FLOW_CURVE_QUANTITIES, "critical_load")
        means = seed_steady_means(point["runs"], window, quantities).reset_index()
        if stress_ratio is None:
            control, target = "rate", point["rate_ratio"]
            means["rate_ratio"] = target
            means["sigma"] = stress_over_sigma0(means["eta_r"], target)
        else:
            control, target = "stress", stress_ratio
            means["rate_ratio"] = measured_rate_ratio(means["critical_load"], point["eta_f"], point["d_small"])
            means["sigma"] = float(stress_ratio)
        frames.append(means.assign(point=name, phi=point["phi"], mu=point["mu"], control=control, target=target))
    table = pd.concat(frames, ignore_index=True)
    return table[["point", "phi", "mu", "control", "target", "seed", *FLOW_CURVE_QUANTITIES, *DERIVED_QUANTITIES]]


def flow_curve_table(per_seed: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """One row per point of ``per_seed`` (`per_seed_table`): point, phi, mu, control, target, n_seeds,
    and for each of ``FLOW_CURVE_QUANTITIES`` and ``DERIVED_QUANTITIES`` its mean over seeds, ``_low`` and
    ``_high`` (t-interval at ``level``; NaN for a quantity no seed recorded; the imposed one's interval has
    zero width). Sorted by phi, mu, control and target."""
    rows = []
    for (name, phi, mu, control, target), seeds in per_seed.groupby(
        ["point", "phi", "mu", "control", "target"], sort=False
    ):
        row = {"point": name, "phi": phi, "mu": mu, "control": control, "target": target, "n_seeds": len(seeds)}
        for quantity in (*FLOW_CURVE_QUANTITIES, *DERIVED_QUANTITIES):
            values = seeds[quantity].to_numpy(dtype=float)
            if np.isnan(values).all():
                row.update({quantity: np.nan, f"{quantity}_low": np.nan, f"{quantity}_high": np.nan})
                continue
            interval = t_interval(values, level)
            row.update({quantity: interval.mean, f"{quantity}_low": interval.low, f"{quantity}_high": interval.high})
        rows.append(row)
    return pd.DataFrame(rows).sort_values(["phi", "mu", "control", "target"]).reset_index(drop=True)


def onset_stress(per_seed: pd.DataFrame, level: float = LEVEL) -> dict:
    """sigma* / sigma_0 of f = exp(-sigma*/sigma) (module docstring) from the `per_seed_table` rows of
    one flow curve (one per seed and point): the per-seed slopes'
    t-interval, that of the per-seed geometric means of the per-point estimates (every point weighted
    alike) and that of their paired difference from the slopes, how many points per seed had 0 < f < 1,
    and the smallest and largest per-point
    estimate -ln f sigma / sigma_0 (over seeds and points). NaN where a seed has no such point."""
    slopes, equal_weights, estimates, used = [], [], [], []
    for _, seed_rows in per_seed.groupby("seed"):
        fraction = seed_rows["frictional_fraction"].to_numpy(dtype=float)
        sigma = seed_rows["sigma"].to_numpy(dtype=float)
        usable = (fraction > 0) & (fraction < 1)
        used.append(int(usable.sum()))
        if not usable.any():
            slopes.append(np.nan)
            equal_weights.append(np.nan)
            continue
        x, y = 1.0 / sigma[usable], -np.log(fraction[usable])
        slopes.append(float(x @ y / (x @ x)))
        equal_weights.append(float(np.exp(np.mean(np.log(y * sigma[usable])))))
        estimates.extend(y * sigma[usable])
    slopes = np.asarray(slopes)
    if np.isnan(slopes).any() or len(slopes) < 2:
        return {"sigma_star": np.nan, "low": np.nan, "high": np.nan, "points_per_seed": used}
    interval = t_interval(slopes, level)
    equal = t_interval(np.asarray(equal_weights), level)
    weighting = t_interval(np.asarray(equal_weights) - slopes, level)  # paired: the same seeds
    return {
        "sigma_star": interval.mean,
        "low": interval.low,
        "high": interval.high,
        "sigma_star_equal_weights": equal.mean,
        "equal_weights_low": equal.low,
        "equal_weights_high": equal.high,
        "weighting_difference": weighting.mean,
        "weighting_difference_low": weighting.low,
        "weighting_difference_high": weighting.high,
        "points_per_seed": used,
        "estimate_min": float(np.min(estimates)),
        "estimate_max": float(np.max(estimates)),
        "per_seed": [float(slope) for slope in slopes],
    }


def onset_differences(onsets: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """sigma* of each curve minus that of the curve of the next lower phi (same mu and control), with
    Welch's interval over the two curves' per-seed slopes (``onsets`` rows with phi, mu, control and
    `onset_stress`'s ``per_seed``; curves without an onset are skipped)."""
    rows = []
    for (mu, control), curves in onsets.groupby(["mu", "control"]):
        curves = curves[curves["per_seed"].map(lambda seeds: isinstance(seeds, list) and len(seeds) >= 2)]
        curves = curves.sort_values("phi")
        for (_, lower), (_, higher) in zip(curves.iloc[:-1].iterrows(), curves.iloc[1:].iterrows()):
            interval = welch_interval(higher["per_seed"], lower["per_seed"], level)
            rows.append({"mu": mu, "control": control, "phi_low": lower["phi"], "phi_high": higher["phi"],
                         "difference": interval.mean, "low": interval.low, "high": interval.high})  # fmt: skip
    columns = ["mu", "control", "phi_low", "phi_high", "difference", "low", "high"]
    return pd.DataFrame(rows, columns=columns)


def thickening_exponents(per_seed: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """The secant exponent d ln eta_r / d ln sigma between neighbouring imposed values (rates or
    stresses) of each curve (module docstring), per seed, from the `per_seed_table` rows: one row per
    (phi, mu, control, target_low, target_high) with the mean over the seeds both points share, its
    t-interval at ``level`` and n_seeds."""
    rows = []
    for (phi, mu, control), curve in per_seed.groupby(["phi", "mu", "control"]):
        targets = sorted(curve["target"].unique())
        by_target = {target: curve[curve["target"] == target].set_index("seed") for target in targets}
        for low_target, high_target in zip(targets, targets[1:]):
            low, high = by_target[low_target], by_target[high_target]
            seeds = low.index.intersection(high.index)
            exponents = (np.log(high.loc[seeds, "eta_r"]) - np.log(low.loc[seeds, "eta_r"])) / (
                np.log(high.loc[seeds, "sigma"]) - np.log(low.loc[seeds, "sigma"])
            )
            row = {"phi": phi, "mu": mu, "control": control, "target_low": low_target, "target_high": high_target}
            row["n_seeds"] = len(seeds)
            if len(seeds) >= 2:
                interval = t_interval(exponents.to_numpy(dtype=float), level)
                row.update({"exponent": interval.mean, "low": interval.low, "high": interval.high})
            else:
                row.update({"exponent": np.nan, "low": np.nan, "high": np.nan})
            rows.append(row)
    columns = ["phi", "mu", "control", "target_low", "target_high", "exponent", "low", "high", "n_seeds"]
    return pd.DataFrame(rows, columns=columns)


#: Statistics of ``curve_shape``: the slope and the quadratic coefficient of ln rate in ln sigma
SHAPE_STATISTICS = ("slope", "curvature")
#: The slope's effect size, named before the fresh packings of docs/thickening.md ran: |b| = 0.1, a
#: viscosity exponent of 0.9 or 1.1; a slope interval inside (-0.1, 0.1) reads as vertical within it
SLOPE_EFFECT = 0.1
SHAPE_COLUMNS = ["phi", "mu", "control", "statistic", "targets", "value", "low", "high", "n_seeds", "per_seed"]


def curve_shape(per_seed: pd.DataFrame, window, level: float = LEVEL) -> pd.DataFrame:
    """The shape of each curve of ``per_seed`` (`per_seed_table`) over its imposed values inside
    ``window`` ([low, high]; module docstring): per seed with every one of those points, the slope and
    the quadratic coefficient of ln rate_ratio in ln sigma; one row per (phi, mu, control, statistic)
    with the mean over seeds, its t-interval at ``level``, n_seeds, the targets used ("0.05 0.1 0.2")
    and the per-seed values ("seed=value; ..."). Empty (with its columns) when ``window`` is None."""
    rows = []
    if window is not None:
        low, high = window
        for (phi, mu, control), curve in per_seed.groupby(["phi", "mu", "control"]):
            inside = curve[(curve["target"] >= low - 1e-12) & (curve["target"] <= high + 1e-12)]
            targets = sorted(inside["target"].unique())
            if len(targets) < 3:
                raise ValueError(
                    f"the curve at phi = {phi:g}, mu = {mu:g} has {len(targets)} point(s) in the shape window "
                    f"{list(window)}; its slope and curvature need 3 or more"
                )
            values = {statistic: {} for statistic in SHAPE_STATISTICS}
            for seed, rows_of_seed in inside.groupby("seed"):
                if len(rows_of_seed) != len(targets):
                    continue  # a seed missing a point would change what the statistic measures
                x = np.log(rows_of_seed["sigma"].to_numpy(dtype=float))
                y = np.log(rows_of_seed["rate_ratio"].to_numpy(dtype=float))
                values["slope"][seed] = float(np.polyfit(x, y, 1)[0])
                values["curvature"][seed] = float(np.polyfit(x, y, 2)[0])
            for statistic, by_seed in values.items():
                row = {"phi": phi, "mu": mu, "control": control, "statistic": statistic}
                row["targets"] = " ".join(f"{target:g}" for target in targets)
                row["n_seeds"] = len(by_seed)
                row["per_seed"] = "; ".join(f"{seed}={value:.4f}" for seed, value in sorted(by_seed.items()))
                if len(by_seed) >= 2:
                    interval = t_interval(np.fromiter(by_seed.values(), dtype=float), level)
                    row.update({"value": interval.mean, "low": interval.low, "high": interval.high})
                else:
                    row.update({"value": np.nan, "low": np.nan, "high": np.nan})
                rows.append(row)
    return pd.DataFrame(rows, columns=SHAPE_COLUMNS)


#: Parameters of the Wyart-Cates viscosity (``wyart_cates_fit``)
WYART_CATES_PARAMETERS = ("A", "phi_J0", "phi_Jmu")


def wyart_cates_viscosity(phi, fraction, A: float, phi_J0: float, phi_Jmu: float):
    """eta = A (1 - phi / phi_J(f))^-2 with phi_J(f) = f phi_Jmu + (1 - f) phi_J0 (Wyart and Cates 2014)."""
    jamming = np.asarray(fraction, dtype=float) * phi_Jmu + (1.0 - np.asarray(fraction, dtype=float)) * phi_J0
    return A * (1.0 - np.asarray(phi, dtype=float) / jamming) ** -2


def frictionless_steady(loaded: dict) -> pd.DataFrame:
    """Each seed's steady eta_r of rate-independent frictionless datasets (mu = 0: every contact
    frictionless, the f = 0 limit of a flow curve), from {name: (phi, steady_window, startup stress
    table)}: columns point, phi, seed, eta_r, frictional_fraction (0)."""
    frames = []
    for name, (phi, window, runs) in loaded.items():
        means = seed_steady_means(runs, window, ("eta_r",)).reset_index()
        frames.append(means.assign(point=name, phi=float(phi), frictional_fraction=0.0))
    columns = ["point", "phi", "seed", "eta_r", "frictional_fraction"]
    return pd.concat(frames, ignore_index=True)[columns] if frames else pd.DataFrame(columns=columns)


def wyart_cates_fit(
    per_seed: pd.DataFrame, level: float = LEVEL, frictionless: pd.DataFrame | None = None
) -> pd.DataFrame:
    r"""The Wyart-Cates viscosity fitted per seed to every point of every flow curve of one friction
    coefficient, at the frictional fraction the simulation measured there: least squares on
    $\ln\eta_r$ over the points (each seed's points of all volume fractions), for A, phi_J0 (the
    frictionless jamming fraction) and phi_Jmu (the frictional one), both above the densest phi.
    ``frictionless`` (`frictionless_steady`): points at f = 0 of other volume fractions, joined to the
    same seed's points of every friction coefficient; one at a volume fraction of the curves is left
    out (the same packing as the curves' own low rates). Needs two volume fractions at least (else A
    and the jamming fractions are one combination). One row per (mu, parameter): the t-interval over
    seeds of the per-seed values (seed noise only: the form's misfit, common to every seed, is not in
    it), and per mu the rms residual of ln eta_r (``parameter`` "rms_log_residual")."""
    from scipy.optimize import least_squares

    rows = []
    for mu, curves in per_seed.groupby("mu"):
        if frictionless is not None and not frictionless.empty:
            missing = sorted(set(curves["seed"]) - set(frictionless["seed"]))
            if missing:
                raise ValueError(f"the frictionless points have no seed {missing} of the flow curves")
            # a frictionless point at a volume fraction of the curves has their packings (same seed and
            # phi): the curves' own low rates are that measurement already
            joined = frictionless["seed"].isin(set(curves["seed"])) & ~frictionless["phi"].isin(set(curves["phi"]))
            curves = pd.concat([curves, frictionless[joined]], ignore_index=True)
        if curves["phi"].nunique() < 2:
            continue
        densest = float(curves["phi"].max())
        fitted = {name: [] for name in (*WYART_CATES_PARAMETERS, "rms_log_residual")}
        for _, points in curves.groupby("seed"):
            phi = points["phi"].to_numpy(dtype=float)
            fraction = points["frictional_fraction"].to_numpy(dtype=float)
            log_eta = np.log(points["eta_r"].to_numpy(dtype=float))

            def residual(x, phi=phi, fraction=fraction, log_eta=log_eta):
                return np.log(wyart_cates_viscosity(phi, fraction, *x)) - log_eta

            start = (1.0, min(densest + 0.1, 0.73), densest + 0.03)
            solution = least_squares(
                residual, start, bounds=([1e-3, densest + 1e-4, densest + 1e-4], [1e3, 0.74, 0.74])
            )
            for name, value in zip(WYART_CATES_PARAMETERS, solution.x):
                fitted[name].append(float(value))
            fitted["rms_log_residual"].append(float(np.sqrt(np.mean(solution.fun**2))))
        for name, values in fitted.items():
            interval = t_interval(values, level)
            low, high = interval.low, interval.high
            rows.append({"mu": mu, "parameter": name, "value": interval.mean, "low": low, "high": high})
    return pd.DataFrame(rows, columns=["mu", "parameter", "value", "low", "high"])
