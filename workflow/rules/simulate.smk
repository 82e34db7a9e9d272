rule pack:
    """Random non-overlapping bidisperse packing at phi for one seed (pack.lmp)."""
    output:
        **run_outputs(f"{RESULTS}/seed{{seed}}/packing", PACK_FILES),
    params:
        particles=setting("particles"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/pack_seed{{seed}}.log",
    script:
        "../scripts/pack.py"


rule startup:
    """Startup simple shear to run.startup_strain with trajectory, stress table and checkpoint."""
    input:
        data=rules.pack.output.data,
        plugin=PLUGIN_LIBRARY,
    output:
        **run_outputs(f"{RESULTS}/seed{{seed}}/startup"),
    params:
        kind="startup",
        settings=lambda wildcards: SIMULATION_SETTINGS[wildcards.study],
        strain=setting("run", "startup_strain"),
    threads: setting("run", "mpi_ranks")
    resources:
        mpi_ranks=setting("run", "mpi_ranks"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/startup_seed{{seed}}.log",
    script:
        "../scripts/shear.py"


rule rotate:
    """Shear rotation by theta from the seed's startup checkpoint, to run.rotation_strain."""
    input:
        checkpoint=rules.startup.output.checkpoint,
        marker=rules.startup.output.run_complete,
        plugin=PLUGIN_LIBRARY,
    output:
        **run_outputs(f"{RESULTS}/seed{{seed}}/rotation_theta{{angle}}"),
    params:
        kind="rotation",
        settings=lambda wildcards: SIMULATION_SETTINGS[wildcards.study],
        strain=setting("run", "rotation_strain"),
        theta_deg=angle_value,
    threads: setting("run", "mpi_ranks")
    resources:
        mpi_ranks=setting("run", "mpi_ranks"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/rotate_seed{{seed}}_theta{{angle}}.log",
    script:
        "../scripts/shear.py"
