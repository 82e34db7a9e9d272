"""Flow protocols (suspension_fabric.io.protocols): segments, labels and the run tree that shares common
prefixes; the config key ``protocols`` (suspension_fabric.study.config); the fabric models along a
protocol (suspension_fabric.models.fabric_models.integrate_segment, protocol_fabric) checked against an
independent lab-frame integration and the paper's shear rotation; and the protocol tables
(suspension_fabric.analysis.protocol_tables) on synthetic per-run tables. Pure Python, no LAMMPS."""

from __future__ import annotations

import copy
import dataclasses
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy.integrate import solve_ivp

from suspension_fabric.analysis import frames
from suspension_fabric.analysis.protocol_tables import (
    FLOW_FRAME,
    PROTOCOL_COLUMNS,
    aggregate_protocol_seeds,
    protocol_table,
    protocol_tables,
    read_protocol_table,
)
from suspension_fabric.analysis.tables import TABLE_COLUMNS, VALUE_COLUMNS
from suspension_fabric.io.protocols import (
    PAPER_STARTUP,
    RUN_NAME_MAX,
    PaperRunNames,
    Protocol,
    ProtocolError,
    Segment,
    number_label,
    paper_protocols,
    parse_protocols,
    protocol_runs,
    run_tree,
)
from suspension_fabric.models import fabric_models as fm
from suspension_fabric.study.config import ConfigError, study_protocols, study_run_tree, validate_config

REPO = Path(__file__).resolve().parents[2]
PHI = 0.45
# a generic fabric with every component non-zero, so that every term of the frame maps is exercised
FABRIC0 = frames.vec_to_sym([0.031, 0.024, 0.027, -0.006, 0.002, 0.0015])


# =========================================================================== io.protocols
@pytest.mark.parametrize(
    "kwargs, key",
    [
        ({"strain": 0.0}, "strain"),
        ({"strain": -1.0}, "strain"),
        ({"strain": math.nan}, "strain"),
        ({"strain": math.inf}, "strain"),
        ({"strain": True}, "strain"),
        ({"strain": "2"}, "strain"),
        ({"strain": 1.0, "flow_angle_deg": math.inf}, "flow_angle_deg"),
        ({"strain": 1.0, "flow_angle_deg": math.nan}, "flow_angle_deg"),
        ({"strain": 1.0, "flow_angle_deg": False}, "flow_angle_deg"),
        ({"strain": 1.0, "turning_deg_per_strain": -math.inf}, "turning_deg_per_strain"),
        ({"strain": 1.0, "turning_deg_per_strain": math.nan}, "turning_deg_per_strain"),
    ],
)
def test_segment_refuses_bad_values(kwargs, key):
    with pytest.raises(ProtocolError, match=key):
        Segment(**kwargs)


def test_segment_stores_floats_and_defaults():
    segment = Segment(2)
    assert segment == Segment(2.0, 0.0, 0.0)
    assert all(type(value) is float for value in segment.as_dict().values())
    assert segment.as_dict() == {"strain": 2.0, "flow_angle_deg": 0.0, "turning_deg_per_strain": 0.0}


def test_segment_angles():
    """t(gamma) = flow_angle_deg + w gamma; the end angle is t(strain)."""
    segment = Segment(1.5, 10.0, 40.0)
    np.testing.assert_allclose(segment.flow_angle_at(np.array([0.0, 0.5, 1.5])), [10.0, 30.0, 70.0])
    assert segment.end_angle_deg == pytest.approx(70.0)
    assert Segment(2.0, 90.0).end_angle_deg == 90.0


@pytest.mark.parametrize(
    "segment, label",
    [
        (Segment(2, 90), "theta90for2"),
        (Segment(5, 0, 45), "theta0turn45for5"),
        (Segment(2, -45), "thetam45for2"),
        (Segment(2.5, 22.5, -10), "theta22.5turnm10for2.5"),
        (Segment(5), "theta0for5"),
        (Segment(1e-5, 180), "theta180for1em05"),
    ],
)
def test_segment_labels(segment, label):
    assert segment.label == label


def test_number_label():
    assert [number_label(v) for v in (45, 22.5, -30, 1e-5, 0)] == ["45", "22.5", "m30", "1em05", "0"]


def test_start_strains_and_total_strain():
    """start_k = sum of the strains of the segments before k; total = sum of all."""
    protocol = Protocol("p", (Segment(5), Segment(2, 180), Segment(2.5, 0, 30)))
    assert protocol.start_strains == (0.0, 5.0, 7.0)
    assert protocol.total_strain == 9.5
    assert protocol.histories == (protocol.segments[:1], protocol.segments[:2], protocol.segments)


def test_protocol_needs_a_segment():
    with pytest.raises(ProtocolError, match="p: no segments"):
        Protocol("p", ())


STARTUP, ROTATION = 5.0, 2.0


def _reversal_protocols():
    startup = Segment(STARTUP)
    return [
        Protocol("back", (startup, Segment(ROTATION, 180), Segment(2, 0))),
        Protocol("back_turn", (startup, Segment(ROTATION, 180), Segment(1, 180, 45))),
        Protocol("half", (startup, Segment(ROTATION, 90))),
        Protocol("rotary", (startup, Segment(3, 0, 30))),
    ]


def _check_tree(tree):
    """Parents precede their children and a child's history is its parent's plus one segment."""
    order = list(tree)
    for position, (name, node) in enumerate(tree.items()):
        assert node.run == name and node.segment == node.history[-1] and node.index == len(node.history) - 1
        if node.parent is None:
            assert node.index == 0
        else:
            assert order.index(node.parent) < position
            assert tree[node.parent].history == node.history[:-1]


def test_run_tree_shares_prefixes_with_paper_names():
    protocols = _reversal_protocols()
    tree = run_tree(protocols, PaperRunNames(STARTUP, ROTATION))
    _check_tree(tree)
    # 4 protocols, 10 segments, but the startup and the 180-degree reversal run once each
    assert list(tree) == [
        "startup",
        "rotation_theta180",
        "rotation_theta180_theta0for2",
        "rotation_theta180_theta180turn45for1",
        "rotation_theta90",
        "startup_theta0turn30for3",
    ]
    assert tree["rotation_theta180_theta0for2"].parent == "rotation_theta180"
    assert tree["rotation_theta180_theta180turn45for1"].parent == "rotation_theta180"
    assert tree["startup_theta0turn30for3"].parent == "startup"
    assert protocol_runs(protocols[0], tree) == ("startup", "rotation_theta180", "rotation_theta180_theta0for2")
    assert protocol_runs(protocols[2], tree) == ("startup", "rotation_theta90")


def test_run_tree_default_names():
    """Without fixed names every run is ``<parent>_<label>``, the label alone from a packing."""
    tree = run_tree(_reversal_protocols()[:2])
    _check_tree(tree)
    assert list(tree) == [
        "theta0for5",
        "theta0for5_theta180for2",
        "theta0for5_theta180for2_theta0for2",
        "theta0for5_theta180for2_theta180turn45for1",
    ]
    assert tree["theta0for5"].parent is None


def test_paper_family_keeps_its_names():
    angles = [0, 45, 90, 180, -30]
    protocols = paper_protocols(angles, STARTUP, ROTATION)
    names = ["rotation_theta0", "rotation_theta45", "rotation_theta90", "rotation_theta180", "rotation_thetam30"]
    assert list(protocols) == [PAPER_STARTUP, *names]
    assert protocols["rotation_theta45"].segments == (Segment(STARTUP), Segment(ROTATION, 45))
    tree = run_tree(protocols.values(), PaperRunNames(STARTUP, ROTATION))
    _check_tree(tree)
    assert list(tree) == list(protocols)
    for name, protocol in protocols.items():
        assert protocol_runs(protocol, tree)[-1] == name


@pytest.mark.parametrize(
    "segments, name",
    [
        ((Segment(STARTUP), Segment(3.0, 90)), "startup_theta90for3"),  # another rotation strain
        ((Segment(STARTUP), Segment(ROTATION, 90, 10)), "startup_theta90turn10for2"),  # turning
        ((Segment(4.0),), "theta0for4"),  # another startup strain
        ((Segment(STARTUP, 30),), "theta30for5"),  # another startup angle
    ],
)
def test_paper_names_only_for_the_paper_histories(segments, name):
    tree = run_tree([Protocol("p", segments)], PaperRunNames(STARTUP, ROTATION))
    assert list(tree)[-1] == name


def test_protocol_runs_outside_the_tree():
    tree = run_tree(_reversal_protocols()[:1], PaperRunNames(STARTUP, ROTATION))
    with pytest.raises(ProtocolError, match="half is not in the run tree"):
        protocol_runs(_reversal_protocols()[2], tree)


def test_run_tree_refuses_one_name_for_two_histories():
    """Strains equal to 6 significant digits share a label: the tree refuses, it does not merge them."""
    protocols = [Protocol("a", (Segment(1.0000001),)), Protocol("b", (Segment(1.0000002),))]
    with pytest.raises(ProtocolError, match="theta0for1 given to two flow histories"):
        run_tree(protocols)


def test_a_long_history_gets_a_short_name_that_still_names_it_alone():
    """Twenty reversals of 2 strain after a startup: a name that would pass RUN_NAME_MAX characters
    becomes <first run>_seg<index>_<digest>_<label> (the digest of the whole history), its children
    append their labels to it, and the short prefixes keep their joined labels."""
    strokes = tuple(Segment(2.0, 180.0 * ((k + 1) % 2)) for k in range(20))
    oscillation = Protocol("oscillation", (Segment(5.0), *strokes))
    longer = Protocol("longer", (Segment(5.0), *strokes[:12], Segment(3.0, 180.0)))
    tree = run_tree([oscillation, longer])
    names = protocol_runs(oscillation, tree)
    assert max(len(name) for name in names) <= RUN_NAME_MAX
    assert names[1] == "theta0for5_theta180for2" and names[2] == "theta0for5_theta180for2_theta0for2"
    shortened = [name for name in names if name.startswith("theta0for5_seg")]
    assert shortened and shortened[0].endswith("_theta180for2") and names[-1].endswith("_theta0for2")
    other = protocol_runs(longer, tree)
    assert other[:12] == names[:12] and other[13] not in names
    assert len(tree) == len(set(tree)) == 21 + 1
    again = run_tree([longer, oscillation])  # the names depend on the history, not on the order
    assert protocol_runs(oscillation, again) == names


@pytest.mark.parametrize(
    "section, key",
    [
        ({"rev": [{"strain": 1}, {"strain": -1}]}, "protocols.rev.1.strain"),
        ({"rev": [{"strain": 0}]}, "protocols.rev.0.strain"),
        ({"rev": [{"strian": 1}]}, "protocols.rev.0"),
        ({"rev": [{"turning_deg_per_strain": 10}]}, "protocols.rev.0.strain"),
        ({"rev": [{"strain": 1, "flow_angle_deg": math.nan}]}, "protocols.rev.0.flow_angle_deg"),
        ({"rev": [3]}, "protocols.rev.0"),
        ({"rev": []}, "protocols.rev"),
        ({"rev": {"strain": 1}}, "protocols.rev"),
        ({"my-rev": [{"strain": 1}]}, "protocols.my-rev"),
    ],
)
def test_parse_protocols_errors_name_the_key(section, key):
    with pytest.raises(ProtocolError, match=f"config key '{key}'"):
        parse_protocols(section)


def test_parse_protocols():
    parsed = parse_protocols({"rev": [{"strain": 5}, {"strain": 2, "flow_angle_deg": 180}]})
    assert parsed == {"rev": Protocol("rev", (Segment(5), Segment(2, 180)))}
    with pytest.raises(ProtocolError, match="config key 'protocols'"):
        parse_protocols([{"strain": 1}])


# =========================================================================== config
def _test_config(protocols):
    config = yaml.safe_load((REPO / "config" / "test.yaml").read_text())
    config["protocols"] = copy.deepcopy(protocols)
    return config


START = 0.3  # run.startup_strain of config/test.yaml (dt 1e-4, dump and table strides 0.01)


@pytest.mark.parametrize(
    "protocols, key",
    [
        ({"rev": [{"strain": START}, {"strain": -0.1, "flow_angle_deg": 180}]}, "protocols.rev.1.strain"),
        ({"rev": [{"strain": 0}]}, "protocols.rev.0.strain"),
        ({"rev": [{"strian": 0.1}]}, "protocols.rev.0"),
        ({"rev": [{"strain": START}, {"turning_deg_per_strain": 10}]}, "protocols.rev.1"),
        ({"rev": [{"strain": math.nan}]}, "protocols.rev.0.strain"),
        ({"startup": [{"strain": 0.1}]}, "protocols.startup"),
        ({"rotation_theta90": [{"strain": 0.1}]}, "protocols.rotation_theta90"),
        ({"my-rev": [{"strain": 0.1}]}, "protocols"),
        ({"rev": [{"strain": START}, {"strain": 0.015, "flow_angle_deg": 180}]}, "protocols.rev.1.strain"),
        ({"rev": [{"strain": 0.30005}]}, "protocols.rev.0.strain"),
        ({"rev": []}, "protocols.rev"),
    ],
)
def test_config_refuses_bad_protocols(protocols, key):
    with pytest.raises(ConfigError, match=f"config key '{key}'"):
        validate_config(_test_config(protocols))


def test_config_names_the_bad_protocol_name_and_stride():
    with pytest.raises(ConfigError, match="my-rev"):
        validate_config(_test_config({"my-rev": [{"strain": 0.1}]}))
    with pytest.raises(ConfigError, match="run.dump_strain strides"):
        validate_config(_test_config({"rev": [{"strain": START}, {"strain": 0.015}]}))


def test_config_fills_segment_defaults_and_shares_runs():
    protocols = {
        "reversal": [{"strain": START}, {"strain": 0.1, "flow_angle_deg": 180}, {"strain": 0.2}],
        "rotary": [{"strain": START}, {"strain": 0.2, "turning_deg_per_strain": 45}],
    }
    config = validate_config(_test_config(protocols))
    assert config["protocols"]["reversal"][2] == {"strain": 0.2, "flow_angle_deg": 0.0, "turning_deg_per_strain": 0.0}
    assert config["protocols"]["rotary"][1] == {"strain": 0.2, "flow_angle_deg": 0.0, "turning_deg_per_strain": 45}
    own = study_protocols(config)
    assert list(own) == ["startup", "rotation_theta0", "rotation_theta90", "reversal", "rotary"]
    assert own["reversal"].segments == (Segment(START), Segment(0.1, 180), Segment(0.2))
    tree = study_run_tree(config)
    _check_tree(tree)
    # the reversal's first two runs are the paper's startup and its (unlisted) 180-degree rotation
    assert list(tree) == [
        "startup",
        "rotation_theta0",
        "rotation_theta90",
        "rotation_theta180",
        "rotation_theta180_theta0for0.2",
        "startup_theta0turn45for0.2",
    ]


# =========================================================================== models
PARAMS = {
    "gw": {"beta": 8.0},
    "modified": {"beta": 8.0, "A": 30.0},
    "separate_rates": {"beta_e": 6.0, "beta_c": 10.0, "A": 25.0},
}
AFFINE_MODELS = [fm.GW, fm.MODIFIED, fm.SEPARATE_RATES]
# each built-in model and its copy that is not declared affine (integrated by solve_ivp)
MODELS = [pytest.param(model, id=model.key) for model in AFFINE_MODELS] + [
    pytest.param(dataclasses.replace(model, affine=False, key=f"{model.key}_ode"), id=f"{model.key}_ode")
    for model in AFFINE_MODELS
]


def _params(model):
    return PARAMS[model.key.removesuffix("_ode")]


def _lab_frame_segment(model, fabric0, strains, params, turning_deg_per_strain):
    """Reference for integrate_segment: in the fixed frame of the segment's initial flow, solve_ivp of
    dN/dgamma = rhs(N, L(gamma)) with L(gamma) = B(t)^T L0 B(t), t = w gamma, L0 = e1 e2, B the basis
    rotation_about_gradient(t); then the components in the turning frame, X = B(t) N B(t)^T."""
    w = math.radians(turning_deg_per_strain)
    L0 = frames.simple_shear_gradient()

    def rhs(gamma, v):
        B = frames.rotation_about_gradient(w * gamma)
        flow = fm.flow_of(B.T @ L0 @ B)
        return frames.sym_to_vec(model.rhs(frames.vec_to_sym(v), flow, params, PHI))

    solution = solve_ivp(
        rhs, (0.0, strains[-1]), frames.sym_to_vec(fabric0), t_eval=strains, method="DOP853", rtol=1e-12, atol=1e-14
    )
    assert solution.success
    lab = frames.vec_to_sym(solution.y.T)
    return frames.to_basis(lab, frames.rotation_about_gradient(w * np.asarray(strains)))


@pytest.mark.parametrize("turning", [45.0, -30.0, 360.0])
@pytest.mark.parametrize("model", MODELS)
def test_turning_segment_equals_lab_frame_integration(model, turning):
    """X(gamma) of d X/dgamma = rhs(X, e1e2) + K X - X K, K = w dB/dt, equals B(w gamma) N(gamma) B^T with
    N the lab-frame solution of dN/dgamma = rhs(N, B^T L0 B) (frame indifference of rhs)."""
    strains = np.linspace(0.0, 2.0, 6)
    got = fm.integrate_segment(model, FABRIC0, strains, _params(model), PHI, turning)
    expected = _lab_frame_segment(model, FABRIC0, strains, _params(model), turning)
    assert got.shape == (len(strains), 3, 3)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-8)
    # the frame turns, not the fabric: the invariants agree with the lab-frame ones
    np.testing.assert_allclose(np.trace(got, axis1=1, axis2=2), np.trace(expected, axis1=1, axis2=2), atol=1e-8)


@pytest.mark.parametrize("model", MODELS)
def test_fixed_segment_is_simple_shear(model):
    """turning 0: integrate_segment = integrate(L = e1 e2); a turning rate w -> 0 tends to it (error O(w))."""
    strains = np.linspace(0.0, 3.0, 7)
    params = _params(model)
    expected = fm.integrate(model, FABRIC0, frames.simple_shear_gradient(), strains, params, PHI)
    np.testing.assert_allclose(fm.integrate_segment(model, FABRIC0, strains, params, PHI, 0.0), expected, atol=1e-12)
    slow = fm.integrate_segment(model, FABRIC0, strains, params, PHI, 1e-7)
    np.testing.assert_allclose(slow, expected, atol=1e-8)


@pytest.mark.parametrize("theta_deg", [0.0, 45.0, 90.0, 135.0, 180.0, -60.0])
@pytest.mark.parametrize("model", AFFINE_MODELS, ids=lambda m: m.key)
def test_paper_rotation_protocol_equals_shear_rotation(model, theta_deg):
    """protocol_fabric(startup 5, then 2 at theta) = startup_shear and then shear_rotation(theta)."""
    protocol = paper_protocols([theta_deg], 5.0, 2.0)[f"rotation_theta{number_label(theta_deg)}"]
    before, after = np.linspace(0.0, 5.0, 6), np.linspace(0.0, 2.0, 9)
    params = _params(model)
    startup, rotation = fm.protocol_fabric(model, protocol, [before, after], params, PHI)
    np.testing.assert_allclose(startup, fm.startup_shear(model, before, params, PHI), atol=1e-12)
    expected = fm.shear_rotation(model, math.radians(theta_deg), after, params, PHI, startup_strain=5.0)
    np.testing.assert_allclose(rotation, expected, atol=1e-12)


@pytest.mark.parametrize("model", [MODELS[1], MODELS[4]])
def test_full_turn_is_no_change(model):
    """A change of flow angle by 360 degrees is none: (3 at 0, 2 at 360) = 5 of startup shear; the
    second segment also equals (3 at 0, 2 at 0)."""
    params = _params(model)
    strains = np.linspace(0.0, 2.0, 5)
    full_turn = Protocol("p", (Segment(3.0), Segment(2.0, 360.0)))
    straight = Protocol("q", (Segment(3.0), Segment(2.0, 0.0)))
    got = fm.protocol_fabric(model, full_turn, [[3.0], strains], params, PHI)[1]
    np.testing.assert_allclose(got, fm.protocol_fabric(model, straight, [[3.0], strains], params, PHI)[1], atol=1e-14)
    np.testing.assert_allclose(got, fm.startup_shear(model, 3.0 + strains, params, PHI), atol=1e-9)


def test_reversal_component_map():
    """rotation_about_gradient(pi) = diag(-1, 1, -1): B X B^T keeps n11, n22, n33, n13 and flips n12, n23."""
    basis = frames.rotation_about_gradient(math.pi)
    np.testing.assert_allclose(basis, np.diag([-1.0, 1.0, -1.0]), atol=1e-15)
    n11, n22, n33, n12, n13, n23 = frames.sym_to_vec(FABRIC0)
    np.testing.assert_allclose(
        frames.sym_to_vec(frames.to_basis(FABRIC0, basis)), [n11, n22, n33, -n12, n13, -n23], atol=1e-15
    )


@pytest.mark.parametrize("model", AFFINE_MODELS, ids=lambda m: m.key)
def test_reversal_in_a_protocol(model):
    """After 5 of startup shear, a reversal (180 or -180 degrees) starts from (n11, n22, n33, -n12, n13,
    -n23) of the startup's end; the reversed shear then brings n12 back to the steady value > 0."""
    params = _params(model)
    segment_strains = [[5.0], [0.0, 40.0]]
    for angle in (180.0, -180.0):
        (end,), (start, late) = fm.protocol_fabric(
            model, Protocol("r", (Segment(5.0), Segment(40.0, angle))), segment_strains, params, PHI
        )
        n11, n22, n33, n12, n13, n23 = frames.sym_to_vec(end)
        np.testing.assert_allclose(frames.sym_to_vec(start), [n11, n22, n33, -n12, n13, -n23], atol=1e-14)
        assert n12 < 0 < start[0, 1]  # G-W-type models: steady n12 < 0 (compression axis)
        np.testing.assert_allclose(late, fm.steady_state(model, params, PHI), atol=1e-8)


@pytest.mark.parametrize("model", [MODELS[1], MODELS[4]])
def test_continuity_after_a_turning_segment(model):
    """The last frame of a turning segment (0 + 40 x 1.5 = 60 degrees at its end) is the first of the next
    at 60 degrees (also at 60 + 360); at 90 degrees the next starts from it turned by 30 degrees,
    B(30 deg) X B(30 deg)^T."""
    params = _params(model)
    turning = Segment(1.5, 0.0, 40.0)
    strains = [np.linspace(0.0, 2.0, 3), np.linspace(0.0, 1.5, 4), [0.0, 0.5]]
    outputs = {}
    for angle in (60.0, 420.0, 90.0):
        protocol = Protocol("c", (Segment(2.0), turning, Segment(1.0, angle)))
        outputs[angle] = fm.protocol_fabric(model, protocol, strains, params, PHI)
    end_of_turning = outputs[60.0][1][-1]
    np.testing.assert_allclose(outputs[60.0][2][0], end_of_turning, atol=1e-14)
    np.testing.assert_allclose(outputs[420.0][2][0], end_of_turning, atol=1e-14)
    turned = frames.to_basis(end_of_turning, frames.rotation_about_gradient(math.radians(30.0)))
    np.testing.assert_allclose(outputs[90.0][2][0], turned, atol=1e-14)
    # the turning segment itself starts from the startup's end (no jump: same angle 0)
    np.testing.assert_allclose(outputs[60.0][1][0], outputs[60.0][0][-1], atol=1e-14)


@pytest.mark.parametrize("model", [MODELS[2], MODELS[5]])
def test_turning_segment_split_in_two_is_the_same(model):
    """Semigroup: (1 turning at 40 from 0, then 0.5 turning at 40 from 40) = 1.5 turning at 40 from 0."""
    params = _params(model)
    whole = Protocol("w", (Segment(2.0), Segment(1.5, 0.0, 40.0)))
    split = Protocol("s", (Segment(2.0), Segment(1.0, 0.0, 40.0), Segment(0.5, 40.0, 40.0)))
    end_whole = fm.protocol_fabric(model, whole, [[2.0], [1.5]], params, PHI)[1][-1]
    end_split = fm.protocol_fabric(model, split, [[2.0], [1.0], [0.5]], params, PHI)[2][-1]
    np.testing.assert_allclose(end_split, end_whole, atol=1e-9)


def test_protocol_fabric_needs_one_grid_per_segment():
    protocol = Protocol("p", (Segment(1.0), Segment(1.0, 90.0)))
    with pytest.raises(ValueError, match="1 strain grids for 2 segments"):
        fm.protocol_fabric(fm.GW, protocol, [[0.0, 1.0]], PARAMS["gw"], PHI)


def test_sampling_a_segment_does_not_change_the_next():
    """The next segment starts from the fabric at the end of this one (its strain), whatever strains
    are asked for: sampling segment 0 (strain 1) at 1.5 must be refused (ValueError) or leave segment 1
    as it is when sampled only up to 1."""
    protocol = Protocol("p", (Segment(1.0), Segment(1.0, 30.0)))
    params = PARAMS["gw"]
    reference = fm.protocol_fabric(fm.GW, protocol, [[0.0, 0.5, 1.0], [0.0, 0.5]], params, PHI)
    try:
        beyond = fm.protocol_fabric(fm.GW, protocol, [[0.0, 0.5, 1.5], [0.0, 0.5]], params, PHI)
    except ValueError:
        return
    np.testing.assert_allclose(beyond[1], reference[1], atol=1e-12)


# =========================================================================== protocol tables
SEEDS = (1, 2, 5)
DT = 0.01


def _values(run, seed, strain):
    """A value per (run, seed, strain, column) that differs between runs and non-linearly between seeds."""
    offset = sum(map(ord, run)) % 7
    return {
        column: 0.01 * (k + 1) + 0.1 * offset + 0.003 * seed**2 + 0.02 * strain
        for k, column in enumerate(VALUE_COLUMNS)
    }


def _run_table(tree, run, seed, theta_shift=0.0):
    """A synthetic per-run table (analysis.tables.TABLE_COLUMNS) of run ``run``: frames every DT of its
    segment's strain, theta the segment's flow angle at each strain."""
    segment = tree[run].segment
    strain = np.linspace(0.0, segment.strain, round(segment.strain / DT) + 1)
    table = pd.DataFrame(
        {
            "seed": seed,
            "theta": segment.flow_angle_at(strain) + theta_shift,
            "N": 40,
            "phi": 0.45 + 1e-4 * seed,
            "step": 1000 * tree[run].index + np.arange(len(strain)),
            "strain": strain,
            **_values(run, seed, strain),
        }
    )
    return table[list(TABLE_COLUMNS)]


TABLE_PROTOCOLS = {
    "reversal": Protocol("reversal", (Segment(0.3), Segment(0.1, 180.0), Segment(0.2, 0.0))),
    "rotary": Protocol("rotary", (Segment(0.3), Segment(0.2, 90.0, 45.0))),
}


def _tree():
    return run_tree(TABLE_PROTOCOLS.values(), PaperRunNames(0.3, 0.1))


def test_protocol_table_joins_segments_along_the_strain():
    """strain = start_k + segment_strain; the segment's boundary rows are both kept, at the same strain."""
    tree = _tree()
    protocol = TABLE_PROTOCOLS["reversal"]
    runs = protocol_runs(protocol, tree)
    assert runs == ("startup", "rotation_theta180", "rotation_theta180_theta0for0.2")
    table = protocol_table(protocol, runs, lambda run, seed: _run_table(tree, run, seed), SEEDS, VALUE_COLUMNS)
    assert list(table.columns) == [*PROTOCOL_COLUMNS, *VALUE_COLUMNS]
    assert len(table) == len(SEEDS) * (31 + 11 + 21)
    assert (table["frame"] == FLOW_FRAME).all() and (table["protocol"] == "reversal").all()
    starts = np.array(protocol.start_strains)[table["segment"].to_numpy()]
    np.testing.assert_allclose(table["strain"], starts + table["segment_strain"], atol=1e-15)
    for seed, rows in table.groupby("seed"):
        assert rows["strain"].max() == pytest.approx(protocol.total_strain)
        for boundary, (before, after) in zip((0.3, 0.4), ((0, 1), (1, 2))):
            at = rows[np.isclose(rows["strain"], boundary)]
            assert sorted(at["segment"]) == [before, after]
            assert at.loc[at["segment"] == after, "segment_strain"].item() == 0.0
        assert set(rows.loc[rows["segment"] == 1, "theta"]) == {180.0}
        # values are the run tables' own, row for row
        for index, run in enumerate(runs):
            segment_rows = rows[rows["segment"] == index]
            expected = pd.DataFrame(_values(run, seed, segment_rows["segment_strain"].to_numpy()))
            np.testing.assert_allclose(segment_rows[list(VALUE_COLUMNS)].to_numpy(), expected.to_numpy())


def test_protocol_tables_aggregate_means_and_sems():
    """Per (protocol, segment, segment_strain): mean over seeds and sem = std(ddof=1)/sqrt(n_seeds)."""
    tree = _tree()
    runs = {name: protocol_runs(p, tree) for name, p in TABLE_PROTOCOLS.items()}
    table, aggregate = protocol_tables(
        TABLE_PROTOCOLS, runs, lambda run, seed: _run_table(tree, run, seed), SEEDS, VALUE_COLUMNS
    )
    assert set(table["protocol"]) == {"reversal", "rotary"}
    pd.testing.assert_frame_equal(aggregate_protocol_seeds(table, VALUE_COLUMNS), aggregate)
    assert len(aggregate) == len(table) / len(SEEDS)
    assert (aggregate["n_seeds"] == len(SEEDS)).all() and (aggregate["frame"] == FLOW_FRAME).all()
    for (name, index), rows in aggregate.groupby(["protocol", "segment"]):
        protocol = TABLE_PROTOCOLS[name]
        segment, run = protocol.segments[index], runs[name][index]
        np.testing.assert_allclose(rows["strain"], protocol.start_strains[index] + rows["segment_strain"])
        np.testing.assert_allclose(rows["theta"], segment.flow_angle_at(rows["segment_strain"].to_numpy()))
        per_seed = np.stack(
            [pd.DataFrame(_values(run, s, rows["segment_strain"].to_numpy())).to_numpy() for s in SEEDS]
        )
        for k, column in enumerate(VALUE_COLUMNS):
            np.testing.assert_allclose(rows[f"{column}_mean"], per_seed[..., k].mean(axis=0), rtol=1e-12)
            np.testing.assert_allclose(
                rows[f"{column}_sem"], per_seed[..., k].std(axis=0, ddof=1) / math.sqrt(len(SEEDS)), rtol=1e-9
            )
    # the turning segment keeps its turning angle, 90 + 45 gamma
    turning = aggregate[(aggregate["protocol"] == "rotary") & (aggregate["segment"] == 1)]
    np.testing.assert_allclose(turning["theta"].iloc[[0, -1]], [90.0, 99.0])


def test_protocol_table_refuses_a_flow_angle_mismatch():
    tree = _tree()
    protocol = TABLE_PROTOCOLS["reversal"]
    runs = protocol_runs(protocol, tree)

    def read(run, seed):  # the 180-degree run's table at flow angle 0
        return _run_table(tree, run, seed, theta_shift=-180.0 if run == "rotation_theta180" else 0.0)

    with pytest.raises(ValueError, match="segment 1: run rotation_theta180 of seed 1"):
        protocol_table(protocol, runs, read, SEEDS, VALUE_COLUMNS)
    # a turning segment read from a table at a fixed angle
    rotary = TABLE_PROTOCOLS["rotary"]

    def fixed(run, seed):
        table = _run_table(tree, run, seed)
        return table.assign(theta=table["theta"].iloc[0])

    with pytest.raises(ValueError, match="rotary, segment 1"):
        protocol_table(rotary, protocol_runs(rotary, tree), fixed, SEEDS, VALUE_COLUMNS)
    with pytest.raises(ValueError, match="2 runs for 3 segments"):
        protocol_table(protocol, runs[:2], read, SEEDS, VALUE_COLUMNS)


def test_read_protocol_table(tmp_path):
    tree = _tree()
    protocol = TABLE_PROTOCOLS["rotary"]
    table, aggregate = protocol_tables(
        {"rotary": protocol},
        {"rotary": protocol_runs(protocol, tree)},
        lambda run, seed: _run_table(tree, run, seed),
        SEEDS,
        VALUE_COLUMNS,
    )
    for name, frame in (("runs.csv", table), ("aggregate.csv", aggregate)):
        frame.to_csv(tmp_path / name, index=False)
        back = read_protocol_table(tmp_path / name)
        pd.testing.assert_frame_equal(back, frame, check_dtype=False)
    table.drop(columns="segment_strain").to_csv(tmp_path / "cut.csv", index=False)
    with pytest.raises(ValueError, match=r"cut.csv: not a protocol table \(no column\(s\) \['segment_strain'\]\)"):
        read_protocol_table(tmp_path / "cut.csv")
    table.assign(frame="paper").to_csv(tmp_path / "paper.csv", index=False)
    with pytest.raises(ValueError, match="frame"):
        read_protocol_table(tmp_path / "paper.csv")
    with pytest.raises(FileNotFoundError):
        read_protocol_table(tmp_path / "absent.csv")
