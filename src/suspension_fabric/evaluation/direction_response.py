r"""The response to a change of flow direction at one steady state: each rotated run against the run
at $\theta = 0$ continued from the same checkpoint (same seed, same startup), over windows of strain
after the change.

Per seed $s$, angle $\theta$ and window $W$ (strain since the change, half open: $(a, b]$), a
quantity $q$ is averaged over the frames in $W$, $\bar q_s(\theta, W)$, and compared with the control $\bar q_s(0, W)$:

- $\eta_r$ by the relative change $\bar\eta_s(\theta, W) / \bar\eta_s(0, W) - 1$; at controlled
  stress the physical rate changes by $1/(1 + \cdot) - 1$ of it, as $\dot\gamma = \sigma/\eta$;
- the frictional fraction $f = Z_{frictional}/Z_{touching}$ (of the window means), the contacts per
  particle $Z_{touching}$ and the fabric's $\langle nn\rangle_{12}$ (in the frame of the new flow) by
  the difference $\bar q_s(\theta, W) - \bar q_s(0, W)$.

The seeds are the independent units: each cell (state point, angle, quantity, window) gets the mean
over seeds with its t-interval, the t-test's p-value, and the Holm-adjusted p-value over every cell
of the table, read at once. A cell is ``lower`` or ``higher`` where the adjusted p is below
$1 - \mathrm{level}$ (``level`` the confidence level, `LEVEL` by default), else ``not decided``.
``between_points`` compares two state points' per-seed values of one cell (Welch's interval:
different steady states, independent runs).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from suspension_fabric.analysis.seed_statistics import LEVEL, adjusted_p, t_interval, t_test_p, welch_interval

__all__ = [
    "RESPONSE_WINDOWS",
    "RESPONSE_QUANTITIES",
    "per_seed_responses",
    "response_table",
    "between_points",
    "neighbour_comparisons",
]

#: Windows of strain after the change, chosen before the runs: the first half strain (the
#: transient) and the rest of a 2-strain segment (the recovery)
RESPONSE_WINDOWS = ((0.0, 0.5), (0.5, 2.0))
#: (quantity, how it is compared with the control): "relative" (ratio - 1) or "difference"
RESPONSE_QUANTITIES = (
    ("eta_r", "relative"),
    ("frictional_fraction", "difference"),
    ("Z_touching", "difference"),
    ("n12", "difference"),
)


def _window_means(runs: pd.DataFrame, window, columns) -> pd.DataFrame:
    """Per (seed, theta) the mean of ``columns`` over the frames with strain in ``window`` = (low,
    high] (strain counted from the change: the frame at the change itself, the state before the new
    flow acts, is in no window, and a frame on the edge between two windows is in the first only); a
    (seed, theta) without a frame there is an error naming it."""
    low, high = window
    runs = runs.assign(theta=runs["theta"].astype(float))
    inside = runs[(runs["strain"] > low + 1e-9) & (runs["strain"] <= high + 1e-9)]
    means = inside.groupby(["seed", "theta"])[list(columns)].mean()
    missing = sorted(set(map(tuple, runs[["seed", "theta"]].drop_duplicates().to_numpy())) - set(means.index))
    if missing:
        raise ValueError(f"(seed, theta) {missing} have no frame in the window {list(window)} of strain")
    return means


def per_seed_responses(stress_runs: pd.DataFrame, fabric_runs: pd.DataFrame, windows=RESPONSE_WINDOWS) -> pd.DataFrame:
    """One row per seed, angle (theta != 0), quantity and window: the response (module docstring)
    against the same seed's theta = 0 run. ``stress_runs`` and ``fabric_runs`` are one state point's
    rotation tables (columns seed, theta, strain and eta_r, Z_touching, Z_frictional; n12). A seed
    without its control is an error naming it."""
    rows = []
    for window in windows:
        stress = _window_means(stress_runs, window, ["eta_r", "Z_touching", "Z_frictional"])
        stress["frictional_fraction"] = stress["Z_frictional"] / stress["Z_touching"]
        means = stress.join(_window_means(fabric_runs, window, ["n12"]), how="inner")
        for (seed, theta), values in means.iterrows():
            if theta == 0:
                continue
            if (seed, 0.0) not in means.index:
                raise ValueError(f"seed {seed} has no run at theta = 0 to compare theta = {theta:g} with")
            control = means.loc[(seed, 0.0)]
            for quantity, comparison in RESPONSE_QUANTITIES:
                value = (
                    values[quantity] / control[quantity] - 1.0
                    if comparison == "relative"
                    else (values[quantity] - control[quantity])
                )
                rows.append(
                    {"seed": seed, "theta": theta, "quantity": quantity, "comparison": comparison,
                     "window_low": window[0], "window_high": window[1], "response": float(value)}
                )  # fmt: skip
    return pd.DataFrame(rows)


def response_table(per_seed: pd.DataFrame, level: float = LEVEL) -> pd.DataFrame:
    """One row per cell of ``per_seed`` (`per_seed_responses` rows, with a ``point`` column and any
    columns that describe it): mean over seeds, t-interval at ``level``, n_seeds, p, the Holm-adjusted
    p over every cell, and the reading ("lower", "higher" or "not decided" at the adjusted p)."""
    keys = [column for column in per_seed.columns if column not in ("seed", "response")]
    rows = []
    for cell, seeds in per_seed.groupby(keys, sort=False):
        values = seeds["response"].to_numpy(dtype=float)
        interval = t_interval(values, level)
        rows.append(
            {**dict(zip(keys, cell)), "mean": interval.mean, "low": interval.low, "high": interval.high,
             "n_seeds": len(values), "p": t_test_p(values)}
        )  # fmt: skip
    table = pd.DataFrame(rows)
    table["p_holm"] = adjusted_p(table["p"].to_numpy(), "holm")
    decided = table["p_holm"] < 1.0 - level
    table["reading"] = np.where(decided, np.where(table["mean"] < 0, "lower", "higher"), "not decided")
    return table


def between_points(per_seed: pd.DataFrame, first: str, second: str, *, theta, quantity, window, level=LEVEL):
    """The mean response at point ``first`` minus that at ``second`` for one angle, quantity and
    window (``per_seed`` with a ``point`` column), and how it was taken: per seed (a paired
    t-interval) where both points have the same seeds, which then share their packings (a packing
    depends on the seed and the particles only); Welch's interval otherwise. Returns (interval,
    "paired" or "Welch")."""
    cell = (
        (per_seed["theta"] == theta)
        & (per_seed["quantity"] == quantity)
        & (per_seed["window_low"] == window[0])
        & (per_seed["window_high"] == window[1])
    )
    values = [per_seed[cell & (per_seed["point"] == point)].set_index("seed")["response"] for point in (first, second)]
    if set(values[0].index) == set(values[1].index):
        return t_interval(values[0] - values[1].reindex(values[0].index), level), "paired"
    return welch_interval(values[0].to_numpy(), values[1].to_numpy(), level), "Welch"


def neighbour_comparisons(per_seed: pd.DataFrame, ordered, labels: dict, level=LEVEL) -> pd.DataFrame:
    """Each point of ``ordered`` (point names, by imposed rate or stress) against the one before it,
    for every angle and quantity over the first window (`between_points`): columns first, second (their
    ``labels``), theta, quantity, window_low, window_high, mean, low, high, test (paired or Welch)."""
    window = RESPONSE_WINDOWS[0]
    rows = []
    for second, first in zip(ordered, ordered[1:]):
        for theta in sorted(set(per_seed["theta"])):
            for quantity, _ in RESPONSE_QUANTITIES:
                interval, test = between_points(per_seed, first, second, theta=theta, quantity=quantity,
                                                window=window, level=level)  # fmt: skip
                rows.append(
                    {"first": labels[first], "second": labels[second], "theta": theta, "quantity": quantity,
                     "window_low": window[0], "window_high": window[1], "mean": interval.mean, "low": interval.low,
                     "high": interval.high, "test": test}
                )  # fmt: skip
    return pd.DataFrame(rows)
