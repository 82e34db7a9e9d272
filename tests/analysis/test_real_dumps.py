"""Seams between the LAMMPS runner and the analysis, on real LAMMPS dumps.

One small real system (N = 60, phi = 0.45, packed with gap_margin = 0 so that near
contacts exist from the first frame), sheared by simulation/lammps/inputs/segment.lmp (from a packing) to strain
0.02 and then rotated by theta = 60 deg (segment.lmp from the checkpoint) for strain 0.01, both through the
Python runner with the project's plugin force model; dumps every 0.005 strain
(5 + 3 frames, ~100 near-contact pairs each). About a second of LAMMPS in all.

What is compared
    ``FabricAnalysis`` (MDAnalysis' dump reader, float32 storage, cell-list search)
    against ``fabric_reference.brute_force_near_contacts`` (all pairs, 27 images), with
    the paper frame written out in this file from the convention of frames.py rather
    than taken from it: startup e1 = x (flow), e2 = z (gradient), e3 = e1 x e2 = -y;
    after a rotation by theta e1' = cos(theta) e1 - sin(theta) e3 = (cos, sin, 0) (the
    flow of segment.lmp, checked on the dumped boxes), e2' = e2,
    e3' = sin(theta) e1 + cos(theta) e3. Two references:
    (A) brute force on exactly the float32 data MDAnalysis holds: agreement to float64
        round-off (1e-12), i.e. the analysis adds no error of its own;
    (B) brute force on the frames read by ``dumpio.iter_dump_frames`` in float64 (the
        dump's %.15g text): agreement to the float32 storage error bounded below.

Tolerances of (B) (float32 round-off, derived, not fitted)
    MDAnalysis stores coordinates, box lengths and box angles as float32, relative
    rounding u = 2**-24. With L the extent of a frame (largest |coordinate - origin|
    or box-vector sum, ~5.2 here) a stored coordinate is off by <= u L and a box vector
    rebuilt from float32 lengths and angles (degrees, < 180) by <= (1 + pi) u L per
    component. A minimum-image separation x_j - x_i - (lattice shift, at most one of
    each box vector) is therefore off by at most DELTA = 16 u L per component
    (2 u L + 3 (1 + pi) u L < 16 u L; ~5e-6 here, measured <~ 2 u L ~ 6e-7),
    |dr| <= sqrt(3) DELTA. To first order |dn| <= |dr| / r for the unit normal and
    |d(n_k n_l)| <= 2 |dn|, so each fabric component is off by at most
    2 (M / N) sqrt(3) DELTA / r_min, the tolerance used (~3e-5 for M ~ 100 pairs,
    N = 60, r_min ~ 1; a worst case that aligns all errors: the measured deviation is
    <~ 5e-8). One pair more or less would change a component by up to 1/N ~ 1.7e-2,
    a wrong frame mapping by ~2e-2 or more (asserted to exceed 100 tolerances).
    Pair sets and counts must agree exactly; that needs every pair's gap to be further
    than the float32 error (2 sqrt(3) DELTA, covering radii stored in float32 too)
    from the threshold eps * min(d_i, d_j), which is asserted, not assumed.
"""

from __future__ import annotations

import itertools
import re
import shutil

import numpy as np
import pytest
from MDAnalysis.lib.mdamath import triclinic_vectors

from suspension_fabric.analysis.fabric import FabricAnalysis, near_contact_pairs, open_dump
from suspension_fabric.analysis.fabric_reference import brute_force_near_contacts
from suspension_fabric.io.dumpio import iter_dump_frames, scan_dump
from suspension_fabric.simulation.lammps import ForceModel, ShearSettings, pack, run_rotation, run_startup
from suspension_fabric.simulation.lammps.plugin import plugin_path

pytestmark = pytest.mark.lammps

N_PARTICLES = 60
PHI = 0.45
DT = 2.0e-5
STARTUP_STRAIN = 0.02
ROTATION_STRAIN = 0.01
THETA_DEG = 60.0
EPS = 0.01
SETTINGS = ShearSettings(dt=DT, dump_strain=0.005, table_strain=0.001, thermo_strain=0.005, restart_strain=0.01)
U32 = 2.0**-24  # float32 unit round-off

# Paper basis of the startup shear, rows e1, e2, e3 in simulation components.
STARTUP_BASIS = np.array(
    [
        [1.0, 0.0, 0.0],  # e1 = x, flow
        [0.0, 0.0, 1.0],  # e2 = z, gradient
        [0.0, -1.0, 0.0],
    ]
)  # e3 = e1 x e2 = -y, vorticity


def rotation_in_startup_frame(theta_deg: float) -> np.ndarray:
    """R with rows e1', e2', e3' in startup paper components: e1' = c e1 - s e3, e3' = s e1 + c e3."""
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def rotated_basis(theta_deg: float) -> np.ndarray:
    """Paper basis of the shear rotated by theta, rows in simulation components."""
    return rotation_in_startup_frame(theta_deg) @ STARTUP_BASIS


# ---------------------------------------------------------------------------- the runs


@pytest.fixture(scope="module")
def force_model():
    return ForceModel(plugin=plugin_path())


@pytest.fixture(scope="module")
def startup(tmp_path_factory, force_model):
    packing = pack(tmp_path_factory.mktemp("pack") / "packing", N_PARTICLES, phi=PHI, seed=3, gap_margin=0.0)
    return run_startup(
        tmp_path_factory.mktemp("startup") / "run",
        packing.data_file,
        STARTUP_STRAIN,
        force_model=force_model,
        settings=SETTINGS,
        progress=None,
    )


@pytest.fixture(scope="module")
def rotation(tmp_path_factory, startup, force_model):
    return run_rotation(
        tmp_path_factory.mktemp("rotation") / "rot",
        startup.checkpoint_file,
        THETA_DEG,
        ROTATION_STRAIN,
        force_model=force_model,
        settings=SETTINGS,
        progress=None,
    )


RUNS = {
    # name: (run fixture, flow angle of its shear, paper basis of its shear)
    "startup": ("startup", 0.0, STARTUP_BASIS),
    "rotation": ("rotation", THETA_DEG, rotated_basis(THETA_DEG)),
}


@pytest.fixture(scope="module")
def analyses(startup, rotation):
    """FabricAnalysis results of both dumps, each in the paper frame of its own shear."""
    runs = {"startup": startup, "rotation": rotation}
    return {
        name: FabricAnalysis.from_dump(
            runs[name].dump_file,
            dt=DT,
            shear_rate=1.0,
            shear_start_step=runs[name].first_step,
            flow_angle_deg=RUNS[name][1],
            eps=EPS,
            expected_n_atoms=N_PARTICLES,
        )
        .run()
        .results
        for name in RUNS
    }


def frame_extent(positions, box_rows) -> float:
    """L of the tolerance derivation: largest |coordinate| (from the box origin) or box-vector sum."""
    return max(np.abs(positions).max(), np.abs(box_rows).sum(axis=0).max())


def reference(positions, radii, box_rows, basis) -> dict:
    """Brute-force near contacts of one configuration and their fabric in ``basis`` (rows).

    ``positions`` relative to the box origin. Also the float32 error bounds of the module
    docstring for this frame, and the smallest distance |gap - eps d_min| of any pair
    from the near-contact threshold.
    """
    n = len(radii)
    pairs, separations = brute_force_near_contacts(positions, radii, box_rows, EPS)
    distances = np.linalg.norm(separations, axis=1)
    normals = separations / distances[:, None]
    paper_normals = normals @ basis.T  # n . e_a for a = 1, 2, 3
    # every pair near the threshold, from either side (twice eps catches them all)
    wide_pairs, wide_separations = brute_force_near_contacts(positions, radii, box_rows, 2 * EPS)
    i, j = wide_pairs.T
    gaps = np.linalg.norm(wide_separations, axis=1) - radii[i] - radii[j]
    thresholds = EPS * 2.0 * np.minimum(radii[i], radii[j])
    delta = 16.0 * U32 * frame_extent(positions, box_rows)
    return {
        "pairs": pairs,
        "separations": separations,
        "fabric_simulation": normals.T @ normals / n,
        "fabric": paper_normals.T @ paper_normals / n,
        "paper_normals": paper_normals,
        "n_pairs": len(pairs),
        "volume_fraction": np.sum(4.0 / 3.0 * np.pi * radii**3) / abs(np.linalg.det(box_rows)),
        "delta": delta,
        "tensor_tol": 2.0 * len(pairs) / n * np.sqrt(3.0) * delta / distances.min(),
        "threshold_margin": np.abs(gaps - thresholds).min(),
    }


def text_reference(frame, basis) -> dict:
    """:func:`reference` of a frame read by iter_dump_frames (float64, the dump's digits)."""
    relative = frame.positions - np.asarray(frame.box.origin)
    return {"step": frame.step, **reference(relative, frame.radii, frame.box.edge_vectors, basis)}


@pytest.fixture(scope="module")
def references(startup, rotation):
    """Brute force on the float64 text of every frame of both dumps."""
    runs = {"startup": startup, "rotation": rotation}
    return {
        name: [text_reference(frame, RUNS[name][2]) for frame in iter_dump_frames(runs[name].dump_file)]
        for name in RUNS
    }


@pytest.fixture(scope="module")
def float32_references(startup, rotation):
    """Brute force on exactly what MDAnalysis holds: float32 positions and radii, and the box
    rebuilt from its float32 lengths and angles by MDAnalysis' own triclinic_vectors."""
    runs = {"startup": startup, "rotation": rotation}
    out = {}
    for name in RUNS:
        universe = open_dump(runs[name].dump_file)
        out[name] = [
            {
                "step": int(ts.data["step"]),
                **reference(
                    np.asarray(ts.positions, dtype=float),
                    np.asarray(ts.data["radius"], dtype=float),
                    triclinic_vectors(ts.dimensions, dtype=np.float64),
                    RUNS[name][2],
                ),
            }
            for ts in universe.trajectory
        ]
    return out


# ---------------------------------------------------------------------------- analysis vs brute force


@pytest.mark.parametrize("name", list(RUNS))
def test_paper_basis_is_the_flow_of_the_run(name, request):
    """e1 of the basis used below is the run's flow and e2 its gradient: in the dumped boxes
    the top face (c = (xz, yz, lz)) moves by strain * lz * e1, i.e. (xz, yz) grows as
    (strain lz) (e1_x, e1_y) and e1_z = 0, e2 = z; (1, 0) for startup and
    (cos 60, sin 60) for the rotation, whose e1' = cos e1 - sin e3 with e3 = -y."""
    run = request.getfixturevalue(RUNS[name][0])
    basis = RUNS[name][2]
    frames = list(iter_dump_frames(run.dump_file))
    strain = (frames[-1].step - frames[0].step) * DT
    first, last = frames[0].box, frames[-1].box
    velocity = np.array([last.xz - first.xz, last.yz - first.yz, 0.0]) / (strain * first.lz)
    np.testing.assert_allclose(velocity, basis[0], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(basis[1], [0.0, 0.0, 1.0])
    np.testing.assert_allclose(np.cross(basis[0], basis[1]), basis[2], atol=1e-15)  # right-handed


@pytest.mark.parametrize("name", list(RUNS))
def test_float32_frames_give_the_brute_force_pairs(name, references, request):
    """Kernel on MDAnalysis' float32 frames = brute force on the float64 text, pair by pair.

    ``near_contact_pairs`` (what FabricAnalysis calls per frame) on ``open_dump``'s
    timesteps finds exactly the brute-force pair set (i < j, lexicographic), each
    minimum-image separation within DELTA = 16 u L per component of the float64 one;
    every pair's gap is further than 2 sqrt(3) DELTA from eps * min(d_i, d_j), so float32
    rounding cannot move a pair across the threshold (the premise of the exact counts).
    """
    run = request.getfixturevalue(RUNS[name][0])
    universe = open_dump(run.dump_file, expected_n_atoms=N_PARTICLES)
    refs = references[name]
    assert universe.trajectory.n_frames == len(refs) >= 3
    for ts, ref in zip(universe.trajectory, refs):
        assert ts.data["step"] == ref["step"]
        assert ref["n_pairs"] > N_PARTICLES  # near contacts present (gap_margin = 0)
        assert ref["threshold_margin"] > 2.0 * np.sqrt(3.0) * ref["delta"], (
            f"step {ref['step']}: a pair lies within float32 round-off of the threshold"
        )
        contacts = near_contact_pairs(
            np.asarray(ts.positions, dtype=float), np.asarray(ts.data["radius"], dtype=float), ts.dimensions, EPS
        )
        np.testing.assert_array_equal(contacts.pairs, ref["pairs"])
        np.testing.assert_allclose(contacts.separations, ref["separations"], rtol=0, atol=ref["delta"])


@pytest.mark.parametrize("name", list(RUNS))
def test_fabric_analysis_is_exact_on_the_float32_data_it_reads(name, analyses, float32_references):
    """On identical input the analysis has no error beyond float64 round-off.

    Brute force on MDAnalysis' own float32 positions, radii and box (lengths and angles
    -> triclinic_vectors), in float64, mapped to the paper frame here: same step, same
    number of near-contact pairs, and <nn> (paper and simulation frame) within 1e-12
    (sums of ~100 unit-normal products over N = 60; both sides differ only in how
    the same minimum-image vector is computed, ~1e-15 L). This pins everything but the
    float32 storage, which the comparison with the float64 text below bounds.
    """
    results, refs = analyses[name], float32_references[name]
    np.testing.assert_array_equal(results.step, [r["step"] for r in refs])
    np.testing.assert_array_equal(results.n_pairs, [r["n_pairs"] for r in refs])
    for k, ref in enumerate(refs):
        np.testing.assert_allclose(results.fabric[k], ref["fabric"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(results.fabric_simulation[k], ref["fabric_simulation"], rtol=0, atol=1e-12)
        assert results.volume_fraction[k] == pytest.approx(ref["volume_fraction"], rel=1e-12)


@pytest.mark.parametrize("name", list(RUNS))
def test_fabric_analysis_matches_brute_force_in_the_paper_frame(name, analyses, references):
    """FabricAnalysis per frame = brute force on float64 frames mapped to the paper frame.

    <nn>_ab = (1/N) sum over near-contact pairs of (n . e_a)(n . e_b), e_a the paper basis
    of the run's shear (startup: e1 = x, e2 = z, e3 = -y; rotation by 60 deg:
    e1' = cos e1 - sin e3, e3' = sin e1 + cos e3), all nine entries and the six named
    components within 2 (M/N) sqrt(3) DELTA / r_min (float32, module docstring); the
    simulation-frame fabric likewise; n_pairs = M exactly and Z = 2 M / N; step as
    dumped and strain = (step - first step of the run) dt rate; volume fraction
    sum(4/3 pi a^3) / V = the packing's phi (the shear keeps the volume), to float32.
    """
    results, refs = analyses[name], references[name]
    first_step = refs[0]["step"]
    np.testing.assert_array_equal(results.step, [r["step"] for r in refs])
    np.testing.assert_allclose(results.strain, (results.step - first_step) * DT * 1.0, rtol=0, atol=1e-15)
    assert results.n_particles == N_PARTICLES
    np.testing.assert_array_equal(results.n_pairs, [r["n_pairs"] for r in refs])
    np.testing.assert_allclose(results.coordination, [2.0 * r["n_pairs"] / N_PARTICLES for r in refs], rtol=1e-15)
    for k, ref in enumerate(refs):
        tol = ref["tensor_tol"]
        assert tol < 1e-4  # far below one pair's share, 1/N
        np.testing.assert_allclose(
            results.fabric[k], ref["fabric"], rtol=0, atol=tol, err_msg=f"{name} step {ref['step']}: paper-frame fabric"
        )
        np.testing.assert_allclose(
            results.fabric_simulation[k],
            ref["fabric_simulation"],
            rtol=0,
            atol=tol,
            err_msg=f"{name} step {ref['step']}: simulation frame",
        )
        for component, (a, b) in {
            "n11": (0, 0),
            "n22": (1, 1),
            "n33": (2, 2),
            "n12": (0, 1),
            "n13": (0, 2),
            "n23": (1, 2),
        }.items():
            assert results[component][k] == pytest.approx(ref["fabric"][a, b], abs=tol), component
        assert results.volume_fraction[k] == pytest.approx(PHI, rel=1e-6)
        assert ref["volume_fraction"] == pytest.approx(PHI, rel=1e-9)
        # the frame mapping is visible at this tolerance (a wrong one would not pass)
        assert np.abs(ref["fabric"] - ref["fabric_simulation"]).max() > 100 * tol


def full_fourth_moment(results, k) -> np.ndarray:
    """The 3x3x3x3 <nnnn> of frame k from its 15 named components (n1111 ... n3333)."""
    tensor = np.empty((3, 3, 3, 3))
    for a, b, c, d in itertools.product(range(3), repeat=4):
        tensor[a, b, c, d] = results["n" + "".join(str(i + 1) for i in sorted((a, b, c, d)))][k]
    return tensor


@pytest.mark.parametrize("name", list(RUNS))
def test_fourth_moment_and_harmonics_match_brute_force_in_the_paper_frame(name, analyses, references):
    """<nnnn>_abcd = (1/N) sum over the brute-force near contacts of (n.e_a)(n.e_b)(n.e_c)(n.e_d), e_a
    the paper basis of the run's shear written out in this file, within twice the fabric's float32
    tolerance (|d(n_a n_b n_c n_d)| <= 4 |dn|); the trace identity <nnnn>_abkk = <nn>_ab to round-off;
    and the spherical-harmonic amplitudes against their polynomials in n (polar axis e3, azimuth
    from e1): a_00 = (Z/2) / sqrt(4 pi), a_20 = sqrt(5/(16 pi)) (3 <nn>_33 - Tr<nn>),
    a_2,2 = sqrt(15/(16 pi)) (<nn>_11 - <nn>_22), a_2,-2 = sqrt(15/(4 pi)) <nn>_12,
    a_40 = (3/16) sqrt(1/pi) (35 <nnnn>_3333 - 30 <nn>_33 + 3 Tr<nn>), each from the brute force."""
    results, refs = analyses[name], references[name]
    for k, ref in enumerate(refs):
        tol = 2.0 * ref["tensor_tol"]
        n = ref["paper_normals"]
        brute = np.einsum("pa,pb,pc,pd->abcd", n, n, n, n) / N_PARTICLES
        fourth = full_fourth_moment(results, k)
        np.testing.assert_allclose(fourth, brute, rtol=0, atol=tol, err_msg=f"{name} step {ref['step']}")
        np.testing.assert_allclose(np.einsum("abkk->ab", fourth), results.fabric[k], rtol=0, atol=1e-12)
        second, trace = ref["fabric"], np.trace(ref["fabric"])
        expected = {
            "Y0_0": trace / np.sqrt(4.0 * np.pi),
            "Y2_0": np.sqrt(5.0 / (16.0 * np.pi)) * (3.0 * second[2, 2] - trace),
            "Y2_p2": np.sqrt(15.0 / (16.0 * np.pi)) * (second[0, 0] - second[1, 1]),
            "Y2_m2": np.sqrt(15.0 / (4.0 * np.pi)) * second[0, 1],
            "Y4_0": 3.0 / 16.0 * np.sqrt(1.0 / np.pi) * (35.0 * brute[2, 2, 2, 2] - 30.0 * second[2, 2] + 3.0 * trace),
        }
        for column, value in expected.items():
            assert results[column][k] == pytest.approx(value, abs=4.0 * tol), (name, ref["step"], column)


def test_first_rotated_frame_is_the_last_startup_frame_rotated(startup, rotation, analyses):
    """Shear rotation by theta: <nn>' = R <nn> R^T, R rows e1' = (c, 0, -s), e2, e3' = (s, 0, c).

    From e1' = cos(theta) e1 - sin(theta) e3, e3' = sin(theta) e1 + cos(theta) e3
    (c = cos theta, s = sin theta), the first rotated frame analysed in the rotated
    frame and the last startup frame (the same configuration) in the startup frame obey
        n11' = c^2 n11 - 2 c s n13 + s^2 n33,   n22' = n22,
        n33' = s^2 n11 + 2 c s n13 + c^2 n33,   n13' = c s (n11 - n33) + (c^2 - s^2) n13,
        n12' = c n12 - s n23,                   n23' = s n12 + c n23,
    which reduce to n12' = c n12, n23' = s n12 only if n23 = 0 (not so for a finite
    sample, checked below). Same pairs: n_pairs' = n_pairs. Tolerance 3x the float32
    tensor bound: each side carries one bound, and |R E R^T|_kl <= (|c| + |s|)^2 max|E|.
    """
    last_startup = list(iter_dump_frames(startup.dump_file))[-1]
    first_rotated = next(iter_dump_frames(rotation.dump_file))
    assert first_rotated.step == last_startup.step == startup.last_step == rotation.first_step
    np.testing.assert_allclose(first_rotated.positions, last_startup.positions, rtol=0, atol=1e-12)
    before, after = analyses["startup"], analyses["rotation"]
    assert after.strain[0] == 0.0 and before.strain[-1] == pytest.approx(STARTUP_STRAIN, abs=1e-15)
    assert after.n_pairs[0] == before.n_pairs[-1]
    tol = 3.0 * text_reference(last_startup, STARTUP_BASIS)["tensor_tol"]
    n = before.fabric[-1]
    c, s = np.cos(np.radians(THETA_DEG)), np.sin(np.radians(THETA_DEG))
    R = rotation_in_startup_frame(THETA_DEG)
    np.testing.assert_allclose(after.fabric[0], R @ n @ R.T, rtol=0, atol=tol)
    n11, n22, n33, n12, n13, n23 = (before[key][-1] for key in ("n11", "n22", "n33", "n12", "n13", "n23"))
    expected = {
        "n11": c**2 * n11 - 2 * c * s * n13 + s**2 * n33,
        "n22": n22,
        "n33": s**2 * n11 + 2 * c * s * n13 + c**2 * n33,
        "n13": c * s * (n11 - n33) + (c**2 - s**2) * n13,
        "n12": c * n12 - s * n23,
        "n23": s * n12 + c * n23,
    }
    for key, value in expected.items():
        assert after[key][0] == pytest.approx(value, abs=tol), key
    # the general formula matters here: n23 is not negligible
    assert abs(s * n23) > 100 * tol


# ---------------------------------------------------------------------------- truncated dumps


def _cut(text: str, line: int, keep: int | None = None) -> str:
    """``text`` cut inside its last frame: before line ``line`` of that frame (0 = its
    'ITEM: TIMESTEP' line, 9 = its first atom line), plus ``keep`` characters of that line
    (default: half of it)."""
    start = text.rindex("ITEM: TIMESTEP")
    lines = text[start:].splitlines(keepends=True)
    offset = start + sum(len(row) for row in lines[:line])
    return text[: offset + (len(lines[line]) // 2 if keep is None else keep)]


# name: (cut text, expected message after "<path>: frame 4 (step 1000) is truncated: ")
CUTS = {
    "mid atom line": (
        lambda text: _cut(text, 9 + 30),
        r"30 of 60 atom lines complete, the file ends inside atom line 31$",
    ),
    "atom line boundary": (lambda text: _cut(text, 9 + 30, keep=0), r"30 of 60 atom lines complete$"),
    "inside the last atom line": (
        lambda text: _cut(text, 9 + 59),
        r"59 of 60 atom lines complete, the file ends inside atom line 60$",
    ),
    "inside BOX BOUNDS": (lambda text: _cut(text, 6), r"the file ends inside its header$"),
}


@pytest.fixture(scope="module", params=list(CUTS))
def truncated(request, startup, tmp_path_factory):
    """(path, expected message regex, intact frames before it) of a copy of the startup dump
    cut inside its last frame."""
    source = startup.dump_file
    summary = scan_dump(source)
    path = tmp_path_factory.mktemp("cut") / "cut.dump"
    shutil.copyfile(source, path)
    cut, detail = CUTS[request.param]
    text = cut(path.read_text())
    path.write_text(text)
    last = summary.n_frames - 1
    assert summary.n_frames == 5 and summary.n_atoms == N_PARTICLES
    where = rf"{re.escape(str(path))}: frame {last} \(step {summary.steps[-1]}\) is truncated: "
    return path, where + detail, list(iter_dump_frames(source))[:-1]


@pytest.mark.fault("named")
def test_scan_dump_names_file_frame_and_step_of_a_truncated_frame(truncated):
    """scan_dump on a dump cut inside its last frame: ValueError '<path>: frame 4 (step 1000)
    is truncated: <k> of 60 atom lines complete[, the file ends inside atom line k+1]' (a cut
    line has no newline; LAMMPS ends every line), or '... the file ends inside its header'."""
    path, message, _ = truncated
    with pytest.raises(ValueError, match=message):
        scan_dump(path)


@pytest.mark.fault("named")
def test_fabric_analysis_rejects_a_truncated_dump(truncated):
    """FabricAnalysis.from_dump(...).run() on the cut dump raises scan_dump's ValueError
    (file, frame, step) before MDAnalysis opens the file: MDAnalysis' DumpReader itself
    (2.11) drops such a frame, or reads a cut last atom line as a complete one, silently."""
    path, message, _ = truncated
    with pytest.raises(ValueError, match=message):
        FabricAnalysis.from_dump(
            path, dt=DT, shear_rate=1.0, shear_start_step=0, eps=EPS, expected_n_atoms=N_PARTICLES
        ).run()


@pytest.mark.fault("named")
def test_iter_dump_frames_yields_the_intact_frames_then_names_the_truncated_one(truncated):
    """iter_dump_frames on the cut dump yields frames 0-3 unchanged (float64 equal to those
    of the intact dump), then raises ValueError naming the file, frame 4 and step 1000
    (it never drops the cut frame silently)."""
    path, message, intact = truncated
    frames = []
    with pytest.raises(ValueError, match=message):
        for frame in iter_dump_frames(path):
            frames.append(frame)
    assert [f.step for f in frames] == [f.step for f in intact]
    for got, want in zip(frames, intact):
        np.testing.assert_array_equal(got.positions, want.positions)
        np.testing.assert_array_equal(got.radii, want.radii)
        assert got.box == want.box
