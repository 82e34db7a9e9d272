"""fits.json: the steady fits of every model of the config, written and read in one format.

Format 2 (`FITS_FORMAT`) holds each model once, under ``models``::

    {"format": 2, "phi": ..., "steady_window": [a, b], "n_seeds": n, "fit_errors": "...",
     "targets": {"n11": {"mean": ..., "sem": ...}, ..., "Z": {...}},
     "models": {key: {"label": ..., "fitted_to": ["n12", ...],
                      "parameters": {name: value}, "errors": {name: jackknife error},
                      "errors_propagated": {name: error}, "correlations": {"beta,A": r},
                      "steady_state": {"n11": ..., ...}}},
     "provenance": {...}}

Format 1 (no ``format`` key) stored G-W and the modified model twice: at the top level
(``gw``, ``modified``, ``model_steady_state``) and, from the model plug-ins on, again under
``models`` without the propagated errors; before the jackknife (no ``fit_errors`` key) its
``<parameter>_err`` was the propagated error. [`upgrade_fits`][suspension_fabric.models.fits_file.upgrade_fits] is the
one step from 1 to 2; every reader goes through it ([`read_fits`][suspension_fabric.models.fits_file.read_fits], the
datasets' recorded fits).
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from .fabric_models import BUILT_IN

__all__ = ["FITS_FORMAT", "upgrade_fits", "write_fits", "read_fits"]

FITS_FORMAT = 2


def _format_1_models(fits: dict) -> dict:
    """The ``models`` section of a format-1 file: its own if it has one (every model), else the
    paper's two models from the top level; propagated errors and the beta-A correlation from the
    top level, where they exist."""
    models = {key: dict(entry) for key, entry in (fits.get("models") or {}).items()}
    jackknifed = "fit_errors" in fits  # before the jackknife, ``<name>_err`` was the propagated error
    for key in ("gw", "modified"):
        top = fits.get(key)
        if top is None:
            continue
        names = [name for name in BUILT_IN[key].names if name in top]
        entry = models.setdefault(
            key,
            {
                "label": BUILT_IN[key].label,
                "fitted_to": list(top.get("fitted_to", BUILT_IN[key].steady_targets)),
                "parameters": {name: top[name] for name in names},
                "errors": {name: top.get(f"{name}_err") if jackknifed else None for name in names},
                "steady_state": fits.get("model_steady_state", {}).get(key),
            },
        )
        suffix = "_err_propagated" if jackknifed else "_err"
        entry["errors_propagated"] = {name: top.get(f"{name}{suffix}") for name in names}
        if "beta_A_correlation" in top:
            entry["correlations"] = {"beta,A": top["beta_A_correlation"]}
    for entry in models.values():
        entry.setdefault("errors_propagated", dict.fromkeys(entry["parameters"]))
        entry.setdefault("correlations", {})
    return models


def upgrade_fits(fits: dict, source: str = "fits") -> dict:
    """``fits`` in the current format (`FITS_FORMAT`); a format-1 content is converted (see
    the module docstring), a format this package does not know is an error naming ``source``."""
    if not isinstance(fits, dict):
        raise ValueError(f"{source}: fits must be a JSON object, got {type(fits).__name__}")
    version = fits.get("format", 1)
    if version == FITS_FORMAT:
        return fits
    if version != 1:
        raise ValueError(f"{source}: fits format {version!r} is not one this package reads (1 or {FITS_FORMAT})")
    kept = {key: value for key, value in fits.items() if key not in ("gw", "modified", "model_steady_state", "models")}
    return {"format": FITS_FORMAT, **kept, "models": _format_1_models(fits)}


def write_fits(fits: dict, path: str | os.PathLike) -> Path:
    """Write fits as indented JSON (NaN errors become null)."""
    path = Path(path)
    text = json.dumps(fits, indent=2, sort_keys=False, allow_nan=True).replace("NaN", "null")
    path.write_text(text + "\n")
    return path


def read_fits(path: str | os.PathLike) -> dict:
    """A fits.json in the current format; errors name the file and the missing key."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"fits file not found: {path}")
    fits = upgrade_fits(json.loads(path.read_text()), str(path))
    for key in ("phi", "targets", "models"):
        if key not in fits:
            raise ValueError(f"{path}: missing key {key!r}")
    return fits
