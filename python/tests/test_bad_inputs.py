"""Bad input raises ValueError whose message names the argument, says what was wrong and what
was expected. Each case breaks exactly one thing of an otherwise valid scan."""

import re

import numpy as np
import pytest
import zeroreg
from conftest import KITCHEN, frame_spec

H, W = 48, 64


def valid_view():
    depth = np.full((H, W), 1500, np.uint16)
    K = np.array([[60.0, 0, 32], [0, 60.0, 24], [0, 0, 1]])
    return {
        "color": np.zeros((H, W, 3), np.uint8),
        "depth": depth,
        "depth_scale": 1000.0,
        "intrinsics": K,
        "T_scan_camera": np.eye(4),
    }


def nan_at(array, index):
    a = np.array(array, dtype=np.float64)
    a[index] = np.nan
    return a


def scaled_pose():
    T = np.eye(4)
    T[:3, :3] *= 2.0
    return T


def bad_last_row():
    T = np.eye(4)
    T[3, 0] = 0.5
    return T


def reflection():
    T = np.eye(4)
    T[0, 0] = -1.0
    return T


def float_depth(values):
    d = np.full((H, W), 1.5, np.float32)
    d[3, 5] = values
    return d


VIEW_CASES = [
    # (key, value, expected message prefix/pattern)
    ("color", np.zeros((H, W, 3), np.float32),
     "source.views[0].color: dtype float32; expected dtype uint8 with shape (H, W, 3), RGB"),
    ("color", np.zeros((H, W), np.uint8),
     "source.views[0].color: shape (48, 64); expected (H, W, 3) uint8 RGB"),
    ("color", np.zeros((H, W, 4), np.uint8),
     "source.views[0].color: shape (48, 64, 4); expected (H, W, 3) uint8 RGB"),
    ("color", [[0, 0, 0]],
     "source.views[0].color: got list; expected a numpy array of dtype uint8"),
    ("depth", np.full((H, W + 1), 1500, np.uint16),
     "source.views[0].depth: shape (48, 65) does not match colour (48, 64)"),
    ("depth", np.full((H, W, 1), 1500, np.uint16),
     "source.views[0].depth: shape (48, 64, 1); expected (H, W)"),
    ("depth", np.full((H, W), 1.5, np.float64),
     "source.views[0].depth: dtype float64; expected uint16 (with depth_scale) or float32 "
     "(metres)"),
    ("depth", np.zeros((H, W), np.uint16),
     "source.views[0].depth: has no valid pixel"),
    ("depth_scale", None, "source.views[0].depth_scale: missing; uint16 depth needs depth_scale"),
    ("depth_scale", 0.0, "source.views[0].depth_scale: is 0.0; expected a positive number"),
    ("depth_scale", float("nan"), "source.views[0].depth_scale: is nan; expected a positive"),
    ("depth_scale", "mm", "source.views[0].depth_scale: got str; expected a positive number"),
    ("intrinsics", nan_at(valid_view()["intrinsics"], (0, 0)),
     "source.views[0].intrinsics: element [0, 0] is NaN; expected finite numbers"),
    ("intrinsics", np.eye(3)[:, :2],
     "source.views[0].intrinsics: shape (3, 2); expected camera matrix (3, 3)"),
    ("intrinsics", np.diag([-60.0, 60.0, 1.0]),
     "source.views[0].intrinsics: focal length fx = -60, fy = 60 is invalid"),
    ("intrinsics", np.array([[60.0, 1, 32], [0, 60, 24], [0, 0, 1]]),
     "source.views[0].intrinsics: not a pinhole camera matrix"),
    ("intrinsics", np.array([["a", "b", "c"]] * 3),
     "source.views[0].intrinsics: dtype <U1; expected numbers"),
    ("T_scan_camera", nan_at(np.eye(4), (0, 3)),
     "source.views[0].T_scan_camera: element [0, 3] is NaN; expected finite numbers"),
    ("T_scan_camera", np.eye(3),
     "source.views[0].T_scan_camera: shape (3, 3); expected rigid transform (4, 4)"),
    ("T_scan_camera", scaled_pose(),
     "source.views[0].T_scan_camera: rotation is not rigid (max |R^T R - I| = 3"),
    ("T_scan_camera", reflection(),
     "source.views[0].T_scan_camera: rotation is not rigid (max |R^T R - I| = 0, det R = -1)"),
    ("T_scan_camera", bad_last_row(),
     "source.views[0].T_scan_camera: last row is [0.5, 0, 0, 1]; expected [0, 0, 0, 1]"),
    ("pose", np.eye(4),
     "source.views[0]: unknown key 'pose'; known keys: name, color, depth, depth_scale, "
     "intrinsics, T_scan_camera, T_world_camera_gt"),
]


@pytest.fixture(scope="module")
def sift_pipeline():
    # Scans are checked before any image work, so these tests need no model.
    return zeroreg.Pipeline({"features": {"backend": "sift"}})


@pytest.mark.parametrize("key,value,message", VIEW_CASES)
def test_bad_view_field(sift_pipeline, key, value, message):
    view = valid_view()
    view[key] = value
    with pytest.raises(ValueError) as error:
        sift_pipeline.register({"views": [view]}, {"views": [valid_view()]})
    assert str(error.value).startswith(message), str(error.value)


@pytest.mark.parametrize(
    "depth,depth_scale,message",
    [
        (float_depth(np.nan), None,
         "source.views[0].depth: value nan at pixel (row 3, col 5); expected finite metres >= 0"),
        (float_depth(np.inf), None, "source.views[0].depth: value inf at pixel (row 3, col 5)"),
        (float_depth(-1.0), None, "source.views[0].depth: value -1 at pixel (row 3, col 5)"),
        (float_depth(1.0), 1000.0,
         "source.views[0].depth_scale: given for float32 depth; float32 depth is already in "
         "metres"),
    ],
)
def test_bad_float_depth(sift_pipeline, depth, depth_scale, message):
    view = valid_view()
    view["depth"], view["depth_scale"] = depth, depth_scale
    with pytest.raises(ValueError) as error:
        sift_pipeline.register({"views": [view]}, {"views": [valid_view()]})
    assert str(error.value).startswith(message), str(error.value)


def test_float_depth_and_other_valid_forms_pass_the_checks(sift_pipeline):
    # The valid baseline really is valid (so each case above fails for its one reason): a
    # featureless black image registers without error, as an invalid result.
    view = valid_view()
    r = sift_pipeline.register({"views": [view]}, {"views": [valid_view()]})
    assert not r.valid and r.reason
    view["depth"], view["depth_scale"] = np.full((H, W), 1.5, np.float32), None
    view["intrinsics"] = view["intrinsics"].tolist()  # lists of numbers are fine
    view["color"] = np.zeros((H, W * 2, 3), np.uint8)[:, ::2]  # non-contiguous too
    assert not sift_pipeline.register({"views": [view]}, {"views": [valid_view()]}).valid


def test_errors_name_the_target_and_the_view_index(sift_pipeline):
    second = valid_view()
    second["depth"] = np.full((H + 1, W), 1500, np.uint16)
    with pytest.raises(
        ValueError,
        match=re.escape("target.views[1].depth: shape (49, 64) does not match colour (48, 64)"),
    ):
        sift_pipeline.register({"views": [valid_view()]}, {"views": [valid_view(), second]})


@pytest.mark.parametrize(
    "scan,message",
    [
        (42, "source: got int; expected a path string, a zeroreg.Scan or a dict with 'views'"),
        ({"views": []}, "source.views: is empty; expected at least one view"),
        ({}, "source.views: missing; expected a list of views"),
        ({"views": valid_view()}, "source.views: got dict; expected a list of views"),
        ({"views": [valid_view()], "cloud": None}, "source: unknown key 'cloud'"),
        ({"views": [valid_view()], "points": np.zeros((5, 2))},
         "source.points: shape (5, 2); expected points in metres (N, 3)"),
        ({"views": [valid_view()], "points": nan_at(np.zeros((5, 3)), (4, 1))},
         "source.points: element [4, 1] is NaN"),
        ({"views": [valid_view()], "points": np.zeros((5, 3)), "colors": np.zeros((4, 3))},
         "source.colors: 4 colours for 5 points; expected one colour per point"),
        ({"views": [valid_view()], "T_world_scan_gt": np.zeros((4, 4))},
         "source.T_world_scan_gt: last row is [0, 0, 0, 0]"),
        ({"views": [42]}, "source.views[0]: got int; expected a dict"),
        ({"views": [{"depth": valid_view()["depth"]}]},
         "source.views[0].color: missing; expected an (H, W, 3) uint8 RGB array"),
    ],
)
def test_bad_scan(sift_pipeline, scan, message):
    with pytest.raises(ValueError) as error:
        sift_pipeline.register(scan, {"views": [valid_view()]})
    assert str(error.value).startswith(message), str(error.value)


def test_bad_view_object_is_named_like_a_dict(sift_pipeline):
    view = zeroreg.View(**valid_view())
    view.depth = view.depth[:, :-1]
    with pytest.raises(ValueError, match=re.escape("source.views[0].depth: shape (48, 63)")):
        sift_pipeline.register(zeroreg.Scan(views=[view]), {"views": [valid_view()]})


def test_input_error_from_cpp_is_a_value_error(sift_pipeline):
    # zeroreg::InputError thrown by the C++ loaders arrives as ValueError with its message.
    expected = f"{KITCHEN}: frame id 99999 not in the dataset"
    with pytest.raises(ValueError, match=re.escape(expected)):
        sift_pipeline.register(frame_spec(99999), frame_spec(0))
    with pytest.raises(ValueError, match="not found; expected DIR@N"):
        zeroreg.load_scan("no/such/scan")
    with pytest.raises(ValueError, match=re.escape("no/such.png")):
        zeroreg.read_depth("no/such.png")


def test_a_path_argument_of_another_type_is_a_type_error_naming_it():
    with pytest.raises(TypeError, match=re.escape("spec: got int; expected a path")):
        zeroreg.load_scan(5)
    with pytest.raises(TypeError, match=re.escape("path: got float; expected a path")):
        zeroreg.read_color(1.5)
    with pytest.raises(TypeError, match=re.escape("path: got NoneType; expected a path")):
        zeroreg.read_depth(None)


# Config messages come from the C++ config reader (zeroreg::ApplyConfigJson), whose exact
# punctuation is its own; the test pins what matters: the argument, the key and the problem.
@pytest.mark.parametrize(
    "config,seed,parts",
    [
        ({"features": {"max_kp": 10}}, None, ["config", "unknown key 'features.max_kp'"]),
        ({"object_match": {"seed": 3}}, None,
         ["config", "object_match.seed was removed", "top-level \"seed\""]),
        ({"lift": {"holes_are_edges": True}}, None, ["config", "lift.holes_are_edges was removed"]),
        ({"ransac": {"inlier_threshold_m": "5cm"}}, None,
         ["config", "ransac.inlier_threshold_m is \"5cm\"", "expected a number > 0"]),
        ({"ransac": {"confidence": 1.5}}, None, ["config", "ransac", "confidence", "(0, 1)"]),
        ({"features": {"backend": object()}}, None,
         ["config.features.backend: cannot use a value of type object"]),
        (42, None, ["config: expected None, a dict or the path of a JSON config file"]),
        ("no/such/config.json", None, ["no/such/config.json: config file not found"]),
        (None, -1, ["seed: -1 is not a non-negative 64-bit integer"]),
        (None, 1.5, ["seed: expected a non-negative int or None"]),
    ],
)
def test_bad_config(config, seed, parts):
    with pytest.raises(ValueError) as error:
        zeroreg.Pipeline(config, seed=seed)
    message = str(error.value)
    assert message.startswith(parts[0]), message
    position = 0
    for part in parts:  # in this order
        position = message.find(part, position)
        assert position >= 0, f"{part!r} not in {message!r}"
