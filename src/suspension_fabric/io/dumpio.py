"""LAMMPS text dumps: the triclinic box, a dump writer, and a header scanner.

The project's trajectories are ``dump custom`` text files with the columns
``id type radius x y z`` (see `DUMP_COLUMNS`) in a restricted triclinic box
(LAMMPS ``xy xz yz`` tilts; the shear uses ``xz`` and ``yz`` with z the gradient).

- **Restricted triclinic box** (<https://docs.lammps.org/Howto_triclinic.html>): edge vectors
  a = (lx, 0, 0), b = (xy, ly, 0), c = (xz, yz, lz) from the origin (xlo, ylo, zlo). A point is
  x = origin + s_a a + s_b b + s_c c with fractional (LAMMPS "scaled") coordinates s in [0, 1)
  for the primary cell.
- **Triclinic dump header**: ``ITEM: BOX BOUNDS xy xz yz pp pp pp`` followed by three lines
  ``xlo_bound xhi_bound xy`` / ``ylo_bound yhi_bound xz`` / ``zlo_bound zhi_bound yz`` where the
  bounds are those of the axis-aligned bounding box of the tilted cell:
  xlo_bound = xlo + min(0, xy, xz, xy + xz), xhi_bound = xhi + max(0, xy, xz, xy + xz),
  ylo_bound = ylo + min(0, yz), yhi_bound = yhi + max(0, yz), z bounds unchanged. MDAnalysis'
  ``DumpReader`` inverts exactly this.
- **Reading with MDAnalysis** (checked in tests/analysis/test_fabric*.py): ``DumpReader`` takes
  the first coordinate set it finds in the order unscaled (x y z), scaled (xs ys zs), unwrapped
  (xu yu zu), scaled unwrapped, unless ``lammps_coordinate_convention`` forces one; scaled
  coordinates are converted to Cartesian ones. It translates positions so that the box origin is
  0, sorts atoms by ``id``, stores positions and box as float32 (so lengths carry a relative error
  of ~1e-7), and sets ``ts.time`` = step x dt with dt = 1, i.e. the LAMMPS step. It assumes every
  frame has the same number of lines, which is why
  [`scan_dump`][suspension_fabric.io.dumpio.scan_dump] checks the headers of all frames before
  MDAnalysis opens a file.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from itertools import islice
from pathlib import Path

import numpy as np

__all__ = [
    "DUMP_COLUMNS",
    "TriclinicBox",
    "DumpFrame",
    "DumpSummary",
    "write_lammps_dump",
    "scan_dump",
    "DumpFrameData",
    "iter_dump_frames",
    "iter_frame_blocks",
]

#: Column layout of the project's trajectory dumps (``dump custom ... id type radius x y z``).
DUMP_COLUMNS: tuple[str, ...] = ("id", "type", "radius", "x", "y", "z")

_SUPPORTED_COLUMNS = {"id", "type", "radius", "x", "y", "z", "xs", "ys", "zs"}


@dataclass(frozen=True)
class TriclinicBox:
    """LAMMPS restricted triclinic box: lengths, tilt factors and origin.

    Edge vectors are a = (lx, 0, 0), b = (xy, ly, 0), c = (xz, yz, lz).
    """

    lx: float
    ly: float
    lz: float
    xy: float = 0.0
    xz: float = 0.0
    yz: float = 0.0
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if not all(np.isfinite([self.lx, self.ly, self.lz, self.xy, self.xz, self.yz])):
            raise ValueError(f"box parameters must be finite, got {self}")
        if min(self.lx, self.ly, self.lz) <= 0:
            raise ValueError(f"box lengths must be positive, got {self}")

    @property
    def edge_vectors(self) -> np.ndarray:
        """Rows a, b, c (float64, simulation frame)."""
        return np.array([[self.lx, 0.0, 0.0], [self.xy, self.ly, 0.0], [self.xz, self.yz, self.lz]])

    @property
    def volume(self) -> float:
        return self.lx * self.ly * self.lz

    def mdanalysis_dimensions(self) -> np.ndarray:
        """``[lx, ly, lz, alpha, beta, gamma]`` (edge lengths |a|, |b|, |c|, angles in degrees)."""
        a, b, c = self.edge_vectors
        la, lb, lc = (float(np.linalg.norm(v)) for v in (a, b, c))
        alpha = np.degrees(np.arccos(np.clip(b @ c / (lb * lc), -1.0, 1.0)))
        beta = np.degrees(np.arccos(np.clip(a @ c / (la * lc), -1.0, 1.0)))
        gamma = np.degrees(np.arccos(np.clip(a @ b / (la * lb), -1.0, 1.0)))
        return np.array([la, lb, lc, alpha, beta, gamma])

    def dump_bounds(self) -> tuple[tuple[float, float, float], ...]:
        """The three ``BOX BOUNDS`` rows of a triclinic dump (bounding box plus tilt)."""
        xlo, ylo, zlo = self.origin
        xhi, yhi, zhi = xlo + self.lx, ylo + self.ly, zlo + self.lz
        xy, xz, yz = self.xy, self.xz, self.yz
        return (
            (xlo + min(0.0, xy, xz, xy + xz), xhi + max(0.0, xy, xz, xy + xz), xy),
            (ylo + min(0.0, yz), yhi + max(0.0, yz), xz),
            (zlo, zhi, yz),
        )

    def to_fractional(self, positions) -> np.ndarray:
        """Fractional (LAMMPS scaled) coordinates s with x = origin + s @ edge_vectors."""
        shifted = np.asarray(positions, dtype=float) - np.asarray(self.origin, dtype=float)
        return np.linalg.solve(self.edge_vectors.T, shifted.T).T


@dataclass
class DumpFrame:
    """One trajectory frame to write: step, box, positions (N, 3), radii (N,).

    ``types`` defaults to 1 for radius equal to the smallest radius and 2 otherwise;
    ``ids`` defaults to 1..N.
    """

    step: int
    box: TriclinicBox
    positions: np.ndarray
    radii: np.ndarray
    types: np.ndarray | None = None
    ids: np.ndarray | None = None


def _format_frame(frame: DumpFrame, columns: Sequence[str], float_format: str) -> str:
    positions = np.asarray(frame.positions, dtype=float)
    radii = np.asarray(frame.radii, dtype=float)
    n_atoms = len(positions)
    if positions.shape != (n_atoms, 3) or radii.shape != (n_atoms,):
        raise ValueError(
            f"frame at step {frame.step}: positions must be (N, 3) and radii (N,), "
            f"got {positions.shape} and {radii.shape}"
        )
    ids = np.arange(1, n_atoms + 1) if frame.ids is None else np.asarray(frame.ids, dtype=int)
    if frame.types is None:
        types = np.where(np.isclose(radii, radii.min()), 1, 2) if n_atoms else np.zeros(0, int)
    else:
        types = np.asarray(frame.types, dtype=int)
    scaled = frame.box.to_fractional(positions) if n_atoms else np.zeros((0, 3))
    values = {
        "id": ids,
        "type": types,
        "radius": radii,
        "x": positions[:, 0],
        "y": positions[:, 1],
        "z": positions[:, 2],
        "xs": scaled[:, 0],
        "ys": scaled[:, 1],
        "zs": scaled[:, 2],
    }
    integer_columns = {"id", "type"}
    lines = [
        "ITEM: TIMESTEP",
        str(int(frame.step)),
        "ITEM: NUMBER OF ATOMS",
        str(n_atoms),
        "ITEM: BOX BOUNDS xy xz yz pp pp pp",
    ]
    lines += [" ".join(float_format % v for v in row) for row in frame.box.dump_bounds()]
    lines.append("ITEM: ATOMS " + " ".join(columns))
    formats = ["%d" if c in integer_columns else float_format for c in columns]
    row_format = " ".join(formats)
    table = zip(*(values[c] for c in columns))
    lines += [row_format % row for row in table]
    return "\n".join(lines) + "\n"


def write_lammps_dump(
    path: str | os.PathLike,
    frames: Iterable[DumpFrame],
    columns: Sequence[str] = DUMP_COLUMNS,
    float_format: str = "%.12g",
) -> Path:
    """Write ``frames`` as a LAMMPS ``dump custom`` text file with a triclinic box.

    Positions are written as given (not wrapped), as LAMMPS does between
    re-neighbourings. ``columns`` chooses the per-atom columns from
    id, type, radius, x y z (unscaled) and xs ys zs (scaled, i.e. fractional);
    leaving some out makes deliberately incomplete dumps for tests.
    Returns the path.
    """
    unknown = [c for c in columns if c not in _SUPPORTED_COLUMNS]
    if unknown:
        raise ValueError(f"unsupported dump columns {unknown}; choose from {sorted(_SUPPORTED_COLUMNS)}")
    path = Path(path)
    with open(path, "w") as handle:
        for frame in frames:
            handle.write(_format_frame(frame, columns, float_format))
    return path


@dataclass
class DumpSummary:
    """Header facts of a dump: path, steps of all frames, atom count, atom columns."""

    path: Path
    steps: np.ndarray
    n_atoms: int
    columns: tuple[str, ...]
    triclinic: bool = True

    @property
    def n_frames(self) -> int:
        return len(self.steps)


def _expect_item(line: str, item: str, path: Path, frame: int) -> None:
    if not line.startswith(f"ITEM: {item}"):
        found = repr(line.rstrip("\n")) if line else "end of file"
        raise ValueError(f"{path}: frame {frame}: expected 'ITEM: {item}', found {found}")


def scan_dump(path: str | os.PathLike, expected_n_atoms: int | None = None) -> DumpSummary:
    """See `_scan_dump`; bytes that are not text are a ``ValueError`` naming the file too."""
    try:
        return _scan_dump(path, expected_n_atoms)
    except UnicodeDecodeError as err:
        raise ValueError(f"{path}: not a text dump ({err})") from None


def _scan_dump(path: str | os.PathLike, expected_n_atoms: int | None = None) -> DumpSummary:
    """Read and check the frame headers of a LAMMPS text dump, skipping the atom lines.

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` naming the file
    (and the frame) for: no frames, a truncated frame (the file ends inside a header
    or atom line, or before all atom lines), a malformed header, an atom
    count that changes between frames or differs from ``expected_n_atoms``, atom
    columns that change between frames, or steps that do not increase.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"trajectory dump not found: {path}")
    steps: list[int] = []
    n_atoms: int | None = None
    columns: tuple[str, ...] | None = None
    triclinic = True
    with open(path) as handle:
        frame = 0
        step: int | None = None

        def header_line() -> str:
            # LAMMPS ends every line, so a header line without its newline (or none at
            # all) means the file was cut off inside this frame's header.
            text = handle.readline()
            if not text.endswith("\n"):
                where = f"frame {frame}" if step is None else f"frame {frame} (step {step})"
                raise ValueError(f"{path}: {where} is truncated: the file ends inside its header")
            return text

        while True:
            line = handle.readline()
            if not line:
                break
            step = None
            if not line.endswith("\n"):
                raise ValueError(f"{path}: frame {frame} is truncated: the file ends inside its header")
            _expect_item(line, "TIMESTEP", path, frame)
            step_text = header_line()
            try:
                step = int(step_text)
            except ValueError as err:
                raise ValueError(f"{path}: frame {frame}: malformed header ({err})") from err
            _expect_item(header_line(), "NUMBER OF ATOMS", path, frame)
            count_text = header_line()
            try:
                frame_atoms = int(count_text)
            except ValueError as err:
                raise ValueError(f"{path}: frame {frame}: malformed header ({err})") from err
            if n_atoms is None:
                n_atoms = frame_atoms
            elif frame_atoms != n_atoms:
                raise ValueError(
                    f"{path}: the number of atoms changes from {n_atoms} to {frame_atoms} "
                    f"at frame {frame} (step {step})"
                )
            box_line = header_line()
            _expect_item(box_line, "BOX BOUNDS", path, frame)
            triclinic = "xy" in box_line.split()
            box_rows = [header_line() for _ in range(3)]
            expected_fields = 3 if triclinic else 2
            if any(len(r.split()) != expected_fields for r in box_rows):
                raise ValueError(f"{path}: frame {frame}: malformed BOX BOUNDS rows")
            atoms_line = header_line()
            _expect_item(atoms_line, "ATOMS", path, frame)
            frame_columns = tuple(atoms_line.split()[2:])
            if columns is None:
                columns = frame_columns
            elif frame_columns != columns:
                raise ValueError(f"{path}: atom columns change from {columns} to {frame_columns} at frame {frame}")
            atom_rows = list(islice(handle, frame_atoms))
            cut = _truncation(atom_rows, frame_atoms)
            if cut:
                raise ValueError(f"{path}: frame {frame} (step {step}) is truncated: {cut}")
            if steps and step <= steps[-1]:
                raise ValueError(f"{path}: steps must increase, frame {frame} has step {step} after {steps[-1]}")
            steps.append(step)
            frame += 1
    if not steps:
        raise ValueError(f"{path}: empty trajectory (no frames)")
    if expected_n_atoms is not None and n_atoms != expected_n_atoms:
        raise ValueError(f"{path}: expected {expected_n_atoms} atoms, the dump has {n_atoms}")
    return DumpSummary(
        path=path, steps=np.asarray(steps, dtype=np.int64), n_atoms=int(n_atoms), columns=columns, triclinic=triclinic
    )


def _truncation(rows: list[str], n_atoms: int) -> str | None:
    """None if ``rows`` are ``n_atoms`` complete lines, else what is missing.

    A line without its newline can only be the end of a file cut off inside it (LAMMPS
    ends every line), so it counts as incomplete even when all ``n_atoms`` lines are there.
    """
    partial = bool(rows) and not rows[-1].endswith("\n")
    if len(rows) == n_atoms and not partial:
        return None
    complete = len(rows) - partial
    detail = f"{complete} of {n_atoms} atom lines complete"
    if partial:
        detail += f", the file ends inside atom line {complete + 1}"
    return detail


@dataclass
class DumpFrameData:
    """One dump frame read back in float64: step, box, ids, types, radii, positions (sorted by id)."""

    step: int
    box: TriclinicBox
    ids: np.ndarray
    types: np.ndarray
    radii: np.ndarray
    positions: np.ndarray


def iter_dump_frames(path: str | os.PathLike) -> Iterator[DumpFrameData]:
    """Frames of a ``dump custom ... id type radius x y z`` text dump, in float64, atoms sorted by id.

    Raises ``ValueError`` naming the file, frame and step for a malformed or truncated
    frame (or bytes that are not text); the frames before it are yielded first.
    """
    blocks = iter_frame_blocks(path)
    frame_index = 0
    while True:
        try:
            step, lines = next(blocks)
        except StopIteration:
            return
        except UnicodeDecodeError as err:
            raise ValueError(f"{path}: frame {frame_index}: not a text dump ({err})") from None
        try:
            yield _parse_frame(path, frame_index, step, lines)
        except (ValueError, IndexError, KeyError) as err:
            if str(path) in str(err):
                raise
            raise ValueError(
                f"{path}: frame {frame_index} (step {step}) is malformed ({type(err).__name__}: {err})"
            ) from None
        frame_index += 1


def _parse_frame(path, frame_index: int, step: int, lines: list[str]) -> DumpFrameData:
    """One frame's block of [`iter_frame_blocks`][suspension_fabric.io.dumpio.iter_frame_blocks] (see
    [`iter_dump_frames`][suspension_fabric.io.dumpio.iter_dump_frames])."""
    # a step line without its newline is the end of a file cut inside the step number
    step_known = len(lines) > 1 and lines[1].endswith("\n")
    where = f"{path}: frame {frame_index}" + (f" (step {step})" if step_known else "")
    if len(lines) < 9:
        if not lines[-1].endswith("\n"):  # only the file's last line lacks one
            raise ValueError(f"{where} is truncated: the file ends inside its header")
        raise ValueError(f"{where} is truncated: incomplete header ({len(lines)} of 9 lines)")
    n_atoms = int(lines[3])
    box_header = lines[4]
    if "xy" not in box_header.split():
        raise ValueError(f"{where}: expected a triclinic box")
    bounds = [[float(v) for v in line.split()] for line in lines[5:8]]
    (xlo_b, xhi_b, xy), (ylo_b, yhi_b, xz), (zlo, zhi, yz) = bounds
    xlo = xlo_b - min(0.0, xy, xz, xy + xz)
    xhi = xhi_b - max(0.0, xy, xz, xy + xz)
    ylo = ylo_b - min(0.0, yz)
    yhi = yhi_b - max(0.0, yz)
    box = TriclinicBox(xhi - xlo, yhi - ylo, zhi - zlo, xy, xz, yz, (xlo, ylo, zlo))
    columns = lines[8].split()[2:]
    rows = lines[9:]
    if len(rows) == n_atoms + 1 and not rows[-1].endswith("\n"):
        # iter_frame_blocks appends a cut-off first line of the next frame to this one
        raise ValueError(
            f"{path}: frame {frame_index + 1} (after step {step}) is truncated: "
            f"the file ends inside its first line {rows[-1]!r}"
        )
    if len(rows) > n_atoms:
        raise ValueError(f"{where}: {len(rows)} atom lines for {n_atoms} atoms")
    cut = _truncation(rows, n_atoms)
    if cut:
        raise ValueError(f"{where} is truncated: {cut}")
    table = np.loadtxt(rows, ndmin=2)
    index = {name: k for k, name in enumerate(columns)}
    table = table[np.argsort(table[:, index["id"]])]
    return DumpFrameData(
        step=step,
        box=box,
        ids=table[:, index["id"]].astype(int),
        types=table[:, index["type"]].astype(int),
        radii=table[:, index["radius"]],
        positions=table[:, [index["x"], index["y"], index["z"]]],
    )


def iter_frame_blocks(path: str | os.PathLike) -> Iterator[tuple[int, list[str]]]:
    """(step, lines) of each frame of a text dump, lines as read (with newlines), unparsed.

    A frame runs from one ``ITEM: TIMESTEP`` line to the next; a frame cut off at the end
    of the file (a killed run) is yielded as it is, so callers can drop or reject it.
    """
    block: list[str] = []
    index = 0
    with open(path) as handle:
        for line in handle:
            if line.startswith("ITEM: TIMESTEP") and block:
                yield _block_step(path, block, index, at_end=False), block
                block = []
                index += 1
            elif not block and not line.startswith("ITEM: TIMESTEP"):
                raise ValueError(f"{path}: expected 'ITEM: TIMESTEP', found {line!r}")
            block.append(line)
    if block:
        yield _block_step(path, block, index, at_end=True), block


def _block_step(path, block: list[str], index: int, at_end: bool) -> int:
    try:
        return int(block[1])
    except (IndexError, ValueError):
        if at_end and len(block) <= 2:
            raise ValueError(f"{path}: frame {index} is truncated: the file ends before its step is complete") from None
        raise ValueError(f"{path}: frame {index}: no readable step after 'ITEM: TIMESTEP'") from None
