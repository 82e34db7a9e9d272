"""Near-contact detection, fabric tensors and the trajectory analysis (suspension_fabric.analysis.fabric)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.analysis.fabric import (
    FOURTH_MOMENT_COMPONENTS,
    HARMONIC_COLUMNS,
    FabricAnalysis,
    direction_moments,
    fabric_tensor,
    near_contact_pairs,
    open_dump,
    real_spherical_harmonics,
)
from suspension_fabric.analysis.fabric_reference import brute_force_fabric_tensor, brute_force_near_contacts
from suspension_fabric.analysis.frames import simulation_to_paper
from suspension_fabric.analysis.tables import (
    MOMENT_COLUMNS,
    TABLE_COLUMNS,
    fabric_table,
    read_fabric_table,
    write_fabric_table,
)
from suspension_fabric.io.dumpio import DumpFrame, TriclinicBox, scan_dump, write_lammps_dump

EPS = 0.01


def random_box(rng) -> TriclinicBox:
    """Box with all three tilts anywhere in [-L/2, L/2] (LAMMPS keeps them there with flip yes)."""
    lx, ly, lz = rng.uniform(5.0, 8.0, size=3)
    return TriclinicBox(
        lx,
        ly,
        lz,
        xy=rng.uniform(-0.5, 0.5) * lx,
        xz=rng.uniform(-0.5, 0.5) * lx,
        yz=rng.uniform(-0.5, 0.5) * ly,
        origin=tuple(rng.uniform(-5.0, 5.0, size=3)),
    )


def random_configuration(rng, n, box, fractional_range=(0.0, 1.0)):
    """Bidisperse radii 0.5/0.7 and positions with fractional coordinates in ``fractional_range``."""
    fractional = rng.uniform(*fractional_range, size=(n, 3))
    positions = np.asarray(box.origin) + fractional @ box.edge_vectors
    radii = np.where(rng.random(n) < 0.5, 0.5, 0.7)
    return positions, radii


def lattice_shifts(positions, pairs, separations, box):
    """Integer lattice translation taking the raw difference x_j - x_i to the minimum image."""
    raw = positions[pairs[:, 1]] - positions[pairs[:, 0]]
    shifts = (separations - raw) @ np.linalg.inv(box.edge_vectors)
    assert np.allclose(shifts, np.round(shifts), atol=1e-8)
    return np.round(shifts).astype(int)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("fractional_range", [(0.0, 1.0), (-1.5, 2.5)], ids=["inside", "outside"])
def test_near_contacts_equal_brute_force(seed, fractional_range):
    """Pairs with |r_ij|_min-image - a_i - a_j < eps * 2 min(a_i, a_j) equal the 27-image O(N^2) search.

    Random triclinic boxes (xy, xz, yz tilts up to half a box length), coordinates in
    the primary cell ("inside") or up to two cells outside it ("outside"). The
    configurations must contain pairs connected through the periodic boundary and
    through the tilted (z) boundary, so that both are exercised.
    """
    rng = np.random.default_rng(1000 + seed)
    box = random_box(rng)
    n = int(rng.integers(150, 300))
    positions, radii = random_configuration(rng, n, box, fractional_range)

    contacts = near_contact_pairs(positions, radii, box.mdanalysis_dimensions(), EPS)
    ref_pairs, ref_separations = brute_force_near_contacts(positions, radii, box.edge_vectors, EPS)

    assert len(ref_pairs) > 50
    np.testing.assert_array_equal(contacts.pairs, ref_pairs)
    np.testing.assert_allclose(contacts.separations, ref_separations, atol=1e-10)
    shifts = lattice_shifts(positions, ref_pairs, ref_separations, box)
    assert np.any(shifts != 0, axis=1).sum() > 5, "no pairs across the periodic boundary"
    assert np.sum(shifts[:, 2] != 0) > 2, "no pairs across the tilted z boundary"

    fabric, n_pairs = fabric_tensor(positions, radii, box.mdanalysis_dimensions(), EPS)
    ref_fabric, ref_n_pairs = brute_force_fabric_tensor(positions, radii, box.edge_vectors, EPS)
    assert n_pairs == ref_n_pairs
    np.testing.assert_allclose(fabric, ref_fabric, atol=1e-12)
    assert np.isclose(np.trace(fabric), n_pairs / n)


def test_threshold_is_strict_and_uses_smaller_diameter():
    """Near contact iff h < eps * min(d_i, d_j): gaps a relative 1e-6 below / above the threshold.

    Pairs: small-small (threshold 0.01), large-large d = 1.4 (threshold 0.014) and
    small-large (threshold 0.01, the smaller diameter), each once just inside and
    once just outside, placed across a tilted boundary.
    """
    box = TriclinicBox(30.0, 30.0, 30.0, xz=11.0, yz=-7.0)
    rows = box.edge_vectors
    radius_pairs = [(0.5, 0.5), (0.7, 0.7), (0.5, 0.7)]
    positions, radii, expected = [], [], []
    direction = np.array([0.3, -0.4, 0.866])
    direction /= np.linalg.norm(direction)
    for k, (ai, aj) in enumerate(radius_pairs):
        threshold = EPS * 2 * min(ai, aj)
        for m, factor in enumerate((1 - 1e-6, 1 + 1e-6)):
            start = np.array([3.0 + 8.0 * k, 4.0 + 12.0 * m, 29.2])
            # j sits just above the z = lz face, stored at its image through the tilted face
            end = start + (ai + aj + threshold * factor) * direction - rows[2]
            positions += [start, end]
            radii += [ai, aj]
            expected.append(factor < 1)
    positions, radii = np.array(positions), np.array(radii)
    contacts = near_contact_pairs(positions, radii, box.mdanalysis_dimensions(), EPS)
    expected_pairs = [(2 * q, 2 * q + 1) for q, inside in enumerate(expected) if inside]
    assert [tuple(p) for p in contacts.pairs] == expected_pairs
    np.testing.assert_allclose(contacts.gaps, [EPS * 2 * min(a) * (1 - 1e-6) for a in radius_pairs], rtol=1e-9)


def test_gap_exactly_at_threshold_is_not_a_near_contact():
    """The inequality is strict: h = eps * min(d) exactly (binary-exact numbers) is excluded.

    eps = 1/4, radii 1/2, centre distance 5/4 in a cubic box of side 8: h = 1/4 = eps * 1.
    """
    box = TriclinicBox(8.0, 8.0, 8.0)
    positions = np.array([[1.0, 1.0, 1.0], [2.25, 1.0, 1.0], [5.0, 5.0, 5.0], [5.0, 5.0, 6.125]])
    contacts = near_contact_pairs(positions, np.full(4, 0.5), box.mdanalysis_dimensions(), eps=0.25)
    assert [tuple(p) for p in contacts.pairs] == [(2, 3)]


def hand_made_configuration():
    """Twelve particles forming six isolated pairs with known normals and gaps.

    Returns positions, radii, box, and the expected near-contact normals.
    """
    box = TriclinicBox(12.0, 12.0, 12.0, xz=3.0, yz=-2.0)
    c = box.edge_vectors[2]
    diagonal_xy = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    diagonal_yz = np.array([0.0, 1.0, 1.0]) / np.sqrt(2)
    z = np.array([0.0, 0.0, 1.0])
    y = np.array([0.0, 1.0, 0.0])
    x = np.array([1.0, 0.0, 0.0])
    layout = [
        # (first centre, radius i, radius j, unit vector i->j, centre distance, near contact?)
        ((1.0, 1.0, 3.0), 0.5, 0.5, x, 1.005, True),  # h = 0.005 < 0.01
        ((6.0, 1.0, 3.0), 0.7, 0.7, diagonal_xy, 1.413, True),  # h = 0.013 < 0.014
        ((1.0, 6.0, 3.0), 0.5, 0.5, y, 1.011, False),  # h = 0.011 > 0.01
        ((6.0, 6.0, 3.0), 0.7, 0.5, diagonal_yz, 1.15, True),  # overlap h = -0.05
        ((1.0, 1.0, 8.0), 0.7, 0.5, x, 1.212, False),  # h = 0.012 > min(d) eps
        ((6.0, 6.0, 11.6), 0.5, 0.7, z, 1.209, True),  # across the tilted z face
    ]
    positions, radii, normals = [], [], []
    for start, ai, aj, unit, distance, inside in layout:
        start = np.array(start)
        end = start + distance * unit
        if end[2] > box.lz:  # store j at its image below the tilted face
            end = end - c
        positions += [start, end]
        radii += [ai, aj]
        if inside:
            normals.append(unit)
    return np.array(positions), np.array(radii), box, np.array(normals)


def test_hand_made_configuration_gives_exact_fabric():
    """<nn> = (1/N) sum_pairs n n with known normals x, (x+y)/sqrt2, (y+z)/sqrt2, z; N = 12.

    Checks the count (4 pairs, Z = 2*4/12), the per-pair threshold with the smaller
    diameter, overlaps counted, and a pair through the tilted periodic face.
    """
    positions, radii, box, normals = hand_made_configuration()
    expected = sum(np.outer(n, n) for n in normals) / len(positions)
    fabric, n_pairs = fabric_tensor(positions, radii, box.mdanalysis_dimensions(), EPS)
    assert n_pairs == 4
    np.testing.assert_allclose(fabric, expected, atol=1e-14)
    np.testing.assert_allclose(np.trace(fabric), 4 / 12, atol=1e-14)


def in_plane_configuration():
    """Six pairs with normals in the simulation x-z plane (paper e1-e2 plane at t = 0)."""
    box = TriclinicBox(14.0, 14.0, 14.0, xz=2.5, yz=1.5)
    angles = np.radians([20.0, 35.0, 50.0, 110.0, 60.0, 45.0])
    positions, radii = [], []
    for k, alpha in enumerate(angles):
        start = np.array([2.0 + 4.0 * (k % 3), 3.0 + 5.0 * (k // 3), 5.0])
        positions += [start, start + 1.004 * np.array([np.cos(alpha), 0.0, np.sin(alpha)])]
        radii += [0.5, 0.5]
    return np.array(positions), np.array(radii), box


@pytest.mark.parametrize("theta_deg", [30.0, 90.0, 135.0, -60.0, 180.0])
def test_rotated_frame_components(tmp_path, theta_deg):
    """In the frame of flow angle theta: <nn>'_12 = cos(theta) <nn>_12, <nn>'_23 = sin(theta) <nn>_12.

    For a fabric whose only off-diagonal paper component at t = 0 is <nn>_12 (normals in
    the flow-gradient plane, <nn>_33 = 0), also <nn>'_11 = cos^2(theta) <nn>_11,
    <nn>'_33 = sin^2(theta) <nn>_11, <nn>'_13 = sin(theta) cos(theta) <nn>_11, <nn>'_22 = <nn>_22.
    Evaluated through the trajectory analysis of a one-frame dump.
    """
    positions, radii, box = in_plane_configuration()
    path = write_lammps_dump(tmp_path / "frame.dump", [DumpFrame(0, box, positions, radii)])
    startup = FabricAnalysis.from_dump(path, dt=1e-4).run().results
    rotated = FabricAnalysis.from_dump(path, dt=1e-4, flow_angle_deg=theta_deg).run().results
    n11, n22, n12 = startup.n11[0], startup.n22[0], startup.n12[0]
    assert abs(n12) > 0.1
    np.testing.assert_allclose([startup.n13[0], startup.n23[0], startup.n33[0]], 0.0, atol=1e-6)
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    np.testing.assert_allclose(rotated.n12[0], c * n12, atol=1e-6)
    np.testing.assert_allclose(rotated.n23[0], s * n12, atol=1e-6)
    np.testing.assert_allclose(rotated.n11[0], c**2 * n11, atol=1e-6)
    np.testing.assert_allclose(rotated.n33[0], s**2 * n11, atol=1e-6)
    np.testing.assert_allclose(rotated.n13[0], s * c * n11, atol=1e-6)
    np.testing.assert_allclose(rotated.n22[0], n22, atol=1e-6)


@pytest.mark.parametrize(
    "tilts, expected_bounds",
    [
        ((-1.0, -3.0, 2.0), [[-3.0, 11.0, -1.0], [2.0, 12.0, -3.0], [3.0, 9.0, 2.0]]),
        ((1.0, 3.0, -2.0), [[1.0, 15.0, 1.0], [0.0, 10.0, 3.0], [3.0, 9.0, -2.0]]),
    ],
)
def test_dump_bounds_follow_lammps_triclinic_convention(tmp_path, tilts, expected_bounds):
    """BOX BOUNDS rows: xlo + min(0, xy, xz, xy+xz), xhi + max(0, xy, xz, xy+xz), xy /
    ylo + min(0, yz), yhi + max(0, yz), xz / zlo, zhi, yz.

    Origin (1, 2, 3), lengths 10, 8, 6; tilts chosen so that xy + xz sets the x bound.
    MDAnalysis must read back the same box and the positions minus the origin.
    """
    xy, xz, yz = tilts
    box = TriclinicBox(10.0, 8.0, 6.0, xy=xy, xz=xz, yz=yz, origin=(1.0, 2.0, 3.0))
    rng = np.random.default_rng(5)
    positions = np.asarray(box.origin) + rng.random((20, 3)) @ box.edge_vectors
    path = write_lammps_dump(tmp_path / "box.dump", [DumpFrame(7, box, positions, np.full(20, 0.5))])
    lines = path.read_text().splitlines()
    assert lines[4] == "ITEM: BOX BOUNDS xy xz yz pp pp pp"
    bounds = np.array([[float(v) for v in line.split()] for line in lines[5:8]])
    np.testing.assert_allclose(bounds, expected_bounds)
    universe = open_dump(path)
    np.testing.assert_allclose(universe.dimensions, box.mdanalysis_dimensions(), rtol=1e-6)
    np.testing.assert_allclose(universe.atoms.positions, positions - box.origin, atol=2e-5)
    assert universe.trajectory.ts.time == 7


def test_unreduced_tilts_give_the_same_contacts():
    """A box with tilts beyond half a length (LAMMPS without flip) is the same lattice as its
    reduced form: a=(L,0,0), b=(0.7L,L,0), c=(1.3L,-0.8L,L) ~ b-a=(-0.3L,L,0), c+b-2a=(0,0.2L,L).
    Contacts must equal the brute-force search in the reduced box. At L = 3.2 the unreduced
    cell is too narrow (half smallest face distance 0.72 < 2 a_max (1 + eps) = 1.414), the
    reduced one is not (1.53).
    """
    rng = np.random.default_rng(77)
    length = 3.2
    box = TriclinicBox(length, length, length, xy=0.7 * length, xz=1.3 * length, yz=-0.8 * length)
    reduced_rows = np.array([[length, 0, 0], [-0.3 * length, length, 0], [0, 0.2 * length, length]])
    positions, radii = random_configuration(rng, 25, box, (0.0, 1.0))
    contacts = near_contact_pairs(positions, radii, box.mdanalysis_dimensions(), EPS)
    ref_pairs, ref_separations = brute_force_near_contacts(positions, radii, reduced_rows, EPS)
    assert len(ref_pairs) > 20
    np.testing.assert_array_equal(contacts.pairs, ref_pairs)
    np.testing.assert_allclose(contacts.separations, ref_separations, atol=1e-9)


def synthetic_trajectory(rng, n=160, n_frames=5, first_step=2000, stride=500):
    """Frames with random bidisperse configurations and tilts that grow and flip like a shear run."""
    radii = np.where(np.arange(n) % 2 == 0, 0.5, 0.7)
    frames = []
    for k in range(n_frames):
        tilt = ((0.3 * k + 0.2) % 1.0 - 0.5) * 7.0
        box = TriclinicBox(7.0, 7.0, 7.5, xz=tilt * np.cos(0.7), yz=tilt * np.sin(0.7), origin=(-3.5, -3.5, 0.0))
        positions, _ = random_configuration(rng, n, box, (-0.1, 1.1))
        frames.append(DumpFrame(first_step + stride * k, box, positions, radii))
    return frames


@pytest.mark.parametrize(
    "columns",
    [("id", "type", "radius", "x", "y", "z"), ("id", "type", "radius", "xs", "ys", "zs")],
    ids=["unscaled", "scaled"],
)
def test_trajectory_to_table_matches_kernel(tmp_path, columns):
    """Analysis rows equal the kernel on the written frames, rotated to the paper frame of theta.

    n_kl = simulation_to_paper(fabric_tensor(frame), theta)_kl, Z = 2 n_pairs / N,
    strain = (step - start_step) dt rate, phi = sum(4/3 pi a^3) / V; unscaled and
    scaled dump coordinates give the same table, and the CSV round trip is exact.
    """
    rng = np.random.default_rng(11)
    frames = synthetic_trajectory(rng)
    path = write_lammps_dump(tmp_path / "run.dump", frames, columns=columns)
    theta_deg, dt, rate, start = 45.0, 2e-4, 0.5, 1500
    analysis = FabricAnalysis.from_dump(
        path,
        dt=dt,
        shear_rate=rate,
        shear_start_step=start,
        flow_angle_deg=theta_deg,
        expected_n_atoms=160,
    ).run()
    table = fabric_table(analysis, seed=3)
    assert list(table.columns) == [*TABLE_COLUMNS, *MOMENT_COLUMNS]
    assert len(table) == len(frames)
    for row, frame in zip(table.itertuples(), frames):
        fabric, n_pairs = fabric_tensor(frame.positions, frame.radii, frame.box.mdanalysis_dimensions())
        paper = simulation_to_paper(fabric, np.radians(theta_deg))
        assert n_pairs > 20
        assert row.step == frame.step
        assert row.strain == pytest.approx((frame.step - start) * dt * rate, rel=1e-12)
        assert row.Z == pytest.approx(2 * n_pairs / 160, rel=1e-12)
        got = [row.n11, row.n22, row.n33, row.n12, row.n13, row.n23]
        want = [paper[0, 0], paper[1, 1], paper[2, 2], paper[0, 1], paper[0, 2], paper[1, 2]]
        np.testing.assert_allclose(got, want, atol=1e-6)
    phi = np.sum(4 / 3 * np.pi * frames[0].radii ** 3) / frames[0].box.volume
    assert table["phi"].iloc[0] == pytest.approx(phi, rel=1e-6)
    assert (table["seed"] == 3).all() and (table["theta"] == 45.0).all() and (table["N"] == 160).all()
    csv = write_fabric_table(table, tmp_path / "run.csv")
    pd.testing.assert_frame_equal(read_fabric_table(csv, moments=True), table, rtol=1e-8, atol=1e-15)
    pd.testing.assert_frame_equal(read_fabric_table(csv), table[list(TABLE_COLUMNS)])  # exact
    pd.testing.assert_frame_equal(pd.read_csv(csv), table, rtol=1e-8, atol=1e-15)
    # a table made before the moments were recorded reads with them empty
    table[list(TABLE_COLUMNS)].to_csv(tmp_path / "old.csv", index=False)
    old = read_fabric_table(tmp_path / "old.csv", moments=True)
    assert list(old.columns) == list(table.columns) and old[list(MOMENT_COLUMNS)].isna().all().all()


def test_real_spherical_harmonics_are_orthonormal():
    """integral over the sphere of Y_lm Y_l'm' = delta for every recorded (l, m): Gauss-Legendre in
    cos(polar) (24 nodes, exact to degree 47) times the trapezoidal rule in the azimuth (48 points,
    exact to trigonometric degree 47), exact for these products of degree 12."""
    cosines, weights = np.polynomial.legendre.leggauss(24)
    azimuths = np.arange(48) * 2.0 * np.pi / 48
    sines = np.sqrt(1.0 - cosines**2)
    normals = np.stack(
        np.broadcast_arrays(
            sines[:, None] * np.cos(azimuths)[None, :], sines[:, None] * np.sin(azimuths)[None, :], cosines[:, None]
        ),
        axis=-1,
    ).reshape(-1, 3)
    values = real_spherical_harmonics(normals)
    quadrature = (weights[:, None] * np.full(48, 2.0 * np.pi / 48)[None, :]).ravel()
    gram = values.T @ (quadrature[:, None] * values)
    np.testing.assert_allclose(gram, np.eye(len(HARMONIC_COLUMNS)), atol=1e-12)


def test_direction_moments_of_a_hand_made_configuration():
    """Three pairs along e1, e2 and (e1 + e3)/sqrt(2), N = 4 particles: <nn> = (1/4) sum n n,
    <nnnn>_ijkl = (1/4) sum n_i n_j n_k n_l written out per component, and a_00 = (3/4)/sqrt(4 pi)."""
    s = 1.0 / np.sqrt(2.0)
    normals = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [s, 0.0, s]])
    second, fourth, harmonics = direction_moments(normals, 4)
    np.testing.assert_allclose(second, np.array([[1.5, 0.0, 0.5], [0.0, 1.0, 0.0], [0.5, 0.0, 0.5]]) / 4, atol=1e-15)
    by_name = dict(zip(FOURTH_MOMENT_COMPONENTS, fourth))
    assert by_name["n1111"] == pytest.approx((1.0 + 0.25) / 4)
    assert by_name["n2222"] == pytest.approx(1.0 / 4)
    assert by_name["n1113"] == by_name["n1133"] == by_name["n1333"] == by_name["n3333"] == pytest.approx(0.25 / 4)
    assert by_name["n1122"] == by_name["n1222"] == by_name["n2233"] == 0.0
    assert harmonics[HARMONIC_COLUMNS.index("Y0_0")] == pytest.approx(0.75 / np.sqrt(4.0 * np.pi))


# ---- bad input -------------------------------------------------------------------------


def small_frames(n=10, steps=(0, 100), radii=True):
    box = TriclinicBox(6.0, 6.0, 6.0, xz=1.0)
    rng = np.random.default_rng(0)
    return [DumpFrame(s, box, rng.random((n, 3)) * 6.0, np.full(n, 0.5)) for s in steps]


def test_missing_file_is_named(tmp_path):
    """A missing dump raises FileNotFoundError naming the path."""
    missing = tmp_path / "nowhere.dump"
    with pytest.raises(FileNotFoundError, match="nowhere.dump"):
        FabricAnalysis.from_dump(missing, dt=1e-4)


@pytest.mark.parametrize("dropped", ["radius", "type"])
def test_missing_column_is_named(tmp_path, dropped):
    """A dump without the radius or type column raises ValueError naming the file and column."""
    columns = [c for c in ("id", "type", "radius", "x", "y", "z") if c != dropped]
    path = write_lammps_dump(tmp_path / f"no_{dropped}.dump", small_frames(), columns=columns)
    with pytest.raises(ValueError, match=rf"no_{dropped}\.dump.*'{dropped}'"):
        FabricAnalysis.from_dump(path, dt=1e-4)


def test_empty_trajectory(tmp_path):
    """An empty dump raises ValueError naming the file."""
    path = tmp_path / "empty.dump"
    path.write_text("")
    with pytest.raises(ValueError, match=r"empty\.dump.*empty trajectory"):
        FabricAnalysis.from_dump(path, dt=1e-4)


def test_changing_atom_count(tmp_path):
    """N changing between frames raises ValueError naming the file and the frame."""
    frames = small_frames(n=10, steps=(0,)) + small_frames(n=11, steps=(100,))
    path = write_lammps_dump(tmp_path / "growing.dump", frames)
    with pytest.raises(ValueError, match=r"growing\.dump.*changes from 10 to 11 at frame 1"):
        FabricAnalysis.from_dump(path, dt=1e-4)


def test_expected_atom_count_mismatch(tmp_path):
    """expected_n_atoms different from the dump's N raises ValueError naming the file."""
    path = write_lammps_dump(tmp_path / "ten.dump", small_frames(n=10))
    with pytest.raises(ValueError, match=r"ten\.dump.*expected 12 atoms"):
        FabricAnalysis.from_dump(path, dt=1e-4, expected_n_atoms=12)


def test_truncated_frame(tmp_path):
    """A dump cut inside a frame raises ValueError naming the file and frame."""
    path = write_lammps_dump(tmp_path / "cut.dump", small_frames(n=10))
    text = path.read_text().splitlines(keepends=True)
    path.write_text("".join(text[:-3]))
    with pytest.raises(ValueError, match=r"cut\.dump: frame 1 .*truncated"):
        scan_dump(path)


def test_non_finite_positions(tmp_path):
    """NaN coordinates raise ValueError: in the kernel, and in the analysis naming file and step."""
    frames = small_frames(n=10)
    frames[1].positions[4, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        fabric_tensor(frames[1].positions, frames[1].radii, frames[1].box.mdanalysis_dimensions())
    path = write_lammps_dump(tmp_path / "nan.dump", frames)
    analysis = FabricAnalysis.from_dump(path, dt=1e-4)
    with pytest.raises(ValueError, match=r"nan\.dump: frame 1 \(step 100\): non-finite positions"):
        analysis.run()


def test_frame_before_shear_start(tmp_path):
    """A frame whose step precedes shear_start_step (negative strain) is an error."""
    path = write_lammps_dump(tmp_path / "early.dump", small_frames(n=10))
    with pytest.raises(ValueError, match=r"step 0\) precedes the shear start step 50"):
        FabricAnalysis.from_dump(path, dt=1e-4, shear_start_step=50).run()


def test_box_too_small_for_unique_minimum_image():
    """A cell narrower than twice the near-contact distance is rejected (ambiguous image)."""
    box = TriclinicBox(2.5, 6.0, 6.0)
    positions = np.array([[0.2, 1.0, 1.0], [1.4, 1.0, 1.0]])
    with pytest.raises(ValueError, match="box too small"):
        fabric_tensor(positions, np.array([0.7, 0.7]), box.mdanalysis_dimensions())
