"""When suspension_fabric.simulation.lammps.plugin.build_plugin recompiles the plugin.

build_plugin decides from a stamp of what the library was compiled from: the library is stale
when it or its stamp is missing, when the stamp's compile-command fingerprint differs from the
current command (compiler, flags, the list of .cpp files, the header packages' versions), or
when the contents of a .cpp/.h in the source folder differ from those compiled; file times and
locations do not count (a library stamped before stamps held contents is judged by file times,
as it was built). The tests point the module at a copy of simulation/lammps/plugin_source in
tmp_path (module globals, restored by monkeypatch) and replace the compiler by a fake that
writes the concatenated .cpp sources to the ``-o`` path, so no real compile runs and the
project's own build/plugin is never touched.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import threading
import time
from pathlib import Path
from types import SimpleNamespace

import pytest

import suspension_fabric.simulation.lammps.plugin as plugin_module

OLD = time.time() - 1000.0  # mtimes set explicitly: no dependence on the clock resolution


class FakeCompiler:
    """Stands in for subprocess.run in the plugin module; records each compile command."""

    def __init__(self):
        self.commands = []
        self.during_compile = None  # optional callable run after reading the sources
        self.returncode = 0

    def __call__(self, command, **kwargs):
        self.commands.append(list(command))
        output = Path(command[command.index("-o") + 1])
        sources = [Path(arg) for arg in command if arg.endswith(".cpp")]
        text = "".join(source.read_text() for source in sources)
        if self.during_compile is not None:
            self.during_compile()
        if self.returncode == 0:
            output.write_text(text)
        return subprocess.CompletedProcess(command, self.returncode, stdout="", stderr="error: fake")


@pytest.fixture
def tree(tmp_path, monkeypatch):
    """Copy of simulation/lammps/plugin_source (all mtimes OLD) and an empty build dir, wired into the module."""
    source = tmp_path / "plugin"
    shutil.copytree(plugin_module.PLUGIN_SOURCE_DIR, source)
    for path in source.iterdir():
        os.utime(path, (OLD, OLD))
    build = tmp_path / "build"
    monkeypatch.setattr(plugin_module, "PLUGIN_SOURCE_DIR", source)
    monkeypatch.setattr(plugin_module, "PLUGIN_BUILD_DIR", build)
    monkeypatch.setattr(plugin_module, "PLUGIN_LIBRARY", build / "libsuspension_fabric_lammps.so")
    monkeypatch.setattr(plugin_module, "_COMMAND_STAMP", build / "libsuspension_fabric_lammps.cmd")
    compiler = FakeCompiler()
    monkeypatch.setattr(plugin_module, "subprocess", SimpleNamespace(run=compiler))
    monkeypatch.setattr(plugin_module.shutil, "which", lambda name: f"/usr/bin/{name}")
    return SimpleNamespace(
        source=source,
        build=build,
        library=plugin_module.PLUGIN_LIBRARY,
        stamp=plugin_module._COMMAND_STAMP,
        compiler=compiler,
    )


def build(tree):
    assert Path(plugin_module.PLUGIN_LIBRARY).is_relative_to(tree.build)  # never the real build
    return plugin_module.build_plugin()


def built_once(tree):
    """Build, then age the library so that later edits are unambiguously newer."""
    assert build(tree) == tree.library
    assert len(tree.compiler.commands) == 1
    os.utime(tree.library, (OLD + 10, OLD + 10))
    return tree


def test_first_call_compiles_every_cpp_and_later_calls_reuse_the_library(tree):
    """Missing library -> one compile of all .cpp files into the library path (atomic: no
    temporary file left); unchanged sources -> no further compile; force=True -> compile."""
    built_once(tree)
    command = tree.compiler.commands[0]
    assert sorted(arg for arg in command if arg.endswith(".cpp")) == sorted(str(p) for p in tree.source.glob("*.cpp"))
    assert tree.library.read_text().count("lammpsplugin_init") >= 1
    assert sorted(p.name for p in tree.build.iterdir()) == sorted([tree.library.name, tree.stamp.name])
    assert not plugin_module._is_stale()
    for _ in range(3):
        assert build(tree) == tree.library
    assert len(tree.compiler.commands) == 1
    plugin_module.build_plugin(force=True)
    assert len(tree.compiler.commands) == 2


def touch(path):
    os.utime(path, None)  # now: newer than the aged library


def edit(path, text="\n// edited\n"):
    path.write_text(path.read_text() + text)


def edit_header(tree):
    header = tree.source / "lubrication.h"
    header.write_text(header.read_text().replace("6.0 * pi_eta", "6.5 * pi_eta"))


def add_source(tree):
    extra = tree.source / "fix_extra_sf.cpp"
    extra.write_text("// new style\n")
    os.utime(extra, (OLD, OLD))  # an old file (e.g. copied with its time): the command changes


def remove_source(tree):
    (tree.source / "fix_stokes_sf.cpp").unlink()


CHANGES = {
    "edited .cpp": lambda tree: edit(tree.source / "pair_lubricate_sf.cpp"),
    "edited .h": edit_header,
    "added .cpp": add_source,
    "removed .cpp": remove_source,
    "new flags": lambda tree: setattr(plugin_module, "CXX_FLAGS", (*plugin_module.CXX_FLAGS, "-g")),
    "library deleted": lambda tree: tree.library.unlink(),
    "stamp deleted": lambda tree: tree.stamp.unlink(),
}


@pytest.mark.parametrize("change", CHANGES)
def test_change_of_an_input_triggers_one_rebuild(tree, monkeypatch, change):
    """A .cpp or .h with other contents, a different set of .cpp files, other compile flags,
    or a missing library or stamp make the library stale: the next call compiles once, and
    the call after that does not."""
    monkeypatch.setattr(plugin_module, "CXX_FLAGS", plugin_module.CXX_FLAGS)  # restored after "new flags"
    built_once(tree)
    CHANGES[change](tree)
    assert plugin_module._is_stale()
    build(tree)
    assert len(tree.compiler.commands) == 2
    assert not plugin_module._is_stale()
    build(tree)
    assert len(tree.compiler.commands) == 2


def test_file_times_and_locations_do_not_trigger_a_rebuild(tree, tmp_path, monkeypatch):
    """Sources touched (a fresh clone, a checkout of another branch and back) or the whole source
    folder moved elsewhere with new file times (a moved checkout) rebuild nothing; the library
    and any copy of it with its stamp pass the staleness check."""
    built_once(tree)
    copy = tmp_path / "elsewhere" / "lib.so"
    plugin_module.install_plugin(copy)
    os.utime(copy, (OLD, OLD))  # older than every source
    for path in tree.source.iterdir():
        touch(path)
    assert not plugin_module._is_stale()
    plugin_module.check_not_stale(tree.library)
    plugin_module.check_not_stale(copy)
    moved = tmp_path / "moved_plugin"
    shutil.copytree(tree.source, moved)  # new times, another path
    monkeypatch.setattr(plugin_module, "PLUGIN_SOURCE_DIR", moved)
    version = plugin_module.plugin_version()
    assert not plugin_module._is_stale()
    build(tree)
    assert len(tree.compiler.commands) == 1
    monkeypatch.setattr(plugin_module, "PLUGIN_SOURCE_DIR", tree.source)
    assert plugin_module.plugin_version() == version


def test_the_plugin_version_follows_the_sources_contents_and_flags(tree, monkeypatch):
    """The workflow segments' plugin param: changed by an edit of a source, an added source or other
    flags; not by file times or the README."""
    version = plugin_module.plugin_version()
    touch(tree.source / "fix_stokes_sf.cpp")
    edit(tree.source / "README.md")
    assert plugin_module.plugin_version() == version
    edit(tree.source / "fix_stokes_sf.cpp")
    edited = plugin_module.plugin_version()
    assert edited != version
    add_source(tree)
    added = plugin_module.plugin_version()
    assert added not in {version, edited}
    monkeypatch.setattr(plugin_module, "CXX_FLAGS", (*plugin_module.CXX_FLAGS, "-g"))
    assert plugin_module.plugin_version() not in {version, edited, added}


def test_a_library_stamped_by_file_times_is_judged_by_them(tree):
    """A library built before the stamp recorded contents ("<command hash> <newest source time>")
    stays valid while no source is newer than its compile, and is rebuilt (with a content stamp)
    once one is."""
    built_once(tree)
    tree.stamp.write_text(f"{plugin_module._legacy_command_fingerprint()} {int((OLD + 5) * 1e9)}\n")
    assert not plugin_module._is_stale()
    plugin_module.check_not_stale(tree.library)
    touch(tree.source / "imposed_flow.h")
    with pytest.raises(plugin_module.PluginBuildError, match="imposed_flow.h changed"):
        plugin_module.check_not_stale(tree.library)
    build(tree)
    assert len(tree.compiler.commands) == 2
    assert plugin_module._read_stamp(tree.stamp)["format"] == 2
    touch(tree.source / "imposed_flow.h")
    assert not plugin_module._is_stale()


def test_files_that_are_not_sources_do_not_trigger_a_rebuild(tree):
    """README.md and other non-.cpp/.h files in the source folder are not build inputs."""
    built_once(tree)
    edit(tree.source / "README.md")
    (tree.source / "notes.txt").write_text("scratch\n")
    assert not plugin_module._is_stale()
    build(tree)
    assert len(tree.compiler.commands) == 1


def test_source_saved_during_the_compile_makes_the_new_library_stale(tree):
    """A source edited while the compiler runs (after it read the sources, before the library
    is written) is not in the library, so the library must count as stale afterwards, although
    the library file is newer than the edit."""
    built_once(tree)
    edit(tree.source / "pair_lubricate_sf.cpp")
    cpp = tree.source / "fix_stokes_sf.cpp"

    def save_during_compile():
        cpp.write_text(cpp.read_text() + "\n// edited during the compile\n")

    tree.compiler.during_compile = save_during_compile
    build(tree)
    tree.compiler.during_compile = None
    assert "edited during the compile" not in tree.library.read_text()
    assert tree.library.stat().st_mtime_ns >= cpp.stat().st_mtime_ns
    assert plugin_module._is_stale()
    with pytest.raises(plugin_module.PluginBuildError, match="fix_stokes_sf.cpp changed"):
        plugin_module.check_not_stale(tree.library)
    build(tree)
    assert "edited during the compile" in tree.library.read_text()
    assert not plugin_module._is_stale()


def test_failed_compile_keeps_the_old_library_and_retries(tree):
    """A compile error raises PluginBuildError with the compiler's message, leaves the previous
    library and no temporary file, and the library stays stale, so the next call tries again."""
    built_once(tree)
    old_library = tree.library.read_text()
    edit(tree.source / "pair_lubricate_sf.cpp")
    tree.compiler.returncode = 1
    with pytest.raises(plugin_module.PluginBuildError, match="error: fake"):
        build(tree)
    assert tree.library.read_text() == old_library
    assert sorted(p.name for p in tree.build.iterdir()) == sorted([tree.library.name, tree.stamp.name])
    assert plugin_module._is_stale()
    tree.compiler.returncode = 0
    build(tree)
    assert len(tree.compiler.commands) == 3 and not plugin_module._is_stale()


def test_install_plugin_builds_only_if_needed_and_copies_atomically(tmp_path, tree):
    """install_plugin(target) builds if the library is missing or stale, never otherwise (unless
    forced), and provides it at target: an identical copy with the time of copying (not older
    than the library) and the library's stamp beside it, no temporary file left, copied again only
    if its stamp differs from the library's, judged stale once a source's contents change. At the
    library's own path it copies nothing; a deleted library is rebuilt."""
    target = tmp_path / "elsewhere" / "lib.so"
    assert plugin_module.install_plugin(target) == tree.library
    assert len(tree.compiler.commands) == 1
    assert target.read_bytes() == tree.library.read_bytes()
    assert target.stat().st_mtime_ns >= tree.library.stat().st_mtime_ns
    assert sorted(p.name for p in target.parent.iterdir()) == ["lib.cmd", "lib.so"]
    assert (target.parent / "lib.cmd").read_text() == tree.stamp.read_text()
    plugin_module.check_not_stale(target)
    os.utime(tree.library, (OLD + 10, OLD + 10))
    os.utime(target, (OLD + 10, OLD + 10))
    plugin_module.install_plugin(target)  # up to date: no compile, no copy, both keep their times
    assert len(tree.compiler.commands) == 1
    assert tree.library.stat().st_mtime == OLD + 10 and target.stat().st_mtime == OLD + 10
    (target.parent / "lib.cmd").unlink()  # a copy without its stamp is copied again
    plugin_module.install_plugin(target)
    assert len(tree.compiler.commands) == 1 and target.stat().st_mtime > OLD + 10
    edit(tree.source / "pair_lubricate_sf.cpp")
    with pytest.raises(plugin_module.PluginBuildError, match="stale.*pair_lubricate_sf.cpp changed"):
        plugin_module.check_not_stale(target)

    assert plugin_module.install_plugin(tree.library) == tree.library  # stale: rebuilt
    assert len(tree.compiler.commands) == 2
    tree.library.unlink()
    assert plugin_module.install_plugin(tree.library) == tree.library and tree.library.is_file()
    assert len(tree.compiler.commands) == 3
    plugin_module.install_plugin(tree.library, force=True)
    assert len(tree.compiler.commands) == 4
    assert sorted(p.name for p in tree.build.iterdir()) == sorted([tree.library.name, tree.stamp.name])


def test_builds_started_together_compile_once(tree):
    """Two simulations that find the library missing at the same moment (two local jobs, a
    cluster's first batch): one compiles under the build folder's lock, the other waits and
    takes that library."""
    tree.compiler.during_compile = lambda: time.sleep(0.5)
    results = []
    threads = [threading.Thread(target=lambda: results.append(build(tree))) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert results == [tree.library, tree.library]
    assert len(tree.compiler.commands) == 1
