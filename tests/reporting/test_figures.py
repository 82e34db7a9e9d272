"""What the paper's figures plot (suspension_fabric.reporting.figures), read back from the matplotlib artists.

Small synthetic seed aggregates and prediction tables, with a different known function for
every component, model and protocol, go into figure_startup / figure_rotation; the tests read
the plotted arrays (Line2D data, error-bar segments, QuadMesh values and cell edges) and the
legend / title texts back, so plotting a wrong column, model, protocol or angle fails.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest

from suspension_fabric.reporting import figures

FITS = {
    "phi": 0.45,
    "gw": {"beta": 12.3456},
    "modified": {"beta": 7.891, "A": 43.21},
    "targets": {"n12": {"mean": -0.1, "sem": 0.001}},
    "models": {
        "gw": {"label": "G-W (Eq. 1)", "parameters": {"beta": 12.3456}},
        "modified": {"label": "modified G-W (Eq. 2)", "parameters": {"beta": 7.891, "A": 43.21}},
    },
}
STARTUP_COMPONENTS = ("n11", "n22", "n33", "n12")
OFFSETS = {"n11": 0.3, "n22": 0.2, "n33": 0.1, "n12": -0.05}  # distinct per component
MODEL_OFFSETS = {"gw": 1.0, "modified": 2.0}


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


# ---------------------------------------------------------------------------- Fig. 1


def startup_tables(n_frames=100):
    """(aggregate, predictions): aggregate rows shuffled, with a theta = 90 block to ignore;
    predictions with rotation rows at theta = 0 that must not be drawn in Fig. 1."""
    strain = np.linspace(0.0, 9.9, n_frames)
    blocks = []
    for theta, sign in ((0.0, 1.0), (90.0, -1.0)):
        block = pd.DataFrame({"theta": theta, "N": 500, "phi": 0.45, "strain": strain, "n_seeds": 3})
        for k, name in enumerate(STARTUP_COMPONENTS):
            block[f"{name}_mean"] = sign * (OFFSETS[name] + 0.01 * (k + 1) * strain)
            block[f"{name}_sem"] = 0.001 * (k + 1) * (1.0 + strain)
        blocks.append(block)
    aggregate = pd.concat(blocks, ignore_index=True)
    aggregate.loc[(aggregate["theta"] == 0.0) & (aggregate["strain"] == 0.0), "n22_sem"] = np.nan
    aggregate = aggregate.sample(frac=1.0, random_state=1)

    rows = []
    for key, offset in MODEL_OFFSETS.items():
        for protocol, scale in (("startup", 1.0), ("rotation", -3.0)):
            grid = np.linspace(0.0, 10.0, 201 if protocol == "startup" else 31)
            frame = pd.DataFrame({"model": key, "protocol": protocol, "theta": 0.0, "strain": grid})
            for k, name in enumerate(STARTUP_COMPONENTS):
                frame[name] = scale * (offset + k + np.sin(grid + k))
            rows.append(frame)
    return aggregate, pd.concat(rows, ignore_index=True)


def expected_prediction(predictions, key, name):
    rows = predictions[(predictions["model"] == key) & (predictions["protocol"] == "startup")]
    return rows["strain"].to_numpy(), rows[name].to_numpy()


def test_startup_figure_plots_simulation_columns_with_standard_errors():
    """Each panel shows, per component c in (11, 22, 33, 12), markers at (strain, c_mean) of the
    theta = 0 rows sorted by strain, thinned to every k-th frame from the first with k the
    smallest stride giving at most max_markers markers (100 frames, 40 -> k = 3, 34 markers),
    and error bars from c_mean - c_sem to c_mean + c_sem (a NaN sem draws a zero-length bar)."""
    aggregate, predictions = startup_tables()
    fig = figures.figure_startup(aggregate, predictions, FITS, max_markers=40)
    sim = aggregate[aggregate["theta"] == 0.0].sort_values("strain")
    shown = sim.iloc[::3]
    assert len(shown) == 34
    axes = fig.axes[:2]
    for ax in axes:
        assert len(ax.containers) == len(STARTUP_COMPONENTS)
        for container, name in zip(ax.containers, STARTUP_COMPONENTS):
            data_line, _, (bars,) = container.lines
            mean = shown[f"{name}_mean"].to_numpy()
            # errorbar keeps the pandas values as an object array
            np.testing.assert_allclose(np.asarray(data_line.get_xdata(), dtype=float), shown["strain"], rtol=1e-12)
            np.testing.assert_allclose(np.asarray(data_line.get_ydata(), dtype=float), mean, rtol=1e-12)
            segments = np.array(bars.get_segments())  # (markers, 2 ends, (x, y))
            sem = shown[f"{name}_sem"].fillna(0.0).to_numpy()
            np.testing.assert_allclose(segments[:, 0, 0], shown["strain"], rtol=1e-12)
            np.testing.assert_allclose(segments[:, 0, 1], mean - sem, rtol=1e-12, atol=1e-15)
            np.testing.assert_allclose(segments[:, 1, 1], mean + sem, rtol=1e-12, atol=1e-15)
    first_bar = np.array(axes[0].containers[1].lines[2][0].get_segments()[0])
    assert first_bar[0, 1] == first_bar[1, 1]  # the NaN sem of n22 at strain 0


def test_startup_figure_max_markers_is_an_upper_bound():
    """len(markers) <= max_markers for any number of frames (and every frame when fewer)."""
    for n_frames, max_markers in ((100, 40), (79, 40), (201, 40), (30, 40), (41, 40)):
        aggregate, predictions = startup_tables(n_frames)
        fig = figures.figure_startup(aggregate, predictions, FITS, max_markers=max_markers)
        n_markers = len(fig.axes[0].containers[0].lines[0].get_xdata())
        assert n_markers <= max_markers, (n_frames, n_markers)
        if n_frames <= max_markers:
            assert n_markers == n_frames
        else:
            assert n_markers >= max_markers // 2  # thinned no more than needed
        plt.close(fig)


def test_startup_figure_draws_each_models_startup_prediction_in_its_panel():
    """Panel (a) draws the G-W and panel (b) the modified startup prediction of every component
    as a line (x = prediction strain, y = prediction column; rotation rows are not drawn), in
    the colour of that component's markers; the legend lists the four simulated components and
    the fitted parameters to 3 significant digits (G-W beta = 12.3; modified beta = 7.89,
    A = 43.2); the titles name the models and the suptitle N, phi and the number of seeds."""
    aggregate, predictions = startup_tables()
    fig = figures.figure_startup(aggregate, predictions, FITS)
    labels = {"gw": r"G-W (Eq. 1), $\beta$ = 12.3", "modified": r"modified G-W (Eq. 2), $\beta$ = 7.89, $A$ = 43.2"}
    titles = {"gw": "(a) G-W (Eq. 1)", "modified": "(b) modified G-W (Eq. 2)"}
    for ax, key in zip(fig.axes[:2], ("gw", "modified")):
        marker_lines = [container.lines[0] for container in ax.containers]
        # the prediction curves; not the markers, the empty legend handle or the y = 0 line
        curves = [line for line in ax.lines if line not in marker_lines and len(line.get_xdata()) > 2]
        assert len(curves) == len(STARTUP_COMPONENTS)
        for curve, marker_line, name in zip(curves, marker_lines, STARTUP_COMPONENTS):
            strain, values = expected_prediction(predictions, key, name)
            np.testing.assert_allclose(curve.get_xdata(), strain, rtol=1e-12)
            np.testing.assert_allclose(curve.get_ydata(), values, rtol=1e-12)
            assert curve.get_color() == marker_line.get_color()
        texts = [text.get_text() for text in ax.get_legend().get_texts()]
        expected_texts = [rf"$\langle nn\rangle_{{{name[1:]}}}$ simulation" for name in STARTUP_COMPONENTS]
        expected_texts.append(labels[key])
        assert sorted(texts) == sorted(expected_texts)
        assert ax.get_title() == titles[key]
    suptitle = fig._suptitle.get_text()
    assert "N = 500" in suptitle and "phi = 0.45" in suptitle and "3 seeds" in suptitle


# ---------------------------------------------------------------------------- Fig. 2

N12_SS = FITS["targets"]["n12"]["mean"]
ROTATION_STRAINS = np.array([0.0, 0.5, 1.0, 1.5, 2.0])


def rotation_value(source, column, theta_deg, strain):
    """Known fields, even in theta for n12 and odd for n23 (the symmetry of shear rotation),
    different for the simulation and each model."""
    shift = {"simulation": 0.0, "gw": 0.3, "modified": 0.6}[source]
    t = np.radians(theta_deg)
    if column == "n12":
        return N12_SS * (1.0 + shift + 0.5 * np.cos(t) + 0.3 * (t / np.pi) ** 2) * (1.0 - 0.2 * strain)
    return N12_SS * (0.4 + shift) * (np.sin(t) + 0.2 * np.sin(2 * t)) * (1.0 + strain)


def rotation_tables(sim_thetas):
    sim = []
    for theta in sim_thetas:
        block = pd.DataFrame({"theta": float(theta), "N": 500, "strain": ROTATION_STRAINS, "n_seeds": 3})
        for column in ("n12", "n23"):
            block[f"{column}_mean"] = rotation_value("simulation", column, theta, ROTATION_STRAINS)
            block[f"{column}_sem"] = 0.001
        sim.append(block)
    rows = []
    for key in ("gw", "modified"):
        for theta in np.arange(0.0, 181.0, 15.0):
            frame = pd.DataFrame({"model": key, "protocol": "rotation", "theta": theta, "strain": ROTATION_STRAINS})
            for column in ("n12", "n23"):
                frame[column] = rotation_value(key, column, theta, ROTATION_STRAINS)
            rows.append(frame)
        # startup rows (another strain grid, theta 0) must stay out of the polar maps
        rows.append(
            pd.DataFrame(
                {
                    "model": key,
                    "protocol": "startup",
                    "theta": 0.0,
                    "strain": np.linspace(0, 20, 11),
                    "n12": 5.0,
                    "n23": 5.0,
                }
            )
        )
    return pd.concat(sim, ignore_index=True), pd.concat(rows, ignore_index=True)


def check_polar_map(ax, source, column, thetas_deg, span_deg=(-180.0, 180.0)):
    """Cell edges and values of the QuadMesh in ``ax`` against the known field.

    Radius edges: midpoints of the strains, clipped at 0. Angle edges: ``span_deg`` in cells of
    at most 2 degrees, each cell owned by the nearest plotted angle; value = field(owner angle,
    strain)/n12_ss."""
    (mesh,) = ax.collections
    values = np.ma.getdata(mesh.get_array())
    coords = mesh.get_coordinates()
    theta_edges, radius_edges = coords[0, :, 0], coords[:, 0, 1]
    np.testing.assert_allclose(radius_edges, [0.0, 0.25, 0.75, 1.25, 1.75, 2.25], atol=1e-12)
    np.testing.assert_allclose(theta_edges[[0, -1]], np.radians(span_deg), atol=1e-12)
    assert np.all(np.diff(theta_edges) <= np.radians(2.0) + 1e-12)
    centres = np.degrees(0.5 * (theta_edges[1:] + theta_edges[:-1]))
    thetas_deg = np.asarray(thetas_deg, dtype=float)
    owners = thetas_deg[np.abs(centres[:, None] - thetas_deg[None, :]).argmin(axis=1)]
    expected = rotation_value(source, column, owners[None, :], ROTATION_STRAINS[:, None]) / N12_SS
    assert values.shape == expected.shape
    np.testing.assert_allclose(values, expected, rtol=1e-12, atol=1e-14)
    return values


def polar_axes(fig):
    return [ax for ax in fig.axes if ax.name == "polar"]


def test_rotation_figure_maps_each_component_of_each_source_by_angle_and_strain():
    """Rows simulation / G-W / modified, columns 12 / 23: panel (r, c) shows component c of
    source r divided by <nn>_12^ss at radius = strain and angle = theta; the simulation (theta
    in 0..180 every 45 degrees) is completed to -180..0 by parity (12 even, 23 odd), the models
    on their own 15-degree grid; one symmetric colour scale per column, +-max |value| over the
    three rows; the suptitle says the negative half was filled by symmetry."""
    sim, predictions = rotation_tables([0, 45, 90, 135, 180])
    fig = figures.figure_rotation(sim, predictions, FITS)
    axes = polar_axes(fig)
    assert len(axes) == 6
    sim_thetas = [-180, -135, -90, -45, 0, 45, 90, 135, 180]
    model_thetas = np.arange(-180.0, 181.0, 15.0)
    sources = [
        ("simulation", sim_thetas, "simulation"),
        ("gw", model_thetas, "G-W (Eq. 1)"),
        ("modified", model_thetas, "modified G-W (Eq. 2)"),
    ]
    maxima = {"n12": [], "n23": []}
    for r, (source, thetas, title) in enumerate(sources):
        for c, column in enumerate(("n12", "n23")):
            ax = axes[2 * r + c]
            values = check_polar_map(ax, source, column, thetas)
            maxima[column].append(np.abs(values).max())
            assert ax.get_title() == f"({'abcdef'[2 * r + c]}) {title}"
    for c, column in enumerate(("n12", "n23")):
        limit = max(maxima[column])
        for r in range(3):
            np.testing.assert_allclose(axes[2 * r + c].collections[0].get_clim(), (-limit, limit), rtol=1e-12)
    suptitle = fig._suptitle.get_text()
    assert "filled by symmetry" in suptitle and f"{N12_SS:.4g}" in suptitle


def test_the_polar_maps_go_into_the_pdf_as_images(tmp_path):
    """Each polar map is drawn into the PDF as an image (at the PNG's 200 dpi), not as one vector path
    per cell: at the reference's scale those were 4e5 paths, half a minute and 8.7 MB to write."""
    sim, predictions = rotation_tables([0, 45, 90, 135, 180])
    fig = figures.figure_rotation(sim, predictions, FITS)
    meshes = [ax.collections[0] for ax in polar_axes(fig)]
    assert all(mesh.get_rasterized() for mesh in meshes)
    pdf, _ = figures.save_figure(fig, tmp_path / "fig2_rotation")
    assert pdf.read_bytes().count(b"/Subtype /Image") >= len(meshes)


def test_rotation_figure_keeps_simulated_negative_angles():
    """A simulation that already has theta < 0 is plotted as given (no mirroring, no note)."""
    sim, predictions = rotation_tables([-90, 0, 90, 180])
    fig = figures.figure_rotation(sim, predictions, FITS)
    check_polar_map(polar_axes(fig)[1], "simulation", "n23", [-90, 0, 90, 180], span_deg=(-135.0, 180.0))
    assert "symmetry" not in fig._suptitle.get_text()
