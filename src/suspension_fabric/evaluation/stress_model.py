"""The Gillissen-Wilson stress relation: fitted on the steady state, tested through shear rotations.

In the Gillissen-Wilson (G-W) model the stress is a static function of the fabric and the
strain rate (as the paper, Acharya and Mari, arXiv:2506.05222, writes it; the shear-thickening
version: Gillissen, Ness, Peterson, Wilson and Cates, Phys. Rev. Lett. 123, 214504 (2019)). The particle stress has a
hydrodynamic term on the full strain rate and a contact term on its compressive part, both
through the fourth moment <nnnn> of the contact directions:

    sigma^p / (eta_f gammadot) = a_H <nnnn>:E^ + a_C <nnnn>:E^_c

with E^ = E/gammadot and E^_c its negative-eigenvalue part
([`gillissen_wilson.split_strain_rate`][suspension_fabric.models.gillissen_wilson.split_strain_rate]), <nnnn> from <nn>
by the fabric equation's closure
([`gillissen_wilson.contract_closure`][suspension_fabric.models.gillissen_wilson.contract_closure]). The coefficient
names are this project's. The fourth moment is normalised like the fabric (per particle, Tr<nn> = Z/2), so a_H and a_C
absorb the number density and cannot be taken from papers that normalise otherwise: they are fitted here.

Fit ([`fit_relation`][suspension_fabric.evaluation.stress_model.fit_relation]): the simulation separates the lubrication
stress (the hydrodynamic term) from the contact stress, so a_H = sigma^lub_12 / (<nnnn>:E^)_12 and
a_C = sigma^con_12 / (<nnnn>:E^_c)_12 at the steady state of startup shear. Everything else
(the normal stresses, the pressure, every transient) is then a prediction. Because the
steady fabrics of the sources differ (the G-W model's trace is far from the simulation's),
the coefficients are fitted per fabric source: the simulated <nn> and each fabric model's own
steady state. The total adds the solvent (1 on 12) and the Einstein term (2.5 phi on 12) of
[`suspension_fabric.analysis.stress`][suspension_fabric.analysis.stress]; the kinetic part (O(1/eta_f)) is left out.

Predictions after a rotation ([`stress_predictions`][suspension_fabric.evaluation.stress_model.stress_predictions]) come
from (a) the seed-mean simulated fabric and (b) each fabric model's predicted fabric, all in the rotated paper
frame (e1', e2, e3'), where the flow is simple shear e1' e2 again. Errors
([`relation_errors`][suspension_fabric.evaluation.stress_model.relation_errors]) are |prediction - simulation| /
sigma_12^ss of the total shear stress.

The viscosity after a rotation
([`viscosity_transients`][suspension_fabric.evaluation.stress_model.viscosity_transients]) is decided per seed, like the
fabric claims (docs/verdict_statistics.md): the integrated deficit of eta_r below the seed's own steady eta_r^ss,s over
the first W strain, with a t-interval over seeds. Its minimum, the strain of the minimum and the recovery strain are
kept as description, with seed-bootstrap intervals.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.analysis.seed_statistics import LEVEL, bootstrap_means, t_interval
from suspension_fabric.analysis.tables import TOLERANCE, fabric_tensors, settle_strain, settle_strains, steady_state
from suspension_fabric.models import stress_relations as relations
from suspension_fabric.models.stress_relations import relation_terms

from .model_vs_simulation import error_sizes

__all__ = [
    "SIMULATED",
    "source_labels",
    "PREDICTED_COLUMNS",
    "relation_terms",
    "steady_value",
    "source_steady_fabrics",
    "summarise_relation_errors",
    "fit_relation",
    "relation_fits",
    "relation_stress",
    "stress_predictions",
    "relation_errors",
    "seed_steady_viscosity",
    "viscosity_deficits",
    "viscosity_transients",
    "moving_average",
]

#: The fabric source that is the simulation's own <nn> (the others are the models of fits.json).
SIMULATED = "simulation"
#: Quantities a prediction gives, each in units of eta_f gammadot.
PREDICTED_COLUMNS = relations.STRESS_QUANTITIES


def fit_relation(
    steady_fabric,
    lubrication_12: float,
    contact_12: float,
    lubrication_12_sem: float = np.nan,
    contact_12_sem: float = np.nan,
) -> dict:
    """a_H and a_C (with the errors of the stress targets) from a steady fabric and the
    steady lubrication and contact shear stresses (units eta_f gammadot): the G-W relation's
    [`suspension_fabric.models.stress_relations.coefficients`][]."""
    return relations.coefficients(
        relations.GW_RELATION, steady_fabric, lubrication_12, contact_12, {}, lubrication_12_sem, contact_12_sem
    )


def steady_value(stress_steady: pd.DataFrame, quantity: str) -> tuple[float, float]:
    """(mean, sem) of a quantity at theta = 0 in the stress steady-state table."""
    rows = stress_steady[(stress_steady["quantity"] == quantity) & np.isclose(stress_steady["theta"], 0.0)]
    if len(rows) != 1:
        raise ValueError(f"stress steady-state table has {len(rows)} rows for {quantity} at theta = 0, expected 1")
    return float(rows["mean"].iloc[0]), float(rows["sem"].iloc[0])


def source_steady_fabrics(fits: dict) -> dict[str, np.ndarray]:
    """The steady fabric of each source: the simulated targets and the own steady state of each
    model of fits.json's ``models`` (models.fabric)."""
    simulated = fabric_tensors({name: value["mean"] for name, value in fits["targets"].items() if name in COMPONENTS})
    return {
        SIMULATED: simulated,
        **{key: fabric_tensors(entry["steady_state"]) for key, entry in fits["models"].items()},
    }


def source_labels(fits: dict) -> dict[str, str]:
    """{source: display name} of the fabric sources of
    [`source_steady_fabrics`][suspension_fabric.evaluation.stress_model.source_steady_fabrics]."""
    return {SIMULATED: "simulated <nn>", **{key: f"{entry['label']} fabric" for key, entry in fits["models"].items()}}


def relation_stress(fabric, coefficients: dict, phi: float) -> pd.DataFrame:
    """The G-W relation's stress for fabric(s) (..., 3, 3) in the paper frame of simple shear e1 e2:
    one row per fabric with `PREDICTED_COLUMNS`
    ([`stress_relations.relation_stress`][suspension_fabric.models.stress_relations.relation_stress])."""
    fabrics = np.asarray(fabric, dtype=float).reshape(-1, 3, 3)
    return pd.DataFrame(relations.relation_stress(relations.GW_RELATION, fabrics, coefficients, {}, phi))[
        list(PREDICTED_COLUMNS)
    ]


def relation_fits(stress_steady: pd.DataFrame, fits: dict) -> pd.DataFrame:
    """Per source: a_H, a_C (fitted on the steady lubrication and contact sigma_12) and the
    steady eta_r, N1, N2 and Pi the relation then predicts, beside the simulated ones."""
    lub, lub_sem = steady_value(stress_steady, "lubrication_12")
    con, con_sem = steady_value(stress_steady, "contact_12")
    measured = {name: steady_value(stress_steady, name) for name in ("eta_r", "N1", "N2", "Pi")}
    rows = []
    labels = source_labels(fits)
    for source, fabric in source_steady_fabrics(fits).items():
        coefficients = fit_relation(fabric, lub, con, lub_sem, con_sem)
        predicted = relation_stress(fabric, coefficients, fits["phi"]).iloc[0]
        row = {"source": source, "label": labels[source], **coefficients}
        for name, (mean, sem) in measured.items():
            row[f"{name}_predicted"] = float(predicted[name])
            row[f"{name}_simulated"] = mean
            row[f"{name}_simulated_sem"] = sem
        rows.append(row)
    return pd.DataFrame(rows)


def stress_predictions(
    relation: pd.DataFrame,
    startup_aggregate: pd.DataFrame,
    rotation_aggregate: pd.DataFrame,
    predictions: pd.DataFrame,
    phi: float,
) -> pd.DataFrame:
    """The relation's stress along startup and every rotation, per source (module docstring).

    ``startup_aggregate`` and ``rotation_aggregate`` are the seed aggregates of the fabric
    (``n11_mean`` ...), ``predictions`` the fabric models' predictions (``predictions.csv``).
    Columns: source, protocol, theta, strain and `PREDICTED_COLUMNS`.
    """
    coefficients = relation.set_index("source")
    blocks = []

    def add(source, protocol, frame, fabric):
        block = relation_stress(fabric, coefficients.loc[source], phi)
        block.insert(0, "strain", frame["strain"].to_numpy(dtype=float))
        block.insert(0, "theta", frame["theta"].to_numpy(dtype=float))
        block.insert(0, "protocol", protocol)
        block.insert(0, "source", source)
        blocks.append(block)

    for protocol, aggregate in (("startup", startup_aggregate), ("rotation", rotation_aggregate)):
        add("simulation", protocol, aggregate, fabric_tensors(aggregate, "_mean"))
        for key in coefficients.index.drop("simulation"):
            rows = predictions[(predictions["model"] == key) & (predictions["protocol"] == protocol)]
            add(key, protocol, rows, fabric_tensors(rows))
    return pd.concat(blocks, ignore_index=True)


def relation_errors(
    stress_startup: pd.DataFrame, stress_rotation: pd.DataFrame, predicted: pd.DataFrame, sigma12_ss: float
) -> pd.DataFrame:
    """rms and max |prediction - simulation| / sigma12_ss per source, protocol, angle and quantity
    (eta_r, N1, N2, total_23, contact_12, lubrication_12) over the simulated strains (seed means;
    the relation is evaluated at the same strains, matched to 1e-9)."""
    rows = []
    for protocol, simulation in (("startup", stress_startup), ("rotation", stress_rotation)):
        for source in dict.fromkeys(predicted["source"]):
            mine = predicted[(predicted["source"] == source) & (predicted["protocol"] == protocol)]
            for theta, sim in simulation.groupby("theta", sort=True):
                sim = sim.sort_values("strain")
                pred = mine[np.isclose(mine["theta"], theta)].sort_values("strain")
                strains, predicted_strains = sim["strain"].to_numpy(), pred["strain"].to_numpy()
                off_grid = ValueError(
                    f"{protocol}: source {source} at theta={theta} is not on the simulation's strain grid"
                )
                if len(pred) == 0:
                    raise off_grid
                # the closer of the neighbours on either side: a strain summed from the step may
                # sit a rounding below its grid value (0.09999999999999999 for 0.1)
                after = np.searchsorted(predicted_strains, strains).clip(0, len(pred) - 1)
                before = (after - 1).clip(0, None)
                closer = np.abs(predicted_strains[before] - strains) < np.abs(predicted_strains[after] - strains)
                nearest = np.where(closer, before, after)
                if not np.allclose(predicted_strains[nearest], strains, rtol=1e-9, atol=1e-9):
                    raise off_grid
                on_grid = pred.iloc[nearest]
                for name in ("eta_r", "N1", "N2", "total_23", "contact_12", "lubrication_12"):
                    diff = (on_grid[name].to_numpy() - sim[f"{name}_mean"].to_numpy()) / abs(sigma12_ss)
                    rows.append(
                        {"protocol": protocol, "source": source, "theta": float(theta), "quantity": name}
                        | error_sizes(diff)
                    )
    return pd.DataFrame(rows)


def summarise_relation_errors(errors: pd.DataFrame) -> pd.DataFrame:
    """Angle-averaged rms error per protocol, quantity and source (columns ``rms_<source>``)."""
    mean = errors.groupby(["protocol", "quantity", "source"], sort=False)["rms_error"].mean().unstack("source")
    return mean[list(dict.fromkeys(errors["source"]))].add_prefix("rms_").reset_index()


def moving_average(strain, values, width: float) -> np.ndarray:
    """Centred running mean of ``values`` over the points within ``width``/2 in strain of each
    point (fewer at the ends), along the last axis (so several curves at once); ``width`` 0
    returns the values unchanged."""
    strain, values = np.asarray(strain, dtype=float), np.asarray(values, dtype=float)
    if width <= 0:
        return values.copy()
    near = (np.abs(strain[:, None] - strain[None, :]) <= 0.5 * width + 1e-12).astype(float)
    return values @ near.T / near.sum(axis=1)


def seed_steady_viscosity(startup_runs: pd.DataFrame, steady_window) -> pd.Series:
    """Each seed's own steady eta_r^ss,s: the mean of eta_r over strain_min <= strain <= strain_max
    of that seed's startup stress run (the frames
    [`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state] averages; the
    seed mean of these values is its ``mean``). A Series indexed by seed; a seed with fewer than 2 frames in the window
    is an error."""
    if startup_runs["theta"].nunique() != 1:
        raise ValueError(f"startup stress runs hold several angles: {sorted(startup_runs['theta'].unique())}")
    values = {
        int(seed): float(steady_state(rows, *steady_window, value_columns=("eta_r",))["mean"].iloc[0])
        for seed, rows in startup_runs.groupby("seed", sort=True)
    }
    return pd.Series(values, name="eta_ss_seed").rename_axis("seed")


def _seed_eta_ss(eta_ss, seeds) -> dict[int, float]:
    """{seed: eta_r^ss,s} for the given seeds from a mapping seed -> value; a missing seed is an error."""
    eta_ss = {int(k): float(v) for k, v in dict(eta_ss).items()}
    missing = sorted(int(s) for s in seeds if int(s) not in eta_ss)
    if missing:
        raise ValueError(f"no steady eta_r for seed(s) {missing} (have {sorted(eta_ss)})")
    return {int(s): eta_ss[int(s)] for s in seeds}


def _window_integral(strain: np.ndarray, values: np.ndarray, window: float, theta: float, seed) -> float:
    """Trapezoidal integral of ``values`` over the frames with 0 <= strain <= ``window``; if
    ``window`` falls between two frames the last piece ends at it (linear interpolation)."""
    tolerance = 1e-9 * max(1.0, window)
    if abs(strain[0]) > tolerance:
        raise ValueError(f"theta={theta}: seed {seed}'s run starts at strain {strain[0]:g} after the rotation, not 0")
    if strain[-1] < window - tolerance:
        raise ValueError(
            f"theta={theta}: seed {seed}'s run ends at strain {strain[-1]:g} after the rotation, "
            f"shorter than the window {window:g}"
        )
    inside = strain < window - tolerance
    x = np.append(strain[inside], window)
    y = np.append(values[inside], np.interp(window, strain, values))
    return float(np.trapezoid(y, x))


def viscosity_deficits(stress_runs: pd.DataFrame, eta_ss, window: float) -> pd.DataFrame:
    """Per seed s and angle theta, the integrated viscosity deficit after the rotation

        V_s(theta) = integral_0^W (1 - eta_r,s(theta, gamma) / eta_r^ss,s) d gamma

    (trapezoidal rule on the frames, W = ``window``), with ``eta_ss`` a mapping seed ->
    eta_r^ss,s, the seed's own steady viscosity
    ([`seed_steady_viscosity`][suspension_fabric.evaluation.stress_model.seed_steady_viscosity]). 0.1 means 10 % below
    steady for one strain. A run shorter than W is an error naming the angle and both strains. Long table: seed, theta,
    window, eta_ss_seed, deficit."""
    window = float(window)
    if not window > 0.0:
        raise ValueError(f"deficit window must be positive, got {window}")
    rows = []
    for (theta, seed), run in stress_runs.groupby(["theta", "seed"], sort=True):
        run = run.sort_values("strain")
        strain = run["strain"].to_numpy(dtype=float)
        if np.any(np.diff(strain) <= 0.0):
            raise ValueError(f"theta={theta}: seed {seed} has duplicated strain values")
        eta_ss_seed = _seed_eta_ss(eta_ss, [seed])[int(seed)]
        deficit = _window_integral(
            strain, 1.0 - run["eta_r"].to_numpy(dtype=float) / eta_ss_seed, window, float(theta), int(seed)
        )
        rows.append(
            {"seed": int(seed), "theta": float(theta), "window": window, "eta_ss_seed": eta_ss_seed, "deficit": deficit}
        )
    return pd.DataFrame(rows, columns=["seed", "theta", "window", "eta_ss_seed", "deficit"])


def _with_interval(statistic, whole: np.ndarray, resampled: np.ndarray | None, level: float) -> tuple:
    """(statistic of the all-seed curve, percentile interval of it over the resampled curves);
    ``statistic`` takes curves stacked on the first axis and returns one value per curve."""
    value = float(statistic(whole[None])[0])
    if resampled is None:
        return value, np.nan, np.nan
    low, high = np.quantile(np.asarray(statistic(resampled), dtype=float), [0.5 - level / 2.0, 0.5 + level / 2.0])
    return value, float(low), float(high)


def viscosity_transients(
    stress_runs: pd.DataFrame,
    eta_ss,
    window: float,
    level: float = LEVEL,
    tolerance: float = TOLERANCE,
    smoothing_strain: float = 0.1,
) -> pd.DataFrame:
    """Per angle, the integrated viscosity deficit with its t-interval over seeds (the deciding
    number), and the viscosity minimum, its strain and the recovery strain as description.

    ``eta_ss`` maps seed -> that seed's own steady eta_r^ss,s
    ([`seed_steady_viscosity`][suspension_fabric.evaluation.stress_model.seed_steady_viscosity]).

    Deficit: the per-seed V_s(theta) of
    [`viscosity_deficits`][suspension_fabric.evaluation.stress_model.viscosity_deficits] over [0, ``window``]; columns
    deficit (seed mean), deficit_se, deficit_low, deficit_high, the Student t-interval at ``level`` over the n_seeds
    seeds
    ([`suspension_fabric.analysis.seed_statistics.t_interval`][suspension_fabric.analysis.seed_statistics.t_interval]).

    Description: on the seed-mean curve  mean_s eta_r,s(gamma) / mean_s eta_r^ss,s  (the study's
    eta_r / eta_r^ss), smoothed by a centred running mean over ``smoothing_strain`` (the
    frame-to-frame noise of a few seeds is ~10 %, the size of the band): its minimum, the strain
    of the minimum, and the recovery strain (first strain from which it stays within
    ``tolerance`` of 1; censored at the run's end if it never does: recovery_settled False),
    each with the seed-bootstrap percentile interval at ``level`` (_low, _high;
    [`suspension_fabric.analysis.seed_statistics.seed_bootstrap`][], every resample takes whole seeds,
    their rotation curves with their own steady state; a resample whose curve never settles
    counts with the run's last strain). These are descriptive only: a minimum and a first
    crossing are not smooth functions of the seeds, their bootstrap intervals are coarse with a
    few seeds, and no verdict rests on them.
    """
    level = float(level)
    deficits = viscosity_deficits(stress_runs, eta_ss, window)
    rows = []
    for theta, group in stress_runs.groupby("theta", sort=True):
        curves = {int(seed): rows_.sort_values("strain") for seed, rows_ in group.groupby("seed")}
        strain = next(iter(curves.values()))["strain"].to_numpy(dtype=float)
        for seed, rows_ in curves.items():
            other = rows_["strain"].to_numpy(dtype=float)
            if len(other) != len(strain) or not np.allclose(other, strain, rtol=1e-9, atol=1e-12):
                raise ValueError(
                    f"theta={theta}: the strains of seed {seed} differ from those of seed {next(iter(curves))}"
                )
        eta = {seed: rows_["eta_r"].to_numpy(dtype=float) for seed, rows_ in curves.items()}
        steady = _seed_eta_ss(eta_ss, curves)

        # per seed its eta_r curve and its steady value: a resample's curve is the ratio of their means
        seeds = list(curves)
        per_seed = np.column_stack([np.stack([eta[s] for s in seeds]), [steady[s] for s in seeds]])

        def smoothed(means: np.ndarray) -> np.ndarray:
            return moving_average(strain, means[..., :-1] / means[..., -1:], smoothing_strain)

        whole = smoothed(per_seed.mean(axis=0))
        resampled = smoothed(bootstrap_means(per_seed)) if len(seeds) > 1 else None
        minimum = _with_interval(lambda c: c.min(axis=-1), whole, resampled, level)
        at = _with_interval(lambda c: strain[np.argmin(c, axis=-1)], whole, resampled, level)
        recovery = _with_interval(lambda c: settle_strains(strain, c - 1.0, tolerance)[0], whole, resampled, level)
        interval = t_interval(deficits.loc[deficits["theta"] == theta, "deficit"], level)
        row = {
            "theta": float(theta),
            "window": float(window),
            "deficit": interval.mean,
            "deficit_se": interval.se,
            "deficit_low": interval.low,
            "deficit_high": interval.high,
            "n_seeds": interval.n,
            "level": level,
        }
        for name, (value, low, high) in (("minimum", minimum), ("strain_at_min", at), ("recovery_strain", recovery)):
            row.update({name: value, f"{name}_low": low, f"{name}_high": high})
        row["recovery_settled"] = settle_strain(strain, whole - 1.0, tolerance)[1]
        row["smoothing_strain"] = float(smoothing_strain)
        rows.append(row)
    return pd.DataFrame(rows)
