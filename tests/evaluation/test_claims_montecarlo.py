"""Monte Carlo check of the decision rule through the claim pipeline (docs/verdict_statistics.md).

Synthetic studies of 4 seeds whose true effect sits exactly at each claim's threshold:
the simulated r12 = 1 - a(theta) exp(-g/0.3) and r23 = b(theta) exp(-g/0.5), G-W with 1.25 times
the r12 dip and 1/1.25 of the r23 transient (so E[T] = 0 for C1 and C2), and the modified model
sqrt(0.8) of the way from the simulation to G-W at every strain (so its squared bias is 0.8 of
G-W's and E[T] = 0 for C3, C4). Each seed adds noise that is shared by all its angles (an offset,
as every angle of a seed branches from one checkpoint) plus AR(1) noise along the strain.

With the 95 % two-sided t-interval over seeds, a claim whose T is linear in the data (C1, C2)
must come out "confirmed" in 2.5 % and "refuted" in 2.5 % of the studies; the test allows 4
binomial standard errors. Treating angles as independent units, or a normal instead of a t
quantile (7.2 % per side with 3 degrees of freedom), would fail it. The mean-square claims (C3,
C4) are quadratic in the noise; their rates must be lower (the rule is conservative there).
Beyond the threshold on the paper's side the wrong verdict must stay rarer than 2.5 % and the
right one must be found most of the time.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.evaluation import claims

STRAIN = np.round(np.arange(0.0, 2.0 + 1e-9, 0.02), 10)
THETAS = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
N_SEEDS, LEVEL = 4, 0.95
PER_SIDE = (1.0 - LEVEL) / 2.0


def truth(factor: float, mse_share: float):
    dip = 0.4 * np.sin(np.radians(THETAS) / 2.0) ** 2
    r12 = 1.0 - dip[:, None] * np.exp(-STRAIN / 0.3)
    r23 = 0.5 * np.sin(np.radians(THETAS))[:, None] * np.exp(-STRAIN / 0.5)
    gw = {"r12": 1.0 - factor * dip[:, None] * np.exp(-STRAIN / 0.3), "r23": r23 / factor}
    modified = {c: sim + np.sqrt(mse_share) * (gw[c] - sim) for c, sim in (("r12", r12), ("r23", r23))}
    return {"r12": r12, "r23": r23}, {"reference": gw, "challenger": modified}


def noise(rng, scale: float) -> np.ndarray:
    ar = np.empty((N_SEEDS, len(THETAS), len(STRAIN)))
    ar[..., 0] = rng.standard_normal(ar.shape[:2])
    rho = 0.9
    for k in range(1, len(STRAIN)):
        ar[..., k] = rho * ar[..., k - 1] + np.sqrt(1 - rho**2) * rng.standard_normal(ar.shape[:2])
    return scale * (0.03 * ar + 0.04 * rng.standard_normal((N_SEEDS, 1, 1)))


def verdict_rates(factor: float, mse_share: float, studies: int, seed: int, noise_scale: float = 1.0) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    sim, models = truth(factor, mse_share)
    choice = claims.Choice("primary", 2.0)
    verdicts = []
    for _ in range(studies):
        e12, e23 = noise(rng, noise_scale), noise(rng, noise_scale)
        replicates = [
            claims.SeedReplicate(
                s + 1, -0.1, {}, THETAS, STRAIN, {"r12": sim["r12"] + e12[s], "r23": sim["r23"] + e23[s]}, models
            )
            for s in range(N_SEEDS)
        ]
        table = claims.claim_table(claims.claim_values(claims.angle_statistics(replicates, choice)), LEVEL)
        verdicts.append(table.set_index("claim")["verdict"])
    verdicts = pd.DataFrame(verdicts)
    return pd.DataFrame({"confirmed": (verdicts == "confirmed").mean(), "refuted": (verdicts == "refuted").mean()})


def test_false_verdict_rates_at_the_threshold_match_the_level():
    studies = 1200
    rates = verdict_rates(1.25, 0.8, studies, seed=11)
    tolerance = 4.0 * np.sqrt(PER_SIDE * (1 - PER_SIDE) / studies)
    for claim in ("C1", "C2"):  # linear in the data: exact t-interval
        for verdict in ("confirmed", "refuted"):
            assert abs(rates.loc[claim, verdict] - PER_SIDE) < tolerance, (claim, verdict, rates.loc[claim].to_dict())
    for claim in ("C3", "C4", "C3'", "C4'"):  # quadratic in the noise: conservative, below the level itself
        for verdict in ("confirmed", "refuted"):
            assert rates.loc[claim, verdict] < PER_SIDE, (claim, verdict, rates.loc[claim].to_dict())


def test_beyond_the_threshold_the_rule_finds_the_effect_and_rarely_refutes():
    studies = 400
    # G-W 2.5 times off, the modified model's squared bias 0.3 of G-W's, half the noise
    rates = verdict_rates(2.5, 0.3, studies, seed=12, noise_scale=0.5)
    tolerance = 4.0 * np.sqrt(PER_SIDE * (1 - PER_SIDE) / studies)
    for claim in ("C1", "C2", "C3", "C4"):
        assert rates.loc[claim, "refuted"] < PER_SIDE + tolerance, (claim, rates.loc[claim].to_dict())
        assert rates.loc[claim, "confirmed"] > 0.5, (claim, rates.loc[claim].to_dict())
