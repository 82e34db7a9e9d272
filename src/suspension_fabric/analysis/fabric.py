r"""Near-contact detection and fabric tensors $\langle nn\rangle$ from LAMMPS trajectories.

Definitions (see the package docstring for the frames). A pair $(i, j)$ of spheres with radii
$a_i$, $a_j$ and centre distance $r$ (minimum image of the periodic triclinic box) is a near
contact when its surface gap $h = r - (a_i + a_j)$ satisfies $h < \epsilon\min(d_i, d_j)$,
$d = 2a$, $\epsilon = 0.01$ by default (the paper's threshold, Acharya and Mari,
arXiv:2506.05222). Overlapping pairs ($h < 0$) are near contacts. The fabric is

$$
\langle nn\rangle_{kl} = \frac{1}{N}\sum_{\text{near contacts}} n_k n_l,
\qquad \operatorname{Tr}\langle nn\rangle = \frac{n_{\text{pairs}}}{N} = \frac{Z}{2},
$$

each pair counted once, with $n$ the unit centre-to-centre vector (its sign does not matter),
$N$ the number of particles and $Z = 2n_{\text{pairs}}/N$ the near-contact coordination number.

Fourth moment and direction distribution ([`direction_moments`][suspension_fabric.analysis.fabric.direction_moments]).
With the same normalisation,

$$
\langle nnnn\rangle_{ijkl} = \frac{1}{N}\sum_{\text{near contacts}} n_in_jn_kn_l,
\qquad \langle nnnn\rangle_{ijkk} = \langle nn\rangle_{ij}
$$

($n$ a unit vector); its 15 independent components ($i \le j \le k \le l$) are
`FOURTH_MOMENT_COMPONENTS`. The distribution of near-contact directions per particle,
symmetrised over $n$ and $-n$ (a pair has no sign), is written with the real orthonormal
spherical harmonics $Y_{lm}$ ($\int Y_{lm}Y_{l'm'}\,\mathrm{d}\Omega = \delta_{ll'}\delta_{mm'}$
over the sphere) as

$$
\begin{split}
f(n) &= \frac{1}{N}\sum_{\text{near contacts}}\delta(n - n_c)
= \sum_{l\ \text{even}}\sum_{m=-l}^{l} a_{lm}\,Y_{lm}(n), \\
a_{lm} &= \frac{1}{N}\sum_{\text{near contacts}} Y_{lm}(n_c),
\end{split}
$$

recorded up to $l = 6$ (`HARMONIC_COLUMNS`, ``Y<l>_<m>`` with m written ``m2`` for -2,
``p2`` for +2). Polar axis e3 (vorticity), azimuth from e1 (flow) towards e2 (gradient); Y_l0 is
the Legendre polynomial's, Y_lm for m > 0 sqrt(2) (-1)^m Re and for m < 0 sqrt(2) (-1)^m Im of
the complex Y_l^|m| (scipy.special.sph_harm_y). Hence $a_{00} = (Z/2)/\sqrt{4\pi}$, and the
$l = 2$ and $l = 4$ amplitudes are linear in $\langle nn\rangle$ and $\langle nnnn\rangle$ (e.g.
$a_{20} = \sqrt{5/(16\pi)}\,(3\langle nn\rangle_{33} - \operatorname{Tr}\langle nn\rangle)$). Both
in the frame of the current flow, as $\langle nn\rangle$.

- **Frames**: [`fabric_tensor`][suspension_fabric.analysis.fabric.fabric_tensor] works in the
  simulation frame (LAMMPS x, y, z; z is the gradient direction).
  [`FabricAnalysis`][suspension_fabric.analysis.fabric.FabricAnalysis] reports the paper frame of
  the current shear, whose flow direction is (cos t, sin t, 0) with t the flow angle: t = 0 for
  startup shear, t = theta after a shear rotation by theta
  ([`suspension_fabric.analysis.frames.simulation_to_paper`][suspension_fabric.analysis.frames.simulation_to_paper]).
- **Strain**: MDAnalysis' dump reader stores the LAMMPS step in ``ts.data['step']`` (and
  ``ts.time`` = step, dt being unknown to it), and the box tilts flip, so the strain is computed
  as (step - shear_start_step) * dt * shear_rate, counted from the step at which the current
  shear started (the rotation step for a rotated run).
- **Precision**: MDAnalysis stores positions and box in float32; the kernel computes in float64
  from what it is given. Pairs whose gap lies within ~1e-6 (times the box length) of the
  threshold may therefore be classified differently from an exact float64 calculation on the
  unrounded coordinates; LAMMPS' default dump format (%g, six significant digits) is a much
  larger source of such rounding than float32.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass

import MDAnalysis as mda
import numpy as np
from MDAnalysis.analysis.base import AnalysisBase
from MDAnalysis.lib.distances import self_capped_distance
from MDAnalysis.lib.mdamath import triclinic_box, triclinic_vectors
from scipy.special import sph_harm_y

from suspension_fabric.io.dumpio import scan_dump

from .components import (
    COMPONENTS,
    DEFAULT_EPS,
    FOURTH_MOMENT_COMPONENTS,
    HARMONIC_COLUMNS,
    HARMONIC_ORDERS,
    component_label,
)
from .frames import paper_basis_in_simulation_frame, simulation_to_paper

__all__ = [
    "DEFAULT_EPS",
    "COMPONENTS",
    "component_label",
    "NearContacts",
    "box_vectors",
    "near_contact_pairs",
    "fabric_tensor",
    "contact_normals",
    "FOURTH_MOMENT_COMPONENTS",
    "HARMONIC_ORDERS",
    "HARMONIC_COLUMNS",
    "real_spherical_harmonics",
    "direction_moments",
    "tensor_components",
    "open_dump",
    "FabricAnalysis",
]

# Relative widening of the neighbour-search cutoff: the search runs in float32
# inside MDAnalysis, the exact test afterwards in float64.
_SEARCH_CUTOFF_MARGIN = 1e-3


@dataclass
class NearContacts:
    """Near-contact pairs of one configuration.

    ``pairs`` (M, 2) with i < j, ``separations`` (M, 3) minimum-image vectors from
    i to j in the simulation frame, ``gaps`` (M,) surface gaps h (negative = overlap).
    """

    pairs: np.ndarray
    separations: np.ndarray
    gaps: np.ndarray

    def __len__(self) -> int:
        return len(self.pairs)


def _check_dimensions(dimensions) -> np.ndarray:
    dims = np.asarray(dimensions, dtype=float)
    if dims.shape != (6,) or not np.all(np.isfinite(dims)):
        raise ValueError(f"dimensions must be six finite numbers [lx, ly, lz, alpha, beta, gamma], got {dimensions!r}")
    if np.any(dims[:3] <= 0) or np.any(dims[3:] <= 0) or np.any(dims[3:] >= 180):
        raise ValueError(f"invalid box dimensions {dims.tolist()}: lengths > 0, 0 < angles < 180")
    return dims


def box_vectors(dimensions) -> np.ndarray:
    """Reduced edge vectors (rows, float64) of the periodic lattice given by ``dimensions``.

    The rows are lower triangular as in LAMMPS (a along x, b in the xy plane) with
    tilts reduced to |b_x| <= a_x / 2, |c_x| <= a_x / 2, |c_y| <= b_y / 2 by adding
    lattice vectors (as LAMMPS' ``flip`` does); the periodic system is unchanged and
    the cell is as wide as possible, so boxes with unflipped tilts work too.
    """
    vectors = triclinic_vectors(_check_dimensions(dimensions), dtype=np.float64)
    if not np.any(vectors):
        raise ValueError(f"degenerate box dimensions {list(dimensions)}")
    a, b, c = vectors.copy()
    b = b - np.round(b[0] / a[0]) * a
    c = c - np.round(c[1] / b[1]) * b
    c = c - np.round(c[0] / a[0]) * a
    return np.array([a, b, c])


def _perpendicular_widths(vectors: np.ndarray) -> np.ndarray:
    """Distances between opposite faces of the cell spanned by ``vectors``."""
    a, b, c = vectors
    volume = abs(np.dot(a, np.cross(b, c)))
    return volume / np.linalg.norm([np.cross(b, c), np.cross(c, a), np.cross(a, b)], axis=1)


def _check_configuration(positions, radii, eps):
    positions = np.asarray(positions, dtype=float)
    radii = np.asarray(radii, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"positions must have shape (N, 3), got {positions.shape}")
    if radii.shape != (len(positions),):
        raise ValueError(f"radii must have shape ({len(positions)},), got {radii.shape}")
    if not np.all(np.isfinite(positions)):
        bad = np.flatnonzero(~np.all(np.isfinite(positions), axis=1))
        raise ValueError(f"positions contain non-finite values (particles {bad[:10].tolist()})")
    if not np.all(np.isfinite(radii)) or np.any(radii <= 0):
        raise ValueError("radii must be finite and positive")
    if not np.isfinite(eps) or eps < 0:
        raise ValueError(f"eps must be finite and >= 0, got {eps}")
    return positions, radii


def near_contact_pairs(positions, radii, dimensions, eps: float = DEFAULT_EPS) -> NearContacts:
    """All pairs with surface gap h < eps * min(d_i, d_j) under the minimum image.

    ``positions`` (N, 3) may lie anywhere (they are wrapped into the cell first),
    ``radii`` (N,), ``dimensions`` = [lx, ly, lz, alpha, beta, gamma] as in MDAnalysis.
    Candidates come from ``MDAnalysis.lib.distances.self_capped_distance`` with cutoff
    2 a_max (1 + eps), the largest centre distance a near contact can have; each
    candidate is then tested exactly, with its minimum-image vector computed in float64
    (MDAnalysis' ``minimize_vectors`` would cast the box to float32). Raises ``ValueError`` if the box is
    so small that a pair could be in near contact through two images
    (cutoff >= half the smallest distance between opposite faces).
    """
    positions, radii = _check_configuration(positions, radii, eps)
    rows = box_vectors(dimensions)
    empty = NearContacts(np.zeros((0, 2), dtype=np.intp), np.zeros((0, 3)), np.zeros(0))
    if len(positions) < 2:
        return empty
    max_contact_distance = 2.0 * radii.max() * (1.0 + eps)
    half_width = 0.5 * _perpendicular_widths(rows).min()
    if max_contact_distance >= half_width:
        raise ValueError(
            f"box too small: near-contact distance {max_contact_distance:.6g} is not below half "
            f"the smallest cell width ({half_width:.6g}); the minimum image is ambiguous"
        )
    inverse = np.linalg.inv(rows)
    # Wrap in float64 so the float32 search sees coordinates inside its cell.
    fractional = positions @ inverse
    wrapped = (fractional - np.floor(fractional)) @ rows
    search_cutoff = min(max_contact_distance * (1.0 + _SEARCH_CUTOFF_MARGIN), 0.999 * half_width)
    candidates = self_capped_distance(wrapped, search_cutoff, box=triclinic_box(*rows), return_distances=False)
    if len(candidates) == 0:
        return empty
    candidates = np.sort(np.asarray(candidates, dtype=np.intp), axis=1)
    i, j = candidates[:, 0], candidates[:, 1]
    # Rounding the fractional components gives the exact minimum image here: a vector
    # shorter than half of every face distance has all fractional components in
    # (-1/2, 1/2), and the box check above guarantees that for near contacts.
    fractional = (wrapped[j] - wrapped[i]) @ inverse
    separations = (fractional - np.round(fractional)) @ rows
    distances = np.linalg.norm(separations, axis=1)
    gaps = distances - (radii[i] + radii[j])
    is_contact = gaps < eps * 2.0 * np.minimum(radii[i], radii[j])
    coincident = is_contact & (distances == 0.0)
    if np.any(coincident):
        k = np.flatnonzero(coincident)[0]
        raise ValueError(f"particles {i[k]} and {j[k]} coincide; their contact normal is undefined")
    order = np.lexsort((j[is_contact], i[is_contact]))
    return NearContacts(candidates[is_contact][order], separations[is_contact][order], gaps[is_contact][order])


def contact_normals(positions, radii, dimensions, eps: float = DEFAULT_EPS) -> np.ndarray:
    """Unit centre-to-centre vectors (n_pairs, 3) of the near-contact pairs, simulation frame
    (arguments as in [`near_contact_pairs`][suspension_fabric.analysis.fabric.near_contact_pairs])."""
    separations = near_contact_pairs(positions, radii, dimensions, eps).separations
    return separations / np.linalg.norm(separations, axis=1)[:, None] if len(separations) else np.zeros((0, 3))


def fabric_tensor(positions, radii, dimensions, eps: float = DEFAULT_EPS) -> tuple[np.ndarray, int]:
    """Fabric <nn> (3x3, simulation frame) and the number of near-contact pairs.

    <nn>_kl = (1/N) sum over near-contact pairs (each once) of n_k n_l, N = len(positions),
    so the trace is n_pairs / N = Z / 2. Arguments as in
    [`near_contact_pairs`][suspension_fabric.analysis.fabric.near_contact_pairs].
    """
    normals = contact_normals(positions, radii, dimensions, eps)
    return normals.T @ normals / len(positions), len(normals)


def real_spherical_harmonics(normals) -> np.ndarray:
    """Y_lm(n) (module docstring) of unit vectors (..., 3) for the orders of HARMONIC_ORDERS, in the
    order of HARMONIC_COLUMNS: shape (..., len(HARMONIC_COLUMNS))."""
    normals = np.asarray(normals, dtype=float)
    polar = np.arccos(np.clip(normals[..., 2], -1.0, 1.0))
    azimuth = np.arctan2(normals[..., 1], normals[..., 0])
    values = []
    for l in HARMONIC_ORDERS:  # noqa: E741
        for m in range(-l, l + 1):
            complex_y = sph_harm_y(l, abs(m), polar, azimuth)
            if m == 0:
                values.append(complex_y.real)
            else:
                part = complex_y.imag if m < 0 else complex_y.real
                values.append(np.sqrt(2.0) * (-1.0) ** m * part)
    return np.stack(values, axis=-1)


def direction_moments(normals, n_particles: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(<nn> 3x3, <nnnn>'s `FOURTH_MOMENT_COMPONENTS` (15,), the amplitudes a_lm of
    `HARMONIC_COLUMNS`) of near-contact normals (n_pairs, 3) in the frame they are given in,
    each summed over the pairs and divided by the number of particles (module docstring)."""
    normals = np.asarray(normals, dtype=float).reshape(-1, 3)
    second = normals.T @ normals / n_particles
    index = np.array(list(FOURTH_MOMENT_COMPONENTS.values()))
    fourth = np.prod(normals[:, index], axis=-1).sum(axis=0) / n_particles
    harmonics = real_spherical_harmonics(normals).sum(axis=0) / n_particles
    return second, fourth, harmonics


def tensor_components(tensors) -> dict[str, np.ndarray]:
    """The six independent components of symmetric tensor(s) (..., 3, 3), keyed as in `COMPONENTS`."""
    tensors = np.asarray(tensors, dtype=float)
    return {name: tensors[..., k, l] for name, (k, l) in COMPONENTS.items()}


_COORDINATE_SETS = (("x", "y", "z"), ("xs", "ys", "zs"), ("xu", "yu", "zu"), ("xsu", "ysu", "zsu"))


def open_dump(path: str | os.PathLike, expected_n_atoms: int | None = None) -> mda.Universe:
    """MDAnalysis Universe of a ``dump custom ... id type radius x y z`` trajectory.

    Checks first, with errors naming the file: it exists and has frames
    (``FileNotFoundError`` / ``ValueError``), all frames have the same atom count
    (equal to ``expected_n_atoms`` if given) and columns, and the columns include
    id, type, radius and one set of coordinates (x y z, xs ys zs, xu yu zu or
    xsu ysu zsu; MDAnalysis takes the first present in that order).
    The reader's dt is set to 1 so that ``ts.time`` is the LAMMPS step.
    """
    summary = scan_dump(path, expected_n_atoms=expected_n_atoms)
    columns = set(summary.columns)
    missing = [c for c in ("id", "type", "radius") if c not in columns]
    if missing:
        raise ValueError(
            f"{summary.path}: dump lacks the column(s) {missing}; "
            f"expected 'dump custom ... id type radius x y z', found {list(summary.columns)}"
        )
    if not any(set(cs) <= columns for cs in _COORDINATE_SETS):
        raise ValueError(f"{summary.path}: dump has no coordinate columns, found {list(summary.columns)}")
    if not summary.triclinic:
        raise ValueError(f"{summary.path}: expected a triclinic box ('BOX BOUNDS xy xz yz ...')")
    with warnings.catch_warnings():
        # The dump has no masses; they are irrelevant here.
        warnings.filterwarnings("ignore", message="Guessed all Masses to 1.0")
        return mda.Universe(
            str(summary.path),
            format="LAMMPSDUMP",
            topology_format="LAMMPSDUMP",
            additional_columns=["radius"],
            dt=1.0,  # ts.time = LAMMPS step, stated
        )


class FabricAnalysis(AnalysisBase):
    """Per-frame near-contact fabric of a LAMMPS trajectory, in the paper frame of its shear.

    Parameters
    ----------
    universe
        Universe of a dump with a ``radius`` column (see [`open_dump`][suspension_fabric.analysis.fabric.open_dump], or
        use [`from_dump`][suspension_fabric.analysis.fabric.FabricAnalysis.from_dump]). All atoms are particles.
    dt
        LAMMPS time step (time units, = strain units at shear rate 1).
    shear_rate
        Imposed shear rate of the current shear.
    shear_start_step
        LAMMPS step at which the current shear started: 0 for startup, the rotation
        step for a rotated run. Frames before it raise ``ValueError``.
    flow_angle_deg
        Flow direction (cos t, sin t, 0) of the current shear at its start, in degrees: 0
        for startup, theta after a shear rotation by theta.
    turning_deg_per_strain
        Rate at which the flow direction turns (rotary shear), degrees per unit strain:
        the flow angle of a frame at strain gamma is flow_angle_deg + turning x gamma.
    eps
        Near-contact threshold, gap < eps * min(d_i, d_j).
    expected_n_atoms
        If given, the universe must have exactly this many atoms.

    Results (``self.results``), one entry per analysed frame
    --------------------------------------------------------
    - ``step``, ``strain``: LAMMPS step and strain (step - shear_start_step) * dt * shear_rate.
    - ``flow_angle_deg``: (n_frames,) flow angle of each frame, degrees.
    - ``fabric``: (n_frames, 3, 3) <nn> in the frame of the current flow (e1 the flow direction at
      the frame's strain, e2 gradient, e3 = e1 x e2); ``fabric_simulation`` the same in x, y, z.
    - ``n11``, ``n22``, ``n33``, ``n12``, ``n13``, ``n23``: Components of ``fabric``.
    - ``fourth_moment``, ``harmonics``: (n_frames, 15) <nnnn> (`FOURTH_MOMENT_COMPONENTS`, also one
      result each, e.g. ``n1122``) and (n_frames, 28) the amplitudes a_lm of the near-contact
      directions (`HARMONIC_COLUMNS`, also one result each), in the frame of the current flow.
    - ``n_pairs``, ``coordination``: Number of near-contact pairs and Z = 2 n_pairs / N.
    - ``volume_fraction``: sum(4/3 pi a^3) / box volume of each frame.
    - ``n_particles``: N (int).
    """

    def __init__(
        self,
        universe: mda.Universe,
        *,
        dt: float,
        shear_rate: float = 1.0,
        shear_start_step: int = 0,
        flow_angle_deg: float = 0.0,
        turning_deg_per_strain: float = 0.0,
        eps: float = DEFAULT_EPS,
        expected_n_atoms: int | None = None,
        verbose: bool = False,
    ):
        super().__init__(universe.trajectory, verbose=verbose)
        self.universe = universe
        self.source = getattr(universe.trajectory, "filename", None) or "<universe>"
        checked = (
            ("dt", dt),
            ("shear_rate", shear_rate),
            ("eps", eps),
            ("flow_angle_deg", flow_angle_deg),
            ("turning_deg_per_strain", turning_deg_per_strain),
        )
        for name, value in checked:
            if not np.isfinite(value):
                raise ValueError(f"{self.source}: {name} must be finite, got {value}")
        if dt <= 0:
            raise ValueError(f"{self.source}: dt must be positive, got {dt}")
        if eps < 0:
            raise ValueError(f"{self.source}: eps must be >= 0, got {eps}")
        n_atoms = len(universe.atoms)
        if expected_n_atoms is not None and n_atoms != expected_n_atoms:
            raise ValueError(f"{self.source}: expected {expected_n_atoms} atoms, found {n_atoms}")
        if n_atoms == 0:
            raise ValueError(f"{self.source}: no atoms")
        self.dt = float(dt)
        self.shear_rate = float(shear_rate)
        self.shear_start_step = int(shear_start_step)
        self.flow_angle_deg = float(flow_angle_deg)
        self.turning_deg_per_strain = float(turning_deg_per_strain)
        self.eps = float(eps)
        self.n_particles = n_atoms

    @classmethod
    def from_dump(cls, path: str | os.PathLike, *, expected_n_atoms: int | None = None, **kwargs):
        """Open and check the dump at ``path`` ([`open_dump`][suspension_fabric.analysis.fabric.open_dump]) and build
        the analysis."""
        universe = open_dump(path, expected_n_atoms=expected_n_atoms)
        return cls(universe, expected_n_atoms=expected_n_atoms, **kwargs)

    def _prepare(self):
        if "radius" not in self._trajectory.ts.data:
            raise ValueError(
                f"{self.source}: frames carry no 'radius' column (open with additional_columns=['radius'])"
            )
        self.results.step = np.zeros(self.n_frames, dtype=np.int64)
        self.results.fabric_simulation = np.zeros((self.n_frames, 3, 3))
        self.results.n_pairs = np.zeros(self.n_frames, dtype=np.int64)
        self.results.volume_fraction = np.zeros(self.n_frames)
        self.results.fourth_moment = np.zeros((self.n_frames, len(FOURTH_MOMENT_COMPONENTS)))
        self.results.harmonics = np.zeros((self.n_frames, len(HARMONIC_COLUMNS)))

    def _single_frame(self):
        ts = self._ts
        step = int(ts.data.get("step", round(ts.time)))
        where = f"{self.source}: frame {ts.frame} (step {step})"
        if step < self.shear_start_step:
            raise ValueError(f"{where} precedes the shear start step {self.shear_start_step}")
        positions = np.asarray(ts.positions, dtype=float)
        radii = np.asarray(ts.data["radius"], dtype=float)
        if not np.all(np.isfinite(positions)):
            raise ValueError(f"{where}: non-finite positions")
        if ts.dimensions is None:
            raise ValueError(f"{where}: no box")
        try:
            normals = contact_normals(positions, radii, ts.dimensions, self.eps)
            volume = abs(np.linalg.det(box_vectors(ts.dimensions)))
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from err
        index = self._frame_index
        # the higher moments in the frame of this frame's flow (rotating them afterwards would need
        # the Wigner matrices of every order)
        basis = paper_basis_in_simulation_frame(np.radians(self._flow_angle_deg(step)))
        _, fourth, harmonics = direction_moments(normals @ basis.T, self.n_particles)
        self.results.step[index] = step
        self.results.fabric_simulation[index] = normals.T @ normals / self.n_particles
        self.results.n_pairs[index] = len(normals)
        self.results.fourth_moment[index] = fourth
        self.results.harmonics[index] = harmonics
        self.results.volume_fraction[index] = np.sum(4.0 / 3.0 * np.pi * radii**3) / volume

    def _strain(self, step):
        return (np.asarray(step) - self.shear_start_step) * self.dt * self.shear_rate

    def _flow_angle_deg(self, step):
        return self.flow_angle_deg + self.turning_deg_per_strain * self._strain(step)

    def _conclude(self):
        results = self.results
        results.n_particles = self.n_particles
        results.strain = self._strain(results.step)
        results.flow_angle_deg = self._flow_angle_deg(results.step)
        results.fabric = simulation_to_paper(results.fabric_simulation, np.radians(results.flow_angle_deg))
        for name, values in tensor_components(results.fabric).items():
            results[name] = values
        for k, name in enumerate(FOURTH_MOMENT_COMPONENTS):
            results[name] = results.fourth_moment[:, k]
        for k, name in enumerate(HARMONIC_COLUMNS):
            results[name] = results.harmonics[:, k]
        results.coordination = 2.0 * results.n_pairs / self.n_particles
