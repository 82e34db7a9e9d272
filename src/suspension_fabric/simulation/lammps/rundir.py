"""Run directories: work that survives a killed run, resumes from its restarts, and is published whole.

A run destined for ``<parent>/<name>`` works in ``<parent>/.<name>.partial`` (never an
output of a workflow rule, so neither Snakemake's incomplete-output handling nor a failed
job deletes it). Each launch of LAMMPS is a *segment*, a subfolder ``segment-NN`` with its
own log, trajectory, stress table and the alternating restart files LAMMPS writes while
running. A later launch with the same settings continues from the newest restart file
that LAMMPS can read (a truncated or corrupt one is skipped with a message, then the
previous one is tried, then strain 0); with different settings the partial work is
discarded, with a message. Each segment records the segment and step it continued from,
so the finished run is the chain of segments from the first one to the last: the outputs
are stitched from it, keeping from each segment the rows and frames on the run's own
output grid up to and including the step where the next segment took over. Only then is the run checked
and published: written into a temporary sibling, the completion marker
`COMPLETION_MARKER` last, then renamed into place. A directory holding the marker is
a finished run; a run that finishes but fails its checks goes to ``<name>.failed``.
"""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

from suspension_fabric.io.dumpio import iter_frame_blocks
from suspension_fabric.io.stressio import iter_table_rows

__all__ = [
    "COMPLETION_MARKER",
    "KEPT_MARKER",
    "ResumePoint",
    "PartialRun",
    "is_complete",
    "restore_marker",
    "partial_dir",
    "failed_dir",
    "publish",
]

#: File written last into a finished run directory (JSON: parameters, wall time, results).
COMPLETION_MARKER = "run_complete.json"
# A copy of the marker under a name no workflow rule declares: Snakemake deletes a job's declared
# marker when the job starts, and a rerun asking for exactly the finished run puts it back from here.
KEPT_MARKER = ".run_complete.kept.json"
SETTINGS_FILE = "settings.json"
SEGMENT_FILE = "segment.json"

#: ``probe(restart_file) -> step``; raises ``ValueError`` saying why a file is unreadable.
RestartProbe = Callable[[Path], int]


def partial_dir(output_dir: Path) -> Path:
    return output_dir.with_name(f".{output_dir.name}.partial")


def failed_dir(output_dir: Path) -> Path:
    return output_dir.with_name(f"{output_dir.name}.failed")


def restore_marker(output_dir, expect: Mapping, files: Iterable[str]) -> bool:
    """Put back the completion marker of the finished run in ``output_dir`` (from its kept copy) if
    the marker is missing, every item of ``expect`` equals the run record's (compared as JSON) and
    every one of ``files`` is there; True if the folder then holds that finished run."""
    output_dir = Path(output_dir)
    kept = output_dir / KEPT_MARKER
    if (output_dir / COMPLETION_MARKER).is_file() or not kept.is_file():
        return False
    try:
        record = json.loads(kept.read_text())
    except ValueError:
        return False
    wanted = json.loads(json.dumps(dict(expect), default=str))
    if any(record.get(key) != value for key, value in wanted.items()):
        return False
    if not all((output_dir / name).is_file() for name in files):
        return False
    shutil.copy2(kept, output_dir / COMPLETION_MARKER)
    return True


def is_complete(output_dir) -> bool:
    """True if ``output_dir`` holds a finished run (its completion marker exists)."""
    return (Path(output_dir) / COMPLETION_MARKER).is_file()


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


@dataclass(frozen=True)
class ResumePoint:
    """Where a run continues: a readable restart file of a segment, its step, the run's first step."""

    segment: Path
    restart_file: Path
    step: int
    first_step: int


class PartialRun:
    """The working directory of one run, ``.<name>.partial`` next to its output directory."""

    def __init__(
        self, output_dir: Path, settings: dict, restart_names: Iterable[str] = (), table_name: str | None = None
    ):
        self.output_dir = Path(output_dir).resolve()
        self.path = partial_dir(self.output_dir)
        self.settings = json.loads(json.dumps(settings, default=str))
        self.restart_names = tuple(restart_names)
        self.table_name = table_name

    # ------------------------------------------------------------------ segments
    def segments(self) -> list[Path]:
        return sorted(self.path.glob("segment-*")) if self.path.is_dir() else []

    @staticmethod
    def segment_record(segment: Path) -> dict:
        return json.loads((segment / SEGMENT_FILE).read_text())

    def _write_record(self, segment: Path, record: dict) -> None:
        (segment / SEGMENT_FILE).write_text(json.dumps(record, indent=2) + "\n")

    def new_segment(self, resume: ResumePoint | None) -> Path:
        """A fresh segment folder; records the segment and step it continues from."""
        self.path.mkdir(parents=True, exist_ok=True)
        settings_file = self.path / SETTINGS_FILE
        if not settings_file.is_file():
            settings_file.write_text(json.dumps(self.settings, indent=2) + "\n")
        existing = self.segments()
        number = 1 + (int(existing[-1].name.split("-")[1]) if existing else 0)
        segment = self.path / f"segment-{number:02d}"
        segment.mkdir()
        self._write_record(
            segment,
            {
                "parent": resume.segment.name if resume else None,
                "start_step": resume.step if resume else None,
                "resume_file": str(resume.restart_file) if resume else None,
                "started_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                "status": "running",
            },
        )
        return segment

    def finish_segment(self, segment: Path, status: str, wall_time: float) -> None:
        record = self.segment_record(segment)
        record.update(status=status, wall_time_s=wall_time)
        self._write_record(segment, record)

    def chain(self, last: Path) -> list[tuple[Path, int | None]]:
        """(segment, start step) from the first segment of the run to ``last``."""
        links = []
        segment: Path | None = last
        while segment is not None:
            record = self.segment_record(segment)
            links.append((segment, record["start_step"]))
            segment = self.path / record["parent"] if record["parent"] else None
        return links[::-1]

    # ------------------------------------------------------------------ resume
    def discard(self, reason: str) -> None:
        if self.path.exists():
            _say(f"{self.path}: {reason}; discarding the partial run and starting from strain 0")
            shutil.rmtree(self.path)

    def resume_point(self, probe: RestartProbe) -> ResumePoint | None:
        """The newest readable restart of earlier segments with the same settings, or None."""
        if not self.path.is_dir():
            return None
        settings_file = self.path / SETTINGS_FILE
        recorded = json.loads(settings_file.read_text()) if settings_file.is_file() else None
        if recorded != self.settings:
            changed = sorted(_changed_keys(recorded or {}, self.settings))
            self.discard(f"it was started with other settings (changed: {', '.join(changed) or 'all'})")
            return None
        candidates = [
            segment / name for segment in self.segments() for name in self.restart_names if (segment / name).is_file()
        ]
        candidates.sort(key=lambda path: path.stat().st_mtime_ns, reverse=True)
        for restart in candidates:
            try:
                step = probe(restart)
            except ValueError as err:
                _say(f"{restart} is unreadable ({err}); trying the previous restart file")
                continue
            first_step = self._first_step(restart.parent)
            if first_step is None or step <= first_step:
                _say(f"{restart} (step {step}) lies before the run's first output; skipped")
                continue
            _say(f"resuming from {restart} at step {step} (first step of the run {first_step})")
            return ResumePoint(restart.parent, restart, step, first_step)
        self.discard("no readable restart file" if candidates else "no restart file was written yet")
        return None

    def _first_step(self, segment: Path) -> int | None:
        """Step of the first stress-table row of the run (the first segment of the chain)."""
        if self.table_name is None:
            return None
        first_segment = self.chain(segment)[0][0]
        rows = iter_table_rows(first_segment / self.table_name)
        try:
            return next(rows)[0]
        except (StopIteration, FileNotFoundError):
            return None

    # ------------------------------------------------------------------ stitching
    def stitch_table(self, last: Path, name: str, first_step: int, stride: int, target: Path) -> None:
        """Stress table of the whole run: each segment's rows on the output grid, until the next took over."""
        with open(self.chain(last)[0][0] / name) as handle:
            header = handle.readline()
        with open(target, "w") as out:
            out.write(header)
            for _step, line in self._select(last, name, first_step, stride, iter_table_rows):
                out.write(line)

    def stitch_dump(self, last: Path, name: str, first_step: int, stride: int, target: Path) -> None:
        """Trajectory of the whole run, stitched like
        [`stitch_table`][suspension_fabric.simulation.lammps.rundir.PartialRun.stitch_table]."""
        with open(target, "w") as out:
            for _step, lines in self._select(last, name, first_step, stride, iter_frame_blocks):
                out.writelines(lines)

    def _select(
        self,
        last: Path,
        name: str,
        first_step: int,
        stride: int,
        reader: Callable[[Path], Iterator[tuple[int, object]]],
    ) -> Iterator[tuple[int, object]]:
        links = self.chain(last)
        for k, (segment, start) in enumerate(links):
            end = links[k + 1][1] if k + 1 < len(links) else None
            entries = reader(segment / name)
            while True:
                try:
                    step, item = next(entries)
                except StopIteration:
                    break
                except ValueError:
                    if end is None:
                        raise
                    break  # a killed segment's last, cut-off entry lies past its restart
                if end is not None and step > end:
                    break
                # the row at a restart step comes from the segment that wrote the restart: the
                # continuing one prints its set-up values there, before any step was taken
                if (start is None or step > start) and (step - first_step) % stride == 0:
                    yield step, item
                if end is not None and step == end:
                    break

    def concatenate_logs(self, last: Path, name: str, target: Path) -> None:
        links = self.chain(last)
        with open(target, "w") as out:
            for segment, start in links:
                source = segment / name
                if len(links) > 1:
                    out.write(f"# ---- {segment.name} (from step {start if start is not None else 'start'})\n")
                if source.is_file():
                    out.write(source.read_text())

    def segment_summary(self, last: Path) -> list[dict]:
        return [{"segment": segment.name, **self.segment_record(segment)} for segment, _ in self.chain(last)]

    def move_to_failed(self) -> Path:
        target = failed_dir(self.output_dir)
        if target.exists():
            shutil.rmtree(target)
        self.path.rename(target)
        return target


def _changed_keys(old: dict, new: dict, prefix: str = "") -> set[str]:
    keys = set()
    for key in set(old) | set(new):
        a, b = old.get(key), new.get(key)
        if isinstance(a, dict) and isinstance(b, dict):
            keys |= _changed_keys(a, b, f"{prefix}{key}.")
        elif a != b:
            keys.add(f"{prefix}{key}")
    return keys


def publish(output_dir: Path, fill: Callable[[Path], dict], overwrite: bool) -> dict:
    """Build a run directory in a temporary sibling with ``fill(dir) -> marker``, then move it into place.

    ``fill`` writes the outputs and returns the completion marker's content (it raises to
    abandon the run; the temporary folder is then removed and nothing at ``output_dir``
    changes). An existing ``output_dir`` is replaced only with ``overwrite``.
    """
    output_dir = Path(output_dir).resolve()
    if output_dir.exists() and not overwrite:
        raise FileExistsError(f"{output_dir} exists; pass overwrite=True to replace it")
    output_dir.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{output_dir.name}.publishing-", dir=output_dir.parent))
    try:
        marker = fill(staging)
        marker["finished_utc"] = time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())
        text = json.dumps(marker, indent=2, default=str) + "\n"
        (staging / COMPLETION_MARKER).write_text(text)
        (staging / KEPT_MARKER).write_text(text)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if output_dir.exists():  # overwrite: move the old one aside first, delete it after
        old = Path(tempfile.mkdtemp(prefix=f".{output_dir.name}.old-", dir=output_dir.parent))
        old.rmdir()
        output_dir.rename(old)
        staging.rename(output_dir)
        shutil.rmtree(old)
    else:
        staging.rename(output_dir)
    return marker
