"""G-W's error after a rotation taken apart: how much is the closure, how much the dynamics.

The Gillissen-Wilson equation (paper Eq. 1) in simple shear Lh = e1 e2 of the current flow,
written with separate rates for breaking (b_e), directed formation (b_c) and isotropic formation
(a), which G-W sets all equal to beta,

    d<nn>/dgamma = Lh.<nn> + <nn>.Lh^T - T:<nnnn> - (phi/15)(2 b_c Eh_c + a Tr(Eh_c) I),
    T = 2 Eh + b_e Eh_e,                                                            (1)

((T:Q)_ij = T_kl Q_ijkl; Lh:<nnnn> = Eh:<nnnn> for a symmetric <nnnn>) rests on two
approximations: the closure, which writes <nnnn> in terms of <nn>, and the dynamics (breaking on
the extensional axis, formation on the compressional one). The fabric tables record the measured
<nnnn> along every run, so (1) can be integrated with the closure replaced, per seed and angle,
from the seed's simulated fabric at the rotation (`FABRIC_VARIANTS`):

``closure``
    G-W as published, <nnnn> = C(<nn>) by the paper's closure C of the model's own <nn>;
``closure_corrected``
    <nnnn> = C(<nn>) + [M(gamma) - C(N(gamma))], M and N the seed's measured <nnnn> and <nn>:
    the closure's error along the run removed while the model keeps its own feedback;
``closure_corrected_rates``
    the same with the three rates fitted separately;
``measured``
    <nnnn> = M(gamma), the measured fourth moment in place of the closure. Only the convection
    then acts on the model's <nn>, so (1) integrates a measured forcing and a dynamics that does
    not hold the measured state shows as a drift;
``measured_rates``
    the same with the three rates fitted separately.

The measured <nnnn> enters as a forcing linear in strain between the table's frames, and (1) is
then solved exactly on every interval ([`solve_forced`][suspension_fabric.evaluation.error_decomposition.solve_forced]).

The rates are fitted per seed on its startup's steady state, by one criterion for every variant it
applies to (`CRITERIA`), so that a difference between two variants is the closure's and not how
their rates were chosen:

``fixed_point``
    the rate for which the variant's own fixed point has the measured steady <nn>_12 (G-W:
    [`suspension_fabric.models.gillissen_wilson.fit_gw`][suspension_fabric.models.gillissen_wilson.fit_gw]; the
    corrected closure, with the closure's measured steady error held:
    [`corrected_fixed_point_beta`][suspension_fabric.evaluation.error_decomposition.corrected_fixed_point_beta]).
    With the measured <nnnn> only the convection acts on
    the model's <nn>, which has no fixed point, so the measured variants have no such rate;
``balance``
    the rate for which the 12 component of (1) vanishes at the measured steady <nn>, with the
    variant's own <nnnn> there (the closure of <nn> for G-W, the measured <nnnn> for the others;
    [`measured_beta`][suspension_fabric.evaluation.error_decomposition.measured_beta]); for the
    separate-rates variants the three rates that bring all six components closest to zero
    (non-negative least squares, [`measured_rates`][suspension_fabric.evaluation.error_decomposition.measured_rates]).

The trace of (1). When <nnnn> contracts to <nn> (the measured moment, and every closure here), the
convection and the 2 Eh:<nnnn> term cancel in the trace, so

    d tr<nn>/dgamma = -b_e Eh_e:<nn> + (phi/15)(b_c + 3a/2)      (tr Eh_c = -1/2 in simple shear),

and a steady state with one rate b_e = b_c = a must have Eh_e:<nn> = phi/6, whatever the closure and
whatever beta ([`steady_extension`][suspension_fabric.evaluation.error_decomposition.steady_extension]
measures it). Where the simulations' steady Eh_e:<nn> is not phi/6, no single rate holds their
steady state: the rate that fits the steady <nn>_12 is not the rate that balances the trace. At any
steady state the breaking flux b_e Eh_e:<nn> equals the formation flux (phi/15)(b_c + 3a/2); the
rates' ratio is that flux balance, not a finding about formation against breaking.

Scores, as the claims' ([`suspension_fabric.evaluation.claims`][suspension_fabric.evaluation.claims]): each seed's
curves in units of its own steady <nn>_12; per seed and angle the mean square of model - seed over the strains of
(0, W]. Two nets of it: the noise floor s^2 subtracted (between-seed variance of the simulated
curve, averaged over the same strains; per seed its jackknife pseudo-value, whose mean over the
seeds is s^2, so the interval carries the floor's error), and the control subtracted, the same seed's score at
theta = 0 (no rotation, the continuation of the startup): what a variant misses without any
rotation is its steady offset and drift, not its response to a rotation, and the paired
per-seed difference needs no estimate of the floor. A seed's score is the mean over the angles of
a group. The seeds are the units: mean with t-interval, and the paired difference from
``closure`` under the same criterion, on the control-subtracted score.

The stress relation ([`suspension_fabric.models.stress_relations`][suspension_fabric.models.stress_relations], ``gw``):
sigma^p/(eta_f gammadot) = a_H <nnnn>:Eh + a_C <nnnn>:Eh_c, with a_H and a_C fitted per seed and
source on the steady sigma^lub_12 and sigma^con_12. Its sources (`STRESS_SOURCES`): G-W's
own fabric (closure; after a rotation the ``closure`` variant's), the measured <nn> through the
closure, and the measured <nnnn>. The steady N1, N2 and Pi and their mean square after a
rotation (in units of the seed's steady eta_r) then say which step loses the normal stresses:
the fabric, the closure or the relation itself.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import scipy.linalg
import scipy.optimize

from suspension_fabric.analysis.components import FOURTH_MOMENT_COMPONENTS
from suspension_fabric.analysis.frames import VECTOR_ORDER, simple_shear_gradient, sym_to_vec, vec_to_sym
from suspension_fabric.analysis.seed_statistics import LEVEL, adjusted_p, t_interval, t_test_p, variance_pseudo_values
from suspension_fabric.analysis.tables import fabric_tensors
from suspension_fabric.models import fabric_models
from suspension_fabric.models import gillissen_wilson as gw_equations
from suspension_fabric.models.gillissen_wilson import hinch_leal_closure
from suspension_fabric.models.stress_relations import GW_RELATION, coefficients, relation_stress, stress_from_forms

from .closure_tests import fourth_moment_tensors
from .model_benchmark import mean_square

__all__ = [
    "FABRIC_VARIANTS",
    "STRESS_SOURCES",
    "STRESS_QUANTITIES",
    "ANGLE_GROUPS",
    "SeedRuns",
    "gw_drive",
    "gw_source",
    "CRITERIA",
    "measured_beta",
    "measured_rates",
    "corrected_fixed_point_beta",
    "steady_extension",
    "steady_residual",
    "solve_forced",
    "gw_with_fourth_moment",
    "variant_rates",
    "seed_fabric_curves",
    "fabric_scores",
    "decomposition_table",
    "has_fourth_moment",
    "decompose",
    "stress_by_seed",
    "stress_decomposition_table",
    "summary_markdown",
]

FABRIC_VARIANTS = {
    "closure": "G-W (the paper's closure)",
    "closure_corrected": "G-W, the closure's error along the run removed",
    "closure_corrected_rates": "separate rates, the closure's error along the run removed",
    "measured": "G-W with the measured ⟨nnnn⟩",
    "measured_rates": "separate rates with the measured ⟨nnnn⟩",
}
STRESS_SOURCES = {
    "model": "G-W's fabric, the closure",
    "closure": "measured ⟨nn⟩, the closure",
    "measured": "measured ⟨nnnn⟩",
}
#: Stress quantities compared, each in units of eta_f gammadot.
STRESS_QUANTITIES = ("eta_r", "N1", "N2", "Pi")
_QUANTITY_LABELS = {"eta_r": "η_r", "N1": "N₁", "N2": "N₂", "Pi": "Π"}
#: How each variant's rates are fitted on the steady state (module docstring), and the variants
#: each criterion applies to.
CRITERIA = {
    "fixed_point": ("closure", "closure_corrected"),
    "balance": tuple(FABRIC_VARIANTS),
}
#: Rotation angles pooled per score, |theta| in degrees (inclusive); theta = 0 is no rotation, the
#: control every other group is paired with.
CONTROL = "control (theta = 0)"
ANGLE_GROUPS = {
    CONTROL: (0.0, 1e-6),
    "all": (1e-6, 180.0),
    "below 90": (1e-6, 89.999),
    "90 to 135": (90.0, 135.0),
    "150 to 180": (149.999, 180.0),
}
#: The rates of (1), (b_e, b_c, a), as table columns.
RATE_NAMES = ("beta_e", "beta_c", "A")
#: Fabric components scored.
SCORED = ("n12", "n23")

_FLOW = fabric_models.flow_of(simple_shear_gradient())


def gw_drive(rate_break: float) -> np.ndarray:
    """T = 2 Eh + b_e Eh_e of (1) in simple shear e1 e2 (3, 3); b_e = beta in G-W."""
    return 2.0 * _FLOW.e_hat + rate_break * _FLOW.e_ext


def gw_source(rate_form: float, rate_iso: float, phi: float) -> np.ndarray:
    """The fabric-independent term (phi/15)(2 b_c Eh_c + a Tr(Eh_c) I) of (1), subtracted;
    b_c = a = beta in G-W (the paper's creation term,
    [`gillissen_wilson.source_part`][suspension_fabric.models.gillissen_wilson.source_part])."""
    return -gw_equations.source_part(_FLOW.e_comp, rate_form, rate_iso, phi)


def _convection(fabric) -> np.ndarray:
    grad = _FLOW.grad_hat
    return grad @ fabric + fabric @ grad.T


def _balance_columns(fabric, fourth, phi: float) -> tuple[np.ndarray, np.ndarray]:
    """(y, A) with the right-hand side of (1) at (fabric, fourth) = y - A @ (b_e, b_c, a) on 6-vectors."""
    fabric, fourth = np.asarray(fabric, dtype=float), np.asarray(fourth, dtype=float)
    y = _convection(fabric) - np.einsum("kl,ijkl->ij", 2.0 * _FLOW.e_hat, fourth)
    columns = (
        np.einsum("kl,ijkl->ij", _FLOW.e_ext, fourth),
        gw_source(1.0, 0.0, phi),
        gw_source(0.0, 1.0, phi),
    )
    return sym_to_vec(y), np.stack([sym_to_vec(c) for c in columns], axis=-1)


def measured_beta(fabric, fourth, phi: float) -> float:
    """G-W's beta for which the 12 component of (1) vanishes at a measured steady <nn> and <nnnn>:
    beta = [Lh.N + N.Lh^T - 2 Eh:M]_12 / [Eh_e:M + (phi/15)(2 Eh_c + Tr(Eh_c) I)]_12."""
    y, columns = _balance_columns(fabric, fourth, phi)
    twelve = VECTOR_ORDER.index("12")
    beta = y[twelve] / columns[twelve].sum()
    if not (np.isfinite(beta) and beta > 0.0):
        raise ValueError(f"no positive beta balances the measured steady <nn>_12 (beta = {beta:.4g})")
    return float(beta)


def steady_residual(fabric, fourth, rates, phi: float) -> np.ndarray:
    """The right-hand side of (1) (6-vector, per unit strain) at a measured <nn> and <nnnn> for the
    rates (b_e, b_c, a): zero where the rates hold the measured state."""
    y, columns = _balance_columns(fabric, fourth, phi)
    return y - columns @ np.asarray(rates, dtype=float)


def measured_rates(fabric, fourth, phi: float) -> tuple[float, float, float]:
    """(b_e, b_c, a) of (1) that balance a measured steady <nn> and <nnnn> best: non-negative least
    squares of the right-hand side's six components (a rate that would have to be negative is 0)."""
    y, columns = _balance_columns(fabric, fourth, phi)
    rates, _ = scipy.optimize.nnls(columns, y)
    return tuple(float(r) for r in rates)


def corrected_fixed_point_beta(fabric, fourth, phi: float) -> float:
    """G-W's beta for which the fixed point of (1) with the corrected closure, C(<nn>) + [M - C(N)]
    with the measured steady error M - C(N) held, has the measured steady <nn>_12 = N_12."""
    excess = np.asarray(fourth, dtype=float) - hinch_leal_closure(np.asarray(fabric, dtype=float))
    twelve = VECTOR_ORDER.index("12")
    target = float(np.asarray(fabric)[0, 1])

    def miss(beta):
        params = {"beta_e": beta, "beta_c": beta, "A": beta}
        M, b = fabric_models.affine_system(fabric_models.SEPARATE_RATES, _FLOW, params, phi)
        forcing = -sym_to_vec(np.einsum("kl,ijkl->ij", gw_drive(beta), excess))
        return float(np.linalg.solve(M, -(b + forcing))[twelve]) - target

    grid = np.geomspace(0.1, 1e3, 121)
    values = np.array([miss(beta) for beta in grid])
    crossings = np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)
    if len(crossings) != 1:
        raise ValueError(
            f"the corrected closure's fixed point reaches the measured <nn>_12 = {target:.4g} at "
            f"{len(crossings)} rates in [0.1, 1000]; expected one"
        )
    k = crossings[0]
    return float(scipy.optimize.brentq(miss, grid[k], grid[k + 1], xtol=1e-13, rtol=1e-13))


def steady_extension(fabric) -> float:
    """Eh_e:<nn>, the extensional projection of a steady <nn> in simple shear: phi/6 for every
    single-rate G-W steady state (the trace of (1), module docstring)."""
    return float(np.einsum("ij,ij->", _FLOW.e_ext, np.asarray(fabric, dtype=float)))


def _forced_propagators(M: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(expm(M h), int_0^h expm(M (h - s)) ds, int_0^h expm(M (h - s)) s ds): the top row of the
    exponential of [[M, I, 0], [0, 0, I], [0, 0, 0]] h."""
    n = M.shape[0]
    block = np.zeros((3 * n, 3 * n))
    block[:n, :n] = M
    block[:n, n : 2 * n] = np.eye(n)
    block[n : 2 * n, 2 * n :] = np.eye(n)
    top = scipy.linalg.expm(block * step)[:n]
    return top[:, :n], top[:, n : 2 * n], top[:, 2 * n :]


def solve_forced(M, b, v0, strains, forcing) -> np.ndarray:
    r"""$v$ at ``strains`` (S, 6) of $\mathrm{d}v/\mathrm{d}\gamma = Mv + b + g(\gamma)$ from ``v0``
    at ``strains[0]``, $g$ linear between its values ``forcing`` (S, 6) at the strains: exact on
    every interval (of length $h = \gamma_{k+1} - \gamma_k$),
    $v_{k+1} = e^{Mh}v_k + J_0(b + g_k) + J_1(g_{k+1} - g_k)/h$ with
    $J_0 = \int_0^h e^{M(h - s)}\,\mathrm{d}s$ and $J_1 = \int_0^h e^{M(h - s)}\,s\,\mathrm{d}s$
    (`_forced_propagators`)."""
    M, b, v0 = (np.asarray(x, dtype=float) for x in (M, b, v0))
    strains, forcing = np.asarray(strains, dtype=float), np.asarray(forcing, dtype=float)
    steps = np.diff(strains)
    if np.any(steps <= 0.0) or forcing.shape != (len(strains), len(v0)):
        raise ValueError("strains must increase and the forcing must have one row per strain")
    cache, out = {}, np.empty((len(strains), len(v0)))
    out[0] = v0
    for k, step in enumerate(steps):
        key = round(float(step), 12)
        if key not in cache:
            cache[key] = _forced_propagators(M, step)
        expm, first, second = cache[key]
        out[k + 1] = expm @ out[k] + first @ (b + forcing[k]) + second @ ((forcing[k + 1] - forcing[k]) / step)
    return out


def _basis_matrix(linear) -> np.ndarray:
    """The (6, 6) matrix of a linear map of symmetric tensors on 6-vectors."""
    return np.swapaxes(sym_to_vec(linear(vec_to_sym(np.eye(6)))), -1, -2)


def gw_with_fourth_moment(fabric0, strains, fourth, fabric, rates, phi: float, variant: str) -> np.ndarray:
    """<nn> (S, 3, 3) of (1) with rates (b_e, b_c, a) from ``fabric0`` along a run of simple shear
    whose measured <nnnn> (S, 3, 3, 3, 3) and <nn> (S, 3, 3) are given at ``strains``: the closure
    (``closure``), the closure with its measured error added (``closure_corrected``,
    ``closure_corrected_rates``) or the measured <nnnn> (``measured``, ``measured_rates``)."""
    rate_break, rate_form, rate_iso = rates
    drive = gw_drive(rate_break)
    params = {"beta_e": rate_break, "beta_c": rate_form, "A": rate_iso}
    if variant == "closure":
        return fabric_models.integrate(
            fabric_models.SEPARATE_RATES,
            fabric0,
            simple_shear_gradient(),
            np.asarray(strains) - strains[0],
            params,
            phi,
        )
    if variant in ("closure_corrected", "closure_corrected_rates"):
        M, b = fabric_models.affine_system(fabric_models.SEPARATE_RATES, _FLOW, params, phi)
        excess = np.asarray(fourth) - hinch_leal_closure(fabric)
    elif variant in ("measured", "measured_rates"):
        M, b = _basis_matrix(_convection), -sym_to_vec(gw_source(rate_form, rate_iso, phi))
        excess = np.asarray(fourth)
    else:
        raise ValueError(f"unknown variant {variant!r}; expected one of {list(FABRIC_VARIANTS)}")
    forcing = -sym_to_vec(np.einsum("kl,sijkl->sij", drive, excess))
    return vec_to_sym(solve_forced(M, b, sym_to_vec(fabric0), strains, forcing))


class SeedRuns:
    """One seed's fabric tables with the fourth moment: the startup and each rotation (by theta),
    cut at the window W after the rotation; the steady <nn> and <nnnn> over ``steady_window``."""

    def __init__(self, startup: pd.DataFrame, rotations: dict[float, pd.DataFrame], steady_window, window: float):
        self.seed = int(startup["seed"].iloc[0])
        startup = startup.dropna(subset=list(FOURTH_MOMENT_COMPONENTS)).sort_values("strain")
        low, high = steady_window
        steady = startup[startup["strain"].between(low - 1e-9, high + 1e-9)]
        if steady.empty:
            raise ValueError(f"seed {self.seed}: no startup frame with the fourth moment in {steady_window}")
        self.fabric_ss = fabric_tensors(steady).mean(axis=0)
        self.fourth_ss = fourth_moment_tensors(steady).mean(axis=0)
        self.n12_ss = float(self.fabric_ss[0, 1])
        self.rotations = {}
        for theta, rows in sorted(rotations.items()):
            rows = rows.sort_values("strain")
            rows = rows[rows["strain"] <= window + 1e-9]
            if rows[list(FOURTH_MOMENT_COMPONENTS)].isna().any().any():
                raise ValueError(f"seed {self.seed}, theta = {theta:g}: the fabric table lacks the fourth moment")
            self.rotations[float(theta)] = rows


def variant_rates(runs: SeedRuns, phi: float) -> dict:
    """{(variant, criterion): (b_e, b_c, a)} for every variant under every criterion that applies
    to it (`CRITERIA`), fitted on the seed's measured steady state."""
    closure_ss = hinch_leal_closure(runs.fabric_ss)
    single = {
        ("closure", "fixed_point"): gw_equations.fit_gw(runs.n12_ss, phi),
        ("closure_corrected", "fixed_point"): corrected_fixed_point_beta(runs.fabric_ss, runs.fourth_ss, phi),
        ("closure", "balance"): measured_beta(runs.fabric_ss, closure_ss, phi),
        ("closure_corrected", "balance"): measured_beta(runs.fabric_ss, runs.fourth_ss, phi),
        ("measured", "balance"): measured_beta(runs.fabric_ss, runs.fourth_ss, phi),
    }
    rates = {key: (beta, beta, beta) for key, beta in single.items()}
    separate = measured_rates(runs.fabric_ss, runs.fourth_ss, phi)
    rates[("closure_corrected_rates", "balance")] = separate
    rates[("measured_rates", "balance")] = separate
    return {key: rates[key] for criterion, variants in CRITERIA.items() for key in ((v, criterion) for v in variants)}


def seed_fabric_curves(runs: SeedRuns, phi: float) -> dict:
    """Per theta: the strains, the simulated <nn> and each (variant, criterion)'s; and the rates
    (b_e, b_c, a) of each ([`variant_rates`][suspension_fabric.evaluation.error_decomposition.variant_rates])."""
    rates = variant_rates(runs, phi)
    curves = {}
    for theta, rows in runs.rotations.items():
        strains = rows["strain"].to_numpy(dtype=float)
        fabric, fourth = fabric_tensors(rows), fourth_moment_tensors(rows)
        curves[theta] = {
            "strain": strains,
            "sim": fabric,
            **{
                key: gw_with_fourth_moment(fabric[0], strains, fourth, fabric, rate, phi, key[0])
                for key, rate in rates.items()
            },
        }
    return {"curves": curves, "rates": rates}


def _component(tensors, component: str) -> np.ndarray:
    return tensors[..., int(component[1]) - 1, int(component[2]) - 1]


def fabric_scores(seed_runs: list[SeedRuns], phi: float, fitted: dict | None = None) -> pd.DataFrame:
    """Per seed, theta, variant, criterion and scored component: the mean square of
    (model - seed)/<nn>_12^ss over (0, W], the noise floor s^2 of that angle and component (the seed's
    pseudo-value: `variance_pseudo_values`), the
    rates and the largest component of (1) at the seed's measured steady <nn> and <nnnn> with those
    rates (``steady_residual``, per unit strain; the closure's own <nnnn> for ``closure``), and the
    seed's steady Eh_e:<nn> (``steady_extension``, phi/6 in any single-rate steady state).
    ``fitted``: {seed: [`seed_fabric_curves`][suspension_fabric.evaluation.error_decomposition.seed_fabric_curves]}, if
    made."""
    fitted = fitted or {}
    per_seed = {runs.seed: (runs, fitted.get(runs.seed) or seed_fabric_curves(runs, phi)) for runs in seed_runs}
    thetas = sorted(set.intersection(*(set(runs.rotations) for runs, _ in per_seed.values())))
    residuals = {}
    for seed, (runs, made) in per_seed.items():
        for key, rate in made["rates"].items():
            fourth = hinch_leal_closure(runs.fabric_ss) if key[0] == "closure" else runs.fourth_ss
            residuals[(seed, key)] = float(np.abs(steady_residual(runs.fabric_ss, fourth, rate, phi)).max())
    rows = []
    for theta in thetas:
        ratios = {
            seed: {name: curve / runs.n12_ss for name, curve in made["curves"][theta].items() if name != "strain"}
            for seed, (runs, made) in per_seed.items()
        }
        strain = next(iter(per_seed.values()))[1]["curves"][theta]["strain"]
        after = strain > 0.0
        for component in SCORED:
            simulated = np.stack([_component(r["sim"], component) for r in ratios.values()])
            if simulated.shape[1] != len(strain):
                raise ValueError(f"theta = {theta:g}: the seeds' rotation runs have other strains")
            floors = variance_pseudo_values(simulated)[:, after].mean(axis=1)
            for (seed, r), floor in zip(ratios.items(), floors):
                for key, rate in per_seed[seed][1]["rates"].items():
                    rows.append(
                        {
                            "seed": seed,
                            "theta": theta,
                            "variant": key[0],
                            "criterion": key[1],
                            "component": component,
                            "mse": float(
                                mean_square(_component(r[key], component), _component(r["sim"], component), strain)
                            ),
                            "floor": float(floor),
                            **dict(zip(RATE_NAMES, rate)),
                            "steady_residual": residuals[(seed, key)],
                            "steady_extension": steady_extension(per_seed[seed][0].fabric_ss),
                            "phi": phi,
                        }
                    )
    return pd.DataFrame(rows)


def _group_scores(scores: pd.DataFrame, group: str) -> pd.DataFrame:
    low, high = ANGLE_GROUPS[group]
    inside = scores[scores["theta"].abs().between(low, high)]
    keys = ["variant", "criterion", "component", "seed"]
    return inside.groupby(keys)[["mse", "floor"]].mean().reset_index()


def _interval_columns(prefix: str, values, level: float) -> dict:
    value = t_interval(np.asarray(values, dtype=float), level)
    return {prefix: value.mean, f"{prefix}_low": value.low, f"{prefix}_high": value.high}


def decomposition_table(scores: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """Per angle group, criterion, variant and component: the seeds' mean square error net of the
    noise floor (``net_mse``) and net of the same seed's theta = 0 control (``minus_control``),
    each with its t-interval, the paired per-seed difference of the control-subtracted score from
    ``closure`` under the same criterion (``difference``; NaN for itself and for the control group)
    with its t-test p-value and that p-value adjusted by Holm's method over every difference of the
    table (``difference_p_holm``: the table's cells are read at once), and the seed mean of the
    steady residual (``steady_residual``)."""
    keys = ["variant", "criterion", "component", "seed"]
    control = _group_scores(scores, CONTROL).set_index(keys)["mse"]
    residual = scores.groupby(["variant", "criterion"])["steady_residual"].mean()
    rows = []
    for group in ANGLE_GROUPS:
        pooled = _group_scores(scores, group).set_index(keys)
        if pooled.empty:
            continue
        net = pooled["mse"] - pooled["floor"]
        beyond = pooled["mse"] - control.reindex(pooled.index)
        for criterion, variants in CRITERIA.items():
            for variant in variants:
                for component in SCORED:
                    mine = (variant, criterion, component)
                    row = {
                        "angles": group,
                        "criterion": criterion,
                        "variant": variant,
                        "label": FABRIC_VARIANTS[variant],
                        "component": component,
                        "n_seeds": len(net.loc[mine]),
                        **_interval_columns("net_mse", net.loc[mine], level),
                        **_interval_columns("minus_control", beyond.loc[mine], level),
                        "difference": np.nan,
                        "difference_low": np.nan,
                        "difference_high": np.nan,
                        "difference_p": np.nan,
                        "steady_residual": residual.loc[(variant, criterion)],
                    }
                    if variant != "closure" and group != CONTROL:
                        base = beyond.loc[("closure", criterion, component)].reindex(beyond.loc[mine].index)
                        row.update(_interval_columns("difference", beyond.loc[mine] - base, level))
                        row["difference_p"] = t_test_p(beyond.loc[mine] - base)
                    rows.append(row)
    table = pd.DataFrame(rows)
    table["difference_p_holm"] = adjusted_p(table["difference_p"], "holm")
    return table.assign(level=level)


# ----------------------------------------------------------------------------- stress
def _measured_terms(fourth) -> tuple[np.ndarray, np.ndarray]:
    return (
        np.einsum("kl,...ijkl->...ij", _FLOW.e_hat, fourth),
        np.einsum("kl,...ijkl->...ij", _FLOW.e_comp, fourth),
    )


def _steady_stress(stress: pd.DataFrame, steady_window) -> pd.Series:
    low, high = steady_window
    return stress[stress["strain"].between(low - 1e-9, high + 1e-9)].mean(numeric_only=True)


def stress_by_seed(
    runs: SeedRuns,
    stress_startup: pd.DataFrame,
    stress_rotations: dict[float, pd.DataFrame],
    phi: float,
    steady_window,
    fitted: dict | None = None,
) -> pd.DataFrame:
    """Per stress source and quantity (`STRESS_QUANTITIES`): the predicted and simulated
    steady values and, per theta, the mean square of (prediction - simulation)/eta_r^ss over (0, W]
    (theta NaN on the steady rows). ``fitted``:
    [`seed_fabric_curves`][suspension_fabric.evaluation.error_decomposition.seed_fabric_curves] of ``runs``, if made."""
    steady = _steady_stress(stress_startup, steady_window)
    lub, con = float(steady["lubrication_12"]), float(steady["contact_12"])
    beta = gw_equations.fit_gw(runs.n12_ss, phi)
    model_ss = fabric_models.steady_state(fabric_models.GW, {"beta": beta}, phi)
    coefficient = {
        "model": coefficients(GW_RELATION, model_ss, lub, con, {}),
        "closure": coefficients(GW_RELATION, runs.fabric_ss, lub, con, {}),
    }
    hydro_ss, contact_ss = _measured_terms(runs.fourth_ss)
    coefficient["measured"] = {"a_H": lub / hydro_ss[0, 1], "a_C": con / contact_ss[0, 1]}

    def predict(source, fabric, fourth):
        if source == "measured":
            return stress_from_forms(*_measured_terms(fourth), coefficient[source], phi)
        return relation_stress(GW_RELATION, fabric, coefficient[source], {}, phi)

    rows = []
    for source in STRESS_SOURCES:
        fabric = model_ss if source == "model" else runs.fabric_ss
        predicted = predict(source, fabric, runs.fourth_ss)
        for quantity in STRESS_QUANTITIES:
            rows.append(
                {
                    "seed": runs.seed,
                    "source": source,
                    "quantity": quantity,
                    "theta": np.nan,
                    "predicted": float(predicted[quantity]),
                    "simulated": float(steady[quantity]),
                    "mse": np.nan,
                }
            )
    eta_ss = float(steady["eta_r"])
    fitted = (fitted or seed_fabric_curves(runs, phi))["curves"]
    for theta, rows_fabric in runs.rotations.items():
        if theta == 0.0:
            continue
        if theta not in stress_rotations:
            raise ValueError(f"seed {runs.seed}, theta = {theta:g}: no stress table for this rotation")
        stress = stress_rotations[theta].sort_values("strain")
        strain = rows_fabric["strain"].to_numpy(dtype=float)
        stress = stress.set_index(stress["strain"].round(9)).reindex(np.round(strain, 9))
        if stress["eta_r"].isna().any():
            raise ValueError(f"seed {runs.seed}, theta = {theta:g}: the stress table lacks frames of the fabric table")
        fourth = fourth_moment_tensors(rows_fabric)
        for source in STRESS_SOURCES:
            fabric = fitted[theta][("closure", "fixed_point")] if source == "model" else fitted[theta]["sim"]
            predicted = predict(source, fabric, fourth)
            for quantity in STRESS_QUANTITIES:
                rows.append(
                    {
                        "seed": runs.seed,
                        "source": source,
                        "quantity": quantity,
                        "theta": theta,
                        "predicted": np.nan,
                        "simulated": np.nan,
                        "mse": float(
                            mean_square(predicted[quantity] / eta_ss, stress[quantity].to_numpy() / eta_ss, strain)
                        ),
                    }
                )
    return pd.DataFrame(rows)


def stress_decomposition_table(per_seed: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """Per source and quantity: the steady prediction and the simulation (t-intervals over seeds),
    their paired difference, and the mean square error after a rotation (all angles but 0) with
    its t-interval."""
    rows = []
    steady = per_seed[per_seed["theta"].isna()]
    after = per_seed[per_seed["theta"].notna()].groupby(["source", "quantity", "seed"])["mse"].mean()
    for source in STRESS_SOURCES:
        for quantity in STRESS_QUANTITIES:
            mine = steady[(steady["source"] == source) & (steady["quantity"] == quantity)].set_index("seed")
            predicted, simulated = (t_interval(mine[c].to_numpy(), level) for c in ("predicted", "simulated"))
            miss = t_interval((mine["predicted"] - mine["simulated"]).to_numpy(), level)
            row = {
                "source": source,
                "label": STRESS_SOURCES[source],
                "quantity": quantity,
                "n_seeds": predicted.n,
                "steady_predicted": predicted.mean,
                "steady_predicted_low": predicted.low,
                "steady_predicted_high": predicted.high,
                "steady_simulated": simulated.mean,
                "steady_simulated_low": simulated.low,
                "steady_simulated_high": simulated.high,
                "steady_miss": miss.mean,
                "steady_miss_low": miss.low,
                "steady_miss_high": miss.high,
            }
            if (source, quantity) in after.index:
                transient = t_interval(after.loc[(source, quantity)].to_numpy(), level)
                row.update(
                    rotation_mse=transient.mean, rotation_mse_low=transient.low, rotation_mse_high=transient.high
                )
            rows.append(row)
    return pd.DataFrame(rows).assign(level=level)


# ----------------------------------------------------------------------------- a study
def has_fourth_moment(fabric: pd.DataFrame) -> bool:
    """Whether every frame of the fabric tables ``fabric`` recorded the fourth moment."""
    return bool(len(fabric)) and not fabric[list(FOURTH_MOMENT_COMPONENTS)].isna().any().any()


def decompose(
    startup: pd.DataFrame,
    rotation: pd.DataFrame,
    stress_startup: pd.DataFrame,
    stress_rotation: pd.DataFrame,
    phi: float,
    steady_window,
    window: float,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """([`fabric_scores`][suspension_fabric.evaluation.error_decomposition.fabric_scores],
    [`stress_by_seed`][suspension_fabric.evaluation.error_decomposition.stress_by_seed] of every seed) of a study from
    its fabric tables with the fourth moment (``startup``, ``rotation``: the runs' tables concatenated) and its per-seed
    stress tables (stress_startup_runs.csv, stress_rotation_runs.csv)."""
    if not (has_fourth_moment(startup) and has_fourth_moment(rotation)):
        raise ValueError("the error decomposition needs the fourth moment in every fabric table")
    seed_runs, stress = [], []
    for seed, rows in startup.groupby("seed"):
        mine = rotation[rotation["seed"] == seed]
        seed_runs.append(SeedRuns(rows, dict(tuple(mine.groupby("theta"))), steady_window, window))
    fitted = {runs.seed: seed_fabric_curves(runs, phi) for runs in seed_runs}
    for runs in seed_runs:
        mine = stress_rotation[stress_rotation["seed"] == runs.seed]
        stress.append(
            stress_by_seed(
                runs,
                stress_startup[stress_startup["seed"] == runs.seed],
                dict(tuple(mine.groupby("theta"))),
                phi,
                steady_window,
                fitted[runs.seed],
            )
        )
    return fabric_scores(seed_runs, phi, fitted), pd.concat(stress, ignore_index=True)


# ----------------------------------------------------------------------------- summary
def _interval_text(mean, low, high, digits: int = 3) -> str:
    return f"{mean:.{digits}g} [{low:.{digits}g}, {high:.{digits}g}]"


def summary_markdown(fabric: pd.DataFrame, stress: pd.DataFrame, scores: pd.DataFrame | None = None) -> str:
    """The decomposition as Markdown: both tables and the paragraph that reads them, every number
    from the tables (``fabric``:
    [`decomposition_table`][suspension_fabric.evaluation.error_decomposition.decomposition_table]; ``stress``:
    [`stress_decomposition_table`][suspension_fabric.evaluation.error_decomposition.stress_decomposition_table];
    ``scores``: [`fabric_scores`][suspension_fabric.evaluation.error_decomposition.fabric_scores], for the rates)."""
    if fabric.empty:
        return "No run of this study recorded the fourth moment: the decomposition needs it.\n"
    level = int(round(100 * fabric["level"].iloc[0]))
    lines = [
        f"Fabric: mean square error after a rotation in units of (⟨nn⟩₁₂ˢˢ)², mean over "
        f"{int(fabric['n_seeds'].max())} seeds [{level}% t-interval], net of the same seed's error without a "
        "rotation (the θ = 0 control, whose own row gives the error net of the seed-noise floor); the difference "
        "is paired per seed, from G-W with the paper's closure whose rate was fitted by the same criterion. "
        "Criteria: *fixed point*, the variant's own fixed point has the measured steady ⟨nn⟩₁₂; *balance*, "
        "the variant's right-hand side vanishes at the measured steady state (12 component; all six for "
        "separate rates). Steady residual: the largest component of that right-hand side, per unit strain.",
        "",
        "| criterion | angles | variant | steady residual | ⟨nn⟩₁₂ | minus G-W | ⟨nn⟩₂₃ | minus G-W |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for (criterion, group, variant), rows in fabric.groupby(["criterion", "angles", "variant"], sort=False):
        cells = []
        for component in SCORED:
            row = rows[rows["component"] == component].iloc[0]
            if group == CONTROL:
                cells.append(_interval_text(row["net_mse"], row["net_mse_low"], row["net_mse_high"]))
            else:
                cells.append(_interval_text(row["minus_control"], row["minus_control_low"], row["minus_control_high"]))
            cells.append(
                ""
                if variant == "closure" or group == CONTROL
                else _interval_text(row["difference"], row["difference_low"], row["difference_high"])
            )
        residual = f"{rows['steady_residual'].iloc[0]:.2g}"
        angles = group.replace("theta", "θ")
        lines.append(
            f"| {criterion.replace('_', ' ')} | {angles} | {FABRIC_VARIANTS[variant]} | {residual} | "
            + " | ".join(cells)
            + " |"
        )
    lines += [
        "",
        f"Stress: the G-W relation's steady N₁, N₂ and Π (units of η_f γ̇) from each source, the "
        f"simulation's, and the mean square error after a rotation in units of (η_rˢˢ)² [{level}% t-intervals].",
        "",
        "| source | quantity | predicted steady | simulated steady | after a rotation |",
        "|---|---|---|---|---|",
    ]
    for _, row in stress.iterrows():
        lines.append(
            f"| {row['label']} | {_QUANTITY_LABELS[row['quantity']]} | "
            f"{_interval_text(row['steady_predicted'], row['steady_predicted_low'], row['steady_predicted_high'])} | "
            f"{_interval_text(row['steady_simulated'], row['steady_simulated_low'], row['steady_simulated_high'])} | "
            f"{_interval_text(row['rotation_mse'], row['rotation_mse_low'], row['rotation_mse_high'])} |"
        )
    lines += ["", _reading(fabric, stress, scores)]
    return "\n".join(lines) + "\n"


def _row(fabric: pd.DataFrame, group: str, variant: str, component: str, criterion: str) -> pd.Series:
    rows = fabric[
        (fabric["angles"] == group)
        & (fabric["variant"] == variant)
        & (fabric["component"] == component)
        & (fabric["criterion"] == criterion)
    ]
    return rows.iloc[0]


def _difference_text(row: pd.Series, level: float, cells: int) -> str:
    """The reading of a difference: larger or smaller only where its Holm-adjusted p-value over the
    table's ``cells`` differences is below 1 - level."""
    decided = row["difference_p_holm"] < 1.0 - level
    verdict = ("larger" if row["difference"] > 0 else "smaller") if decided else "not different"
    interval = _interval_text(row["difference"], row["difference_low"], row["difference_high"])
    return f"{verdict} ({interval}; Holm-adjusted p = {row['difference_p_holm']:.2g} over {cells} differences)"


def _reading(fabric: pd.DataFrame, stress: pd.DataFrame, scores: pd.DataFrame | None = None) -> str:
    parts = ["Reading, plainly:"]
    level, cells = float(fabric["level"].iloc[0]), int(fabric["difference_p"].notna().sum())
    for criterion in CRITERIA:
        name = criterion.replace("_", " ")
        for component, label in (("n12", "⟨nn⟩₁₂"), ("n23", "⟨nn⟩₂₃")):
            groups = [g for g in ANGLE_GROUPS if g not in (CONTROL, "all") and (fabric["angles"] == g).any()]
            readings = []
            for group in groups:
                row = _row(fabric, group, "closure_corrected", component, criterion)
                readings.append(f"{group} degrees {_difference_text(row, level, cells)}")
            full = _row(fabric, "all", "closure", component, criterion)
            parts.append(
                f"With rates fitted by the {name} criterion, G-W's {label} error after a rotation, beyond its error "
                f"without one, is {full['minus_control']:.3g}; with the closure's error removed along each run it is, "
                "per group of angles: " + "; ".join(readings) + "."
            )
    if scores is not None and not scores.empty:
        extension = t_interval(scores.groupby("seed")["steady_extension"].first().to_numpy(), LEVEL)
        measured = _interval_text(extension.mean, extension.low, extension.high)
        phi = float(scores["phi"].iloc[0])
        parts.append(
            f"The trace of (1) ties every single-rate steady state to Eh_e:⟨nn⟩ = φ/6 = {phi / 6:.3g}, whatever the "
            f"closure and the rate; the simulations' steady Eh_e:⟨nn⟩ is {measured} ({int(100 * LEVEL)}% "
            "t-interval over seeds), so no single rate holds both the steady ⟨nn⟩₁₂ and the trace."
        )
        rates = scores[scores["variant"] == "measured_rates"][list(RATE_NAMES)].mean()
        parts.append(
            f"Three separate rates that balance the measured steady state, (b_e, b_c, a) = ({rates['beta_e']:.3g}, "
            f"{rates['beta_c']:.3g}, {rates['A']:.3g}) (seed means), state the steady flux balance "
            "b_e Eh_e:⟨nn⟩ = (φ/15)(b_c + 3a/2), not a ratio of formation to breaking."
        )
    measured = stress[stress["source"] == "measured"].set_index("quantity")
    closure = stress[stress["source"] == "closure"].set_index("quantity")
    model = stress[stress["source"] == "model"].set_index("quantity")
    for quantity in ("N1", "N2", "Pi"):
        parts.append(
            f"Steady {_QUANTITY_LABELS[quantity]}: simulated {measured.loc[quantity, 'steady_simulated']:.3g}; "
            f"the G-W relation gives {model.loc[quantity, 'steady_predicted']:.3g} on G-W's fabric, "
            f"{closure.loc[quantity, 'steady_predicted']:.3g} on the measured ⟨nn⟩ through the closure and "
            f"{measured.loc[quantity, 'steady_predicted']:.3g} on the measured ⟨nnnn⟩."
        )
    return " ".join(parts)
