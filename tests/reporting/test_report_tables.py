"""The report's tables: formatting of values with errors, the tidy tables built from
fits.json, the steady-state table and the error summary, and the HTML pages."""

import re
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest

from suspension_fabric.evaluation import model_vs_simulation
from suspension_fabric.models.fits_file import read_fits, upgrade_fits, write_fits
from suspension_fabric.reporting import fits_page, html_tables, model_errors_page, steady_state_page, verdicts_page

REPO = Path(__file__).resolve().parents[2]
#: Model labels by key, as fits.json records them
LABELS = {"gw": "G-W (Eq. 1)", "modified": "modified G-W (Eq. 2)"}


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
    assert html_tables.format_value_error(value, error) == expected


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
    assert html_tables.format_number(value, significant) == expected


def test_component_labels():
    assert html_tables.component_label("n12") == "⟨nn⟩₁₂"
    assert html_tables.component_label("n33") == "⟨nn⟩₃₃"
    assert html_tables.component_label("Z") == "Z"


@pytest.fixture
def fits():
    """fits.json as :func:`model_vs_simulation.fit_steady_state` writes it (format 2; values of the
    default study, the propagated errors those of the reference study)."""
    return {
        "format": 2,
        "phi": 0.45,
        "steady_window": [2.0, 5.0],
        "n_seeds": 3,
        "fit_errors": model_vs_simulation.FIT_ERRORS,
        "targets": {
            "n11": {"mean": 0.5465, "sem": 0.00193},
            "n12": {"mean": -0.10306, "sem": 0.00194},
            "Z": {"mean": 3.4748, "sem": 0.01035},
        },
        "models": {
            "gw": {
                "label": "G-W (Eq. 1)",
                "fitted_to": ["n12"],
                "parameters": {"beta": 10.747},
                "errors": {"beta": 0.18753},
                "errors_propagated": {"beta": 0.0901},
                "correlations": {},
                "steady_state": {"n11": 0.20831, "n12": -0.10306},
            },
            "modified": {
                "label": "modified G-W (Eq. 2)",
                "fitted_to": ["n11", "n12"],
                "parameters": {"beta": 9.2517, "A": 44.763},
                "errors": {"beta": None, "A": 0.30719},
                "errors_propagated": {"beta": 0.0392, "A": 0.2255},
                "correlations": {"beta,A": 0.9756},
                "steady_state": {"n11": 0.54653, "n12": -0.10306},
            },
        },
        "provenance": {"study": "default", "seeds": [1, 2, 3], "N": 500},
    }


def format_1(fits: dict, jackknifed: bool = True) -> dict:
    """The same fits as a format-1 fits.json wrote them (the paper's two models at the top level),
    or, without ``jackknifed``, as one written before the jackknife (no fit_errors; ``*_err`` the
    propagated error)."""
    old = {key: value for key, value in fits.items() if key not in ("format", "models")}
    for key, entry in fits["models"].items():
        old[key] = {"fitted_to": entry["fitted_to"]}
        for name, value in entry["parameters"].items():
            old[key][name] = value
            if jackknifed:
                old[key][f"{name}_err"] = entry["errors"][name]
                old[key][f"{name}_err_propagated"] = entry["errors_propagated"][name]
            else:
                old[key][f"{name}_err"] = entry["errors_propagated"][name]
        if jackknifed and entry["correlations"]:
            old[key]["beta_A_correlation"] = entry["correlations"]["beta,A"]
    old["model_steady_state"] = {key: entry["steady_state"] for key, entry in fits["models"].items()}
    if not jackknifed:
        del old["fit_errors"]
    return old


EXPECTED_PARAMETERS = [
    ["G-W (Eq. 1)", "β", "10.75 ± 0.19", "10.747 ± 0.090", "⟨nn⟩₁₂"],
    ["modified G-W (Eq. 2)", "β", "9.252 ± —", "9.252 ± 0.039", "⟨nn⟩₁₁, ⟨nn⟩₁₂"],  # null error in fits.json
    ["modified G-W (Eq. 2)", "A", "44.76 ± 0.31", "44.76 ± 0.23", "⟨nn⟩₁₁, ⟨nn⟩₁₂"],
]


def test_fit_parameters_table(fits):
    """Every model once, both errors named: the jackknife over seeds and the propagated one."""
    table = fits_page.fit_parameters_table(fits)
    assert list(table.columns) == [
        "Model",
        "Parameter",
        "Value ± 1σ (jackknife over seeds)",
        "Value ± 1σ (propagated)",
        "Fitted to (steady state)",
    ]
    assert table.values.tolist() == EXPECTED_PARAMETERS


def test_a_format_1_fits_json_reads_as_format_2(fits):
    """upgrade_fits, the one step from format 1: the paper's two models from the top level, with
    their errors, correlation and steady states, and the same table."""
    upgraded = upgrade_fits(format_1(fits))
    assert upgraded == fits
    assert fits_page.fit_parameters_table(upgraded).values.tolist() == EXPECTED_PARAMETERS


def test_fit_parameters_table_of_a_fits_json_without_jackknife(fits):
    """A format-1 fits.json written before the jackknife (no fit_errors key): its <parameter>_err was
    the propagated error and is shown as such, the jackknife column is missing."""
    table = fits_page.fit_parameters_table(upgrade_fits(format_1(fits, jackknifed=False)))
    assert table[fits_page.JACKKNIFE_COLUMN].tolist() == ["10.75 ± —", "9.252 ± —", "44.76 ± —"]
    assert table[fits_page.PROPAGATED_COLUMN].tolist() == ["10.747 ± 0.090", "9.252 ± 0.039", "44.76 ± 0.23"]


def test_fit_targets_table(fits):
    table = fits_page.fit_targets_table(fits).set_index("Quantity")
    assert table.loc["⟨nn⟩₁₁", "Simulation (mean ± s.e.)"] == "0.5465 ± 0.0019"
    assert table.loc["⟨nn⟩₁₁", "G-W (Eq. 1) steady state"] == "0.2083"
    assert table.loc["⟨nn⟩₁₁", "modified G-W (Eq. 2) steady state"] == "0.5465"
    assert table.loc["⟨nn⟩₁₁", "Fit target of"] == "modified G-W (Eq. 2)"
    assert table.loc["⟨nn⟩₁₂", "Fit target of"] == "G-W (Eq. 1), modified G-W (Eq. 2)"
    assert table.loc["Z", "Simulation (mean ± s.e.)"] == "3.475 ± 0.010"
    assert table.loc["Z", "G-W (Eq. 1) steady state"] == "—" and table.loc["Z", "Fit target of"] == "—"


def test_fit_settings(fits):
    settings = dict(fits_page.fit_settings(fits).values.tolist())
    assert settings == {
        "Volume fraction φ": "0.45",
        "Steady-state strain window": "2 ≤ γ ≤ 5",
        "Seeds (independent packings)": "3",
        "Particles N": "500",
        "Study": "default",
    }


def test_fits_round_trip_through_fits_json(tmp_path, fits):
    """The null error written by write_fits is read back as a missing error."""
    fits["models"]["modified"]["errors"]["beta"] = float("nan")
    path = write_fits(fits, tmp_path / "fits.json")
    table = fits_page.fit_parameters_table(read_fits(path))
    assert table[fits_page.JACKKNIFE_COLUMN].tolist() == ["10.75 ± 0.19", "9.252 ± —", "44.76 ± 0.31"]


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
    table = steady_state_page.steady_state_table(steady_rows())
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
    table = steady_state_page.steady_state_table(steady_rows((0.0, 90.0)))
    assert table["Angle θ (deg)"].tolist() == ["0"] * 3 + ["90"] * 3


def test_steady_state_table_without_between_seed_error():
    steady = steady_rows()
    steady["sem_between_seeds"] = np.nan  # a single seed
    assert set(steady_state_page.steady_state_table(steady)["s.e. between seeds"]) == {"—"}


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
    table = model_errors_page.error_summary_table(summary, LABELS)
    assert list(table.columns) == [
        "Protocol",
        "Quantity",
        "rms error, G-W (Eq. 1)",
        "rms error, modified G-W (Eq. 2)",
        "Ratio G-W (Eq. 1) / modified G-W (Eq. 2)",
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
    table = model_errors_page.error_summary_table(
        model_vs_simulation.summarise_errors(errors, ("gw", "modified")), LABELS
    )
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
    path = html_tables.write_html_tables(
        tmp_path / "sub" / "t.html", "Title", [("First", frame), ("Second", frame, "a note")]
    )
    text = path.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and '<meta charset="utf-8">' in text
    assert "a &lt;b&gt;" in text and "x &amp; y" in text and '<p class="note">a note</p>' in text
    parsed = parse(path)
    assert parsed.captions == ["First", "Second"]
    assert parsed.cells == ["a <b>", "x & y", "1.0 ± 0.1"] * 2
    assert not list(path.parent.glob(".*.tmp"))


def test_report_pages(tmp_path, fits):
    page = parse(fits_page.write_fits_page(fits, tmp_path / "fits.html"))
    assert page.captions[0] == "Every model of models.fabric fitted to the steady state"
    assert "10.75 ± 0.19" in page.cells and "44.76 ± 0.31" in page.cells
    assert "44.76 ± 0.23" in page.cells  # the propagated error, in its own column
    assert {"Value ± 1σ (jackknife over seeds)", "Value ± 1σ (propagated)"} <= set(page.cells)
    text = (tmp_path / "fits.html").read_text(encoding="utf-8")
    assert "Jackknife over seeds" in text and "Propagated: linear propagation" in text
    assert "leave-one-out fits: modified G-W (Eq. 2) beta and A: 0.976." in text
    steady = parse(steady_state_page.write_steady_state_page(steady_rows(), tmp_path / "steady.html"))
    assert steady.captions == ["Simulated steady state over the strain window 2 ≤ γ ≤ 5"]
    assert "-0.1031 ± 0.0019" in steady.cells
    summary = pd.DataFrame(
        {
            "protocol": ["startup"],
            "component": ["n12"],
            "rms_gw": [0.327],
            "rms_modified": [0.3284],
            "gw_over_modified": [0.327 / 0.3284],
        }
    )
    errors_page = parse(model_errors_page.write_error_summary_page(summary, LABELS, tmp_path / "errors.html"))
    assert errors_page.captions[0].startswith("Angle-averaged rms error")
    assert ["startup shear", "⟨nn⟩₁₂", "0.327", "0.328", "0.996"] == errors_page.cells[-5:]


# --- The report reads cleanly at 1400 px: angles one way, no Python reprs, the verdict in view ------

#: A Python list as Python prints it: quoted strings, or three numbers or more ("[0, 15, 30]",
#: "[0.0, 15.0]" of floats); an interval "value [low, high]" is two numbers and is no list.
_LIST_REPR = re.compile(r"\[(?:'[^']*'|\"[^\"]*\")|\[-?\d+\.0(?:, |\])|\[-?[\d.]+(?:, -?[\d.]+){2,}\]")
#: An angle as the report prints it: whole degrees without decimals, others as they are.
_ANGLE = re.compile(r"-?\d+(?:\.\d*[1-9])?")
#: A 1400 px window: the report's frame, at the page's 14 px font, less the body's margins (em).
WINDOW_EM = 1400 / 14 - 3


class _Rows(HTMLParser):
    """Each table of a page as (header, rows, wrapped: per column, whether its cells wrap)."""

    def __init__(self):
        super().__init__()
        self.tables, self._cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append({"header": [], "rows": [], "wrapped": []})
        elif tag == "tr" and self.tables:
            self.tables[-1]["rows"].append([])
        elif tag in ("td", "th") and self.tables:
            self._cell = [tag, dict(attrs).get("class") == "text", ""]

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            kind, wrapped, text = self._cell
            table = self.tables[-1]
            if kind == "th":
                table["header"].append(text)
            else:
                table["rows"][-1].append(text)
                if len([row for row in table["rows"] if row]) == 1:  # the first row: the columns' classes
                    table["wrapped"].append(wrapped)
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[2] += data


def _tables(path):
    parser = _Rows()
    parser.feed(path.read_text(encoding="utf-8"))
    for table in parser.tables:
        table["rows"] = [row for row in table["rows"] if row]
    return parser.tables


def _narrowest_widths(table) -> list[float]:
    """Each column's narrowest width in em, as a browser's table layout may shrink it to fit the
    window: a wrapping column (class text) to its min-width (10em) or its longest word, another to
    its longest cell (about 0.6 em a character; a heading wraps at its longest word), plus the
    padding (1.8em). A table whose narrowest widths fit shows every column."""
    widths = []
    for k, heading in enumerate(table["header"]):
        cells = [row[k] for row in table["rows"]]
        words = [len(word) for text in [*cells, heading] for word in text.split()] + [0]
        if table["wrapped"][k]:
            content = max(10.0, 0.6 * max(words))
        else:
            content = 0.6 * max([len(cell) for cell in cells] + words)
        widths.append(content + 1.8)
    return widths


@pytest.mark.parametrize(
    "degrees, expected",
    [
        (0, "0"),
        (0.0, "0"),
        (-0.0, "0"),
        (15.0, "15"),
        (105.0, "105"),
        (15, "15"),
        ("15", "15"),
        ("105.0", "105"),
        (22.5, "22.5"),
        (7.25, "7.25"),
        (15.000000000000002, "15"),
        (-45.0, "-45"),
        (float("nan"), "—"),
        (None, "—"),
    ],
)
def test_format_angle(degrees, expected):
    assert html_tables.format_angle(degrees) == expected


def test_format_angles_and_lists():
    assert html_tables.format_angles([0.0, 15.0, 22.5, 105.0]) == "0, 15, 22.5, 105"
    assert html_tables.format_angles("45.0, 90.0, 135.0") == "45, 90, 135"
    assert html_tables.format_angles("[0, 15]") == "0, 15"
    assert html_tables.format_angles(float("nan")) == "" and html_tables.format_angles("") == ""
    assert html_tables.format_list(["gw", "modified"]) == "gw, modified"


def _claims():
    """The tables of rule verdicts, as verdicts.csv and its companions store them (angles as
    text, a steady-state claim with no angles and no verdict)."""
    verdicts = pd.DataFrame(
        {
            "claim": ["S1", "C1", "C3'"],
            "text": [
                "G-W (Eq. 1) fitted on <nn>_12 (paper beta ~ 10.9)",
                "G-W (Eq. 1) overestimates the effect of a rotation on <nn>_12 for pi/4 <~ |theta| <~ 3pi/4",
                "modified G-W (Eq. 2) significantly better than G-W (Eq. 1) on <nn>'_12 over all angles",
            ],
            "statistic": ["G-W (Eq. 1) beta", "D12(ref) - 1.25 D12(sim)", "0.8 (MSE12 ref - s2) - (MSE12 chal - s2)"],
            "angles": [np.nan, "45.0, 90.0, 135.0", "0, 15, 30, 45, 60, 75, 90, 105, 120, 135, 150, 165, 180"],
            "mean": [10.897882, 0.204412, -0.018],
            "low": [10.698137, 0.150833, -0.025],
            "high": [11.097627, 0.25799, -0.010],
            "level": [np.nan, 0.95, 0.95],
            "verdict": [np.nan, "confirmed", "undecided"],
            "seeds_needed": [np.nan, np.nan, 314.0],
            "criterion": [
                "fitted value +- 2 jackknife errors over seeds; paper 10.9",
                "confirmed if the t-interval over seeds lies above 0, refuted if below",
                "confirmed if the t-interval over seeds lies above 0, refuted if below",
            ],
        }
    )
    thetas = [0.0, 15.0, 45.0, 105.0, 22.5]
    per_angle = pd.DataFrame(
        {
            "claim": "C1",
            "theta": thetas,
            "mean": 0.1,
            "low": 0.05,
            "high": 0.15,
            "verdict": "confirmed",
            "quantity": "D12",
            "sim": 0.01,
            "reference": 0.02,
            "challenger": 0.03,
        }
    )
    edges = pd.DataFrame(
        {
            "claim": ["C1", "C1"],
            "edges": ["as stated", "low edge out"],
            "angles": ["45.0, 90.0, 135.0", "0.0, 45.0, 90.0, 135.0"],
            "mean": [0.2, 0.15],
            "low": [0.15, 0.09],
            "high": [0.26, 0.21],
            "verdict": ["confirmed", "confirmed"],
        }
    )
    choices = pd.DataFrame(
        {
            "choice": ["primary", "primary", "window 1", "window 1"],
            "claim": ["C1", "C3'", "C1", "C3'"],
            "mean": [0.2, -0.018, 0.19, -0.003],
            "low": [0.15, -0.025, 0.15, -0.023],
            "high": [0.26, -0.010, 0.23, 0.017],
            "verdict": ["confirmed", "refuted", "confirmed", "undecided"],
            "seeds_needed": [np.nan, np.nan, np.nan, 314.0],
            "robust": ["confirmed (primary)", "refuted (primary); differs under: window 1"] * 2,
            "level": 0.95,
        }
    )
    recovery = pd.DataFrame({"theta": thetas})
    for key in ("sim_steady", "sim_continuation", "sim_n23"):
        recovery[key], recovery[f"{key}_low"], recovery[f"{key}_high"] = 0.4, 0.1, 0.6
    for role in ("reference", "challenger"):
        recovery[f"{role}_steady"], recovery[f"{role}_n23"] = 0.3, 0.2
    return verdicts, per_angle, edges, choices, recovery


def test_verdicts_page_reads_at_1400_px(tmp_path):
    """The verdict table: the verdict next to the claim and in view in a 1400 px window (the
    claim's text wraps in its cell), angles printed one way, no Python list or NaN printed."""
    labels = {"reference": "G-W (Eq. 1)", "challenger": "modified G-W (Eq. 2)"}
    path = verdicts_page.write_verdicts_page(*_claims(), labels, tmp_path / "verdicts.html")
    tables = _tables(path)
    verdicts = tables[0]
    assert verdicts["header"][:3] == ["", "claim of the paper", "verdict"]
    assert [row[2] for row in verdicts["rows"]] == ["(parameter)", "confirmed", "undecided"]
    widths = _narrowest_widths(verdicts)
    assert sum(widths) < WINDOW_EM, widths  # the whole table fits in the window, the verdict with it
    assert sum(widths[:3]) < WINDOW_EM / 3, widths  # the verdict in its left third
    assert verdicts["wrapped"][1] and not verdicts["wrapped"][2]  # the claim wraps, the verdict does not
    angles = verdicts["header"].index("angles (deg)")
    assert [row[angles] for row in verdicts["rows"]][:2] == ["", "45, 90, 135"]
    for table in tables:
        for heading in ("θ (deg)", "angles"):
            if heading in table["header"]:
                column = table["header"].index(heading)
                for row in table["rows"]:
                    assert all(_ANGLE.fullmatch(a) for a in row[column].split(", ")), row[column]
        for row in table["rows"]:
            for cell in row:
                assert not _LIST_REPR.search(cell) and cell not in ("nan", "None"), cell
    choices = tables[1]
    assert choices["header"][:2] == ["claim", "robust"] and choices["rows"][1][1].startswith("refuted (primary)")
    assert sum(_narrowest_widths(choices)) < WINDOW_EM
    per_angle = tables[2]
    assert [row[1] for row in per_angle["rows"]] == ["0", "15", "45", "105", "22.5"]
    assert [row[0] for row in tables[4]["rows"]] == ["0", "15", "45", "105", "22.5"]  # recovery


def test_wide_tables_scroll_in_their_own_box(tmp_path):
    """Every table of a report page sits in a box that scrolls sideways; long text wraps in its
    cell, numbers stay on one line."""
    frame = pd.DataFrame({"claim": ["a claim of the paper, long enough to be wrapped in its cell"], "T": ["0.20"]})
    path = html_tables.write_html_tables(tmp_path / "t.html", "Title", [("Caption", frame)])
    text = path.read_text(encoding="utf-8")
    assert '<div class="table"><table>' in text and "div.table { max-width: 100%; overflow-x: auto;" in text
    assert '<td class="text">a claim' in text and "<td>0.20</td>" in text
    assert "td.text { white-space: normal;" in text


def _report_config(name: str) -> dict:
    from suspension_fabric.study.config import read_config_file, validate_config

    return validate_config(read_config_file(REPO / "config" / name))


@pytest.mark.parametrize("config_name", ["test.yaml", "paper.yaml"])
def test_report_captions_print_no_python_reprs(config_name):
    """The report's captions (the front page workflow/report/workflow.rst and every figure's and
    table's) print the config's lists as prose and its angles one way: "0, 15, 30", not
    "[0, 15, 30]" or "[0.0, 15.0]"."""
    jinja2 = pytest.importorskip("jinja2")
    config = _report_config(config_name)
    env = jinja2.Environment(trim_blocks=True, lstrip_blocks=True)  # as Snakemake's report renders them
    angles = ", ".join(f"{a:g}" for a in config["angles_deg"])
    captions = sorted((REPO / "workflow" / "report").glob("*.rst"))
    assert len(captions) > 10
    for caption in captions:
        text = env.from_string(caption.read_text()).render(snakemake=SimpleNamespace(config=config))
        assert not _LIST_REPR.search(text), f"{caption.name}: {_LIST_REPR.search(text).group(0)}"
        assert "{{" not in text and "{%" not in text
        if "angles_deg" in caption.read_text():
            assert angles in text, caption.name
    front = env.from_string((REPO / "workflow" / "report" / "workflow.rst").read_text())
    text = front.render(snakemake=SimpleNamespace(config=config))
    assert ", ".join(config["models"]["fabric"]) in text and ", ".join(config["models"]["stress"]) in text
