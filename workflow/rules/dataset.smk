# A study built on a reference dataset (config key `dataset`): the fabric tables come from
# the dataset's files (their SHA-256 checked) instead of simulations; no LAMMPS job exists.
from suspension_fabric.dataset import check_config_matches, read_dataset

DATASET = config["dataset"]
check_config_matches(config, read_dataset(DATASET), DATASET)


rule import_fabric_table:
    """Fabric table of one run, from the reference dataset (instead of simulating it)."""
    input:
        table=f"{DATASET}/seed{{seed}}/{{run}}/fabric.csv",
        record=f"{DATASET}/dataset.json",
    output:
        f"{RESULTS}/seed{{seed}}/{{run}}/fabric.csv",
    wildcard_constraints:
        run=r"startup|rotation_theta[^/]+",
    params:
        run=lambda wildcards: f"seed{wildcards.seed}/{wildcards.run}",
    conda:
        CONDA_ENV
    log:
        f"{RESULTS}/logs/import_seed{{seed}}_{{run}}.log",
    script:
        "../scripts/import_fabric_table.py"
