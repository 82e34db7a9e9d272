"""Unit tests of suspension_fabric.analysis.stress on synthetic stress tables (no LAMMPS).

Conventions checked (module docstring of suspension_fabric.analysis.stress): a table holds LAMMPS
pressure tensors P in the order xx yy zz xy xz yz (total, ``kinetic_``, ``contact_``,
``lubrication_``), the summed contact torque ``contact_torque_x/y/z`` and the box volume
``vol``; each part of the stress is sigma = -P / (eta_f gammadot) (the contact one after
symmetrisation), written in the paper frame of the shear with flow angle t:
e1 = (c, s, 0), e2 = (0, 0, 1), e3 = (s, -c, 0), c = cos t, s = sin t.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis import stress
from suspension_fabric.analysis.stress import (
    PAPER_COMPONENTS,
    PARTS,
    STRESS_TABLE_COLUMNS,
    derived_quantities,
    pressure_tensors,
    read_stress_csv,
    run_stress_table,
    stress_on_frames,
    stress_parts,
    symmetric_contact_pressure,
)

ETA_F = 223.0
RATE = 0.7
PHI = 0.31
ANGLES_DEG = [0.0, 30.0, 90.0, 137.5, -45.0, 180.0]
LAMMPS_ORDER = ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")
PREFIXES = ("", "kinetic_", "contact_", "lubrication_", "stresslet_")


def synthetic_table(rows=7, seed=0, first_step=0, every=10):
    """A table of random values in every column of the current format (shear_run.lmp)."""
    rng = np.random.default_rng(seed)
    table = {
        "step": first_step + every * np.arange(rows, dtype=float),
        "strain": every * 1e-3 * np.arange(rows, dtype=float),
    }
    for prefix in PREFIXES:
        for name in LAMMPS_ORDER:
            table[prefix + name] = rng.normal(size=rows) * 50.0
    table["press"] = rng.normal(size=rows)
    for axis in "xyz":
        table[f"contact_torque_{axis}"] = rng.normal(size=rows) * 300.0
    table["vol"] = rng.uniform(100.0, 200.0, size=rows)
    table["xz"] = rng.normal(size=rows)
    table["yz"] = rng.normal(size=rows)
    table["lz"] = np.full(rows, 6.0)
    return table


def explicit_paper_components(sxx, syy, szz, sxy, sxz, syz, t):
    """The paper-frame components of a symmetric sigma written out by hand."""
    c, s = np.cos(t), np.sin(t)
    return {
        "11": c * c * sxx + 2 * c * s * sxy + s * s * syy,
        "22": szz,
        "33": s * s * sxx - 2 * c * s * sxy + c * c * syy,
        "12": c * sxz + s * syz,
        "13": c * s * (sxx - syy) - (c * c - s * s) * sxy,
        "23": s * sxz - c * syz,
    }


INDEX = {"11": (0, 0), "22": (1, 1), "33": (2, 2), "12": (0, 1), "13": (0, 2), "23": (1, 2)}


def hand_symmetrised_contact(table):
    """P_sym: diagonal as stored, P_xy + T_z/2V, P_xz - T_y/2V, P_yz + T_x/2V."""
    v2 = 2.0 * table["vol"]
    return dict(
        pxx=table["contact_pxx"],
        pyy=table["contact_pyy"],
        pzz=table["contact_pzz"],
        pxy=table["contact_pxy"] + table["contact_torque_z"] / v2,
        pxz=table["contact_pxz"] - table["contact_torque_y"] / v2,
        pyz=table["contact_pyz"] + table["contact_torque_x"] / v2,
    )


# ------------------------------------------------------------------ paper-frame components


@pytest.mark.parametrize("angle_deg", ANGLES_DEG)
def test_particle_parts_match_the_explicit_paper_frame_formulas(angle_deg):
    """For every particle part, sigma = -P/(eta_f gammadot) (contact P symmetrised with the
    torque) and, with c = cos t, s = sin t:
    sigma'_11 = c^2 s_xx + 2cs s_xy + s^2 s_yy, sigma'_22 = s_zz,
    sigma'_33 = s^2 s_xx - 2cs s_xy + c^2 s_yy, sigma'_12 = c s_xz + s s_yz,
    sigma'_13 = cs (s_xx - s_yy) - (c^2 - s^2) s_xy, sigma'_23 = s s_xz - c s_yz;
    the returned tensors are symmetric."""
    table = synthetic_table()
    t = np.radians(angle_deg)
    parts = stress_parts(table, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=angle_deg)
    sources = {
        "kinetic": {k: table[f"kinetic_{k}"] for k in LAMMPS_ORDER},
        "lubrication": {k: table[f"lubrication_{k}"] for k in LAMMPS_ORDER},
        "stresslet": {k: table[f"stresslet_{k}"] for k in LAMMPS_ORDER},
        "contact": hand_symmetrised_contact(table),
    }
    for part, pressure in sources.items():
        sigma = [-pressure[k] / (ETA_F * RATE) for k in LAMMPS_ORDER]
        expected = explicit_paper_components(*sigma, t)
        tensor = parts[part]
        assert tensor.shape == (len(table["step"]), 3, 3)
        np.testing.assert_allclose(tensor, np.swapaxes(tensor, -1, -2), rtol=0, atol=1e-14 * np.abs(tensor).max())
        for component, (a, b) in INDEX.items():
            np.testing.assert_allclose(
                tensor[:, a, b],
                expected[component],
                rtol=1e-12,
                atol=1e-12,
                err_msg=f"{part}_{component} at t = {angle_deg}",
            )


@pytest.mark.parametrize("angle_deg", ANGLES_DEG)
def test_solvent_and_einstein_parts_are_pure_12_in_every_frame(angle_deg):
    """solvent = 2 eta_f E / (eta_f gammadot): 1 on the 12 component; einstein = 5 phi eta_f E:
    2.5 phi on 12; every other paper component 0, whatever the flow angle."""
    table = synthetic_table()
    parts = stress_parts(table, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=angle_deg)
    for part, value in (("solvent", 1.0), ("einstein", 2.5 * PHI)):
        expected = np.zeros((3, 3))
        expected[0, 1] = expected[1, 0] = value
        np.testing.assert_allclose(parts[part], np.broadcast_to(expected, parts[part].shape), rtol=0, atol=1e-15)


@pytest.mark.parametrize("angle_deg", [0.0, 137.5])
def test_total_is_the_sum_of_the_parts(angle_deg):
    """total = contact + lubrication + kinetic + solvent + einstein (not the table's own total
    columns pxx..pyz, which stress_parts does not use, nor the pair stresslets, recorded beside
    the lubrication dipoles as an alternative to them)."""
    table = synthetic_table(seed=3)
    parts = stress_parts(table, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=angle_deg)
    summed = sum(parts[name] for name in PARTS if name != "total")
    np.testing.assert_allclose(parts["total"], summed, rtol=1e-14, atol=1e-14)
    changed = dict(table, pxx=table["pxx"] + 1e3, pxz=table["pxz"] - 7.0, stresslet_pxz=table["stresslet_pxz"] + 50.0)
    again = stress_parts(changed, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=angle_deg)
    np.testing.assert_array_equal(again["total"], parts["total"])
    assert not np.allclose(again["stresslet"], parts["stresslet"])


def test_stresslet_part_is_nan_where_not_recorded(tmp_path):
    """A table without stresslet columns (written before they were recorded) and one whose
    stresslet columns are NaN (the stock force model) give a NaN stresslet part and the same
    other parts; a per-run CSV without the stresslet columns reads back with them NaN."""
    table = synthetic_table(seed=5)
    full = stress_parts(table, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=30.0)
    older = {name: values for name, values in table.items() if not name.startswith("stresslet_")}
    stock = dict(table, **{f"stresslet_{k}": np.full(len(table["step"]), np.nan) for k in LAMMPS_ORDER})
    for variant in (older, stock):
        parts = stress_parts(variant, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=30.0)
        assert np.isnan(parts["stresslet"]).all()
        for name in PARTS:
            np.testing.assert_array_equal(parts[name], full[name])
    frames = stress_on_frames(older, [20, 40], first_step=0, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=30.0)
    frames.insert(0, "seed", 1)
    for name, value in (("theta", 30.0), ("N", 40), ("phi", PHI), ("strain", [0.02, 0.04])):
        frames[name] = value
    old_csv = tmp_path / "old_stress.csv"
    frames.drop(columns=list(stress.OPTIONAL_COLUMNS)).to_csv(old_csv, index=False)
    read = read_stress_csv(old_csv)
    assert list(read.columns) == list(STRESS_TABLE_COLUMNS)
    assert read[list(stress.OPTIONAL_COLUMNS)].isna().all().all()
    np.testing.assert_allclose(read["eta_r"], frames["eta_r"], rtol=1e-15)


def test_stress_parts_rejects_non_positive_viscosity_or_rate():
    """eta_f and the rate divide the pressure: both must be > 0."""
    table = synthetic_table()
    for eta_f, rate in ((0.0, 1.0), (1.0, 0.0), (-1.0, 1.0)):
        with pytest.raises(ValueError, match="eta_f and rate must be positive"):
            stress_parts(table, eta_f=eta_f, rate=rate, phi=PHI, theta_deg=0.0)


# ------------------------------------------------------------------ contact symmetrisation


def lammps_contact_row(pairs, volume):
    """What LAMMPS records for contact pairs (r = x_i - x_j, F = force on i): the virial
    sum r_a F_b / V, upper triangle for the off-diagonals (xy = r_x F_y, xz = r_x F_z,
    yz = r_y F_z), and the summed torque T = -sum r x F (the lever-arm identity)."""
    full = sum(np.outer(r, f) for r, f in pairs) / volume
    torque = -sum(np.cross(r, f) for r, f in pairs)
    row = {
        f"contact_{name}": np.array([full[a, b]])
        for name, (a, b) in zip(LAMMPS_ORDER, ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)))
    }
    row.update({f"contact_torque_{k}": np.array([torque[n]]) for n, k in enumerate("xyz")})
    row["vol"] = np.array([volume])
    return row


@pytest.mark.parametrize("n_pairs", [1, 5])
def test_contact_symmetrisation_of_pairs_with_tangential_forces(n_pairs):
    """For contact pairs with tangential forces (F not along r): with P = sum r F^T / V stored
    upper-triangle and T = -sum r x F, symmetric_contact_pressure = sum (r F^T + F r^T) / 2V
    exactly (one pair, and a sum of pairs: the correction is linear)."""
    rng = np.random.default_rng(n_pairs)
    pairs = []
    for _ in range(n_pairs):
        r = rng.normal(size=3)
        n = r / np.linalg.norm(r)
        tangential = np.cross(n, rng.normal(size=3))
        force = 1e3 * (1.3 * n + 0.4 * tangential)  # repulsive normal part + friction
        pairs.append((r, force))
    volume = 123.4
    row = lammps_contact_row(pairs, volume)
    expected = sum(np.outer(r, f) + np.outer(f, r) for r, f in pairs) / (2.0 * volume)
    got = symmetric_contact_pressure(row)
    assert got.shape == (1, 3, 3)
    np.testing.assert_allclose(got[0], expected, rtol=1e-13, atol=1e-13 * np.abs(expected).max())
    # the correction is not trivial: the stored tensor is not the symmetric one
    stored = pressure_tensors(row, "contact_")[0]
    assert np.abs(stored - expected).max() > 1e-3 * np.abs(expected).max()


def test_contact_symmetrisation_leaves_central_forces_alone():
    """Central forces (F parallel to r) give T = 0 and an already symmetric virial: unchanged."""
    rng = np.random.default_rng(9)
    pairs = [(r, -2.5 * r) for r in rng.normal(size=(4, 3))]
    row = lammps_contact_row(pairs, 50.0)
    np.testing.assert_allclose([row[f"contact_torque_{k}"][0] for k in "xyz"], 0.0, atol=1e-12)
    np.testing.assert_allclose(
        symmetric_contact_pressure(row), pressure_tensors(row, "contact_"), rtol=1e-14, atol=1e-14
    )


# ------------------------------------------------------------------ frames and windows


def windowing_table():
    """Rows every 5 steps from the set-up row at step 100 (= first_step) to 200; the
    lubrication pxz is -(step) so the lubrication 12 component at t = 0 reads step/(eta rate);
    the set-up row holds a huge value that must never show."""
    steps = np.arange(100, 201, 5, dtype=float)
    table = synthetic_table(rows=len(steps))
    for prefix in PREFIXES:
        for name in LAMMPS_ORDER:
            table[prefix + name] = np.zeros(len(steps))
    for axis in "xyz":
        table[f"contact_torque_{axis}"] = np.zeros(len(steps))
    table["step"] = steps
    table["lubrication_pxz"] = -steps
    table["lubrication_pxz"][0] = -1e9  # the set-up row
    return table


def test_stress_on_frames_windows_and_skips_the_set_up_row():
    """Frame at step s: mean over rows with step in (s - h, s + h], h = half the (smallest) frame
    spacing, rows after first_step only: frames 100, 120, 140 (h = 10) average rows
    {105, 110}, {115, ..., 130} and {135, ..., 150}; the set-up row at first_step = 100 is never
    used (its value 1e9 would show)."""
    table = windowing_table()
    frames = stress_on_frames(table, [100, 120, 140], first_step=100, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    np.testing.assert_array_equal(frames["step"], [100, 120, 140])
    np.testing.assert_array_equal(frames["n_rows"], [2, 4, 4])
    expected_steps = [np.mean([105, 110]), np.mean([115, 120, 125, 130]), np.mean([135, 140, 145, 150])]
    np.testing.assert_allclose(frames["lubrication_12"], np.array(expected_steps) / (ETA_F * RATE), rtol=1e-14)
    assert list(frames.columns[:2]) == ["step", "n_rows"]
    expected_columns = {f"{p}_{c}" for p in PARTS for c in PAPER_COMPONENTS} | {"eta_r", "N1", "N2", "Pi"}
    assert expected_columns <= set(frames.columns)


def test_stress_on_frames_single_frame_uses_its_own_row():
    """One frame: no frame spacing, so h = half the row spacing (5 steps): only the row at that
    very step is used."""
    table = windowing_table()
    frames = stress_on_frames(table, [150], first_step=100, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    assert frames["n_rows"].tolist() == [1]
    np.testing.assert_allclose(frames["lubrication_12"], [150.0 / (ETA_F * RATE)], rtol=1e-14)


def test_frame_at_the_set_up_step_takes_the_first_rows_after_it():
    """The frame at first_step takes the rows in (s, s + max(h, row spacing)]: with frames every
    4 steps and rows every 5 (h = 2), frame 100 takes row 105 (not the set-up row 100, whose
    1e9 would show), frame 104 the rows in (102, 106] = {105}, frame 108 (106, 110] = {110};
    a lone frame at first_step likewise takes row 105."""
    table = windowing_table()
    kwargs = dict(first_step=100, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    frames = stress_on_frames(table, [100, 104, 108], **kwargs)
    np.testing.assert_array_equal(frames["n_rows"], [1, 1, 1])
    np.testing.assert_allclose(frames["lubrication_12"], np.array([105.0, 105.0, 110.0]) / (ETA_F * RATE), rtol=1e-14)
    alone = stress_on_frames(table, [100], **kwargs)
    np.testing.assert_allclose(alone["lubrication_12"], [105.0 / (ETA_F * RATE)], rtol=1e-14)


def test_stress_on_frames_errors():
    """A frame with no table row within h, frames that do not increase, no frames: ValueError;
    so does a frame at the set-up step of a table with no row after it."""
    table = windowing_table()
    kwargs = dict(first_step=100, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    with pytest.raises(ValueError, match="no stress-table row within 10 steps of frame step 220"):
        stress_on_frames(table, [180, 200, 220], **kwargs)
    with pytest.raises(ValueError, match="frame steps must increase"):
        stress_on_frames(table, [120, 120, 140], **kwargs)
    with pytest.raises(ValueError, match="no frame steps"):
        stress_on_frames(table, [], **kwargs)
    set_up_only = {name: values[:1] for name, values in table.items()}
    with pytest.raises(ValueError, match="frame step 100"):
        stress_on_frames(set_up_only, [100], **kwargs)


def test_derived_quantities():
    """eta_r = total_12, N1 = total_11 - total_22, N2 = total_22 - total_33,
    Pi = -(1/3) sum over contact, lubrication, kinetic of (11 + 22 + 33) (no solvent/einstein)."""
    rng = np.random.default_rng(4)
    frame = pd.DataFrame({f"{p}_{c}": rng.normal(size=5) for p in PARTS for c in PAPER_COMPONENTS})
    out = derived_quantities(frame)
    np.testing.assert_array_equal(out["eta_r"], frame["total_12"])
    np.testing.assert_allclose(out["N1"], frame["total_11"] - frame["total_22"], rtol=1e-15)
    np.testing.assert_allclose(out["N2"], frame["total_22"] - frame["total_33"], rtol=1e-15)
    trace = sum(frame[f"{p}_{c}"] for p in ("contact", "lubrication", "kinetic") for c in ("11", "22", "33"))
    np.testing.assert_allclose(out["Pi"], -trace / 3.0, rtol=1e-14)
    assert "eta_r" not in frame.columns  # the input is not modified


def test_derived_quantities_of_a_pure_shear_table():
    """A table with only solvent and Einstein parts: eta_r = 1 + 2.5 phi, N1 = N2 = Pi = 0."""
    table = windowing_table()
    table["lubrication_pxz"] = np.zeros_like(table["step"])
    frames = stress_on_frames(table, [120, 140], first_step=100, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=63.0)
    np.testing.assert_allclose(frames["eta_r"], 1.0 + 2.5 * PHI, rtol=1e-15)
    np.testing.assert_allclose(frames[["N1", "N2", "Pi"]].to_numpy(), 0.0, atol=1e-15)


# ------------------------------------------------------------------ old-format tables


OLD_HEADER = (
    "step strain pxx pyy pzz pxy pxz pyz press contact_pxz contact_pyz contact_press "
    "lubrication_pxz lubrication_pyz lubrication_press xz yz lz"
).split()


def old_format_table(rows=3):
    """A table in the format before the stress parts were recorded in full (only the xz, yz
    and scalar pressure of the contact and lubrication parts, no torque, no volume)."""
    return {name: np.arange(rows, dtype=float) for name in OLD_HEADER}


def test_old_format_table_errors_name_the_missing_columns():
    """stress_parts on an old table fails naming a missing column and asking for a rerun;
    pressure_tensors names every missing component of a part (here xx yy zz xy)."""
    table = old_format_table()
    with pytest.raises(ValueError, match=r"lacks column 'contact_torque_x'.*rerun"):
        stress_parts(table, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    with pytest.raises(ValueError) as info:
        pressure_tensors(table, "lubrication_")
    message = str(info.value)
    for name in ("lubrication_pxx", "lubrication_pyy", "lubrication_pzz", "lubrication_pxy"):
        assert name in message
    assert "lubrication_pxz" not in message and "rerun" in message
    with pytest.raises(ValueError, match="kinetic_pxx"):
        pressure_tensors(table, "kinetic_")
    with_torque = dict(
        table, contact_torque_x=table["step"], contact_torque_y=table["step"], contact_torque_z=table["step"]
    )
    with pytest.raises(ValueError, match="lacks column 'vol'"):
        symmetric_contact_pressure(with_torque)


# ------------------------------------------------------------------ run_stress_table


def write_run(tmp_path, table, *, first_step, dt, rate, theta=None, eta_f="223.0"):
    """stress.txt (as shear_run.lmp writes it), run_complete.json (as the runner) of a run."""
    names = list(table)
    data = np.column_stack([table[n] for n in names])
    stress_txt = tmp_path / "stress.txt"
    np.savetxt(stress_txt, data, header=" ".join(names), comments="# ")
    variables = {"dt": repr(dt), "rate": repr(rate)}
    if eta_f is not None:
        variables["eta_f"] = eta_f
    if theta is not None:
        variables["theta_deg"] = repr(theta)
    marker = tmp_path / "run_complete.json"
    marker.write_text(json.dumps({"variables": variables, "results": {"first_step": first_step}}))
    return stress_txt, marker


def write_fabric(tmp_path, steps, *, theta, phi, first_step, dt, rate, seed=5, n=40):
    fabric = pd.DataFrame(
        {
            "seed": seed,
            "theta": theta,
            "N": n,
            "phi": phi,
            "step": steps,
            "strain": (np.asarray(steps) - first_step) * dt * rate,
            "n11": 0.1,
            "n22": 0.1,
            "n33": 0.1,
            "n12": 0.0,
            "n13": 0.0,
            "n23": 0.0,
            "Z": 0.6,
        }
    )
    path = tmp_path / "fabric.csv"
    fabric.to_csv(path, index=False)
    return path


def test_run_stress_table_end_to_end(tmp_path):
    """run_stress_table: frames and metadata of the fabric table, dt/rate/first step/theta/eta_f
    of the marker, phi (for the Einstein part) of the fabric table; the values equal
    stress_on_frames on the same inputs; columns STRESS_TABLE_COLUMNS; read_stress_csv reads
    the written CSV back."""
    table = windowing_table()
    table["kinetic_pxx"] = np.linspace(-1.0, 1.0, len(table["step"]))
    stress_txt, marker = write_run(tmp_path, table, first_step=100, dt=2e-3, rate=RATE, theta=30.0)
    fabric = write_fabric(tmp_path, [100, 120, 140], theta=30.0, phi=PHI, first_step=100, dt=2e-3, rate=RATE)
    out = run_stress_table(stress_txt, marker, fabric)
    assert list(out.columns) == list(STRESS_TABLE_COLUMNS)
    np.testing.assert_array_equal(out["step"], [100, 120, 140])
    np.testing.assert_allclose(out["strain"], [0.0, 20 * 2e-3 * RATE, 40 * 2e-3 * RATE])
    assert (out["seed"] == 5).all() and (out["N"] == 40).all() and np.allclose(out["theta"], 30.0)
    direct = stress_on_frames(table, [100, 120, 140], first_step=100, eta_f=223.0, rate=RATE, phi=PHI, theta_deg=30.0)
    for column in stress.STRESS_VALUE_COLUMNS:
        np.testing.assert_allclose(out[column], direct[column], rtol=1e-12, atol=1e-14, err_msg=column)
    np.testing.assert_allclose(out["einstein_12"], 2.5 * PHI, rtol=1e-15)
    # eta_f given explicitly overrides the marker's
    half = run_stress_table(stress_txt, marker, fabric, eta_f=446.0)
    np.testing.assert_allclose(half["lubrication_12"], 0.5 * out["lubrication_12"], rtol=1e-14)
    csv = tmp_path / "stress.csv"
    out.to_csv(csv, index=False)
    pd.testing.assert_frame_equal(read_stress_csv(csv), out, check_exact=False, rtol=1e-15)


def test_run_stress_table_errors(tmp_path):
    """A fabric table of another flow angle, a marker without eta_f (and none given), a fabric
    table lacking a column, an old-format stress table, and a CSV lacking columns all fail
    with a message naming the problem."""
    table = windowing_table()
    stress_txt, marker = write_run(tmp_path, table, first_step=100, dt=2e-3, rate=RATE, theta=30.0)
    fabric = write_fabric(tmp_path, [120, 140], theta=0.0, phi=PHI, first_step=100, dt=2e-3, rate=RATE)
    with pytest.raises(
        ValueError, match=r"flow angles of its frames \(0.0 ...\) differ from those of the run record's segment \(30.0"
    ):
        run_stress_table(stress_txt, marker, fabric)

    fabric = write_fabric(tmp_path, [120, 140], theta=30.0, phi=PHI, first_step=100, dt=2e-3, rate=RATE)
    pd.read_csv(fabric).drop(columns="phi").to_csv(tmp_path / "no_phi.csv", index=False)
    with pytest.raises(ValueError, match=r"fabric table lacks column\(s\) \['phi'\]"):
        run_stress_table(stress_txt, marker, tmp_path / "no_phi.csv")

    no_eta = tmp_path / "no_eta"
    no_eta.mkdir()
    stress_txt2, marker2 = write_run(no_eta, table, first_step=100, dt=2e-3, rate=RATE, theta=30.0, eta_f=None)
    with pytest.raises(ValueError, match="no variables.eta_f"):
        run_stress_table(stress_txt2, marker2, fabric)
    assert len(run_stress_table(stress_txt2, marker2, fabric, eta_f=223.0)) == 2

    old = tmp_path / "old"
    old.mkdir()
    old_txt, old_marker = write_run(old, old_format_table(), first_step=0, dt=2e-3, rate=RATE, theta=30.0)
    with pytest.raises(ValueError, match="contact_torque_x"):
        run_stress_table(old_txt, old_marker, fabric)

    (tmp_path / "bad.csv").write_text("seed,theta,step\n1,0,0\n")
    with pytest.raises(ValueError, match=r"bad.csv: stress table lacks column\(s\) \['N', 'phi'"):
        read_stress_csv(tmp_path / "bad.csv")
    with pytest.raises(FileNotFoundError):
        read_stress_csv(tmp_path / "missing.csv")


def test_with_lubrication_stress_swaps_the_stresslets_in():
    """analysis.lubrication_stress = stresslet: lubrication_ij = stresslet_ij,
    total_ij = old total_ij - dipole_ij + stresslet_ij, eta_r = new total_12,
    N1 = total_11 - total_22, N2 = total_22 - total_33, Pi = -(1/3) Tr(contact + stresslet + kinetic);
    dipole leaves the table as it is; a NaN stresslet or an unknown choice is an error naming it."""
    rng = np.random.default_rng(8)
    values = {f"{p}_{c}": rng.normal(size=4) for p in (*PARTS, "stresslet") for c in PAPER_COMPONENTS}
    frame = derived_quantities(pd.DataFrame(values))
    assert stress.with_lubrication_stress(frame, "dipole") is frame
    swapped = stress.with_lubrication_stress(frame, "stresslet")
    for c in PAPER_COMPONENTS:
        np.testing.assert_array_equal(swapped[f"lubrication_{c}"], frame[f"stresslet_{c}"])
        np.testing.assert_allclose(
            swapped[f"total_{c}"],
            frame[f"total_{c}"] - frame[f"lubrication_{c}"] + frame[f"stresslet_{c}"],
            rtol=1e-13,
            atol=1e-13,
        )
        np.testing.assert_array_equal(swapped[f"contact_{c}"], frame[f"contact_{c}"])
    np.testing.assert_array_equal(swapped["eta_r"], swapped["total_12"])
    np.testing.assert_allclose(swapped["N1"], swapped["total_11"] - swapped["total_22"], rtol=1e-13)
    np.testing.assert_allclose(swapped["N2"], swapped["total_22"] - swapped["total_33"], rtol=1e-13)
    trace = sum(frame[f"{p}_{c}"] for p in ("contact", "stresslet", "kinetic") for c in ("11", "22", "33"))
    np.testing.assert_allclose(swapped["Pi"], -trace / 3.0, rtol=1e-13)
    with pytest.raises(ValueError, match=r"runs/x\.csv: analysis.lubrication_stress = stresslet, but 1 row"):
        stress.with_lubrication_stress(frame.assign(stresslet_23=[0.0, np.nan, 0.0, 0.0]), "stresslet", "runs/x.csv")
    with pytest.raises(ValueError, match="must be one of \\['dipole', 'stresslet'\\], got 'virial'"):
        stress.with_lubrication_stress(frame, "virial")


def test_read_stress_csv_applies_the_choice_and_names_an_old_file(tmp_path):
    """read_stress_csv(path, 'stresslet') on a table with stresslets equals with_lubrication_stress
    of the plain read; on a CSV from before the stresslets were recorded it fails naming the file."""
    rng = np.random.default_rng(2)
    frame = pd.DataFrame(
        {"seed": 1, "theta": 0.0, "N": 40, "phi": PHI, "step": [10, 20, 30], "strain": [0.01, 0.02, 0.03], "n_rows": 2}
    )
    for p in (*PARTS, "stresslet"):
        for c in PAPER_COMPONENTS:
            frame[f"{p}_{c}"] = rng.normal(size=3)
    frame = derived_quantities(frame)
    path = tmp_path / "stress.csv"
    frame.to_csv(path, index=False)
    pd.testing.assert_frame_equal(
        read_stress_csv(path, "stresslet"), stress.with_lubrication_stress(read_stress_csv(path), "stresslet")
    )
    old = tmp_path / "old.csv"
    frame.drop(columns=list(stress.STRESSLET_COLUMNS)).to_csv(old, index=False)
    with pytest.raises(ValueError, match=f"{old}: analysis.lubrication_stress = stresslet"):
        read_stress_csv(old, "stresslet")


def test_recorded_value_columns_leave_out_what_no_run_recorded():
    """Stresslet columns NaN in every row are left out of the aggregated columns; NaN in some
    rows only is an error naming the seeds without them."""
    frame = pd.DataFrame({"seed": [1, 1, 2], **{c: [0.1, 0.2, 0.3] for c in stress.STRESS_VALUE_COLUMNS}})
    assert stress.recorded_value_columns(frame) == stress.STRESS_VALUE_COLUMNS
    older = frame.assign(**{c: np.nan for c in stress.OPTIONAL_COLUMNS})
    kept = stress.recorded_value_columns(older)
    assert set(kept) == set(stress.STRESS_VALUE_COLUMNS) - set(stress.OPTIONAL_COLUMNS)
    mixed = frame.copy()
    mixed.loc[2, "stresslet_12"] = np.nan
    with pytest.raises(
        ValueError,
        match=r"runs/x: stresslet_12 is recorded in some runs but not in others "
        r"\(missing for seeds \[2\]\)",
    ):
        stress.recorded_value_columns(mixed, "runs/x")


def test_a_critical_load_recorded_in_some_runs_only_is_left_out_with_a_message(capsys):
    """Runs at imposed rate from before the critical load was recorded beside newer ones: the column
    (a constant of the config there) is left out of every run, with a message naming the source."""
    frame = pd.DataFrame({"seed": [1, 1, 2], **{c: [0.1, 0.2, 0.3] for c in stress.STRESS_VALUE_COLUMNS}})
    mixed = frame.copy()
    mixed.loc[2, "critical_load"] = np.nan
    kept = stress.recorded_value_columns(mixed, "runs/y")
    assert "critical_load" not in kept and "stresslet_12" in kept
    assert "runs/y: critical_load recorded in some runs only" in capsys.readouterr().out


def test_a_stress_table_cut_mid_line_is_refused_as_truncated_naming_the_file(tmp_path):
    """A finished run's stress.txt whose last row lacks its newline (cut by a kill or a full disk)
    is refused, naming the file and saying truncated, not read with a row fewer."""
    table = windowing_table()
    stress_txt, marker = write_run(tmp_path, table, first_step=100, dt=2e-3, rate=RATE, theta=30.0)
    text = stress_txt.read_text()
    stress_txt.write_text(text[: text.rstrip("\n").rfind(" ")])  # the last row cut inside a number
    fabric = write_fabric(tmp_path, [120, 140], theta=30.0, phi=PHI, first_step=100, dt=2e-3, rate=RATE)
    with pytest.raises(ValueError, match=rf"{re.escape(str(stress_txt))}: truncated"):
        run_stress_table(stress_txt, marker, fabric)


def test_contact_columns_are_window_means_of_the_counted_contacts():
    """Z_touching = 2 <contacts> / N and Z_frictional = 2 <frictional> / N, the means over each frame's
    window of table rows (the rows in (s - h, s + h], h half the frame spacing): rows at steps 1..4 with
    contacts 0, 20, 30, 50 and frictional 0, 10, 30, 50 give, for frames at 0 (rows 1, 2: the set-up
    frame takes the rows after it) and 4 (rows 3, 4, h = 2) with N = 40, Z_touching = (0.5, 2.0) and
    Z_frictional = (0.25, 2.0), defined also where a row has no contact; a table without counts
    gives NaN, and one with counts but no N is refused."""
    steps = np.arange(0, 5)
    table = {name: np.zeros(5) for name in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")}
    for prefix in ("kinetic_", "contact_", "lubrication_"):
        table.update({f"{prefix}{k}": np.zeros(5) for k in ("pxx", "pyy", "pzz", "pxy", "pxz", "pyz")})
    table.update({f"contact_torque_{k}": np.zeros(5) for k in "xyz"}, vol=np.ones(5), step=steps)
    counted = dict(table, contacts=np.array([0, 0, 20, 30, 50.0]), frictional_contacts=np.array([0, 0, 10, 30, 50.0]))
    frames = stress_on_frames(
        counted, [0, 4], first_step=0, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0, n_particles=40
    )
    np.testing.assert_allclose(frames["Z_touching"], [2 * 10 / 40, 2 * 40 / 40], rtol=1e-15)
    np.testing.assert_allclose(frames["Z_frictional"], [2 * 5 / 40, 2 * 40 / 40], rtol=1e-15)
    plain = stress_on_frames(table, [0, 4], first_step=0, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
    assert plain[list(stress.CONTACT_COLUMNS)].isna().all().all()
    with pytest.raises(ValueError, match="n_particles"):
        stress_on_frames(counted, [0, 4], first_step=0, eta_f=ETA_F, rate=RATE, phi=PHI, theta_deg=0.0)
