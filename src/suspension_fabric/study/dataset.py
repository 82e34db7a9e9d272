"""Reference datasets: a finished study's analysed tables, committed so that its figures, fits
and tables can be rebuilt without simulating.

A dataset folder holds, per run of the study's run tree (``seed<k>/startup``,
``seed<k>/rotation_theta<a>`` and the runs of its own protocols, ``seed<k>/<run>``;
[`suspension_fabric.study.config.study_run_tree`][suspension_fabric.study.config.study_run_tree]):
``fabric.csv`` (the per-frame fabric table, [`suspension_fabric.analysis.tables`][suspension_fabric.analysis.tables]),
``stress.csv`` (the per-frame stress table, [`suspension_fabric.analysis.stress`][suspension_fabric.analysis.stress];
absent from datasets exported before the stress parts were recorded), ``stress.csv.gz``
(the run's stress table, [`suspension_fabric.io.stressio`][suspension_fabric.io.stressio], at 8 significant digits) and
``run.json`` (the run's completion marker: LAMMPS variables, command, wall time, results), and
at the top ``dataset.json``: the study's validated config, the software versions, the SHA-256
of the LAMMPS plugin sources and of every file, the git commit it was made from, and the fits
of the study it came from (fits.json's content,
[`suspension_fabric.models.fits_file`][suspension_fabric.models.fits_file]). Trajectories are never part of it. The
record carries a format version (`DATASET_FORMAT`); [`read_dataset`][suspension_fabric.study.dataset.read_dataset]
upgrades an older record in one step ([`upgrade_dataset`][suspension_fabric.study.dataset.upgrade_dataset]).

A study whose config names a dataset (``dataset: <folder>``) takes its fabric and stress tables
from it (rule ``import_run_table``, which checks each file's SHA-256) instead of simulating; its
config must describe the same simulations
([`check_config_matches`][suspension_fabric.study.dataset.check_config_matches]).

    python -m suspension_fabric.study.dataset export --config config/paper.yaml --to data/reference

Tables that gain columns (the fourth moment of the fabric) are brought into a dataset run by run,
as the study that remakes them finishes its runs
([`refresh_fabric_tables`][suspension_fabric.study.dataset.refresh_fabric_tables]): a run's new fabric table replaces
the recorded one only if its <nn>, Z, steps and strains are those recorded, so the dataset's fits and verdicts stand;
the record keeps the list of refreshes (from the shell: ``python -m suspension_fabric.study.dataset refresh --config
config/paper.yaml --to data/reference``).

From Python, [`load`][suspension_fabric.study.dataset.load] reads a dataset folder or a finished study's results folder
into pandas DataFrames with their provenance::

    from suspension_fabric.study.dataset import load
    reference = load("data/reference")
    reference.steady_fabric.set_index("quantity").loc["n12", "mean"]

A campaign config (suspension_fabric.study.campaign) exports one dataset per point, ``<to>/<point>``;
``campaign.datasets: <to>`` then rebuilds the map from them.
"""

from __future__ import annotations

import argparse
import dataclasses
import gzip
import hashlib
import importlib.metadata
import json
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np
import pandas as pd

from suspension_fabric.analysis.stress import read_stress_csv, recorded_value_columns
from suspension_fabric.analysis.tables import TABLE_COLUMNS, VALUE_COLUMNS, read_fabric_table, steady_state
from suspension_fabric.io.stressio import read_stress_table
from suspension_fabric.models.fits_file import read_fits, upgrade_fits
from suspension_fabric.simulation.lammps.plugin import plugin_sources

from .campaign import study_configs
from .config import SIMULATION_RUN_KEYS, angle_label, load_config, study_run_tree

__all__ = [
    "DATASET_FILE",
    "DATASET_FORMAT",
    "upgrade_dataset",
    "run_names",
    "paper_run_names",
    "export_dataset",
    "refresh_fabric_tables",
    "read_dataset",
    "check_config_matches",
    "check_table_values",
    "import_run_table",
    "has_run_tables",
    "read_dataset_stress",
    "read_fabric_runs",
    "read_stress_runs",
    "RUN_TABLES",
    "Loaded",
    "load",
]

DATASET_FILE = "dataset.json"
#: The analysed per-run tables a dataset carries (datasets exported before the stress parts were
#: recorded have no stress.csv; every export since carries both).
RUN_TABLES = ("fabric.csv", "stress.csv")
VERSIONED_PACKAGES = ("lammps", "MDAnalysis", "numpy", "scipy", "pandas", "snakemake")


def paper_run_names(config: dict) -> list[str]:
    """``seed<k>/startup`` and ``seed<k>/rotation_theta<a>`` for every seed and angle of a study."""
    names = []
    for seed in config["seeds"]:
        names.append(f"seed{seed}/startup")
        names += [f"seed{seed}/rotation_theta{angle_label(a)}" for a in config["angles_deg"]]
    return names


def run_names(config: dict) -> list[str]:
    """Every run of a study, ``seed<k>/<run>``: the paper's
    ([`paper_run_names`][suspension_fabric.study.dataset.paper_run_names]) and those of its own protocols (config key
    ``protocols``), each run once."""
    names = paper_run_names(config)
    paper = set(names)
    runs = study_run_tree({**config, "protocols": config.get("protocols") or {}})
    names += [f"seed{seed}/{run}" for seed in config["seeds"] for run in runs if f"seed{seed}/{run}" not in paper]
    return names


def _sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _plugin_hash() -> str:
    digest = hashlib.sha256()
    for source in plugin_sources():
        digest.update(source.name.encode() + b"\0" + source.read_bytes())
    return digest.hexdigest()


def _git_commit(where: Path) -> str | None:
    result = subprocess.run(["git", "rev-parse", "HEAD"], cwd=where, capture_output=True, text=True)
    return result.stdout.strip() if result.returncode == 0 else None


def _write_stress(table_file: Path, target: Path) -> None:
    table = read_stress_table(table_file)
    names = list(table)
    with gzip.open(target, "wt") as out:
        out.write(",".join(names) + "\n")
        rows = np.column_stack([table[name] for name in names])
        for row in rows:
            out.write(",".join(f"{value:.8g}" for value in row) + "\n")


def read_dataset_stress(path: Path) -> dict[str, np.ndarray]:
    """A dataset's ``stress.csv.gz`` as {column: array} (the columns of the run's stress table)."""
    with gzip.open(path, "rt") as handle:
        names = handle.readline().strip().split(",")
        data = np.loadtxt(handle, delimiter=",", ndmin=2)
    return {name: data[:, k] for k, name in enumerate(names)}


def export_dataset(
    config: dict, results: Path, target: Path, *, repository: Path | None = None, raw_stress: bool = True
) -> dict:
    """Copy the finished runs of a study (``results/<study>``) into the dataset folder ``target``.

    ``raw_stress=False`` leaves out each run's raw stress table (``stress.csv.gz``), which no
    rule reads (a study on the dataset uses the per-frame ``stress.csv``): for datasets kept
    only to be compared with (config key ``verdicts.comparisons``).

    Runs without their analysed tables yet (`RUN_TABLES`, made by the rules fabric_table
    and stress_table) are skipped and listed as missing, so a dataset can be exported while a study
    is still running and completed later, and a run is never exported without its stress table
    (a dataset lacking one run's stress table would drop the stress of every run). A run that
    ``target`` already holds and ``results`` lacks is kept (its files checked against their
    checksums), so a study grown by seeds or angles on another machine completes its dataset; a
    ``target`` whose runs were simulated with other settings is refused, naming the key. Returns
    the dataset record.
    """
    results, target = Path(results), Path(target)
    kept = _runs_to_keep(config, target)
    target.mkdir(parents=True, exist_ok=True)
    files, missing = {}, []
    for name in run_names(config):
        source = results / name
        if not all((source / table).is_file() for table in ("run_complete.json", *RUN_TABLES)):
            if name in kept:
                files.update(kept[name])
            else:
                missing.append(name)
            continue
        (target / name).mkdir(parents=True, exist_ok=True)
        shutil.copy(source / "run_complete.json", target / name / "run.json")
        copied = list(RUN_TABLES)
        for table in copied:
            shutil.copy(source / table, target / name / table)
        if raw_stress:
            _write_stress(source / "stress.txt", target / name / "stress.csv.gz")
            copied.append("stress.csv.gz")
        for file in (*copied, "run.json"):
            files[f"{name}/{file}"] = _sha256(target / name / file)
    fits_file = results / "fits.json"
    fits = read_fits(fits_file) if fits_file.is_file() and not missing else None
    if fits is not None and fits.get("provenance", {}).get("seeds", config["seeds"]) != config["seeds"]:
        fits = None  # fitted on other seeds than the dataset holds (runs kept from an earlier export)
    record = {
        "format": DATASET_FORMAT,
        "study": config["study"],
        "config": config,
        "runs_missing": missing,
        "files": files,
        "fits": fits,
        "versions": {name: importlib.metadata.version(name) for name in VERSIONED_PACKAGES},
        "plugin_sources_sha256": _plugin_hash(),
        "git_commit": _git_commit(repository or Path.cwd()),
        "exported_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    (target / DATASET_FILE).write_text(json.dumps(record, indent=1) + "\n")
    return record


def _runs_to_keep(config: dict, target: Path) -> dict[str, dict[str, str]]:
    """{run: {file key: checksum}} of the runs the dataset ``target`` already holds that are runs
    of ``config`` (none if there is no dataset yet); ``ValueError`` naming the key if its runs were
    simulated with other settings than ``config``'s (seeds and angles may differ)."""
    if not (target / DATASET_FILE).is_file():
        return {}
    record = read_dataset(target)
    here, there = _what_was_simulated(config), _what_was_simulated(record["config"])
    for name in set(here["protocols"]) & set(there["protocols"]):
        if here["protocols"][name] != there["protocols"][name]:
            raise ValueError(
                f"{target} holds runs of protocol '{name}' with other segments ({there['protocols'][name]!r}): "
                "export to another folder (nothing was overwritten)"
            )
    for key in here:
        if key not in ("seeds", "angles_deg", "protocols") and here[key] != there[key]:
            raise ValueError(
                f"{target} holds runs simulated with config key '{key}' = {there[key]!r}, not {here[key]!r}: "
                "export to another folder (nothing was overwritten)"
            )
    kept = {}
    for name in run_names(config):
        keys = [key for key in record["files"] if key.startswith(f"{name}/")]
        if keys:
            for key in keys:
                _checked_file(target, record, key)
            kept[name] = {key: record["files"][key] for key in keys}
    return kept


def refresh_fabric_tables(config: dict, results: Path, target: Path, *, repository: Path | None = None) -> list[str]:
    """Replace the fabric tables of the dataset ``target`` by those of the finished runs of its
    study in ``results`` whose recorded columns (TABLE_COLUMNS: <nn>, Z, steps, strains, ...) are
    exactly the dataset's, e.g. remade with the fourth moment; returns the runs replaced. A run whose
    columns differ is an error naming it (the dataset would no longer be the one its fits came from);
    runs without a new table are left as they are. Checksums are updated and the refresh recorded
    (``refreshes``: commit, time, the runs)."""
    record = read_dataset(target)
    check_config_matches(config, record, target)
    replaced = []
    for name in run_names(record["config"]):
        source = results / name / "fabric.csv"
        key = f"{name}/fabric.csv"
        if not source.is_file() or key not in record["files"] or _sha256(source) == record["files"][key]:
            continue  # not remade, or already this table
        new, old = read_fabric_table(source, moments=True), read_fabric_table(_checked_file(target, record, key))
        if not new[list(TABLE_COLUMNS)].equals(old):
            raise ValueError(f"{source}: its {', '.join(TABLE_COLUMNS)} differ from the dataset's {target / key}")
        shutil.copy(source, target / key)
        record["files"][key] = _sha256(target / key)
        replaced.append(name)
    if replaced:
        record.setdefault("refreshes", []).append(
            {
                "git_commit": _git_commit(repository or Path.cwd()),
                "refreshed_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
                "tables": "fabric.csv",
                "runs": replaced,
            }
        )
        (target / DATASET_FILE).write_text(json.dumps(record, indent=1) + "\n")
    return replaced


def read_dataset(folder: Path) -> dict:
    """The record of a dataset folder; errors name the folder."""
    path = Path(folder) / DATASET_FILE
    if not path.is_file():
        raise FileNotFoundError(
            f"dataset record not found: {path} (export one with `python -m suspension_fabric.study.dataset export`)"
        )
    try:
        record = json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise ValueError(f"{path}: not a readable dataset record ({type(err).__name__}: {err})") from None
    if not isinstance(record, dict) or not {"config", "files", "runs_missing"} <= set(record):
        raise ValueError(f"{path}: not a dataset record (expected config, files and runs_missing)")
    return upgrade_dataset(record, path)


#: The format [`export_dataset`][suspension_fabric.study.dataset.export_dataset] writes.
DATASET_FORMAT = 2
#: ``run`` keys added after format-1 datasets were exported, with the value those datasets were
#: made with (the contact springs taken explicitly by pair granular, the block-Jacobi solve).
KEYS_BEFORE_RECORDED = {"contact_springs": "explicit", "preconditioner": "jacobi"}
#: Keys of config sections added after datasets of the current format were exported, with the value
#: those datasets were made with (the contacts' states lagged, the only solve there was; no local
#: solves; rate-independent friction).
KEYS_ADDED_SINCE = {
    "run": {"contact_solve": "lagged", "local_solve_fraction": 0.0, "initial_guess": "previous"},
    "forces": {"critical_load_rate": None, "critical_load_stress": None},
}


def _with_added_keys(config: dict) -> dict:
    return {**config, **{section: {**keys, **config[section]} for section, keys in KEYS_ADDED_SINCE.items()}}


def upgrade_dataset(record: dict, source: str | Path = "dataset record") -> dict:
    """A dataset record in the current format (`DATASET_FORMAT`). Format 1 (no ``format`` key)
    lacked the ``run`` keys of `KEYS_BEFORE_RECORDED` where they did not exist yet, and held
    fits in fits format 1
    ([`suspension_fabric.models.fits_file.upgrade_fits`][suspension_fabric.models.fits_file.upgrade_fits]); records of
    either format lack the keys of `KEYS_ADDED_SINCE` if exported before they existed. A format
    this package does not know is an error naming ``source``."""
    version = record.get("format", 1)
    if version == DATASET_FORMAT:
        return {**record, "config": _with_added_keys(record["config"])}
    if version != 1:
        raise ValueError(f"{source}: dataset format {version!r} is not one this package reads (1 or {DATASET_FORMAT})")
    config = _with_added_keys({**record["config"], "run": {**KEYS_BEFORE_RECORDED, **record["config"]["run"]}})
    fits = record.get("fits")
    return {
        **record,
        "format": DATASET_FORMAT,
        "config": config,
        "fits": None if fits is None else upgrade_fits(fits, f"{source}: fits"),
    }


def _what_was_simulated(config: dict) -> dict:
    """The config keys that decide the runs and their fabric tables (config.SIMULATION_RUN_KEYS,
    each with its value, the strains, the particles, seeds, angles and eps); steady window and
    models may differ."""
    return {
        "seeds": config["seeds"],
        "angles_deg": config["angles_deg"],
        "particles": config["particles"],
        "forces": dict(config["forces"]),
        **{f"run.{key}": config["run"][key] for key in SIMULATION_RUN_KEYS},
        "run.startup_strain": config["run"]["startup_strain"],
        "run.rotation_strain": config["run"]["rotation_strain"],
        "analysis.eps": config["analysis"]["eps"],
        "protocols": config.get("protocols") or {},
    }


def check_config_matches(config: dict, record: dict, folder: Path) -> None:
    """A study built on a dataset must describe its simulations (`_what_was_simulated`;
    its protocols may be some of the dataset's) and every run it takes must be present (a dataset
    exported while its study ran may lack the runs of protocols this study leaves out). Errors
    name the key."""
    here, there = _what_was_simulated(config), _what_was_simulated(record["config"])
    # a study may take some of the dataset's protocols (each as it was simulated)
    for name, segments in here.pop("protocols").items():
        if there["protocols"].get(name) != segments:
            raise ValueError(
                f"config key 'protocols.{name}' differs from the dataset {folder} "
                f"({segments!r} here, {there['protocols'].get(name)!r} there)"
            )
    for key, value in here.items():
        if value != there[key]:
            raise ValueError(
                f"config key '{key}' differs from the dataset {folder} ({value!r} here, {there[key]!r} there)"
            )
    missing = [name for name in run_names(config) if name in set(record["runs_missing"])]
    if missing:
        raise ValueError(
            f"the dataset {folder} lacks {len(missing)} run(s) of this study, e.g. "
            f"{missing[0]}; export it again once the study has finished"
        )


def has_run_tables(record: dict, table: str, config: dict | None = None) -> bool:
    """Whether every run of a dataset record (of the study ``config`` built on it, if given) carries the
    analysed table ``table`` (e.g. stress.csv)."""
    runs = run_names(config or record["config"])
    return bool(runs) and all(f"{name}/{table}" in record["files"] for name in runs)


def import_run_table(folder: Path, name: str, table: str, target: Path, record: dict | None = None) -> Path:
    """Copy a run's analysed table (``fabric.csv`` or ``stress.csv``) out of a dataset after
    checking its recorded SHA-256 and that its values are those of the record's config
    ([`check_table_values`][suspension_fabric.study.dataset.check_table_values])."""
    if table not in RUN_TABLES:
        raise ValueError(f"unknown run table {table!r}; expected one of {RUN_TABLES}")
    record = read_dataset(folder) if record is None else record
    source = _checked_file(folder, record, f"{name}/{table}")
    check_table_values(source, record["config"], name)
    shutil.copy(source, target)
    return Path(target)


#: The columns of a run table that carry what its record says was simulated.
RECORDED_COLUMNS = ("seed", "N", "phi", "strain")


def check_table_values(path: Path, config: dict, name: str) -> None:
    """A dataset's run table ``seed<k>/<run>`` must carry the values its record says: the seed k, N,
    phi (to the packing's 1e-6) and strains from 0 to its segment's strain (one table stride);
    a record that disagrees with its tables is refused, naming the file and the value."""
    seed_text, run = name.split("/", 1)
    frame = pd.read_csv(path, usecols=list(RECORDED_COLUMNS))
    tree = study_run_tree({**config, "protocols": config.get("protocols") or {}})
    expected = {
        "seed": int(seed_text.removeprefix("seed")),
        "N": config["particles"]["n"],
        "phi": config["particles"]["phi"],
        "strain": tree[run].segment.strain if run in tree else None,
    }
    problems = []
    for column in ("seed", "N"):
        found = sorted(set(frame[column].astype(int)))
        if found != [expected[column]]:
            problems.append(f"{column} {found} (the record: {expected[column]})")
    if not np.allclose(frame["phi"], expected["phi"], rtol=1e-6, atol=0.0):
        problems.append(f"phi {frame['phi'].iloc[0]:.9g} (the record: {expected['phi']})")
    strains = frame["strain"].to_numpy(dtype=float)
    stride = config["run"]["dump_strain"] if path.name == "fabric.csv" else config["run"]["table_strain"]
    if expected["strain"] is not None and (
        abs(strains.min()) > 1e-9 or abs(strains.max() - expected["strain"]) > stride + 1e-9
    ):
        problems.append(
            f"strains {strains.min():g} to {strains.max():g} (the record's segment: {expected['strain']:g})"
        )
    if problems:
        raise ValueError(f"{path}: its values disagree with the dataset's record: {'; '.join(problems)}")


def _checked_file(folder: Path, record: dict, key: str) -> Path:
    """The dataset file ``key`` after checking its recorded SHA-256; errors name the file."""
    source = Path(folder) / key
    if key not in record["files"]:
        raise ValueError(f"the dataset {folder} has no {key}")
    if _sha256(source) != record["files"][key]:
        raise ValueError(f"{source} does not match the SHA-256 recorded in {Path(folder) / DATASET_FILE}")
    return source


def _concatenated_runs(folder: Path, record: dict, table: str, reader) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(startup runs, rotation runs): every run's ``table`` read with ``reader`` after checking its
    SHA-256, concatenated."""
    startup, rotation = [], []
    for name in paper_run_names(record["config"]):
        frame = reader(_checked_file(folder, record, f"{name}/{table}"))
        (startup if name.endswith("/startup") else rotation).append(frame)
    return pd.concat(startup, ignore_index=True), pd.concat(rotation, ignore_index=True)


def read_fabric_runs(folder: Path) -> tuple[dict, pd.DataFrame, pd.DataFrame]:
    """A dataset's record and its fabric tables, concatenated: (record, startup runs, rotation runs),
    every file's SHA-256 checked (the run tables of the workflow's ``aggregate_*`` rules)."""
    record = read_dataset(folder)
    missing = [name for name in paper_run_names(record["config"]) if name in set(record["runs_missing"])]
    if missing:
        raise ValueError(f"the dataset {folder} lacks {len(missing)} run(s), e.g. {missing[0]}")
    return (record, *_concatenated_runs(folder, record, "fabric.csv", read_fabric_table))


def read_stress_runs(folder: Path, record: dict | None = None) -> tuple[pd.DataFrame, pd.DataFrame] | None:
    """A dataset's per-frame stress tables, concatenated: (startup runs, rotation runs), every
    file's SHA-256 checked; None for a dataset exported before the stress parts were recorded.
    ``record``: the dataset's record if already read."""
    record = record or read_dataset(folder)
    if not has_run_tables(record, "stress.csv"):
        return None
    return _concatenated_runs(folder, record, "stress.csv", read_stress_csv)


@dataclasses.dataclass(frozen=True)
class Loaded:
    """A study's tables as DataFrames ([`load`][suspension_fabric.study.dataset.load]). ``fabric_startup``,
    ``fabric_rotation``: the per-frame fabric of every run
    ([`suspension_fabric.analysis.tables`][suspension_fabric.analysis.tables]); ``stress_startup``, ``stress_rotation``:
    the per-frame stress ([`suspension_fabric.analysis.stress`][suspension_fabric.analysis.stress]; None if the runs did
    not record it); ``steady_fabric``, ``steady_stress``: steady states over the config's ``analysis.steady_window``
    ([`suspension_fabric.analysis.tables.steady_state`][suspension_fabric.analysis.tables.steady_state]); ``fits``: the
    fits.json of the study (a dataset's: the one recorded when it was exported); ``verdicts``: tables/verdicts.csv of a
    results folder (None for a dataset, whose verdicts its study rebuilds); ``config``: a dataset's validated config
    (None for a results folder, which does not keep it; its steady states are the study's own tables); ``provenance``:
    where it came from (folder, kind; a dataset's git commit, software versions, plugin-source hash and export
    time; a study's fits provenance)."""

    fabric_startup: pd.DataFrame
    fabric_rotation: pd.DataFrame
    stress_startup: pd.DataFrame | None
    stress_rotation: pd.DataFrame | None
    steady_fabric: pd.DataFrame
    steady_stress: pd.DataFrame | None
    fits: dict | None
    verdicts: pd.DataFrame | None
    config: dict
    provenance: dict


def _steady(runs: pd.DataFrame, window, columns) -> pd.DataFrame:
    return steady_state(runs, *window, value_columns=columns)


def load(path: str | Path) -> Loaded:
    """A dataset folder (with ``dataset.json``: every file's SHA-256 checked) or a finished study's
    results folder (``results/<study>``, with ``tables/`` and ``fits.json``) as
    [`Loaded`][suspension_fabric.study.dataset.Loaded]. Anything else is an error naming the folder and what was
    expected."""
    folder = Path(path)
    if (folder / DATASET_FILE).is_file():
        record, fabric_startup, fabric_rotation = read_fabric_runs(folder)
        stress = read_stress_runs(folder, record)
        provenance = {
            "folder": str(folder),
            "kind": "dataset",
            "study": record["study"],
            **{key: record.get(key) for key in ("git_commit", "versions", "plugin_sources_sha256", "exported_utc")},
        }
        config, fits, verdicts = record["config"], record.get("fits"), None
    elif (folder / "tables" / "startup_runs.csv").is_file() and (folder / "fits.json").is_file():
        tables = folder / "tables"
        fits = read_fits(folder / "fits.json")
        stress = None
        if (tables / "stress_startup_runs.csv").is_file():
            stress = tuple(read_stress_csv(tables / f"stress_{kind}_runs.csv") for kind in ("startup", "rotation"))
        optional = {
            name: pd.read_csv(tables / name) if (tables / name).is_file() else None
            for name in ("verdicts.csv", "stress_steady_state.csv")
        }
        return Loaded(
            read_fabric_table(tables / "startup_runs.csv"),
            read_fabric_table(tables / "rotation_runs.csv"),
            *(stress or (None, None)),
            pd.read_csv(tables / "steady_state.csv"),
            optional["stress_steady_state.csv"],
            fits,
            optional["verdicts.csv"],
            None,
            {"folder": str(folder), "kind": "results", **fits.get("provenance", {})},
        )
    else:
        raise FileNotFoundError(
            f"{folder}: neither a dataset (no {DATASET_FILE}) nor a finished study's results "
            "folder (no tables/startup_runs.csv and fits.json)"
        )
    window = config["analysis"]["steady_window"]
    steady_stress = None
    if stress is not None:
        steady_stress = _steady(stress[0], window, recorded_value_columns(stress[0], str(folder)))
    return Loaded(
        fabric_startup,
        fabric_rotation,
        *(stress or (None, None)),
        _steady(fabric_startup, window, VALUE_COLUMNS),
        steady_stress,
        fits,
        verdicts,
        config,
        provenance,
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description="Export a finished study's tables as a dataset, or refresh them.")
    sub = parser.add_subparsers(dest="command", required=True)
    export = sub.add_parser("export", help="copy results/<study> tables into a dataset folder")
    export.add_argument("--config", type=Path, required=True, help="the study's config file")
    export.add_argument("--to", type=Path, required=True, help="the dataset folder")
    export.add_argument("--results", type=Path, help="default: results/<study>")
    export.add_argument(
        "--without-raw-stress",
        action="store_true",
        help="leave out each run's raw stress table (stress.csv.gz), which no rule reads",
    )
    refresh = sub.add_parser(
        "refresh", help="replace a dataset's fabric tables by those remade in results/<study> (same <nn>, more columns)"
    )
    refresh.add_argument("--config", type=Path, required=True, help="the study's config file")
    refresh.add_argument("--to", type=Path, required=True, help="the dataset folder")
    refresh.add_argument("--results", type=Path, help="default: results/<study>")
    args = parser.parse_args(argv)
    config = load_config(args.config)
    if args.command == "refresh":
        replaced = refresh_fabric_tables(config, args.results or Path("results") / config["study"], args.to)
        print(f"{args.to}: {len(replaced)} fabric tables refreshed")
        return
    if config["campaign"] and args.results:
        parser.error("--results applies to a single study; a campaign's points are read from results/<study>/<point>")
    # a campaign: one dataset per point, <to>/<point>
    targets = (
        {args.to / study["study"].split("/", 1)[1]: study for study in study_configs(config).values()}
        if config["campaign"]
        else {args.to: config}
    )
    for target, study in targets.items():
        results = args.results or Path("results") / study["study"]
        record = export_dataset(study, results, target, raw_stress=not args.without_raw_stress)
        done = sum(1 for key in record["files"] if key.endswith("/run.json"))
        missing = record["runs_missing"]
        print(
            f"{target}: {done} runs exported, {len(missing)} missing"
            + (f" (no run_complete.json, {' or '.join(RUN_TABLES)} yet, e.g. {missing[0]})" if missing else "")
        )


if __name__ == "__main__":
    main()
