"""Tests of the Gillissen-Wilson stress relation (suspension_fabric.evaluation.stress_model), no LAMMPS.

The relation is sigma^p / (eta_f gammadot) = a_H <nnnn>:E^ + a_C <nnnn>:E^_c for simple shear
e1 e2 in the paper frame: E^ = (e1 e2 + e2 e1)/2 and E^_c = -(1/2) v_c v_c with
v_c = (e1 - e2)/sqrt 2 (its negative-eigenvalue part). Expected values are analytic (the
isotropic fourth moment, hand-derived closed forms of the contractions for X13 = X23 = 0,
rotation identities) or computed independently here (the explicit fourth-rank closure); all
input tables are synthetic DataFrames in the formats of the workflow's tables.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from scipy.optimize import brentq

from suspension_fabric.analysis import frames, tables
from suspension_fabric.analysis.stress import EINSTEIN_COEFFICIENT
from suspension_fabric.evaluation import stress_model
from suspension_fabric.models import gillissen_wilson as model
from suspension_fabric.models import stress_relations

RNG = np.random.default_rng(20240611)
PHI = 0.45
E_HAT = 0.5 * np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
V_C = np.array([1.0, -1.0, 0.0]) / np.sqrt(2.0)
E_COMP = -0.5 * np.outer(V_C, V_C)
E_EXT = E_HAT - E_COMP
# steady fabrics like the test study's (paper frame: <nn>_12 < 0, X13 = X23 = 0)
STEADY = {
    "simulation": {"n11": 0.2227, "n22": 0.2413, "n33": 0.1735, "n12": -0.1409, "n13": 0.011, "n23": 0.0054},
    "gw": {"n11": 0.2477, "n22": 0.3342, "n33": 0.2668, "n12": -0.1409, "n13": 0.0, "n23": 0.0},
    "modified": {"n11": 0.2227, "n22": 0.3034, "n33": 0.2034, "n12": -0.1409, "n13": 0.0, "n23": 0.0},
}
LUB_12, LUB_12_SEM = 3.34, 0.17
CON_12, CON_12_SEM = 2.36, 0.78

#: The fabric sources of the tests: the simulation and the two models of fits_dict
SOURCES = ["simulation", "gw", "modified"]


def tensor(components: dict) -> np.ndarray:
    return frames.vec_to_sym([components[f"n{c}"] for c in frames.VECTOR_ORDER])


def shear_fabric(x11, x22, x33, x12) -> np.ndarray:
    return frames.vec_to_sym([x11, x22, x33, x12, 0.0, 0.0])


def random_fabric(scale=0.3) -> np.ndarray:
    a = RNG.normal(size=(3, 3))
    return scale * (a @ a.T + 0.5 * np.eye(3))


def closed_form_terms(fabric) -> tuple[np.ndarray, np.ndarray]:
    """The hand-derived H = <nnnn>:E^ and C = <nnnn>:E^_c for X13 = X23 = 0 (test 2's docstring)."""
    x11, x22, x33, x12 = fabric[0, 0], fabric[1, 1], fabric[2, 2], fabric[0, 1]
    tr, q = x11 + x22 + x33, x11 + x22 - 2 * x12
    h = np.zeros((3, 3))
    h[0, 0] = h[1, 1] = 3 * x12 / 7
    h[2, 2] = x12 / 7
    h[0, 1] = h[1, 0] = (x11 + x22) / 7 - tr / 35
    c = np.zeros((3, 3))
    c[0, 0] = tr / 35 + (-q / 4 - 1.5 * x11 + x12) / 7
    c[1, 1] = tr / 35 + (-q / 4 - 1.5 * x22 + x12) / 7
    c[2, 2] = tr / 70 + (-q / 4 - 0.5 * x33) / 7
    c[0, 1] = c[1, 0] = -tr / 70 + (x11 + x22 - 3 * x12) / 14
    return h, c


def explicit_terms(fabric) -> tuple[np.ndarray, np.ndarray]:
    """H and C with the full fourth-rank closure tensor (independent of contract_closure)."""
    q4 = model.hinch_leal_closure(fabric)
    return np.einsum("ijkl,kl->ij", q4, E_HAT), np.einsum("ijkl,kl->ij", q4, E_COMP)


# ------------------------------------------------------------------ 1. isotropic fabric
def test_strain_rate_parts_of_simple_shear():
    """split_strain_rate(e1 e2) gives E^ = (e1e2 + e2e1)/2 and E^_c = -(1/2) v_c v_c,
    v_c = (e1 - e2)/sqrt 2, gammadot = 1: the kinematics the module evaluates the relation on."""
    _, e_hat, e_ext, e_comp, gammadot = stress_relations._E_HAT
    np.testing.assert_allclose(e_hat, E_HAT, atol=1e-15)
    np.testing.assert_allclose(e_comp, E_COMP, atol=1e-15)
    np.testing.assert_allclose(e_ext, E_EXT, atol=1e-15)
    assert gammadot == pytest.approx(1.0)


@pytest.mark.parametrize("trace", [0.3, 1.275, 3.0])
def test_isotropic_fabric(trace):
    """X = (T/3) I: the closure is the exact isotropic moment (T/15)(d_ij d_kl + d_ik d_jl + d_il d_jk),
    so for symmetric S, <nnnn>:S = (T/15)(Tr S I + 2 S); hence <nnnn>:E^ = (2T/15) E^ and
    <nnnn>:E^_c = (T/15)(2 E^_c + Tr(E^_c) I) (Tr E^_c = -1/2)."""
    fabric = trace / 3.0 * np.eye(3)
    eye = np.eye(3)
    exact = (
        trace
        / 15.0
        * (np.einsum("ij,kl->ijkl", eye, eye) + np.einsum("ik,jl->ijkl", eye, eye) + np.einsum("il,jk->ijkl", eye, eye))
    )
    np.testing.assert_allclose(model.hinch_leal_closure(fabric), exact, atol=1e-15)

    hydro, contact = stress_model.relation_terms(fabric)
    np.testing.assert_allclose(hydro, 2 * trace / 15 * E_HAT, atol=1e-15)
    np.testing.assert_allclose(contact, trace / 15 * (2 * E_COMP + np.trace(E_COMP) * eye), atol=1e-15)
    assert np.trace(E_COMP) == pytest.approx(-0.5)
    # the general symmetric S of the identity, through the same contraction
    s = RNG.normal(size=(3, 3))
    s = s + s.T
    np.testing.assert_allclose(model.contract_closure(s, fabric), trace / 15 * (np.trace(s) * eye + 2 * s), atol=1e-13)


def test_relation_terms_match_the_explicit_closure():
    """relation_terms(X) = (Q(X):E^, Q(X):E^_c) with Q = hinch_leal_closure as a full 4th-rank
    tensor, for general (random, also 13/23 non-zero) fabrics, one and stacked."""
    fabrics = np.stack([random_fabric() for _ in range(4)])
    hydro, contact = stress_model.relation_terms(fabrics)
    assert hydro.shape == contact.shape == (4, 3, 3)
    for k, fabric in enumerate(fabrics):
        h, c = explicit_terms(fabric)
        np.testing.assert_allclose(hydro[k], h, atol=1e-14)
        np.testing.assert_allclose(contact[k], c, atol=1e-14)


# ------------------------------------------------------------------ 2. closed forms
@pytest.mark.parametrize(
    "fabric",
    [
        shear_fabric(0.2477, 0.3342, 0.2668, -0.1409),
        shear_fabric(0.4, 0.3, 0.1, 0.05),
        shear_fabric(0.0, 0.0, 0.0, 0.0),
        shear_fabric(1.0, 0.0, 0.0, 0.0),
        shear_fabric(0.0, 1.0, 0.0, 0.0),
        shear_fabric(0.0, 0.0, 1.0, 0.0),
        shear_fabric(0.0, 0.0, 0.0, 1.0),
    ],
)
def test_closed_forms_in_simple_shear(fabric):
    """For X13 = X23 = 0, q = X11 + X22 - 2 X12, TrX = X11 + X22 + X33:
    H = <nnnn>:E^:   H11 = H22 = 3 X12/7, H33 = X12/7, H12 = (X11 + X22)/7 - TrX/35, H13 = H23 = 0;
    C = <nnnn>:E^_c: C11 = TrX/35 + (1/7)(-q/4 - 3 X11/2 + X12),
                     C22 = TrX/35 + (1/7)(-q/4 - 3 X22/2 + X12),
                     C33 = TrX/70 + (1/7)(-q/4 - X33/2),
                     C12 = -TrX/70 + (X11 + X22 - 3 X12)/14, C13 = C23 = 0, Tr C = -q/4
    (Tr C = E^_c : X exactly, since the closure's contraction returns the fabric).
    Checked on unit fabrics too, i.e. coefficient by coefficient."""
    hydro, contact = stress_model.relation_terms(fabric)
    h, c = closed_form_terms(fabric)
    np.testing.assert_allclose(hydro, h, atol=1e-15)
    np.testing.assert_allclose(contact, c, atol=1e-15)
    q = fabric[0, 0] + fabric[1, 1] - 2 * fabric[0, 1]
    assert np.trace(contact) == pytest.approx(-q / 4, abs=1e-15)
    assert np.trace(contact) == pytest.approx(np.sum(E_COMP * fabric), abs=1e-15)
    assert np.trace(hydro) == pytest.approx(fabric[0, 1], abs=1e-15)  # Tr H = E^:X = X12


# ------------------------------------------------------------------ 3. fit_relation
def test_fit_relation_coefficients_and_errors():
    """a_H = sigma^lub_12 / H12, a_C = sigma^con_12 / C12, a_H_err = sem_lub / H12,
    a_C_err = sem_con / C12, with H12, C12 from the closed forms of test 2."""
    fabric = tensor(STEADY["gw"])
    h, c = closed_form_terms(fabric)
    assert h[0, 1] > 0 and c[0, 1] > 0
    fit = stress_model.fit_relation(fabric, LUB_12, CON_12, LUB_12_SEM, CON_12_SEM)
    assert fit["a_H"] == pytest.approx(LUB_12 / h[0, 1], rel=1e-13)
    assert fit["a_C"] == pytest.approx(CON_12 / c[0, 1], rel=1e-13)
    assert fit["a_H_err"] == pytest.approx(LUB_12_SEM / h[0, 1], rel=1e-13)
    assert fit["a_C_err"] == pytest.approx(CON_12_SEM / c[0, 1], rel=1e-13)
    # errors default to nan
    assert np.isnan(stress_model.fit_relation(fabric, LUB_12, CON_12)["a_H_err"])


@pytest.mark.parametrize(
    "fabric, which",
    [
        # X12 > 0 (contacts along the extension axis): C12 = -0.6/70 + (0.4 - 0.9)/14 < 0, H12 > 0
        (shear_fabric(0.2, 0.2, 0.2, 0.3), "C12"),
        # X33 > 4 (X11 + X22): H12 = (4 (X11 + X22) - X33)/35 = -0.1/35 < 0
        (shear_fabric(0.05, 0.05, 0.5, -0.01), "H12"),
        (np.zeros((3, 3)), "both"),
    ],
)
def test_fit_relation_rejects_non_positive_terms(fabric, which):
    """H12 <= 0 or C12 <= 0 cannot be fitted: ValueError naming both terms (<nnnn>:E^)_12 and
    (<nnnn>:E^_c)_12 with their values."""
    h, c = closed_form_terms(fabric)
    assert (h[0, 1] <= 0) == (which in ("H12", "both")) and (c[0, 1] <= 0) == (which in ("C12", "both"))
    with pytest.raises(ValueError, match=r"\(<nnnn>:E\^\)_12 = .*\(<nnnn>:E\^_c\)_12 = .*positive"):
        stress_model.fit_relation(fabric, LUB_12, CON_12)


# ------------------------------------------------------------------ 4. relation_stress
def test_relation_stress_at_the_fitted_steady_fabric():
    """At the fabric the coefficients were fitted on: lubrication_12 = sigma^lub_12 and
    contact_12 = sigma^con_12; eta_r = total_12 = 1 + 2.5 phi + lub + con;
    N1 = a_H (H11 - H22) + a_C (C11 - C22), N2 = a_H (H22 - H33) + a_C (C22 - C33),
    Pi = -(a_H Tr H + a_C Tr C)/3 = -(a_H X12 - a_C q/4)/3 (closed forms of test 2);
    23 and 13 components vanish for X13 = X23 = 0."""
    fabric = tensor(STEADY["modified"])
    fit = stress_model.fit_relation(fabric, LUB_12, CON_12)
    out = stress_model.relation_stress(fabric, fit, PHI)
    assert list(out.columns) == list(stress_model.PREDICTED_COLUMNS)
    assert len(out) == 1
    row = out.iloc[0]
    assert row["lubrication_12"] == pytest.approx(LUB_12, rel=1e-13)
    assert row["contact_12"] == pytest.approx(CON_12, rel=1e-13)
    assert row["eta_r"] == pytest.approx(1 + EINSTEIN_COEFFICIENT * PHI + LUB_12 + CON_12, rel=1e-13)
    assert EINSTEIN_COEFFICIENT == 2.5
    assert row["total_12"] == row["eta_r"]
    h, c = closed_form_terms(fabric)
    a_h, a_c = fit["a_H"], fit["a_C"]
    q = fabric[0, 0] + fabric[1, 1] - 2 * fabric[0, 1]
    assert row["N1"] == pytest.approx(a_h * (h[0, 0] - h[1, 1]) + a_c * (c[0, 0] - c[1, 1]), rel=1e-12, abs=1e-14)
    assert row["N2"] == pytest.approx(a_h * (h[1, 1] - h[2, 2]) + a_c * (c[1, 1] - c[2, 2]), rel=1e-12)
    assert row["Pi"] == pytest.approx(-(a_h * fabric[0, 1] - a_c * q / 4) / 3, rel=1e-12)
    for name in ("total_23", "total_13", "contact_23", "lubrication_23"):
        assert row[name] == pytest.approx(0.0, abs=1e-15)


def test_relation_stress_shapes():
    """One fabric (3, 3) -> one row; a stack (n, 3, 3) -> n rows, row k equal to the single-fabric
    result of fabric k (incl. 13/23 parts: total_23 = a_H H23 + a_C C23 with explicit H, C)."""
    coefficients = {"a_H": 60.0, "a_C": 25.0}
    fabrics = np.stack([random_fabric() for _ in range(5)])
    many = stress_model.relation_stress(fabrics, coefficients, PHI)
    assert len(many) == 5
    for k, fabric in enumerate(fabrics):
        one = stress_model.relation_stress(fabric, coefficients, PHI)
        assert len(one) == 1
        pd.testing.assert_series_equal(one.iloc[0], many.iloc[k], check_names=False, rtol=1e-14)
        h, c = explicit_terms(fabric)
        particle = 60.0 * h + 25.0 * c
        np.testing.assert_allclose(
            many.loc[k, ["total_23", "total_13", "lubrication_23", "contact_23", "N1", "N2", "Pi"]].to_numpy(float),
            [
                particle[1, 2],
                particle[0, 2],
                60.0 * h[1, 2],
                25.0 * c[1, 2],
                particle[0, 0] - particle[1, 1],
                particle[1, 1] - particle[2, 2],
                -np.trace(particle) / 3,
            ],
            rtol=1e-12,
            atol=1e-14,
        )
        assert many.loc[k, "eta_r"] == pytest.approx(1 + 2.5 * PHI + particle[0, 1], rel=1e-13)


# ------------------------------------------------------------------ 5. linearity, frames
def test_relation_is_linear_in_the_fabric():
    """H(aX + bY) = a H(X) + b H(Y) and the same for C (the closure is linear in <nn>)."""
    x, y = random_fabric(), random_fabric()
    a, b = 1.7, -0.6
    hx, cx = stress_model.relation_terms(x)
    hy, cy = stress_model.relation_terms(y)
    hxy, cxy = stress_model.relation_terms(a * x + b * y)
    np.testing.assert_allclose(hxy, a * hx + b * hy, atol=1e-14)
    np.testing.assert_allclose(cxy, a * cx + b * cy, atol=1e-14)


@pytest.mark.parametrize("theta_deg", [30.0, 90.0, 180.0])
def test_contraction_is_objective(theta_deg):
    """Frame indifference of the contraction: (Q S Q^T):<nnnn>(Q X Q^T) = Q (S:<nnnn>(X)) Q^T for
    Q = frames.rotation_about_gradient(theta), with S = E^ and E^_c."""
    q = frames.rotation_about_gradient(np.radians(theta_deg))
    x = random_fabric()
    for s in (E_HAT, E_COMP):
        np.testing.assert_allclose(
            model.contract_closure(frames.to_basis(s, q), frames.to_basis(x, q)),
            frames.to_basis(model.contract_closure(s, x), q),
            atol=1e-14,
        )


def test_reversal_theta_180():
    """Shear reversal, theta = 180 deg: R = rotation_about_gradient(pi) = diag(-1, 1, -1), and the
    rotated fabric X' = R X R^T has X'12 = -X12, X'23 = -X23, X'13 = X13, same diagonal.
    Because R E^ R^T = -E^ and R E^_c R^T = -E^_e, the relation in the rotated frame
    (simple shear e1' e2 again) gives H(X') = -R H(X) R^T and C(X') = R (C(X) - H(X)) R^T for
    any X. For the steady G-W fabric (X13 = X23 = 0) this means H'12 = H12 (H12 does not depend
    on X12) and C'12 = H12 - C12 = C12 + 3 X12/7 < C12 (X12 < 0), so the predicted
    sigma'_12 = 1 + 2.5 phi + a_H H12 + a_C (H12 - C12): lubrication_12 unchanged, contact_12
    lowered by a_C 3|X12|/7; and N2 from the lubrication term, a_H 2 X12/7, flips sign."""
    beta = 10.9
    before = model.startup_shear(np.array([5.0]), beta)[0]
    after = model.shear_rotation(np.pi, np.array([0.0]), beta, startup_strain=5.0)[0]
    r = frames.rotation_about_gradient(np.pi)
    np.testing.assert_allclose(r, np.diag([-1.0, 1.0, -1.0]), atol=1e-15)
    np.testing.assert_allclose(after, r @ before @ r.T, atol=1e-14)
    assert after[0, 1] == pytest.approx(-before[0, 1], abs=1e-15) and before[0, 1] < 0
    np.testing.assert_allclose(np.diag(after), np.diag(before), atol=1e-15)

    for x in (before, random_fabric()):
        h, c = stress_model.relation_terms(x)
        h_rot, c_rot = stress_model.relation_terms(r @ x @ r.T)
        np.testing.assert_allclose(h_rot, -r @ h @ r.T, atol=1e-14)
        np.testing.assert_allclose(c_rot, r @ (c - h) @ r.T, atol=1e-14)

    h, c = stress_model.relation_terms(before)
    h_rot, c_rot = stress_model.relation_terms(after)
    assert h_rot[0, 1] == pytest.approx(h[0, 1], rel=1e-13)
    assert c_rot[0, 1] == pytest.approx(c[0, 1] + 3 * before[0, 1] / 7, rel=1e-12)
    fit = stress_model.fit_relation(before, LUB_12, CON_12)
    s0 = stress_model.relation_stress(before, fit, PHI).iloc[0]
    s180 = stress_model.relation_stress(after, fit, PHI).iloc[0]
    assert s180["lubrication_12"] == pytest.approx(s0["lubrication_12"], rel=1e-13)
    assert s180["contact_12"] == pytest.approx(fit["a_C"] * (h[0, 1] - c[0, 1]), rel=1e-12)
    assert s180["contact_12"] == pytest.approx(s0["contact_12"] - fit["a_C"] * 3 * abs(before[0, 1]) / 7, rel=1e-12)
    assert s180["eta_r"] == pytest.approx(
        1 + 2.5 * PHI + fit["a_H"] * h[0, 1] + fit["a_C"] * (h[0, 1] - c[0, 1]), rel=1e-13
    )
    assert s180["eta_r"] < s0["eta_r"]
    lub_n2 = lambda x: fit["a_H"] * 2 * x[0, 1] / 7  # noqa: E731
    h_n2 = stress_model.relation_stress(before, {"a_H": fit["a_H"], "a_C": 0.0}, PHI).iloc[0]["N2"]
    h_n2_rot = stress_model.relation_stress(after, {"a_H": fit["a_H"], "a_C": 0.0}, PHI).iloc[0]["N2"]
    assert h_n2 == pytest.approx(lub_n2(before), rel=1e-12) and h_n2_rot == pytest.approx(-h_n2, rel=1e-12)


# ------------------------------------------------------------------ 6. relation_fits
def steady_table(values: dict, skip: str | None = None) -> pd.DataFrame:
    """A stress steady-state table (theta, quantity, mean, sem, ...) with decoy theta = 90 rows."""
    rows = []
    for theta, shift in ((0.0, 0.0), (90.0, 5.0)):
        for quantity, (mean, sem) in values.items():
            if quantity == skip and theta == 0.0:
                continue
            rows.append(
                {
                    "theta": theta,
                    "quantity": quantity,
                    "mean": mean + shift,
                    "sem": sem,
                    "sem_between_seeds": 2 * sem,
                    "tau_strain": 0.02,
                    "n_frames": 21,
                    "n_seeds": 2,
                    "strain_min": 0.1,
                    "strain_max": 0.3,
                }
            )
    return pd.DataFrame(rows)


STEADY_VALUES = {
    "eta_r": (7.16, 0.50),
    "N1": (-0.38, 0.17),
    "N2": (-3.17, 0.44),
    "Pi": (4.69, 0.53),
    "lubrication_12": (LUB_12, LUB_12_SEM),
    "contact_12": (CON_12, CON_12_SEM),
    "total_23": (0.05, 0.04),
}


def fits_dict() -> dict:
    targets = {name: {"mean": value, "sem": 0.01} for name, value in STEADY["simulation"].items()}
    targets["Z"] = {"mean": 1.275, "sem": 0.14}
    return {
        "phi": PHI,
        "targets": targets,
        "models": {key: {"label": key, "steady_state": dict(STEADY[key])} for key in ("gw", "modified")},
    }


def test_relation_fits():
    """One row per source (simulation, gw, modified), fitted on that source's steady fabric:
    a_H = lub/H12, a_C = con/C12 (closed forms of test 2 for the models; explicit closure for the
    simulated fabric, which has X13, X23 != 0), eta_r_predicted = 1 + 2.5 phi + lub + con for
    every source, N1/N2/Pi_predicted = relation_stress of the fitted fabric, and the columns
    *_simulated / *_simulated_sem = the theta = 0 rows of the table (theta = 90 rows ignored)."""
    fits = fits_dict()
    out = stress_model.relation_fits(steady_table(STEADY_VALUES), fits)
    assert list(out["source"]) == ["simulation", "gw", "modified"]
    for _, row in out.iterrows():
        fabric = tensor(STEADY[row["source"]])
        h, c = explicit_terms(fabric)
        if row["source"] != "simulation":
            np.testing.assert_allclose((h, c), closed_form_terms(fabric), atol=1e-15)
        assert row["a_H"] == pytest.approx(LUB_12 / h[0, 1], rel=1e-12)
        assert row["a_C"] == pytest.approx(CON_12 / c[0, 1], rel=1e-12)
        assert row["a_H_err"] == pytest.approx(LUB_12_SEM / h[0, 1], rel=1e-12)
        assert row["a_C_err"] == pytest.approx(CON_12_SEM / c[0, 1], rel=1e-12)
        assert row["eta_r_predicted"] == pytest.approx(1 + 2.5 * PHI + LUB_12 + CON_12, rel=1e-13)
        particle = row["a_H"] * h + row["a_C"] * c
        assert row["N1_predicted"] == pytest.approx(particle[0, 0] - particle[1, 1], rel=1e-12)
        assert row["N2_predicted"] == pytest.approx(particle[1, 1] - particle[2, 2], rel=1e-12)
        assert row["Pi_predicted"] == pytest.approx(-np.trace(particle) / 3, rel=1e-12)
        for name in ("eta_r", "N1", "N2", "Pi"):
            assert row[f"{name}_simulated"] == STEADY_VALUES[name][0]
            assert row[f"{name}_simulated_sem"] == STEADY_VALUES[name][1]


def test_source_steady_fabrics_ignores_z():
    """The simulated fabric is built from the n11..n23 targets only (Z ignored), the models' from
    steady states of fits.json's models, each in VECTOR_ORDER."""
    fabrics = stress_model.source_steady_fabrics(fits_dict())
    assert list(fabrics) == SOURCES
    for source, fabric in fabrics.items():
        np.testing.assert_array_equal(fabric, tensor(STEADY[source]))
        assert fabric[0, 2] == STEADY[source]["n13"] and fabric[1, 2] == STEADY[source]["n23"]


@pytest.mark.parametrize("missing", ["lubrication_12", "contact_12", "eta_r", "N1", "N2", "Pi"])
def test_relation_fits_missing_quantity(missing):
    """A quantity without its theta = 0 row -> ValueError naming it (0 rows, expected 1)."""
    with pytest.raises(ValueError, match=rf"0 rows for {missing} at theta = 0"):
        stress_model.relation_fits(steady_table(STEADY_VALUES, skip=missing), fits_dict())


def test_steady_value_duplicate_rows():
    """Two theta = 0 rows for one quantity -> ValueError (2 rows, expected 1)."""
    table = pd.concat([steady_table(STEADY_VALUES), steady_table({"N1": (1.0, 0.1)})], ignore_index=True)
    with pytest.raises(ValueError, match="2 rows for N1 at theta = 0"):
        stress_model.steady_value(table, "N1")
    assert stress_model.steady_value(table, "N2") == STEADY_VALUES["N2"]


# ------------------------------------------------------------------ 7. predictions and errors
STRAIN = np.round(np.arange(0.0, 1.0 + 1e-9, 0.05), 10)
THETAS = (0.0, 90.0, 180.0)
ERROR_QUANTITIES = ("eta_r", "N1", "N2", "total_23", "contact_12", "lubrication_12")
SIGMA12_SS = 7.16


def fabric_curve(start: np.ndarray, end: np.ndarray, tau: float) -> np.ndarray:
    """(len(STRAIN), 3, 3): end + (start - end) exp(-gamma/tau)."""
    weight = np.exp(-STRAIN / tau)[:, None, None]
    return end + (start - end) * weight


def fabric_rows(fabrics: np.ndarray, theta: float, suffix: str = "", **extra) -> pd.DataFrame:
    vectors = frames.sym_to_vec(fabrics)
    data = {"theta": theta, "strain": STRAIN, **extra}
    for k, name in enumerate(frames.VECTOR_ORDER):
        data[f"n{name}{suffix}"] = vectors[:, k]
    return pd.DataFrame(data)


def synthetic_fabrics():
    """Startup and rotation aggregates (simulation) and predictions (gw, modified), theta in degrees."""
    sim_ss, gw_ss, mod_ss = (tensor(STEADY[s]) for s in ("simulation", "gw", "modified"))
    startup = fabric_rows(fabric_curve(np.zeros((3, 3)), sim_ss, 0.2), 0.0, "_mean", N=40, phi=PHI, n_seeds=2)
    rotation, predictions = [], []
    for key, steady in (("gw", gw_ss), ("modified", mod_ss)):
        predictions.append(
            fabric_rows(fabric_curve(np.zeros((3, 3)), steady, 0.25), 0.0, model=key, protocol="startup")
        )
    for theta in THETAS:
        r = frames.rotation_about_gradient(np.radians(theta))
        rotation.append(
            fabric_rows(fabric_curve(r @ sim_ss @ r.T, sim_ss, 0.3), theta, "_mean", N=40, phi=PHI, n_seeds=2)
        )
        for key, steady in (("gw", gw_ss), ("modified", mod_ss)):
            predictions.append(
                fabric_rows(fabric_curve(r @ steady @ r.T, steady, 0.35), theta, model=key, protocol="rotation")
            )
    return startup, pd.concat(rotation, ignore_index=True), pd.concat(predictions, ignore_index=True)


def relation_table() -> pd.DataFrame:
    return stress_model.relation_fits(steady_table(STEADY_VALUES), fits_dict())


def simulated_stress(aggregate: pd.DataFrame, relation: pd.DataFrame) -> pd.DataFrame:
    """A stress aggregate (theta, strain, <q>_mean, <q>_sem) equal to the relation's stress on the
    simulated fabric, computed here row by row."""
    coefficients = relation.set_index("source").loc["simulation"]
    rows = []
    for _, row in aggregate.iterrows():
        fabric = tensor({f"n{c}": row[f"n{c}_mean"] for c in frames.VECTOR_ORDER})
        h, c = explicit_terms(fabric)
        lub, con = coefficients["a_H"] * h, coefficients["a_C"] * c
        total = lub + con
        total[0, 1] = total[1, 0] = total[0, 1] + 1 + 2.5 * PHI
        values = {
            "eta_r": total[0, 1],
            "N1": total[0, 0] - total[1, 1],
            "N2": total[1, 1] - total[2, 2],
            "total_23": total[1, 2],
            "contact_12": con[0, 1],
            "lubrication_12": lub[0, 1],
        }
        out = {"theta": row["theta"], "N": 40, "phi": PHI, "strain": row["strain"], "n_seeds": 2}
        for name, value in values.items():
            out[f"{name}_mean"], out[f"{name}_sem"] = value, 0.1
        rows.append(out)
    return pd.DataFrame(rows)


def test_stress_predictions_layout_and_values():
    """stress_predictions: per source (simulation from the *_mean aggregates, gw/modified from
    predictions) and protocol, relation_stress of that source's fabric with its own coefficients,
    with source, protocol, theta, strain columns carried over row by row."""
    relation = relation_table()
    startup, rotation, predictions = synthetic_fabrics()
    out = stress_model.stress_predictions(relation, startup, rotation, predictions, PHI)
    assert list(out.columns) == ["source", "protocol", "theta", "strain", *stress_model.PREDICTED_COLUMNS]
    assert len(out) == 3 * len(STRAIN) * (1 + len(THETAS))
    coefficients = relation.set_index("source")
    for source in SOURCES:
        for protocol, theta in [("startup", 0.0), *(("rotation", t) for t in THETAS)]:
            block = out[(out["source"] == source) & (out["protocol"] == protocol) & (out["theta"] == theta)]
            np.testing.assert_array_equal(block["strain"], STRAIN)
            if source == "simulation":
                table = startup if protocol == "startup" else rotation
                rows = table[table["theta"] == theta]
                fabrics = frames.vec_to_sym(rows[[f"n{c}_mean" for c in frames.VECTOR_ORDER]].to_numpy())
            else:
                rows = predictions[
                    (predictions["model"] == source)
                    & (predictions["protocol"] == protocol)
                    & (predictions["theta"] == theta)
                ]
                fabrics = frames.vec_to_sym(rows[[f"n{c}" for c in frames.VECTOR_ORDER]].to_numpy())
            expected = stress_model.relation_stress(fabrics, coefficients.loc[source], PHI)
            np.testing.assert_allclose(
                block[list(stress_model.PREDICTED_COLUMNS)].to_numpy(float),
                expected.to_numpy(float),
                rtol=1e-13,
                atol=1e-14,
            )
    # steady end of startup: eta_r -> 1 + 2.5 phi + lub + con for every source (fitted there)
    ends = out[(out["protocol"] == "startup") & (out["strain"] == STRAIN[-1])]
    np.testing.assert_allclose(ends["eta_r"], 1 + 2.5 * PHI + LUB_12 + CON_12, rtol=2e-2)


def test_relation_errors_zero_and_offset():
    """Simulated stress = relation on the simulated fabric -> rms_error = max_abs_error = 0 for
    source 'simulation' (every protocol, angle, quantity; rows shuffled). Adding d to eta_r_mean
    gives rms = max = d/|sigma12_ss| on eta_r only; the models' errors equal
    rms over strains of |relation(model fabric) - relation(simulated fabric)| / |sigma12_ss|."""
    relation = relation_table()
    startup, rotation, predictions = synthetic_fabrics()
    predicted = stress_model.stress_predictions(relation, startup, rotation, predictions, PHI)
    s_startup = simulated_stress(startup, relation).sample(frac=1.0, random_state=1)
    s_rotation = simulated_stress(rotation, relation).sample(frac=1.0, random_state=2)
    errors = stress_model.relation_errors(
        s_startup, s_rotation, predicted.sample(frac=1.0, random_state=3), -SIGMA12_SS
    )
    assert len(errors) == 3 * (1 + len(THETAS)) * len(ERROR_QUANTITIES)
    assert set(errors["n_strains"]) == {len(STRAIN)}
    sim = errors[errors["source"] == "simulation"]
    np.testing.assert_allclose(sim[["rms_error", "max_abs_error"]].to_numpy(), 0.0, atol=1e-12)

    for _, row in errors[errors["source"] != "simulation"].iterrows():
        mine = predicted[
            (predicted["source"] == row["source"])
            & (predicted["protocol"] == row["protocol"])
            & (predicted["theta"] == row["theta"])
        ].sort_values("strain")
        ref = predicted[
            (predicted["source"] == "simulation")
            & (predicted["protocol"] == row["protocol"])
            & (predicted["theta"] == row["theta"])
        ].sort_values("strain")
        diff = (mine[row["quantity"]].to_numpy() - ref[row["quantity"]].to_numpy()) / SIGMA12_SS
        assert row["rms_error"] == pytest.approx(np.sqrt(np.mean(diff**2)), rel=1e-9, abs=1e-13)
        assert row["max_abs_error"] == pytest.approx(np.abs(diff).max(), rel=1e-9, abs=1e-13)

    d = 0.3
    shifted = s_rotation.assign(eta_r_mean=s_rotation["eta_r_mean"] + d)
    errors = stress_model.relation_errors(s_startup, shifted, predicted, SIGMA12_SS)
    sim = errors[(errors["source"] == "simulation") & (errors["protocol"] == "rotation")]
    eta = sim[sim["quantity"] == "eta_r"]
    assert len(eta) == len(THETAS)
    np.testing.assert_allclose(eta["rms_error"], d / SIGMA12_SS, rtol=1e-12)
    np.testing.assert_allclose(eta["max_abs_error"], d / SIGMA12_SS, rtol=1e-12)
    np.testing.assert_allclose(sim[sim["quantity"] != "eta_r"][["rms_error", "max_abs_error"]], 0.0, atol=1e-12)


def test_relation_errors_accepts_a_finer_prediction_grid():
    """Predictions on a superset of the simulated strains (the simulated grid plus midpoints)
    are matched to the simulated strains: still zero error for 'simulation'."""
    relation = relation_table()
    startup, rotation, predictions = synthetic_fabrics()
    predicted = stress_model.stress_predictions(relation, startup, rotation, predictions, PHI)
    extra = predicted.assign(strain=predicted["strain"] + 0.025, eta_r=predicted["eta_r"] + 100.0)
    errors = stress_model.relation_errors(
        simulated_stress(startup, relation),
        simulated_stress(rotation, relation),
        pd.concat([predicted, extra], ignore_index=True),
        SIGMA12_SS,
    )
    sim = errors[errors["source"] == "simulation"]
    np.testing.assert_allclose(sim["rms_error"], 0.0, atol=1e-12)


def test_relation_errors_matches_strains_a_rounding_below_the_grid():
    """Predicted strains a rounding below the simulated ones (0.09999999999999999 for 0.1, as a
    strain summed from the step gives them) are matched to them, not to the next grid point:
    still zero error for 'simulation'."""
    relation = relation_table()
    startup, rotation, predictions = synthetic_fabrics()
    startup_below = startup.assign(strain=np.nextafter(startup["strain"].to_numpy(), -np.inf))
    rotation_below = rotation.assign(strain=np.nextafter(rotation["strain"].to_numpy(), -np.inf))
    predictions_below = predictions.assign(strain=np.nextafter(predictions["strain"].to_numpy(), -np.inf))
    predicted = stress_model.stress_predictions(relation, startup_below, rotation_below, predictions_below, PHI)
    errors = stress_model.relation_errors(
        simulated_stress(startup, relation), simulated_stress(rotation, relation), predicted, SIGMA12_SS
    )
    sim = errors[errors["source"] == "simulation"]
    np.testing.assert_allclose(sim[["rms_error", "max_abs_error"]].to_numpy(), 0.0, atol=1e-12)


def test_relation_errors_strain_grid_mismatch():
    """A source whose strains miss the simulated ones -> ValueError naming protocol, source, angle."""
    relation = relation_table()
    startup, rotation, predictions = synthetic_fabrics()
    shifted = predictions.copy()
    gw_rotation = (shifted["model"] == "gw") & (shifted["protocol"] == "rotation") & (shifted["theta"] == 90.0)
    shifted.loc[gw_rotation, "strain"] += 0.01
    predicted = stress_model.stress_predictions(relation, startup, rotation, shifted, PHI)
    with pytest.raises(ValueError, match=r"rotation: source gw at theta=90.0 is not on the simulation's strain grid"):
        stress_model.relation_errors(
            simulated_stress(startup, relation), simulated_stress(rotation, relation), predicted, SIGMA12_SS
        )
    # a simulated angle the prediction lacks altogether
    s_rotation = simulated_stress(rotation, relation)
    s_rotation = pd.concat([s_rotation, s_rotation[s_rotation["theta"] == 90.0].assign(theta=45.0)])
    predicted = stress_model.stress_predictions(relation, startup, rotation, predictions, PHI)
    with pytest.raises(ValueError, match=r"theta=45.0 is not on the simulation.s strain grid"):
        stress_model.relation_errors(simulated_stress(startup, relation), s_rotation, predicted, SIGMA12_SS)


def test_summarise_relation_errors():
    """summarise_relation_errors: mean over angles of rms_error per (protocol, quantity, source),
    one column rms_<source> in the order of the sources."""
    rows = []
    for protocol, thetas in (("startup", (0.0,)), ("rotation", (0.0, 90.0, 180.0))):
        for quantity in ("eta_r", "N1"):
            for k, source in enumerate(SOURCES):
                for j, theta in enumerate(thetas):
                    rows.append(
                        {
                            "protocol": protocol,
                            "source": source,
                            "theta": theta,
                            "quantity": quantity,
                            "rms_error": 0.1 * (k + 1) + 0.01 * j + (quantity == "N1"),
                            "max_abs_error": 1.0,
                            "n_strains": 5,
                        }
                    )
    summary = stress_model.summarise_relation_errors(pd.DataFrame(rows))
    assert list(summary.columns) == ["protocol", "quantity", "rms_simulation", "rms_gw", "rms_modified"]
    assert len(summary) == 4
    for _, row in summary.iterrows():
        n = 1 if row["protocol"] == "startup" else 3
        offset = 0.01 * np.mean(np.arange(n)) + (row["quantity"] == "N1")
        for k, source in enumerate(SOURCES):
            assert row[f"rms_{source}"] == pytest.approx(0.1 * (k + 1) + offset, rel=1e-13)


# ------------------------------------------------------------------ 8. viscosity transients
T_GRID = np.round(np.arange(0.0, 2.0 + 1e-9, 0.01), 10)
ETA_SS = 7.0
LEVEL = 0.95


def exponential(amplitude=0.5, tau=0.2):
    """eta_r/eta_ss = 1 - a exp(-g/tau): minimum 1 - a at g = 0, back within 10% for good from the
    first grid strain >= tau ln(10 a)."""
    return 1.0 - amplitude * np.exp(-T_GRID / tau)


def dip(amplitude=0.4, tau=0.25):
    """eta_r/eta_ss = 1 - a (g/tau) exp(1 - g/tau): minimum 1 - a at g = tau; back within 10%
    from the first grid strain >= g*, the root > tau of a (g/tau) exp(1 - g/tau) = 0.1."""
    return 1.0 - amplitude * (T_GRID / tau) * np.exp(1.0 - T_GRID / tau)


def dip_recovery(amplitude=0.4, tau=0.25) -> float:
    root = brentq(lambda g: amplitude * (g / tau) * np.exp(1 - g / tau) - 0.1, tau, 50 * tau)
    return float(T_GRID[np.searchsorted(T_GRID, root)])


def runs_table(curves: dict[float, list[np.ndarray]], eta_ss=None, strain=T_GRID) -> pd.DataFrame:
    """Per-seed stress rows (seed, theta, strain, eta_r = eta_ss,s * curve), shuffled; eta_ss a
    list per seed (seeds 1, 2, ...), ETA_SS for all by default."""
    rows = []
    for theta, per_seed in curves.items():
        for seed, curve in enumerate(per_seed, start=1):
            scale = ETA_SS if eta_ss is None else eta_ss[seed - 1]
            rows.append(
                pd.DataFrame({"seed": seed, "theta": theta, "strain": strain, "eta_r": scale * curve, "N1": 0.0})
            )
    return pd.concat(rows, ignore_index=True).sample(frac=1.0, random_state=4)


def same_steady(n_seeds, value=ETA_SS) -> dict[int, float]:
    return {seed: value for seed in range(1, n_seeds + 1)}


def bootstrap_interval(statistic, curves, level=LEVEL):
    """Percentile interval of statistic(mean of a resample of the curves) over all n^n resamples
    of n seeds with replacement (independent of seed_statistics)."""
    n = len(curves)
    values = [
        statistic(np.mean([curves[k] for k in sample], axis=0)) for sample in itertools.product(range(n), repeat=n)
    ]
    return tuple(np.quantile(values, [0.5 - level / 2, 0.5 + level / 2]))


def test_seed_steady_viscosity_is_each_seeds_mean_over_the_window():
    """Per seed, the mean of eta_r over 2 <= strain <= 5 (both ends in), one value per seed, and
    their mean equals the steady-state table's mean (tables.steady_state) on the same runs."""
    strain = np.round(np.arange(0.0, 5.0 + 1e-9, 0.5), 10)
    rows = []
    for seed, level in ((1, 10.0), (2, 12.0), (3, 11.0)):
        eta = level + 0.1 * seed * np.sin(3.0 * strain) + (strain < 2.0) * 5.0
        rows.append(
            pd.DataFrame(
                {
                    "seed": seed,
                    "theta": 0.0,
                    "N": 100,
                    "phi": PHI,
                    "step": np.arange(len(strain)),
                    "strain": strain,
                    "eta_r": eta,
                }
            )
        )
    startup = pd.concat(rows, ignore_index=True).sample(frac=1.0, random_state=2)
    out = stress_model.seed_steady_viscosity(startup, [2.0, 5.0])
    inside = (strain >= 2.0) & (strain <= 5.0)
    for seed, level in ((1, 10.0), (2, 12.0), (3, 11.0)):
        assert out[seed] == pytest.approx(np.mean(level + 0.1 * seed * np.sin(3.0 * strain[inside])), rel=1e-14)
    steady = tables.steady_state(startup, 2.0, 5.0, value_columns=("eta_r",))
    assert out.mean() == pytest.approx(float(steady["mean"].iloc[0]), rel=1e-14)
    with pytest.raises(ValueError, match="seed 1 has 1 frame"):
        stress_model.seed_steady_viscosity(startup, [4.8, 5.2])


def test_viscosity_deficit_per_seed_and_its_t_interval():
    """eta_r,s = eta_ss,s (1 - a_s exp(-g/g0)) with each seed's own eta_ss,s: the deficit
    integral_0^W (1 - eta_r,s/eta_ss,s) = a_s g0 (1 - exp(-W/g0)) per seed (trapezoidal rule on a
    0.01 grid: relative error (h/g0)^2/12 ~ 3e-4), whatever eta_ss,s; the summary is the seed
    mean with the Student t-interval mean +- t_{(1+level)/2, n-1} sd/sqrt(n) (scipy.stats.t)."""
    amplitudes, g0, window, level = [0.3, 0.45, 0.5, 0.62], 0.2, 1.5, 0.9
    steady = [6.0, 7.5, 8.0, 6.8]
    table = runs_table({120.0: [exponential(a, g0) for a in amplitudes]}, eta_ss=steady)
    eta_ss = dict(zip(range(1, 5), steady))
    per_seed = stress_model.viscosity_deficits(table, eta_ss, window)
    assert list(per_seed.columns) == ["seed", "theta", "window", "eta_ss_seed", "deficit"]
    assert per_seed["seed"].tolist() == [1, 2, 3, 4] and (per_seed["theta"] == 120.0).all()
    assert (per_seed["window"] == window).all() and per_seed["eta_ss_seed"].tolist() == steady
    analytic = np.array(amplitudes) * g0 * (1.0 - np.exp(-window / g0))
    np.testing.assert_allclose(per_seed["deficit"], analytic, rtol=5e-4)
    # exactly the trapezoidal rule on the frames of [0, W]
    inside = T_GRID <= window + 1e-12
    trapezoid = [np.trapezoid(a * np.exp(-T_GRID[inside] / g0), T_GRID[inside]) for a in amplitudes]
    np.testing.assert_allclose(per_seed["deficit"], trapezoid, rtol=1e-12)

    out = stress_model.viscosity_transients(table, eta_ss, window, level, smoothing_strain=0.0).iloc[0]
    values = per_seed["deficit"].to_numpy()
    n, mean, sd = len(values), values.mean(), values.std(ddof=1)
    half = stats.t.ppf(0.5 + level / 2, n - 1) * sd / np.sqrt(n)
    assert out["deficit"] == pytest.approx(mean, rel=1e-13)
    assert out["deficit_se"] == pytest.approx(sd / np.sqrt(n), rel=1e-12)
    assert out["deficit_low"] == pytest.approx(mean - half, rel=1e-12)
    assert out["deficit_high"] == pytest.approx(mean + half, rel=1e-12)
    assert out["n_seeds"] == 4 and out["level"] == level and out["window"] == window
    # the same interval from the analytic per-seed values, to the trapezoidal rule's accuracy
    exact_half = stats.t.ppf(0.95, 3) * analytic.std(ddof=1) / 2.0
    assert out["deficit_low"] == pytest.approx(analytic.mean() - exact_half, rel=2e-3)
    assert out["deficit_high"] == pytest.approx(analytic.mean() + exact_half, rel=2e-3)


def test_viscosity_deficit_window_between_frames_and_at_the_end():
    """A window between two frames ends the last trapezoid at W (linear interpolation); a window
    equal to the run's last strain uses every frame; 1 - eta/eta_ss linear in strain integrates
    exactly."""
    curve = 1.0 - 0.1 * (2.0 - T_GRID)  # 1 - eta/eta_ss = 0.1 (2 - g)
    table = runs_table({30.0: [curve]})
    for window in (0.505, 1.0, 2.0):
        deficit = stress_model.viscosity_deficits(table, same_steady(1), window)["deficit"].iloc[0]
        assert deficit == pytest.approx(0.1 * (2.0 * window - window**2 / 2), rel=1e-12)


def test_viscosity_deficit_of_a_run_shorter_than_the_window_is_an_error():
    """A run that ends before W raises, naming the angle, the run's last strain and W; a seed
    with no steady value raises too."""
    table = runs_table({90.0: [dip(), dip()]})
    with pytest.raises(ValueError, match=r"theta=90\.0: seed 1's run ends at strain 2 .*window 2\.5"):
        stress_model.viscosity_deficits(table, same_steady(2), 2.5)
    with pytest.raises(ValueError, match=r"theta=90\.0: seed 1's run ends at strain 2 .*window 2\.5"):
        stress_model.viscosity_transients(table, same_steady(2), 2.5)
    with pytest.raises(ValueError, match=r"no steady eta_r for seed\(s\) \[2\]"):
        stress_model.viscosity_deficits(table, {1: ETA_SS}, 1.0)


def test_viscosity_transients_identical_seeds():
    """Three identical seeds: exponential 1 - 0.5 exp(-g/0.2): min 0.5 at g = 0, recovery at the first
    grid strain >= 0.2 ln 5 = 0.3219, i.e. 0.33; dip with a = 0.4, tau = 0.25: min 0.6 at g = 0.25,
    recovery at the grid strain after its root; 1 - 0.5 exp(-g/5) never recovers on [0, 2]:
    recovery_settled False, recovery strain = 2 (the last strain). Every bootstrap resample is the
    same curve, so every interval is the value itself; the deficit has s.e. 0 and a zero-width
    t-interval."""
    table = runs_table({0.0: [exponential()] * 3, 90.0: [dip()] * 3, 180.0: [exponential(0.5, 5.0)] * 3})
    out = stress_model.viscosity_transients(table, same_steady(3), 2.0, smoothing_strain=0.0).set_index("theta")
    assert list(out.index) == [0.0, 90.0, 180.0]
    assert (out["n_seeds"] == 3).all() and (out["level"] == LEVEL).all() and (out["window"] == 2.0).all()
    assert 0.2 * np.log(5) == pytest.approx(0.32189, abs=1e-5)
    expected = {0.0: (0.5, 0.0, 0.33, True), 90.0: (0.6, 0.25, dip_recovery(), True), 180.0: (0.5, 0.0, 2.0, False)}
    for theta, (minimum, at, recovery, settled) in expected.items():
        row = out.loc[theta]
        assert row["minimum"] == pytest.approx(minimum, rel=1e-12)
        assert row["strain_at_min"] == pytest.approx(at, abs=1e-12)
        assert row["recovery_strain"] == pytest.approx(recovery, abs=1e-12)
        assert bool(row["recovery_settled"]) is settled
        for name in ("minimum", "strain_at_min", "recovery_strain"):
            assert row[f"{name}_low"] == pytest.approx(row[name], abs=1e-12)
            assert row[f"{name}_high"] == pytest.approx(row[name], abs=1e-12)
        assert row["deficit_se"] == pytest.approx(0.0, abs=1e-15)
        assert row["deficit_low"] == pytest.approx(row["deficit"], abs=1e-12)
        assert row["deficit_high"] == pytest.approx(row["deficit"], abs=1e-12)
    # 1 - 0.5 exp(-g/0.2) over [0, 2]: deficit 0.1 (1 - exp(-10))
    assert out.loc[0.0, "deficit"] == pytest.approx(0.1 * (1 - np.exp(-10.0)), rel=5e-4)
    assert 0.5 < dip_recovery() < 2.0


def test_viscosity_transients_different_seeds():
    """Seeds with different dips (a, tau) = (0.3, 0.2), (0.4, 0.25), (0.5, 0.3): the values are those
    of the seed-mean curve / eta_ss (its minimum, argmin strain, first strain of staying within 10%)
    and the intervals the 2.5% and 97.5% quantiles over all 27 resamples of the seeds with
    replacement, recomputed here; each contains its value and the minimum's has non-zero width."""
    seeds = [dip(0.3, 0.2), dip(0.4, 0.25), dip(0.5, 0.3)]
    out = stress_model.viscosity_transients(runs_table({90.0: seeds}), same_steady(3), 2.0, smoothing_strain=0.0).iloc[
        0
    ]

    def outside_last(mean):
        return T_GRID[np.flatnonzero(np.abs(mean - 1.0) > 0.1)[-1] + 1]

    statistics = {
        "minimum": np.min,
        "strain_at_min": lambda mean: T_GRID[np.argmin(mean)],
        "recovery_strain": outside_last,
    }
    mean = np.mean(seeds, axis=0)
    for name, statistic in statistics.items():
        low, high = bootstrap_interval(statistic, seeds)
        assert out[name] == pytest.approx(statistic(mean), rel=1e-12)
        assert out[f"{name}_low"] == pytest.approx(low, rel=1e-12, abs=1e-12)
        assert out[f"{name}_high"] == pytest.approx(high, rel=1e-12, abs=1e-12)
        assert out[f"{name}_low"] <= out[name] <= out[f"{name}_high"]
    assert out["minimum_high"] > out["minimum_low"]
    assert bool(out["recovery_settled"]) and out["n_seeds"] == 3
    for old in ("eta_min_over_ss_err", "strain_at_min_err", "recovery_strain_err", "recovered"):
        assert old not in out.index


def test_viscosity_transients_resample_each_seeds_own_steady_state():
    """Seeds with their own steady eta_ss,s: the description is on mean_s eta_r,s / mean_s eta_ss,s
    (the study's eta_r/eta_r^ss), and a bootstrap resample divides by the mean steady value of the
    same seeds; the deficit divides each seed by its own."""
    curves, steady = [dip(0.3, 0.2), dip(0.5, 0.3)], [6.0, 9.0]
    table = runs_table({90.0: curves}, eta_ss=steady)
    out = stress_model.viscosity_transients(table, {1: 6.0, 2: 9.0}, 2.0, smoothing_strain=0.0).iloc[0]
    ratio = (6.0 * curves[0] + 9.0 * curves[1]) / 15.0
    assert out["minimum"] == pytest.approx(ratio.min(), rel=1e-12)
    # resamples (1, 1) and (2, 2) are each seed's own curve: the extremes of the 4 resamples
    assert out["minimum_low"] == pytest.approx(
        np.quantile([curves[1].min(), ratio.min(), ratio.min(), curves[0].min()], 0.025), rel=1e-12
    )
    per_seed = stress_model.viscosity_deficits(table, {1: 6.0, 2: 9.0}, 2.0)
    np.testing.assert_allclose(per_seed["deficit"], [np.trapezoid(1 - c, T_GRID) for c in curves], rtol=1e-12)


def test_viscosity_transients_single_seed_and_tolerance():
    """One seed: no bootstrap interval (nan) and an infinite t-interval; a wider tolerance (0.2)
    moves the exponential's recovery to the first grid strain >= 0.2 ln(0.5/0.2) = 0.1833, i.e. 0.19."""
    out = stress_model.viscosity_transients(
        runs_table({0.0: [exponential()]}), same_steady(1), 2.0, tolerance=0.2, smoothing_strain=0.0
    ).iloc[0]
    assert out["recovery_strain"] == pytest.approx(0.19, abs=1e-12)
    assert np.isnan(out["recovery_strain_low"]) and np.isnan(out["recovery_strain_high"]) and out["n_seeds"] == 1
    assert out["deficit_low"] == -np.inf and out["deficit_high"] == np.inf


def test_moving_average_and_smoothed_transients():
    """moving_average: the mean over the points within width/2 of each point (fewer at the ends),
    so a linear series is unchanged inside and an alternating +-a series (frame noise) is damped
    to a/3 by a 3-point window; viscosity_transients smooths the seed mean by it, so a dip of
    1 - 0.5 exp(-gamma/0.2) with +-0.15 frame noise recovers where the noiseless curve does
    (0.2 ln 5 = 0.32), while unsmoothed it never re-enters the 10% band. The deficit is not
    smoothed."""
    strain = T_GRID
    np.testing.assert_allclose(stress_model.moving_average(strain, 2 * strain, 0.02)[1:-1], 2 * strain[1:-1])
    noise = 0.15 * (-1.0) ** np.arange(len(strain))
    damped = stress_model.moving_average(strain, noise, 0.02)
    np.testing.assert_allclose(np.abs(damped[1:-1]), 0.05, rtol=1e-9)
    np.testing.assert_array_equal(stress_model.moving_average(strain, noise, 0.0), noise)
    clean = 1 - 0.5 * np.exp(-strain / 0.2)
    noisy = runs_table({90.0: [clean + noise, clean + noise]})
    raw = stress_model.viscosity_transients(noisy, same_steady(2), 2.0, smoothing_strain=0.0).iloc[0]
    smoothed = stress_model.viscosity_transients(noisy, same_steady(2), 2.0, smoothing_strain=0.1).iloc[0]
    assert not raw["recovery_settled"] and raw["recovery_strain"] == strain[-1]
    assert smoothed["recovery_settled"] and abs(smoothed["recovery_strain"] - 0.33) <= 0.03
    assert smoothed["deficit"] == raw["deficit"] == pytest.approx(np.trapezoid(-(clean + noise - 1.0), strain))
