"""Known-answer tests of suspension_fabric.evaluation.claims (docs/verdict_statistics.md, Secs. 2-6).

1. The functionals (deficit, transverse effect, overshoot excess, mean square) on analytic curves.
2. angle_statistics / claim_values / claim_table on hand-made SeedReplicate objects whose answers are
   closed forms.
3. range_edge_table's moved edges.
4. End to end with seed_replicate on data that IS the G-W model.
5. Choice validation and the list of study choices.

Two closed forms of the trapezoidal rule on a uniform grid of step h are used (both exact, from the
geometric sum / the Euler-Maclaurin formula, which terminates for a quadratic):
  trapezoid of exp(-g/g0) over [0, W] = (h/2) coth(h/(2 g0)) (1 - exp(-W/g0))  -> g0 (1 - exp(-W/g0)),
  trapezoid of g (1 - g) over [0, 1]  = (1 - h^2) / 6                        -> 1/6,
and the sum sum_{k=1}^{N-1} sin(k pi / N) = cot(pi / (2N)).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from suspension_fabric.analysis.fabric import COMPONENTS
from suspension_fabric.evaluation import claims, model_benchmark
from suspension_fabric.evaluation.claims import Choice, Compared, SeedReplicate
from suspension_fabric.models import gillissen_wilson as model
from suspension_fabric.models.fabric_models import GW, MODIFIED

#: The paper's pair, as the default config's verdicts.models names them
COMPARED = Compared(GW, MODIFIED)

# ============================================================================ 1. functionals
H_FINE = 0.001
FINE = np.round(np.arange(0.0, 2.0 + 1e-12, H_FINE), 12)  # [0, 2], step 0.001
W = 2.0
TRAPEZOID_TOL = 1e-5  # trapezoid error (h^2/12) |f'(W) - f'(0)| <~ 1e-7 for these curves


def test_fine_grid():
    """The grid the functionals are checked on: 0, 0.001, ..., 2 (2001 points)."""
    assert len(FINE) == 2001 and FINE[0] == 0.0 and FINE[-1] == 2.0


@pytest.mark.parametrize("a, g0", [(0.5, 0.3), (0.2, 1.0), (-0.1, 0.05)])
def test_deficit_of_exponential_dip(a, g0):
    """D12 of r12 = 1 - a exp(-g/g0) over [0, W] is a g0 (1 - exp(-W/g0)); over [0, 1] the same with W = 1."""
    r12 = 1.0 - a * np.exp(-FINE / g0)
    assert float(claims.deficit(r12, FINE)) == pytest.approx(a * g0 * (1 - math.exp(-W / g0)), abs=TRAPEZOID_TOL)
    half = FINE <= 1.0
    assert float(claims.deficit(r12[half], FINE[half])) == pytest.approx(
        a * g0 * (1 - math.exp(-1.0 / g0)), abs=TRAPEZOID_TOL
    )


def test_deficit_per_angle_and_with_a_baseline_curve():
    """Several angles (axis 0): one deficit each. With a baseline curve b(g) = 1 + 0.05 sin(pi g / 2):
    D12 = integral of (b - r12) = 0.05 x 4/pi + a g0 (1 - exp(-W/g0)) (integral of sin(pi g/2) over
    [0, 2] = 4/pi)."""
    a, g0 = np.array([0.1, 0.4, 0.7]), 0.3
    r12 = 1.0 - a[:, None] * np.exp(-FINE / g0)
    closed = a * g0 * (1 - math.exp(-W / g0))
    got = claims.deficit(r12, FINE)
    assert got.shape == (3,)
    np.testing.assert_allclose(got, closed, atol=TRAPEZOID_TOL)
    baseline = 1.0 + 0.05 * np.sin(np.pi * FINE / 2.0)
    np.testing.assert_allclose(claims.deficit(r12, FINE, baseline), 0.2 / np.pi + closed, atol=TRAPEZOID_TOL)
    np.testing.assert_allclose(claims.deficit(r12, FINE, baseline[None, :]), 0.2 / np.pi + closed, atol=TRAPEZOID_TOL)


def test_transverse_effect_is_oriented_by_the_sign_of_theta():
    """E23 of r23 = c exp(-g/g1) at angles (-60, 60, 120) is sign(theta) c g1 (1 - exp(-W/g1)); the
    angle axis comes before the strain axis; theta = 0 gives 0."""
    thetas = np.array([-60.0, 60.0, 120.0, 0.0])
    c = np.array([0.2, 0.2, -0.15, 0.3])
    g1 = 0.4
    r23 = c[:, None] * np.exp(-FINE / g1)
    expected = np.array([-1.0, 1.0, 1.0, 0.0]) * c * g1 * (1 - math.exp(-W / g1))
    got = claims.transverse_effect(r23, FINE, thetas)
    assert got.shape == (4,)
    np.testing.assert_allclose(got, expected, atol=TRAPEZOID_TOL)
    assert got[0] == pytest.approx(-got[1])


@pytest.mark.parametrize("h", [0.1, 0.03])
def test_overshoot_excess_of_a_sine_bump(h):
    """r12 = 1 + h sin(pi g / W), inside = r12 > 1: X12 = integral of h sin(pi g/W) = 2 h W / pi.
    A mask selecting half the window (g <= W/2): h W / pi, plus the trapezoid's edge term: the masked
    integrand jumps from h (g = 1) to 0 (g = 1.001), and that last segment adds h x step / 2."""
    r12 = 1.0 + h * np.sin(np.pi * FINE / W)
    assert float(claims.overshoot_excess(r12, FINE, r12 > 1.0)) == pytest.approx(2 * h * W / np.pi, abs=TRAPEZOID_TOL)
    half = (r12 > 1.0) & (FINE <= W / 2)
    got = float(claims.overshoot_excess(r12, FINE, half))
    assert got == pytest.approx(h * W / np.pi + h * H_FINE / 2, abs=TRAPEZOID_TOL)
    assert abs(got - h * W / np.pi) <= h * H_FINE / 2 + TRAPEZOID_TOL
    # Nothing inside: 0, whatever the curve.
    assert float(claims.overshoot_excess(r12, FINE, np.zeros_like(FINE, dtype=bool))) == 0.0


def test_overshoot_excess_with_a_baseline_curve():
    """X12 with baseline b(g) = 1 - 0.3 exp(-g/0.2) and r12 = b + h sin(pi g / W) inside everywhere:
    2 h W / pi again (the baseline is subtracted, not 1)."""
    h = 0.05
    b = 1.0 - 0.3 * np.exp(-FINE / 0.2)
    r12 = b + h * np.sin(np.pi * FINE / W)
    got = float(claims.overshoot_excess(r12, FINE, np.ones_like(FINE, dtype=bool), b))
    assert got == pytest.approx(2 * h * W / np.pi, abs=TRAPEZOID_TOL)


def test_mean_square_leaves_strain_zero_out():
    """mean_square = mean over the strains > 0 of (predicted - observed)^2: a difference of 1e6 at
    strain 0 is ignored; with difference 0.1 g elsewhere the value is sum (0.1 g_k)^2 / 2000 over
    g_k = k/1000, k = 1..2000, i.e. 0.01 x 1e-6 x (2000 x 2001 x 4001 / 6) / 2000."""
    observed = 1.0 - 0.3 * np.exp(-FINE / 0.3)
    predicted = observed + 0.1 * FINE
    predicted[0] += 1e6
    expected = 0.01 * 1e-6 * (2000 * 2001 * 4001 / 6) / 2000
    assert float(model_benchmark.mean_square(predicted, observed, FINE)) == pytest.approx(expected, rel=1e-12)
    # Per angle on axis 0, the same rule.
    two = model_benchmark.mean_square(np.stack([predicted, observed]), np.stack([observed, observed]), FINE)
    np.testing.assert_allclose(two, [expected, 0.0], rtol=1e-12, atol=0)


# ============================================================================ 2. hand-made replicates
THETAS = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
H = 0.01
STRAIN = np.round(np.arange(0.0, 2.0 + 1e-9, H), 10)  # 0..2 step 0.01, 201 strains
G0 = 0.3
A_THETA = np.array([0.1, 0.3, 0.5, 0.4, 0.2])  # dip amplitude per angle
SEED_C = {3: 0.01, 7: -0.02, 11: 0.005}  # per-seed constant offset of the simulated r12
SEED_D = {3: 0.004, 7: -0.001, 11: 0.002}  # per-seed slope of the simulated r23
PRIMARY = Choice("primary", 2.0)


def _trap_exp(g0: float, h: float = H, width: float = 2.0) -> float:
    """Exact trapezoid of exp(-g/g0) over [0, width] at step h: (h/2) coth(h/(2 g0)) (1 - exp(-width/g0))."""
    return h / 2.0 / math.tanh(h / (2.0 * g0)) * (1.0 - math.exp(-width / g0))


I_EXP = _trap_exp(G0)


def test_trapezoid_closed_form_is_the_integral():
    """The exact trapezoid value differs from g0 (1 - exp(-W/g0)) by O(h^2) only (and the grid is 0..2)."""
    assert len(STRAIN) == 201 and STRAIN[-1] == 2.0
    assert I_EXP == pytest.approx(G0 * (1 - math.exp(-2.0 / G0)), abs=3e-5)
    assert I_EXP == pytest.approx(
        float(np.sum((np.exp(-STRAIN[1:] / G0) + np.exp(-STRAIN[:-1] / G0)) / 2 * H)), rel=1e-12
    )


def _replicate(seed, thetas=THETAS, a=A_THETA, overshoot_at_90=False) -> SeedReplicate:
    """sim r12 = 1 - a_theta exp(-g/0.3) + c_s; G-W r12 = 1 - 2 a_theta exp(-g/0.3); modified
    r12 = 1 - 1.1 a_theta exp(-g/0.3); r23 = sin(theta) x (0.3, 0.2, 0.25) exp(-g/0.5) for (sim, G-W,
    modified), plus d_s g for the simulation. ``overshoot_at_90``: at 90 deg the modified r12 is
    1 + 0.1 sin(pi g) and the simulated one 1 + k_s |g (1 - g)| with k_s = 1 + 10 c_s."""
    thetas = np.asarray(thetas, dtype=float)
    a = np.asarray(a, dtype=float)[:, None]
    e = np.exp(-STRAIN / G0)[None, :]
    c, d = SEED_C[seed], SEED_D[seed]
    sin = np.sin(np.radians(thetas))[:, None]
    e23 = np.exp(-STRAIN / 0.5)[None, :]
    sim = {"r12": 1.0 - a * e + c, "r23": 0.3 * sin * e23 + d * STRAIN[None, :]}
    gw = {"r12": 1.0 - 2.0 * a * e, "r23": 0.2 * sin * e23}
    modified = {"r12": 1.0 - 1.1 * a * e, "r23": 0.25 * sin * e23}
    if overshoot_at_90:
        i = int(np.flatnonzero(thetas == 90.0)[0])
        modified["r12"][i] = 1.0 + 0.1 * np.sin(np.pi * STRAIN)
        sim["r12"][i] = 1.0 + (1.0 + 10.0 * c) * np.abs(STRAIN * (1.0 - STRAIN))
    return SeedReplicate(
        seed=seed,
        n12_ss=-0.1 - c,
        params={"reference": {"beta": 10.0}, "challenger": {"beta": 9.0, "A": 12.0}},
        thetas=thetas,
        strain=STRAIN.copy(),
        sim=sim,
        models={"reference": gw, "challenger": modified},
    )


@pytest.fixture(scope="module")
def replicates():
    return [_replicate(seed) for seed in SEED_C]


@pytest.fixture(scope="module")
def statistics(replicates):
    return claims.angle_statistics(replicates, PRIMARY)


def _at(table, seed, theta, column):
    row = table[(table["seed"] == seed) & np.isclose(table["theta"], theta)]
    assert len(row) == 1, (seed, theta, column)
    return float(row[column].iloc[0])


def test_angle_statistics_layout(statistics):
    """One row per (seed, theta): 3 seeds x 5 angles; n12_ss is carried over (-0.1 - c_s: -0.08 for seed 7)."""
    assert len(statistics) == 15
    assert sorted(set(statistics["seed"])) == [3, 7, 11]
    for col in (
        "D12_sim",
        "D12_reference",
        "D12_challenger",
        "E23_sim",
        "X12_sim",
        "MSE12_reference",
        "MSE23_challenger",
        "O12_challenger",
        "s2_12",
        "s2_23",
        "n12_ss",
    ):
        assert col in statistics.columns
    assert _at(statistics, 7, 90.0, "n12_ss") == pytest.approx(-0.08)


def test_paired_mse_difference_is_linear_in_the_data(replicates, statistics):
    """MSE_gw - MSE_modified = mean over strains > 0 of (g - x)^2 - (m - x)^2, which equals
    (g - m)(g + m - 2x) pointwise (x simulation, g G-W, m modified); computed here from the latter."""
    after = STRAIN > 0
    for rep in replicates:
        for comp in ("12", "23"):
            x, g, m = rep.sim[f"r{comp}"], rep.models["reference"][f"r{comp}"], rep.models["challenger"][f"r{comp}"]
            product = ((g - m) * (g + m - 2.0 * x))[:, after]
            expected = product.sum(axis=1) / after.sum()
            for k, theta in enumerate(THETAS):
                got = _at(statistics, rep.seed, theta, f"MSE{comp}_reference") - _at(
                    statistics, rep.seed, theta, f"MSE{comp}_challenger"
                )
                assert got == pytest.approx(expected[k], rel=1e-9, abs=1e-15), (rep.seed, theta, comp)


def test_deficits_and_c1_values(statistics):
    """D12(sim) = a_theta I - c_s W and D12(G-W) = 2 a_theta I (I the trapezoid of exp(-g/0.3) over
    [0, 2], W = 2), so C1's T = D12(G-W) - 1.25 D12(sim) = 0.75 a_theta I + 1.25 c_s W per seed and angle."""
    values = claims.claim_values(statistics)
    c1 = values[values["claim"] == "C1"]
    assert len(c1) == 15
    for seed, c in SEED_C.items():
        for theta, a in zip(THETAS, A_THETA):
            assert _at(statistics, seed, theta, "D12_sim") == pytest.approx(a * I_EXP - c * 2.0, abs=1e-12)
            assert _at(statistics, seed, theta, "D12_reference") == pytest.approx(2 * a * I_EXP, abs=1e-12)
            assert _at(statistics, seed, theta, "D12_challenger") == pytest.approx(1.1 * a * I_EXP, abs=1e-12)
            T = 2 * a * I_EXP - 1.25 * (a * I_EXP - 2.0 * c)
            assert T == pytest.approx(0.75 * a * I_EXP + 2.5 * c)
            assert _at(c1, seed, theta, "T") == pytest.approx(T, abs=1e-12)


def test_c1_claim_table_averages_angles_within_seeds(statistics):
    """claim_table's C1: per seed the mean of T over 45, 90, 135; the mean over seeds of that; the
    t-interval (t_{0.975, 2}) of the three per-seed means, not of the nine seed x angle values."""
    chosen = [1, 2, 3]  # 45, 90, 135
    per_seed = np.array(
        [
            np.mean([2 * A_THETA[k] * I_EXP - 1.25 * (A_THETA[k] * I_EXP - 2.0 * c) for k in chosen])
            for c in SEED_C.values()
        ]
    )
    pooled = np.array(
        [2 * A_THETA[k] * I_EXP - 1.25 * (A_THETA[k] * I_EXP - 2.0 * c) for c in SEED_C.values() for k in chosen]
    )
    half_seed = stats.t.ppf(0.975, 2) * np.std(per_seed, ddof=1) / math.sqrt(3)
    half_pooled = stats.t.ppf(0.975, 8) * np.std(pooled, ddof=1) / math.sqrt(9)
    assert abs(half_seed - half_pooled) > 0.01  # the two candidate intervals are far apart

    table = claims.claim_table(claims.claim_values(statistics)).set_index("claim")
    row = table.loc["C1"]
    assert row["angles"] == "45, 90, 135"
    assert row["n_seeds"] == 3
    assert row["mean"] == pytest.approx(per_seed.mean(), abs=1e-12)
    assert row["mean"] == pytest.approx(pooled.mean(), abs=1e-12)  # equal weights: same mean either way
    assert row["low"] == pytest.approx(per_seed.mean() - half_seed, abs=1e-12)
    assert row["high"] == pytest.approx(per_seed.mean() + half_seed, abs=1e-12)
    assert row["se"] == pytest.approx(np.std(per_seed, ddof=1) / math.sqrt(3), abs=1e-12)
    assert row["low"] != pytest.approx(pooled.mean() - half_pooled, abs=1e-6)
    expected_verdict = (
        "confirmed"
        if per_seed.mean() - half_seed > 0
        else "refuted"
        if per_seed.mean() + half_seed < 0
        else "undecided"
    )
    assert row["verdict"] == expected_verdict


def test_noise_floors_are_between_seed_variances(statistics):
    """s2_12 = between-seed variance (ddof 1) of the simulated r12 averaged over strains > 0, as
    each seed's jackknife pseudo-value 3 var(c) - 2 var(c without that seed): the seeds differ by
    the constants c_s, so these are the same at every angle and their mean over seeds is var(c).
    The simulated r23 differs by d_s g, so s2_23 carries var(d)'s pseudo-values x the mean of g^2
    over g = 0.01 k, k = 1..200, i.e. 1e-4 x 201 x 401 / 6 (the strain-0 point left out)."""

    def variance(x):
        return sum((v - sum(x) / len(x)) ** 2 for v in x) / (len(x) - 1)

    def pseudo(table, seed):
        others = [v for s, v in table.items() if s != seed]
        return 3 * variance(list(table.values())) - 2 * variance(others)

    mean_g2 = 1e-4 * 201 * 401 / 6
    for seed in SEED_C:
        rows = statistics[statistics["seed"] == seed]
        np.testing.assert_allclose(rows["s2_12"], pseudo(SEED_C, seed), rtol=1e-9)
        np.testing.assert_allclose(rows["s2_23"], pseudo(SEED_D, seed) * mean_g2, rtol=1e-9)
    by_angle = statistics.groupby("theta")[["s2_12", "s2_23"]].mean()
    np.testing.assert_allclose(by_angle["s2_12"], variance(list(SEED_C.values())), rtol=1e-9)
    np.testing.assert_allclose(by_angle["s2_23"], variance(list(SEED_D.values())) * mean_g2, rtol=1e-9)


def test_one_seed_has_no_noise_floor_and_an_infinite_interval(replicates):
    """A variance with ddof 1 needs two seeds: one seed gets floor 0 (no estimate), its T stays
    finite and every claim's interval is infinite, so nothing is decided."""
    one = claims.angle_statistics(replicates[:1], PRIMARY)
    assert (one["s2_12"] == 0.0).all() and (one["s2_23"] == 0.0).all()
    table = claims.claim_table(claims.claim_values(one))
    decided = table[table["n_seeds"] > 0]
    assert (decided["verdict"] == "undecided").all() and np.isinf(decided["high"]).all()


def test_c3_uses_the_noise_floor(statistics):
    """C3's T = 0.8 (MSE12_reference - s2) - (MSE12_mod - s2) = 0.8 MSE12_reference - MSE12_mod + 0.2 s2."""
    values = claims.claim_values(statistics)
    for claim, comp in (("C3", "12"), ("C4", "23"), ("C3'", "12")):
        rows = values[values["claim"] == claim]
        for _, row in rows.iterrows():
            gw = _at(statistics, row["seed"], row["theta"], f"MSE{comp}_reference")
            mod = _at(statistics, row["seed"], row["theta"], f"MSE{comp}_challenger")
            s2 = _at(statistics, row["seed"], row["theta"], f"s2_{comp}")
            assert row["T"] == pytest.approx(0.8 * (gw - s2) - (mod - s2), rel=1e-12, abs=1e-15)


def test_nn23_claims_leave_out_0_and_180(statistics):
    """C2, C4, C4' have no rows at theta = 0 or 180; the <nn>_12 claims keep every angle."""
    values = claims.claim_values(statistics)
    for key in ("C2", "C4", "C4'"):
        assert sorted(values[values["claim"] == key]["theta"].unique()) == [45.0, 90.0, 135.0], key
    for key in ("C1", "C3", "C3'", "C5", "C6"):
        assert sorted(values[values["claim"] == key]["theta"].unique()) == list(THETAS), key
    table = claims.claim_table(values).set_index("claim")
    assert table.loc["C2", "angles"] == "90, 135"
    assert table.loc["C4'", "angles"] == "45, 90, 135"
    assert table.loc["C3'", "angles"] == "0, 45, 90, 135, 180"


def test_claim_angles_on_a_30_degree_grid():
    """On (0, 30, ..., 180): C2 and C4 (90-180, 180 left out) -> (90, 120, 150); C1 (45-135) ->
    (60, 90, 120); C5 (75-105) -> (90,); C4' -> (30 ... 150)."""
    grid = (0, 30, 60, 90, 120, 150, 180)
    by_key = {c.key: c for c in claims.CLAIMS}
    assert claims.claim_angles(by_key["C2"], grid).tolist() == [90.0, 120.0, 150.0]
    assert claims.claim_angles(by_key["C4"], grid).tolist() == [90.0, 120.0, 150.0]
    assert claims.claim_angles(by_key["C1"], grid).tolist() == [60.0, 90.0, 120.0]
    assert claims.claim_angles(by_key["C5"], grid).tolist() == [90.0]
    assert claims.claim_angles(by_key["C4'"], grid).tolist() == [30.0, 60.0, 90.0, 120.0, 150.0]
    assert claims.claim_angles(by_key["C3'"], grid).tolist() == [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]


def test_overshoot_window_is_the_modified_models():
    """Modified r12(90) = 1 + 0.1 sin(pi g) exceeds 1 only for 0 < g < 1; the simulated r12(90) =
    1 + k_s |g (1 - g)| exceeds 1 on all of (0, 2) \\ {1}. X12(sim) is integrated over the model's
    window only: trapezoid of k_s g (1 - g) on [0, 1] = k_s (1 - h^2)/6 (-> k_s / 6; over the whole
    window it would be k_s (1/6 + 5/6) = k_s). X12(mod) = 0.1 h sum_{k=1}^{99} sin(k pi h) =
    0.1 h cot(pi h / 2) (-> 0.2/pi). At the other angles the modified r12 < 1 everywhere, so X12 = 0
    for every source although the simulated r12 = 1 - a exp(-g/0.3) + c_s exceeds 1 when c_s > 0.
    C5's T = max r12(mod) - 1 - 0.05 = 0.05 at 90; C6's T = 0.25 X12(mod) - X12(sim)."""
    reps = [_replicate(seed, overshoot_at_90=True) for seed in SEED_C]
    table = claims.angle_statistics(reps, PRIMARY)
    values = claims.claim_values(table)
    x_mod = 0.1 * H / math.tan(math.pi * H / 2)
    assert x_mod == pytest.approx(0.2 / math.pi, abs=1e-5)
    for seed, c in SEED_C.items():
        k = 1.0 + 10.0 * c
        x_sim = k * (1 - H**2) / 6
        assert _at(table, seed, 90.0, "X12_sim") == pytest.approx(x_sim, abs=1e-12)
        assert _at(table, seed, 90.0, "X12_sim") == pytest.approx(k / 6, abs=1e-4)
        assert _at(table, seed, 90.0, "X12_challenger") == pytest.approx(x_mod, abs=1e-12)
        assert _at(table, seed, 90.0, "O12_challenger") == pytest.approx(0.1, abs=1e-12)
        assert _at(values[values["claim"] == "C5"], seed, 90.0, "T") == pytest.approx(0.05, abs=1e-12)
        assert _at(values[values["claim"] == "C6"], seed, 90.0, "T") == pytest.approx(0.25 * x_mod - x_sim, abs=1e-12)
        for theta in (0.0, 45.0, 135.0, 180.0):
            for source in ("sim", "reference", "challenger"):
                assert _at(table, seed, theta, f"X12_{source}") == 0.0, (seed, theta, source)
    assert (reps[0].sim["r12"][1] > 1.0).any()  # seed 3 (c > 0): the simulation exceeds 1 at 45 deg


def test_continuation_baseline_is_the_same_seeds_theta_0_curve():
    """baseline "continuation": D12 = integral of r12(theta = 0) - r12(theta) of the same seed. With a
    per-seed dip amplitude at theta = 0, a_0(s): D12(sim) = (a_theta - a_0(s)) I (c_s cancels),
    D12(G-W) = 2 (a_theta - a_0(s)) I, D12(mod) = 1.1 (a_theta - a_0(s)) I; 0 at theta = 0."""
    a0 = {3: 0.1, 7: 0.15, 11: 0.05}
    reps = [_replicate(seed, a=np.r_[a0[seed], A_THETA[1:]]) for seed in SEED_C]
    choice = Choice("x", 2.0, baseline="continuation")
    table = claims.angle_statistics(reps, choice)
    for seed in SEED_C:
        for theta, a in zip(THETAS, np.r_[a0[seed], A_THETA[1:]]):
            delta = (a - a0[seed]) * I_EXP
            assert _at(table, seed, theta, "D12_sim") == pytest.approx(delta, abs=1e-12), (seed, theta)
            assert _at(table, seed, theta, "D12_reference") == pytest.approx(2 * delta, abs=1e-12)
            assert _at(table, seed, theta, "D12_challenger") == pytest.approx(1.1 * delta, abs=1e-12)
    # The steady baseline on the same replicates: 1 - r12.
    steady = claims.angle_statistics(reps, PRIMARY)
    assert _at(steady, 7, 0.0, "D12_sim") == pytest.approx(0.15 * I_EXP + 0.02 * 2.0, abs=1e-12)


def test_continuation_baseline_needs_theta_0():
    """Angles 45..180 only: the steady baseline (1) works, the continuation baseline raises ValueError."""
    reps = [_replicate(seed, thetas=THETAS[1:], a=A_THETA[1:]) for seed in SEED_C]
    claims.angle_statistics(reps, PRIMARY)  # fine with the steady baseline
    with pytest.raises(ValueError, match="theta = 0"):
        claims.angle_statistics(reps, Choice("x", 2.0, baseline="continuation"))


# ============================================================================ 3. range edges
EDGE_THETAS = np.arange(0.0, 181.0, 15.0)


def _text(thetas) -> str:
    return ", ".join(str(int(t)) for t in thetas)


@pytest.fixture(scope="module")
def edge_values():
    """T per (claim, seed, theta) for 4 seeds on 0, 15, ..., 180 (no <nn>_23 rows at 0 and 180)."""
    rng = np.random.default_rng(11)
    rows = []
    for claim in claims.CLAIMS:
        for seed in (1, 2, 3, 4):
            for theta in EDGE_THETAS:
                if claim.skip_symmetric and theta in (0.0, 180.0):
                    continue
                rows.append({"claim": claim.key, "seed": seed, "theta": theta, "T": rng.normal(0.1, 0.3)})
    return pd.DataFrame(rows)


def test_range_edge_table_moves_c1_edges(edge_values):
    """C1 (45-135): low edge out adds 30, low edge in drops 45, high edge in drops 135, high edge out
    adds 150; each row's mean and interval are the t-interval of the per-seed means over its angles."""
    table = claims.range_edge_table(edge_values)
    c1 = table[table["claim"] == "C1"].set_index("edges")
    expected = {
        "as stated": range(45, 136, 15),
        "low edge out": range(30, 136, 15),
        "low edge in": range(60, 136, 15),
        "high edge in": range(45, 121, 15),
        "high edge out": range(45, 151, 15),
    }
    assert set(c1.index) == set(expected)
    for name, angles in expected.items():
        assert c1.loc[name, "angles"] == _text(angles), name
        mine = edge_values[(edge_values["claim"] == "C1") & edge_values["theta"].isin(list(angles))]
        per_seed = mine.groupby("seed")["T"].mean().to_numpy()
        half = stats.t.ppf(0.975, 3) * np.std(per_seed, ddof=1) / 2.0
        assert c1.loc[name, "mean"] == pytest.approx(per_seed.mean(), abs=1e-12)
        assert c1.loc[name, "low"] == pytest.approx(per_seed.mean() - half, abs=1e-12)
        assert c1.loc[name, "high"] == pytest.approx(per_seed.mean() + half, abs=1e-12)


def test_range_edge_table_other_claims(edge_values):
    """C2 (90-180 without 180): as stated 90..165, no 'high edge out' (180 is not eligible), low edge
    out adds 75; C5 (75-105): 60..105 and 75..120 outward, 90..105 and 75..90 inward; no C3'/C4' rows
    (their range is every angle)."""
    table = claims.range_edge_table(edge_values)
    assert not table["claim"].isin(["C3'", "C4'"]).any()
    c2 = table[table["claim"] == "C2"].set_index("edges")["angles"].to_dict()
    assert c2 == {
        "as stated": _text(range(90, 166, 15)),
        "low edge out": _text(range(75, 166, 15)),
        "low edge in": _text(range(105, 166, 15)),
        "high edge in": _text(range(90, 151, 15)),
    }
    c5 = table[table["claim"] == "C5"].set_index("edges")["angles"].to_dict()
    assert c5 == {
        "as stated": "75, 90, 105",
        "low edge out": "60, 75, 90, 105",
        "low edge in": "90, 105",
        "high edge in": "75, 90",
        "high edge out": "75, 90, 105, 120",
    }


# ============================================================================ 4. end to end on G-W data
BETA, PHI = 10.8, 0.45
E2E_SEEDS = (1, 2, 3)
E2E_THETAS = (0.0, 45.0, 90.0, 135.0, 180.0)
STARTUP = np.round(np.arange(0.0, 30.0 + 1e-9, 0.05), 10)
ROTATION = np.round(np.arange(0.0, 2.0 + 1e-9, 0.02), 10)


def _rows(seed, theta, strain, fabric) -> pd.DataFrame:
    """A run table (suspension_fabric.analysis.tables): seed, theta, N, phi, step, strain, n11 ... n23, Z = 2 Tr<nn>."""
    table = pd.DataFrame(
        {"seed": seed, "theta": theta, "N": 500, "phi": PHI, "step": np.arange(len(strain)) * 100, "strain": strain}
    )
    for name, (i, j) in COMPONENTS.items():
        table[name] = fabric[:, i, j]
    table["Z"] = 2.0 * np.trace(fabric, axis1=-2, axis2=-1)
    return table


@pytest.fixture(scope="module")
def gw_runs():
    """Startup (to strain 30, frames every 0.05) and rotation runs (0..180, 2 strain every 0.02) that
    are the G-W model at beta = 10.8, phi = 0.45, from a per-seed initial fabric 0.05 (1 + 0.1 (s - 2)) I."""
    startup, rotation = [], []
    for seed in E2E_SEEDS:
        fabric0 = 0.05 * (1.0 + 0.1 * (seed - 2)) * np.eye(3)
        startup.append(_rows(seed, 0.0, STARTUP, model.startup_shear(STARTUP, BETA, None, PHI, fabric0)))
        after = model.shear_rotation(np.radians(E2E_THETAS), ROTATION, BETA, None, PHI, 30.0, fabric0)
        for k, theta in enumerate(E2E_THETAS):
            rotation.append(_rows(seed, theta, ROTATION, after[k]))
    return pd.concat(startup, ignore_index=True), pd.concat(rotation, ignore_index=True)


def test_gw_runs_are_converged(gw_runs):
    """The steady window [20, 30] is converged: <nn>_12 within 1e-8 of the G-W fixed point."""
    startup, _ = gw_runs
    steady12 = model.steady_state_ode(BETA, None, PHI)[0, 1]
    window = startup[startup["strain"] >= 20.0]
    assert np.abs(window["n12"] - steady12).max() < 1e-8


def _replicates(gw_runs, choice):
    startup, rotation = gw_runs
    return [
        claims.seed_replicate(
            startup[startup["seed"] == s], rotation[rotation["seed"] == s], PHI, (20.0, 30.0), 30.0, choice, COMPARED
        )
        for s in E2E_SEEDS
    ]


@pytest.mark.parametrize(
    "choice",
    [
        Choice("primary", 2.0),
        Choice("state: simulated", 2.0, state="simulated"),
        Choice("state: model steady", 2.0, state="steady"),
    ],
    ids=["primary", "simulated", "steady"],
)
def test_seed_replicate_on_gw_data_recovers_gw(gw_runs, choice):
    """Data = G-W(beta = 10.8): each seed's fitted G-W beta is 10.8 (to 1e-6); its prediction is the
    data, so MSE12_reference, MSE23_reference < 1e-12 and D12(G-W) = D12(sim), E23(G-W) = E23(sim); n12_ss is the
    G-W steady <nn>_12; the effects are not trivially zero (D12(sim) at 90 deg > 0.05). The startup is
    converged at strain 30, so the model's own state, the simulated state at the rotation and the
    model's steady state are one and the same fabric: all three state choices give this."""
    reps = _replicates(gw_runs, choice)
    steady12 = model.steady_state_ode(BETA, None, PHI)[0, 1]
    for rep in reps:
        assert rep.params["reference"]["beta"] == pytest.approx(BETA, abs=1e-6)
        assert rep.n12_ss == pytest.approx(steady12, abs=1e-8)
        assert rep.strain.tolist() == ROTATION.tolist()
        assert rep.thetas.tolist() == list(E2E_THETAS)
    table = claims.angle_statistics(reps, choice)
    assert len(table) == len(E2E_SEEDS) * len(E2E_THETAS)
    assert table["MSE12_reference"].max() < 1e-12
    assert table["MSE23_reference"].max() < 1e-12
    np.testing.assert_allclose(table["D12_reference"], table["D12_sim"], atol=1e-7, rtol=0)
    np.testing.assert_allclose(table["E23_reference"], table["E23_sim"], atol=1e-7, rtol=0)
    assert (table[table["theta"] == 90.0]["D12_sim"] > 0.05).all()
    # C1's T is then D12(sim) (1 - 1.25) = -0.25 D12(sim).
    values = claims.claim_values(table)
    c1 = values[values["claim"] == "C1"].set_index(["seed", "theta"])["T"]
    np.testing.assert_allclose(
        c1.to_numpy(), -0.25 * table.set_index(["seed", "theta"]).loc[c1.index, "D12_sim"], atol=1e-7
    )


def model_gradient():
    """Simple shear L = e1 e2 (velocity gradient du_1/dx_2 = 1), written out here."""
    gradient = np.zeros((3, 3))
    gradient[0, 1] = 1.0
    return gradient


def test_simulated_state_starts_from_the_rotation_runs_first_frame(gw_runs):
    """Rotation runs started from the rotated G-W steady fabric plus a perturbation P (P_11 = 0.01,
    P_23 = 0.005), then sheared by G-W: under state "simulated" the G-W prediction starts from the
    runs' own first frame and is the data (MSE < 1e-12); under state "own" it starts from the
    unperturbed fabric, so at theta = 0 its r12 error at strain 0 is P_12 / n12_ss = 0 and its r23
    error at strain 0 is P_23 / n12_ss: MSE23 > 0."""
    startup, _ = gw_runs
    seed = 2
    fabric0 = 0.05 * np.eye(3)
    perturbation = np.zeros((3, 3))
    perturbation[0, 0] = 0.01
    perturbation[1, 2] = perturbation[2, 1] = 0.005
    before = model.shear_rotation(np.radians(E2E_THETAS), np.array([0.0]), BETA, None, PHI, 30.0, fabric0)[:, 0]
    after = model.integrate_fabric(before + perturbation, model_gradient(), ROTATION, BETA, None, PHI)
    rotation = pd.concat(
        [_rows(seed, theta, ROTATION, after[k]) for k, theta in enumerate(E2E_THETAS)], ignore_index=True
    )
    mine = startup[startup["seed"] == seed]
    simulated = claims.seed_replicate(
        mine, rotation, PHI, (20.0, 30.0), 30.0, Choice("s", 2.0, state="simulated"), COMPARED
    )
    own = claims.seed_replicate(mine, rotation, PHI, (20.0, 30.0), 30.0, Choice("o", 2.0), COMPARED)
    a = claims.angle_statistics([simulated], Choice("s", 2.0, state="simulated"))
    b = claims.angle_statistics([own], Choice("o", 2.0))
    assert a["MSE12_reference"].max() < 1e-12 and a["MSE23_reference"].max() < 1e-12
    assert b["MSE23_reference"].min() > 1e-6
    n12_ss = own.n12_ss
    assert own.sim["r23"][0, 0] - own.models["reference"]["r23"][0, 0] == pytest.approx(0.005 / n12_ss, rel=1e-6)


def test_paper_fit_uses_the_printed_parameters(gw_runs):
    """fit "paper" (docs/verdict_statistics.md Sec. 7): G-W beta 10.9, modified (beta, A) = (9.4, 42.4)
    for every seed, whatever the data."""
    reps = _replicates(gw_runs, Choice("p", 2.0, fit="paper"))
    for rep in reps:
        assert rep.params["reference"] == {"beta": 10.9}
        assert rep.params["challenger"] == {"beta": 9.4, "A": 42.4}


def test_study_claim_values_on_gw_data(gw_runs):
    """study_claim_values: statistics, T values and the per-seed fits table (reference_beta = 10.8)."""
    startup, rotation = gw_runs
    table, values, fits = claims.study_claim_values(
        startup, rotation, PHI, (20.0, 30.0), 30.0, Choice("primary", 2.0), COMPARED
    )
    assert sorted(fits["seed"]) == list(E2E_SEEDS)
    np.testing.assert_allclose(fits["reference_beta"], BETA, atol=1e-6)
    assert set(fits["reference"]) == {"gw"} and set(fits["challenger"]) == {"modified"}
    assert table["MSE12_reference"].max() < 1e-12
    assert set(values["claim"]) == {c.key for c in claims.CLAIMS}


def test_seed_replicate_rejects_a_window_beyond_the_runs(gw_runs):
    """The rotation runs reach strain 2 < window 3: ValueError naming the seed."""
    startup, rotation = gw_runs
    with pytest.raises(ValueError, match="seed 2"):
        claims.seed_replicate(
            startup[startup["seed"] == 2],
            rotation[rotation["seed"] == 2],
            PHI,
            (20.0, 30.0),
            30.0,
            Choice("window 3", 3.0),
            COMPARED,
        )


# ============================================================================ 5. choices
@pytest.mark.parametrize(
    "field, kwargs",
    [
        ("state", {"state": "frozen"}),
        ("fit", {"fit": "transient"}),
        ("baseline", {"baseline": "zero"}),
        ("window", {"window": 0.0}),
        ("window", {"window": -1.0}),
    ],
)
def test_choice_validation_names_the_field(field, kwargs):
    """state not in (own, simulated, steady), fit not in (steady, startup, paper), baseline not in
    (steady, continuation), window <= 0: ValueError whose message names Choice.<field>."""
    arguments = {"name": "x", "window": 2.0, **kwargs}
    with pytest.raises(ValueError, match=rf"Choice\.{field}\b"):
        Choice(**arguments)


def test_study_choices():
    """Primary, then one change at a time: state simulated, state steady, window 1, fit on the startup
    curve, fit with the paper's printed values (added later, docs/verdict_statistics.md Sec. 7),
    continuation baseline; window 3 only when the runs reach strain 3."""
    choices = claims.study_choices(2.0, 2.0)
    assert [c.name for c in choices] == [
        "primary",
        "state: simulated",
        "state: model steady",
        "window 1",
        "fit: startup curve",
        "fit: paper's values",
        "baseline: theta = 0",
    ]
    by_name = {c.name: c for c in choices}
    assert by_name["primary"] == Choice("primary", 2.0)
    assert by_name["state: simulated"].state == "simulated" and by_name["state: model steady"].state == "steady"
    assert by_name["window 1"].window == 1.0
    assert by_name["fit: startup curve"].fit == "startup"
    assert by_name["fit: paper's values"].fit == "paper"
    assert by_name["baseline: theta = 0"].baseline == "continuation"
    longer = [c.name for c in claims.study_choices(2.0, 3.0)]
    assert longer == [
        "primary",
        "state: simulated",
        "state: model steady",
        "window 1",
        "window 3",
        "fit: startup curve",
        "fit: paper's values",
        "baseline: theta = 0",
    ]
    assert "window 2" not in [c.name for c in claims.study_choices(2.0, 3.0)]  # W = 2 is the primary
    assert [c.name for c in claims.study_choices(1.0, 2.0)][3] == "window 2"
    assert {c.name: c.window for c in claims.study_choices(2.0, 3.0)}["window 3"] == 3.0
