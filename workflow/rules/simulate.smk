rule pack:
    """Random non-overlapping bidisperse packing at phi for one seed (pack.lmp)."""
    output:
        **run_outputs(f"{RESULTS}/seed{{seed}}/packing", PACK_FILES),
    params:
        particles=setting("particles"),
        code=code_version("../scripts/pack.py", ignore=SIMULATION_CHECKS),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/pack_seed{{seed}}.log",
    script:
        "../scripts/pack.py"


rule shear_segment:
    """One segment of a flow history for one seed: from the packing (the first segment) or from the
    checkpoint of the segment before, so that protocols sharing a prefix share its runs (segment.lmp)."""
    input:
        unpack(segment_source),
    output:
        **run_outputs(f"{RESULTS}/seed{{seed}}/{{run}}"),
    params:
        settings=lambda wildcards: SIMULATION_SETTINGS[wildcards.study],
        segment=segment_of,
        plugin=PLUGIN,
        code=code_version("../scripts/shear.py", ignore=SIMULATION_CHECKS),
    threads: setting("run", "mpi_ranks")
    resources:
        mpi_ranks=setting("run", "mpi_ranks"),
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/shear_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/shear.py"
