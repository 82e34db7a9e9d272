"""The report's tables: formatting of values with errors, the tidy tables built from
fits.json, the steady-state table and the error summary, and the HTML pages."""

from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.models import model_vs_simulation
from suspension_fabric.reporting import report_tables as rt


@pytest.mark.parametrize(
    "value, error, expected",
    [
        (10.747451663115266, 0.1875276667852699, "10.75 ± 0.19"),
        (9.251708042499269, 0.08136325193278532, "9.252 ± 0.081"),
        (44.76290940195859, 0.3071851763809266, "44.76 ± 0.31"),
        (-0.10306273926003591, 0.0019438531795952384, "-0.1031 ± 0.0019"),
        (3.474763796909492, 0.010346327246160145, "3.475 ± 0.010"),
        (0.0996, 0.00996, "0.100 ± 0.010"),  # the error rounds up into a new digit
        (-0.0001, 0.02, "0.000 ± 0.020"),  # no "-0.000"
        (1234.5, 560.0, "1230 ± 560"),
        (1.234e-9, 5.6e-11, "(1.234 ± 0.056)e-9"),
        (9.25, float("nan"), "9.250 ± —"),
        (9.25, None, "9.250 ± —"),
        (float("nan"), 0.1, "—"),
    ],
)
def test_format_value_error(value, error, expected):
    assert rt.format_value_error(value, error) == expected


@pytest.mark.parametrize(
    "value, significant, expected",
    [
        (3.2373715425731784, 3, "3.24"),
        (0.06494715678410383, 3, "0.0649"),
        (19.597673660189685, 3, "19.6"),
        (0.9957891073525561, 3, "0.996"),
        (1.0, 3, "1.00"),
        (0.0, 4, "0"),
        (-0.0, 4, "0"),
        (2.5e-7, 2, "2.5e-07"),
        (None, 3, "—"),
    ],
)
def test_format_number(value, significant, expected):
    assert rt.format_number(value, significant) == expected


def test_component_labels():
    assert rt.component_label("n12") == "⟨nn⟩₁₂"
    assert rt.component_label("n33") == "⟨nn⟩₃₃"
    assert rt.component_label("Z") == "Z"


@pytest.fixture
def fits():
    """fits.json as :func:`model_vs_simulation.fit_steady_state` writes it (values of the default study;
    the propagated errors are those of the reference study)."""
    return {
        "phi": 0.45,
        "steady_window": [2.0, 5.0],
        "n_seeds": 3,
        "fit_errors": model_vs_simulation.FIT_ERRORS,
        "targets": {
            "n11": {"mean": 0.5465, "sem": 0.00193},
            "n12": {"mean": -0.10306, "sem": 0.00194},
            "Z": {"mean": 3.4748, "sem": 0.01035},
        },
        "gw": {"beta": 10.747, "beta_err": 0.18753, "beta_err_propagated": 0.0901, "fitted_to": ["n12"]},
        "modified": {
            "beta": 9.2517,
            "beta_err": None,
            "beta_err_propagated": 0.0392,
            "A": 44.763,
            "A_err": 0.30719,
            "A_err_propagated": 0.2255,
            "beta_A_correlation": 0.9756,
            "fitted_to": ["n11", "n12"],
        },
        "model_steady_state": {"gw": {"n11": 0.20831, "n12": -0.10306}, "modified": {"n11": 0.54653, "n12": -0.10306}},
        "provenance": {"study": "default", "seeds": [1, 2, 3], "N": 500},
    }


def test_fit_parameters_table(fits):
    """Both errors, named: the jackknife over seeds (fits.json <parameter>_err) and the propagated one."""
    table = rt.fit_parameters_table(fits)
    assert list(table.columns) == [
        "Model",
        "Parameter",
        "Value ± 1σ (jackknife over seeds)",
        "Value ± 1σ (propagated)",
        "Fitted to (steady state)",
    ]
    assert table.values.tolist() == [
        ["G-W (Eq. 1)", "β", "10.75 ± 0.19", "10.747 ± 0.090", "⟨nn⟩₁₂"],
        ["modified G-W (Eq. 2)", "β", "9.252 ± —", "9.252 ± 0.039", "⟨nn⟩₁₁, ⟨nn⟩₁₂"],  # null error in fits.json
        ["modified G-W (Eq. 2)", "A", "44.76 ± 0.31", "44.76 ± 0.23", "⟨nn⟩₁₁, ⟨nn⟩₁₂"],
    ]


def test_fit_parameters_table_of_a_fits_json_without_jackknife(fits):
    """A fits.json written before the jackknife (no fit_errors key): its <parameter>_err was the
    propagated error and is shown as such, the jackknife column is missing."""
    for key in ("gw", "modified"):
        for name in ("beta_err", "A_err"):
            if name in fits[key]:
                fits[key][name] = fits[key].pop(f"{name}_propagated")
        fits[key].pop("beta_A_correlation", None)
    del fits["fit_errors"]
    table = rt.fit_parameters_table(fits)
    assert table[rt.JACKKNIFE_COLUMN].tolist() == ["10.75 ± —", "9.252 ± —", "44.76 ± —"]
    assert table[rt.PROPAGATED_COLUMN].tolist() == ["10.747 ± 0.090", "9.252 ± 0.039", "44.76 ± 0.23"]


def test_fit_targets_table(fits):
    table = rt.fit_targets_table(fits).set_index("Quantity")
    assert table.loc["⟨nn⟩₁₁", "Simulation (mean ± s.e.)"] == "0.5465 ± 0.0019"
    assert table.loc["⟨nn⟩₁₁", "G-W (Eq. 1) steady state"] == "0.2083"
    assert table.loc["⟨nn⟩₁₁", "modified G-W (Eq. 2) steady state"] == "0.5465"
    assert table.loc["⟨nn⟩₁₁", "Fit target of"] == "modified G-W (Eq. 2)"
    assert table.loc["⟨nn⟩₁₂", "Fit target of"] == "G-W (Eq. 1), modified G-W (Eq. 2)"
    assert table.loc["Z", "Simulation (mean ± s.e.)"] == "3.475 ± 0.010"
    assert table.loc["Z", "G-W (Eq. 1) steady state"] == "—" and table.loc["Z", "Fit target of"] == "—"


def test_fit_settings(fits):
    settings = dict(rt.fit_settings(fits).values.tolist())
    assert settings == {
        "Volume fraction φ": "0.45",
        "Steady-state strain window": "2 ≤ γ ≤ 5",
        "Seeds (independent packings)": "3",
        "Particles N": "500",
        "Study": "default",
    }


def test_fits_round_trip_through_fits_json(tmp_path, fits):
    """The null error written by model_vs_simulation.write_fits is read back as a missing error."""
    fits["modified"]["beta_err"] = float("nan")
    path = model_vs_simulation.write_fits(fits, tmp_path / "fits.json")
    table = rt.fit_parameters_table(model_vs_simulation.read_fits(path))
    assert table[rt.JACKKNIFE_COLUMN].tolist() == ["10.75 ± 0.19", "9.252 ± —", "44.76 ± 0.31"]


def steady_rows(thetas=(0.0,)):
    rows = []
    for theta in thetas:
        for quantity, mean, sem in [
            ("n11", 0.5465273, 0.0019303),
            ("n12", -0.1030627, 0.0019439),
            ("Z", 3.4747638, 0.0103463),
        ]:
            rows.append(
                {
                    "theta": theta,
                    "quantity": quantity,
                    "mean": mean,
                    "sem": sem,
                    "sem_between_seeds": 0.00337,
                    "tau_strain": 0.1387,
                    "n_frames": 151,
                    "n_seeds": 3,
                    "strain_min": 2.0,
                    "strain_max": 5.0,
                }
            )
    return pd.DataFrame(rows)


def test_steady_state_table():
    table = rt.steady_state_table(steady_rows())
    assert list(table.columns) == [
        "Quantity",
        "Mean ± s.e.",
        "s.e. between seeds",
        "Autocorrelation strain",
        "Frames per seed",
        "Seeds",
    ]
    assert table.values.tolist() == [
        ["⟨nn⟩₁₁", "0.5465 ± 0.0019", "0.0034", "0.14", "151", "3"],
        ["⟨nn⟩₁₂", "-0.1031 ± 0.0019", "0.0034", "0.14", "151", "3"],
        ["Z", "3.475 ± 0.010", "0.0034", "0.14", "151", "3"],
    ]


def test_steady_state_table_keeps_the_angle_when_there_are_several():
    table = rt.steady_state_table(steady_rows((0.0, 90.0)))
    assert table["Angle θ (deg)"].tolist() == ["0"] * 3 + ["90"] * 3


def test_steady_state_table_without_between_seed_error():
    steady = steady_rows()
    steady["sem_between_seeds"] = np.nan  # a single seed
    assert set(rt.steady_state_table(steady)["s.e. between seeds"]) == {"—"}


def test_error_summary_table():
    summary = pd.DataFrame(
        {
            "protocol": ["startup", "rotation"],
            "component": ["n11", "Z"],
            "rms_gw": [3.2373715, 19.1134576],
            "rms_modified": [0.6368932, 7.4424335],
            "gw_over_modified": [5.0830684, 2.5681731],
        }
    )
    table = rt.error_summary_table(summary)
    assert list(table.columns) == [
        "Protocol",
        "Quantity",
        "rms error, G-W (Eq. 1)",
        "rms error, modified G-W (Eq. 2)",
        "Ratio G-W / modified",
    ]
    assert table.values.tolist() == [
        ["startup shear", "⟨nn⟩₁₁", "3.24", "0.637", "5.08"],
        ["shear rotation", "Z", "19.1", "7.44", "2.57"],
    ]


def test_error_summary_table_from_summarise_errors():
    """Columns as model_vs_simulation.summarise_errors produces them."""
    errors = pd.DataFrame(
        [
            {
                "protocol": "startup",
                "model": model,
                "theta": 0.0,
                "component": "n12",
                "rms_error": rms,
                "max_abs_error": rms,
                "n_strains": 5,
            }
            for model, rms in (("gw", 0.4), ("modified", 0.2))
        ]
    )
    table = rt.error_summary_table(model_vs_simulation.summarise_errors(errors))
    assert table.values.tolist() == [["startup shear", "⟨nn⟩₁₂", "0.400", "0.200", "2.00"]]


class _Tables(HTMLParser):
    """Captions and cell texts of an HTML page."""

    def __init__(self):
        super().__init__()
        self.captions, self.cells, self._target = [], [], None

    def handle_starttag(self, tag, attrs):
        self._target = {"caption": self.captions, "td": self.cells, "th": self.cells}.get(tag)
        if self._target is not None:
            self._target.append("")

    def handle_endtag(self, tag):
        self._target = None

    def handle_data(self, data):
        if self._target is not None:
            self._target[-1] += data


def parse(path):
    parser = _Tables()
    parser.feed(path.read_text(encoding="utf-8"))
    return parser


def test_write_html_tables_escapes_and_captions(tmp_path):
    frame = pd.DataFrame({"a <b>": ["x & y", "1.0 ± 0.1"]})
    path = rt.write_html_tables(tmp_path / "sub" / "t.html", "Title", [("First", frame), ("Second", frame, "a note")])
    text = path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and '<meta charset="utf-8">' in text
    assert "a &lt;b&gt;" in text and "x &amp; y" in text and '<p class="note">a note</p>' in text
    parsed = parse(path)
    assert parsed.captions == ["First", "Second"]
    assert parsed.cells == ["a <b>", "x & y", "1.0 ± 0.1"] * 2
    assert not list(path.parent.glob(".*.tmp"))


def test_report_pages(tmp_path, fits):
    fits_page = parse(rt.write_fits_page(fits, tmp_path / "fits.html"))
    assert fits_page.captions[0] == "Fitted model parameters"
    assert "10.75 ± 0.19" in fits_page.cells and "44.76 ± 0.31" in fits_page.cells
    assert "44.76 ± 0.23" in fits_page.cells  # the propagated error, in its own column
    assert {"Value ± 1σ (jackknife over seeds)", "Value ± 1σ (propagated)"} <= set(fits_page.cells)
    text = (tmp_path / "fits.html").read_text(encoding="utf-8")
    assert "Jackknife over seeds" in text and "Propagated: linear propagation" in text
    assert "leave-one-out fits: 0.976." in text
    steady_page = parse(rt.write_steady_state_page(steady_rows(), tmp_path / "steady.html"))
    assert steady_page.captions == ["Simulated steady state over the strain window 2 ≤ γ ≤ 5"]
    assert "-0.1031 ± 0.0019" in steady_page.cells
    summary = pd.DataFrame(
        {
            "protocol": ["startup"],
            "component": ["n12"],
            "rms_gw": [0.327],
            "rms_modified": [0.3284],
            "gw_over_modified": [0.327 / 0.3284],
        }
    )
    errors_page = parse(rt.write_error_summary_page(summary, tmp_path / "errors.html"))
    assert errors_page.captions[0].startswith("Angle-averaged rms error")
    assert ["startup shear", "⟨nn⟩₁₂", "0.327", "0.328", "0.996"] == errors_page.cells[-5:]
