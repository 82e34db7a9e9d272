# Studies built on a reference dataset (config key `dataset`): the fabric and stress tables come
# from the dataset's files (their SHA-256 checked) instead of simulations; no LAMMPS job exists.
from suspension_fabric.study.dataset import check_config_matches, has_run_tables, read_dataset, run_names

for _name in DATASET_STUDIES:
    _study = STUDIES[_name]
    _record = read_dataset(_study["dataset"])
    check_config_matches(_study, _record, _study["dataset"])
    _tables = ["fabric", "stress"]
    if not has_run_tables(_record, "stress.csv", _study):
        STRESSLESS_STUDIES.append(_name)
        _tables = ["fabric"]
        print(f"Note: the dataset {_study['dataset']} has no per-run stress tables; the stress rules "
              f"are left out of study {_name}.")

    # One job per study (a few hundred file copies with a checksum each), in Snakemake's process.
    rule:
        name:
            "import_run_tables" if len(DATASET_STUDIES) == 1 else f"import_run_tables_{DATASET_STUDIES.index(_name)}"
        input:
            f"{_study['dataset']}/dataset.json",
        output:
            [f"results/{_name}/{run}/{table}.csv" for run in run_names(_study) for table in _tables],
        params:
            runs=[(run, f"{table}.csv") for run in run_names(_study) for table in _tables],
            code=code_version("../scripts/import_run_tables.py"),
        log:
            f"results/{_name}/logs/import_run_tables.log",
        localrule: True
        conda:
            CONDA_ENV
        script:
            "../scripts/import_run_tables.py"
