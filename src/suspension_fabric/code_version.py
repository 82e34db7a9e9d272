"""Content hashes of the code a workflow script runs: every rule's ``code`` param.

Snakemake reruns a job whose params changed since it last ran. The ``code`` param of a rule is
[`code_version`][suspension_fabric.code_version.code_version] of its script: a hash of the script, of every module of
this package the script imports (directly or through other modules of the package, imports inside functions
included), and of the package data next to those modules (the files in their folders that are
not packages: the LAMMPS inputs in ``simulation/lammps/inputs``). So an edit of the code a rule
runs reruns that rule's jobs (and what depends on them), and nothing else.

Left out: the config's validation and a campaign's points (`CONFIG_MODULES`), whose
results reach every rule as its params (the settings it receives); the plugin's C++ sources,
which reach the simulations through the library built from them, an input of theirs (its own
version: ``simulation.lammps.plugin.plugin_version``); and any modules a rule names in ``ignore``
(the simulations leave out their post-run overlap check, workflow/rules/common.smk).

The hash depends on contents alone, never on paths or file times: a moved or re-cloned checkout,
or a regular install of the same code, has the same versions and reruns nothing. Python files
count by their syntax tree without docstrings (``ast.unparse``), so editing comments, docstrings
or the layout of the code reruns nothing, while any change of what runs does (a new Python version
may print some trees differently: a rerun, never a missed one). Data files count byte for byte,
except Markdown (notes for readers). Third-party packages (numpy, MDAnalysis, LAMMPS) and plug-in
modules a config names by module path are not covered.
"""

from __future__ import annotations

import ast
import hashlib
import importlib.util
import json
import os
import tempfile
from collections.abc import Iterable
from pathlib import Path

import suspension_fabric

__all__ = ["CONFIG_MODULES", "CodeVersions", "code_files", "code_version", "imported_modules"]

PACKAGE = "suspension_fabric"
# Reached from every script through workflow_io (job_study_config); what they compute, the settings,
# reaches each rule as its params already (and would bring in every model's code).
CONFIG_MODULES = ("suspension_fabric.study.config", "suspension_fabric.study.campaign")
# Not data of the modules: compiled files, the packaged copy of config/schema.yaml (its defaults
# reach the rules through their params), the plugin's sources (module docstring), notes for readers.
_SKIPPED_FOLDERS = {"__pycache__", "_data", "plugin_source"}
_SKIPPED_SUFFIXES = {".pyc", ".md"}


def _strip_docstrings(tree: ast.AST) -> None:
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            first = node.body[0] if node.body else None
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                if isinstance(first.value.value, str):
                    node.body = node.body[1:] or [ast.Pass()]


class CodeVersions:
    """The code versions of any number of scripts, each file read and parsed once (so make a new
    one to see later edits).

    ``root`` is the package's folder, by default the one Python imports (an editable install's
    source tree, or a copy first on PYTHONPATH): the code the workflow's jobs run. Modules named
    in ``ignore`` (and those under them) are left out of every version, `CONFIG_MODULES` by
    default.
    """

    def __init__(
        self,
        root: str | os.PathLike | None = None,
        ignore: Iterable[str] = CONFIG_MODULES,
        cache: str | os.PathLike | None = None,
    ):
        self.root = Path(root if root is not None else Path(suspension_fabric.__file__).parent)
        self.ignore = tuple(ignore)
        self._modules: dict[str, Path | None] = {}
        self._parsed: dict[Path, tuple[list[str], str]] = {}
        # parsing every module takes ~1 s per workflow load: the results are kept in a file, keyed
        # by each file's bytes and package, so only changed files are parsed again
        self._cache_path = None if cache is None else Path(cache)
        self._cache: dict[str, list] = {}
        self._used: dict[str, list] = {}  # what this load parsed or read: all the file keeps
        self._dirty = False
        if self._cache_path is not None and self._cache_path.is_file():
            try:
                self._cache = json.loads(self._cache_path.read_text())
            except (OSError, ValueError):
                self._cache = {}

    # --- modules
    def module_file(self, name: str) -> Path | None:
        """The file of a module of the package (``suspension_fabric.a.b``), or None."""
        if name not in self._modules:
            found = None
            if name == PACKAGE or name.startswith(PACKAGE + "."):
                base = self.root.joinpath(*name.split(".")[1:])
                found = next((c for c in (base / "__init__.py", base.with_suffix(".py")) if c.is_file()), None)
            self._modules[name] = found
        return self._modules[name]

    def module_name(self, path: Path) -> str:
        parts = path.relative_to(self.root).with_suffix("").parts
        return ".".join([PACKAGE, *(parts[:-1] if parts[-1] == "__init__" else parts)])

    def _parse(self, path: Path) -> tuple[list[str], str]:
        """(every name the file imports that may be a module: ``from a import b`` gives ``a`` and
        ``a.b``, relative imports resolved; the digest of its code without docstrings)."""
        if path not in self._parsed:
            source = path.read_bytes()
            package = None
            if path.is_relative_to(self.root):
                name = self.module_name(path)
                package = name if path.name == "__init__.py" else name.rpartition(".")[0]
            key = f"{package}:{hashlib.sha256(source).hexdigest()}"
            if key in self._cache:
                names, digest = self._cache[key]
                self._parsed[path] = list(names), digest
                self._used[key] = self._cache[key]
                return self._parsed[path]
            tree = ast.parse(source, str(path))
            names = []
            for node in ast.walk(tree):
                if isinstance(node, ast.Import):
                    names += [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom):
                    if node.level and package is None:
                        continue  # a relative import in a script: not this package's
                    base = node.module
                    if node.level:
                        base = importlib.util.resolve_name("." * node.level + (node.module or ""), package)
                    names += [base, *(f"{base}.{alias.name}" for alias in node.names)]
            _strip_docstrings(tree)
            self._parsed[path] = names, hashlib.sha256(ast.unparse(tree).encode()).hexdigest()
            self._cache[key] = self._used[key] = list(self._parsed[path])
            self._dirty = True
        return self._parsed[path]

    def _save_cache(self) -> None:
        """Write the entries this load used, atomically (several workflow loads may share the
        file), when it parsed something new; a cache that cannot be written only costs time."""
        if self._cache_path is None or not self._dirty:
            return
        self._dirty = False
        try:
            self._cache_path.parent.mkdir(parents=True, exist_ok=True)
            with tempfile.NamedTemporaryFile("w", dir=self._cache_path.parent, delete=False, suffix=".tmp") as out:
                json.dump(self._used, out)
            os.replace(out.name, self._cache_path)
        except OSError:
            pass

    def _ignored(self, name: str, ignore: tuple[str, ...]) -> bool:
        return any(name == i or name.startswith(i + ".") for i in ignore)

    def module_files(self, script: str | os.PathLike, ignore: Iterable[str] = ()) -> list[Path]:
        """The files of every module of the package the script imports, transitively, with the
        ``__init__.py`` of every package on the way (importing a module runs them); modules in
        ``ignore`` or the instance's ignore list are left out, and so is what only they import."""
        ignore = self.ignore + tuple(ignore)
        seen: set[Path] = set()
        todo = [Path(script)]
        while todo:
            for name in self._parse(todo.pop())[0]:
                parts = name.split(".")
                for k in range(1, len(parts) + 1):
                    prefix = ".".join(parts[:k])
                    if self._ignored(prefix, ignore):
                        break
                    found = self.module_file(prefix)
                    if found is not None and found not in seen:
                        seen.add(found)
                        todo.append(found)
        return sorted(seen)

    # --- data
    def data_files(self, modules: Iterable[Path]) -> list[Path]:
        """The files in the non-package folders below the modules' folders (package data)."""
        found = set()
        for folder in {module.parent for module in modules}:
            for sub in folder.iterdir():
                if sub.is_dir() and sub.name not in _SKIPPED_FOLDERS and not (sub / "__init__.py").exists():
                    found.update(self._folder_files(sub))
        return sorted(found)

    def _folder_files(self, folder: Path):
        for path in folder.rglob("*"):
            parts = path.relative_to(folder).parts
            skipped = set(parts) & _SKIPPED_FOLDERS or any(part.startswith(".") for part in parts)
            if path.is_file() and not skipped and path.suffix not in _SKIPPED_SUFFIXES:
                yield path

    # --- versions
    def files(self, script: str | os.PathLike, ignore: Iterable[str] = ()) -> dict[str, Path]:
        """{name: file} of everything the script's version covers: the script by its file name,
        the package's files by their path inside the package."""
        modules = self.module_files(script, ignore)
        package_files = {p.relative_to(self.root).as_posix(): p for p in [*modules, *self.data_files(modules)]}
        return {f"script:{Path(script).name}": Path(script), **package_files}

    def _digest(self, path: Path) -> str:
        if path.suffix == ".py":
            return self._parse(path)[1]
        return hashlib.sha256(path.read_bytes()).hexdigest()

    def version(self, script: str | os.PathLike, ignore: Iterable[str] = ()) -> str:
        """The script's code version: 16 hex digits of a SHA-256 over the names and contents of
        [`files`][suspension_fabric.code_version.CodeVersions.files]."""
        digest = hashlib.sha256()
        for name, path in sorted(self.files(script, ignore).items()):
            digest.update(f"{name}\0{self._digest(path)}\n".encode())
        self._save_cache()
        return digest.hexdigest()[:16]


def imported_modules(script: str | os.PathLike, ignore: Iterable[str] = (), root=None) -> list[str]:
    """The names of the package's modules the script imports, transitively (sorted)."""
    versions = CodeVersions(root)
    return sorted(versions.module_name(path) for path in versions.module_files(script, ignore))


def code_files(script: str | os.PathLike, ignore: Iterable[str] = (), root=None) -> dict[str, Path]:
    """{name: file} of everything [`code_version`][suspension_fabric.code_version.code_version] covers
    ([`CodeVersions.files`][suspension_fabric.code_version.CodeVersions.files])."""
    return CodeVersions(root).files(script, ignore)


def code_version(script: str | os.PathLike, ignore: Iterable[str] = (), root=None) -> str:
    """The code version of one script (module docstring); [`CodeVersions`][suspension_fabric.code_version.CodeVersions]
    for many."""
    return CodeVersions(root).version(script, ignore)
