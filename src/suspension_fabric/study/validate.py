"""``python -m suspension_fabric.study.validate FILE...``: validate a study as the workflow does, without running it.

The files are layered in order, as ``--configfile FILE...`` layers them, read strictly and validated
([`suspension_fabric.study.config`][suspension_fabric.study.config]), and a campaign's points are validated too
([`suspension_fabric.study.campaign`][suspension_fabric.study.campaign]); what is wrong is named with its file, line
and key. Snakemake's own message for a ``--configfile`` it cannot parse names neither.
"""

from __future__ import annotations

import sys

from .campaign import study_configs
from .config import ConfigError, load_layered_config, read_config_sources

__all__ = ["main"]


def main(argv: list[str] | None = None) -> int:
    """Validate the studies of the config files ``argv`` (default: the command line); 0 if valid
    (printing their names), 1 naming what is wrong, 2 without files."""
    paths = sys.argv[1:] if argv is None else argv
    if not paths:
        print("usage: python -m suspension_fabric.study.validate CONFIG.yaml [MORE.yaml...]", file=sys.stderr)
        return 2
    try:
        studies = study_configs(load_layered_config(paths), read_config_sources(paths))
    except ConfigError as err:
        print(err, file=sys.stderr)
        return 1
    print(f"{' + '.join(paths)}: valid ({', '.join(studies)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
