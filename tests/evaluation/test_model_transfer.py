"""The transfer model (suspension_fabric.evaluation.model_transfer) on curves whose answer is known: made
by integrating (2) itself, with coefficients linear in phi and mu, at four state points."""

import json

import numpy as np
import pytest

from suspension_fabric.evaluation import model_transfer
from suspension_fabric.evaluation.model_benchmark import SeedCurves
from suspension_fabric.evaluation.protocol_benchmark import ProtocolCurves
from suspension_fabric.io.protocols import Protocol, Segment
from suspension_fabric.models import fabric_models
from suspension_fabric.models.gillissen_wilson import closure_model_rhs, split_strain_rate

NAMES = [name for name in model_transfer.LIBRARY if model_transfer.ORDER[name] <= 1]
PHI0, MU0 = model_transfer.REFERENCE_POINT
# dissipative part of the truth: formation on compression, isotropic formation, breaking; the
# breaking rate grows with phi and the formation with mu
TRUE = {
    "Ec": (-0.8, -2.0, 0.0),
    "tr(Ec) I": (-0.4, 0.0, -0.3),
    "X": (-2.5, -6.0, 0.0),
}


def _truth(phi, mu) -> model_transfer.TransferFit:
    coefficients = np.zeros(3 * len(NAMES))
    for name, (a, b, c) in TRUE.items():
        k = NAMES.index(name)
        coefficients[k], coefficients[len(NAMES) + k], coefficients[2 * len(NAMES) + k] = a, b, c
    return model_transfer.TransferFit(NAMES, coefficients, 0.0)


def _point(phi, mu, seeds=(1, 2)) -> model_transfer.MapPoint:
    model = _truth(phi, mu).model(phi, mu)
    startup_strains, rotation_strains = np.linspace(0.0, 4.0, 201), np.linspace(0.0, 2.0, 101)
    thetas = np.array([0.0, 90.0, 180.0])
    startups, rotations = [], []
    for seed in seeds:
        start = np.diag([0.05, 0.05, 0.05]) + 0.005 * seed * np.diag([1.0, -1.0, 0.0])
        startup = fabric_models.startup_shear(model, startup_strains, {"rate": 1.0}, phi, start)
        startups.append(startup)
        rotations.append(
            fabric_models.rotated_shear(model, startup[-1], np.radians(thetas), rotation_strains, {"rate": 1.0}, phi)
        )
    startup, rotation = np.stack(startups), np.stack(rotations)
    curves = SeedCurves(
        np.array(seeds), startup_strains, startup, thetas, rotation_strains, rotation, startup[:, 0].mean(0),
        float(startup[:, startup_strains >= 2.0, 0, 1].mean()),
    )  # fmt: skip
    return model_transfer.MapPoint(
        f"phi{phi}_mu{mu}",
        phi,
        mu,
        curves,
        {(s, 0.0): (startup_strains, startup[i]) for i, s in enumerate(seeds)},
        {(s, t): (rotation_strains, rotation[i, j]) for i, s in enumerate(seeds) for j, t in enumerate(thetas)},
        4.0,
        (2.0, 4.0),
        10.0,
    )


@pytest.fixture(scope="module")
def points():
    grid = ((0.40, 0.0), (0.45, 0.5), (0.50, 1.0), (0.50, 0.0), (0.40, 1.0), (0.45, 0.0), (0.45, 1.0))
    return [_point(phi, mu) for phi, mu in grid]


def test_the_kinematic_part_is_g_w_affine_deformation_with_the_paper_closure():
    """(2) with no dissipative term: dX/dgamma = L.X + X.L^T - 2 L:<nnnn> (G-W at zero rates)."""
    model = model_transfer.TransferFit(NAMES, np.zeros(3 * len(NAMES)), 0.0).model(0.45, 0.5)
    fabric = np.array([[0.5, -0.1, 0.02], [-0.1, 0.6, 0.03], [0.02, 0.03, 0.55]])
    flow = fabric_models.flow_of(np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    grad_hat, _, e_ext, e_comp, _ = split_strain_rate(flow.grad_hat)
    expected = closure_model_rhs(fabric, grad_hat, e_ext, e_comp, 0.0, 0.0, 0.0, 0.45)
    assert np.allclose(model.rhs(fabric, flow, {"rate": 1.0}, 0.45), expected, atol=1e-12)


def test_coefficients_are_linear_in_phi_and_mu():
    """c_k(phi, mu) = a_k + b_k (phi - phi0) + c_k (mu - mu0), the kinematic part added unchanged."""
    fit = _truth(0.45, 0.5)
    at = fit.at(PHI0 + 0.1, MU0 - 0.5)
    for name, (a, b, c) in TRUE.items():
        assert at[name] == pytest.approx(a + 0.1 * b - 0.5 * c + model_transfer.KINEMATIC.get(name, 0.0))
    assert at["Ee.X + X.Ee"] == pytest.approx(model_transfer.KINEMATIC["Ee.X + X.Ee"])


def test_a_fit_over_the_points_recovers_the_coefficients_that_made_them(points):
    fit = model_transfer._fit_at(points, NAMES, 1e-3, {})
    truth = _truth(0.45, 0.5)
    found = dict(zip(model_transfer._columns(NAMES), fit.coefficients.round(4)))
    assert np.array_equal(fit.coefficients != 0, truth.coefficients != 0), found
    # the weak form's quadrature error (Simpson over 0.02 strain) is what is left
    assert np.allclose(fit.coefficients, truth.coefficients, rtol=2e-3, atol=1e-6), found


def test_each_held_out_point_is_predicted_by_a_fit_on_the_others(points, monkeypatch):
    monkeypatch.setattr(model_transfer, "THRESHOLDS", (1e-3, 0.3))
    scores, folds = model_transfer.leave_one_point_out(points)
    assert list(folds["point"]) == [p.name for p in points]
    for point in points:
        own = scores[point.name]
        assert np.all(own["transfer"] < 1e-5), own["transfer"]  # the truth lies in the form: recovered
        assert np.all(own["gw"][:, [3, 5]].sum(axis=1) > 1e-3)  # G-W is not the truth
    assert (folds["least_eigenvalue"] > 0).all()
    table = model_transfer.point_table(scores, points)
    assert len(table) == 2 * len(points)
    assert np.all(table["p_holm"] >= table["p_one_sided"])


def test_the_model_file_reads_back_and_a_foreign_file_is_refused_by_name(points, tmp_path):
    fit = _truth(0.45, 0.5)
    path = model_transfer.write_transfer_file(tmp_path / "transfer.json", fit, points, "synthetic")
    back, source = model_transfer.read_transfer_file(path)
    assert np.array_equal(back.coefficients, fit.coefficients) and back.names == NAMES
    assert [p["point"] for p in source["points"]] == [p.name for p in points]
    record = json.loads(path.read_text())
    path.write_text(json.dumps({**record, "kind": "sparse"}))
    with pytest.raises(ValueError, match=r"transfer\.json.*kind 'sparse'"):
        model_transfer.read_transfer_file(path)


def test_a_reversal_scores_the_shear_component_and_leaves_out_the_one_symmetry_keeps_at_zero():
    """Curves made by G-W: its error is 0, so T = 0.5 G-W - model < 0 and the target is not met."""
    protocol = Protocol("reversal", (Segment(2.0), Segment(2.0, 180.0)))
    grids = [np.linspace(0.0, 2.0, 51)] * 2
    start = np.eye(3) * 0.05
    fabric = fabric_models.protocol_fabric(fabric_models.GW, protocol, grids, {"beta": 10.0}, 0.45, start)
    curves = ProtocolCurves(
        protocol, np.array([1, 2, 3]), grids, [grids[0], grids[1] + 2.0], [np.stack([f] * 3) for f in fabric], None
    )
    table = model_transfer.protocol_table(_truth(0.45, 0.5), 0.45, 0.5, {"reversal": curves}, 10.0, 10.0, -0.1)
    assert list(table["component"]) == ["n12"]
    assert table["gw"].iloc[0] == pytest.approx(0.0, abs=1e-12)
    assert not table["target_met"].iloc[0]
