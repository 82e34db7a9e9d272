"""The nested cross-validation of the sparse model (suspension_fabric.evaluation.nested_selection):
its seed splits never put a seed on both sides, collinear terms are dropped by the design, and on a
'simulation' that is G-W itself both G-W and the order-1 search (which contains G-W exactly) predict
every held-out seed and angle to the interpolation of the weak form."""

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.components import COMPONENTS
from suspension_fabric.evaluation import model_benchmark, nested_selection
from suspension_fabric.models import fabric_models

PHI = 0.45


def test_seed_splits_hold_each_seed_out_once_and_never_train_on_it():
    seeds = np.arange(1, 17)
    splits = nested_selection.seed_splits(seeds)
    assert len(splits) == nested_selection.SEED_GROUPS
    for train, test in splits:
        assert not set(train) & set(test) and set(train) | set(test) == set(seeds)
    assert sorted(np.concatenate([test for _, test in splits])) == list(seeds)
    with pytest.raises(ValueError, match="cannot be split"):
        nested_selection.seed_splits([1])


def test_a_column_the_design_cannot_tell_apart_is_dropped():
    """A column equal to a combination of two others (to 1e-6) goes; the condition number of
    orthonormal columns is 1."""
    rng = np.random.default_rng(0)
    A = rng.normal(size=(200, 3))
    names = ["a", "b", "c", "a+b"]
    design = np.column_stack([A, A[:, 0] + A[:, 1] + 1e-6 * rng.normal(size=200)])
    kept = nested_selection.independent_terms(design, names)
    assert len(kept) == 3 and "c" in kept
    q, _ = np.linalg.qr(A)
    assert nested_selection.design_conditioning(q) == pytest.approx(1.0)


def _table(seed, theta, strains, fabrics) -> pd.DataFrame:
    table = pd.DataFrame({"seed": seed, "theta": theta, "strain": strains})
    for name, (i, j) in COMPONENTS.items():
        table[name] = fabrics[:, i, j]
    return table


def test_on_g_w_itself_the_nested_scores_are_the_noise():
    """Four seeds of a fast G-W (steady within the steady window, as the simulations are; startup
    from no contacts, rotations every 45 degrees), each with independent noise 1e-4: G-W refitted on
    the training seeds and the order-1 search (which holds G-W exactly) predict every held-out seed
    and angle within a few times the noise ((1e-4 / <nn>_12^ss)^2 ~ 1e-6 per component)."""
    rng = np.random.default_rng(5)
    grid_startup, grid_rotation = np.linspace(0.0, 5.0, 251), np.linspace(0.0, 2.0, 101)
    thetas = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
    params = {"beta": 60.0}
    path = fabric_models.startup_shear(fabric_models.GW, grid_startup, params, PHI)
    rotated = fabric_models.shear_rotation(fabric_models.GW, np.radians(thetas), grid_rotation, params, PHI)
    startups, rotations = [], []
    for seed in (1, 2, 3, 4):

        def noisy(x):
            return x + 1e-4 * rng.normal(size=x.shape) * (x != 0)

        startups.append(_table(seed, 0.0, grid_startup, noisy(path)))
        for theta, curve in zip(thetas, rotated):
            rotations.append(_table(seed, theta, grid_rotation, noisy(curve)))
    startup, rotation = pd.concat(startups, ignore_index=True), pd.concat(rotations, ignore_index=True)
    curves = model_benchmark.seed_curves(startup, rotation, 2.0, (2.0, 5.0))
    errors, folds = nested_selection.nested_errors(startup, rotation, curves, PHI, 5.0, 2, (2.0, 5.0), max_orders=(1,))
    assert set(errors) == {"gw", "sparse_order1"}
    for key, values in errors.items():
        assert values.shape == (4, 6) and values.sum(axis=1).max() < 1e-4, (key, values.max())
    assert len(folds) == 2 * 2 and set(folds["search"]) == {"order <= 1"}
    # every seed is tested once per split, by a fit that did not train on it
    tested = [int(s) for text in folds["test_seeds"] for s in text.split()]
    assert sorted(set(tested)) == [1, 2, 3, 4]
    summary = nested_selection.summary_markdown(nested_selection.nested_comparison(errors, curves), folds)
    assert "order <= 1" in summary and "⟨nn⟩₁₂" in summary


def test_a_model_that_diverges_on_a_held_out_seed_misses_the_target():
    """A searched model whose prediction diverges from one held-out seed's start is scored on the
    other seeds, counts that seed and misses the target, however small its other errors."""
    rng = np.random.default_rng(2)
    seeds, angles, strains = 4, 2, np.linspace(0.0, 2.0, 11)
    rotation = rng.normal(size=(seeds, angles, len(strains), 3, 3)) * 1e-3 - 0.1
    curves = model_benchmark.SeedCurves(
        np.arange(1, seeds + 1), strains, rotation[:, 0], np.array([0.0, 90.0]), strains, rotation, np.eye(3), -0.1
    )
    gw = np.full((seeds, 6), 0.1)
    found = np.full((seeds, 6), 1e-4)
    found[2] = np.inf
    table = nested_selection.nested_comparison({"gw": gw, "sparse_order2": found}, curves)
    assert (table["diverged_seeds"] == 1).all() and not table["target_met"].any()
    assert np.isfinite(table["candidate_net"]).all()
