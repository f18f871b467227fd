"""Registration through the Python module on real 7-Scenes redkitchen frames, 20 -> 0.

Ground truth: T_target_source = inv(P_0) @ P_20 from the dataset's camera-to-world poses. The
tolerance (5 deg, 10 cm) is the ScanNet-style success criterion; the CLI measures 0.3 deg / 0.6 cm
on this pair, so a wrong convention (RGB/BGR swap, transposed pose, wrong depth scale) fails it.
"""

import json
import os

import numpy as np
import pytest
import zeroreg
from conftest import REPO, frame_file, frame_pose, frame_spec, frame_view_dict


def assert_close_to_gt(result, T_gt):
    assert result.valid, result.reason
    T = result.T_target_source
    assert T.shape == (4, 4) and T.dtype == np.float64
    assert zeroreg.rotation_error_deg(T, T_gt) < 5.0
    assert zeroreg.translation_error_m(T, T_gt) < 0.10


def test_paths_land_on_ground_truth(result_20_0_from_paths, gt_20_0):
    assert_close_to_gt(result_20_0_from_paths, gt_20_0)
    assert result_20_0_from_paths.path in ("object", "image-fallback")


def test_numpy_uint16_depth_gives_the_same_result_as_paths(pipeline, result_20_0_from_paths):
    # The same pixels given as arrays (RGB, raw uint16 millimetres + depth_scale) must give
    # exactly the CLI's answer: any difference means the array conversion differs from the files'.
    r = pipeline.register({"views": [frame_view_dict(20)]}, {"views": [frame_view_dict(0)]})
    np.testing.assert_array_equal(r.T_target_source, result_20_0_from_paths.T_target_source)
    np.testing.assert_array_equal(r.source_points, result_20_0_from_paths.source_points)


def _png_rgb(width, height, pixels):
    """A minimal 8-bit RGB PNG (no filter) built with the standard library."""
    import struct
    import zlib

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    rows = b"".join(b"\x00" + pixels[3 * width * y:3 * width * (y + 1)] for y in range(height))
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows))
            + chunk(b"IEND", b""))


def test_read_color_returns_rgb(tmp_path):
    # A PNG stores RGB bytes in order, independently of OpenCV's BGR convention.
    path = tmp_path / "rgb.png"
    pixels = bytes([255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30])  # red, green, blue, mixed
    path.write_bytes(_png_rgb(2, 2, pixels))
    color = zeroreg.read_color(str(path))
    assert color.shape == (2, 2, 3) and color.dtype == np.uint8
    expected = np.frombuffer(pixels, np.uint8).reshape(4, 3)
    np.testing.assert_array_equal(color.reshape(4, 3), expected)


def test_read_color_refuses_other_formats_naming_the_file(tmp_path):
    path = tmp_path / "rgb.ppm"
    path.write_bytes(b"P6\n2 2\n255\n" + bytes(12))
    with pytest.raises(ValueError, match=r"rgb\.ppm.*expected a PNG or JPEG file"):
        zeroreg.read_color(str(path))


def test_load_scan_round_trip_with_float_metres(pipeline, result_20_0_from_paths, gt_20_0):
    source = zeroreg.load_scan(frame_spec(20))
    target = zeroreg.load_scan(frame_spec(0))
    view = source.views[0]
    assert view.color.shape == (480, 640, 3) and view.color.dtype == np.uint8
    assert view.depth.shape == (480, 640) and view.depth.dtype == np.float32
    assert view.depth_scale is None
    np.testing.assert_array_equal(view.intrinsics, [[585, 0, 320], [0, 585, 240], [0, 0, 1]])
    np.testing.assert_array_equal(view.T_scan_camera, np.eye(4))
    # Loaded colour is RGB: equal to read_color of the same file.
    np.testing.assert_array_equal(view.color, zeroreg.read_color(frame_file(20, "color.jpg")))
    # Depth is raw / 1000 with 0 and 65535 invalid.
    raw = zeroreg.read_depth(frame_file(20, "depth.png"))
    expected = np.where((raw == 0) | (raw == 65535), 0, raw / 1000.0).astype(np.float32)
    np.testing.assert_array_equal(view.depth, expected)
    # Ground truth of a single frame is its pose.
    np.testing.assert_allclose(source.T_world_scan_gt, frame_pose(20))
    np.testing.assert_allclose(
        np.linalg.inv(target.T_world_scan_gt) @ source.T_world_scan_gt, gt_20_0, atol=1e-12
    )

    r = pipeline.register(source, target)  # zeroreg.Scan objects go back in unchanged
    np.testing.assert_array_equal(r.T_target_source, result_20_0_from_paths.T_target_source)


def test_scan_and_view_objects(pipeline, gt_20_0):
    src = zeroreg.Scan(views=[zeroreg.View(**frame_view_dict(20))], name="frame 20")
    tgt = zeroreg.Scan(views=[zeroreg.View(**frame_view_dict(0))])
    assert_close_to_gt(pipeline.register(src, tgt), gt_20_0)


def test_two_views_per_scan_use_the_camera_poses(pipeline, gt_20_0):
    # Each scan holds two frames; the second view's pose places it in the first camera's frame
    # (T_scan_camera = inv(P_first) @ P_second). Correspondences from the second view pair are
    # only consistent with the first pair's if the poses are applied correctly.
    def scan(first, second):
        T = np.linalg.inv(frame_pose(first)) @ frame_pose(second)
        return {"views": [frame_view_dict(first), frame_view_dict(second, T_scan_camera=T)]}

    r = pipeline.register(scan(20, 30), scan(0, 10))
    assert_close_to_gt(r, gt_20_0)
    views = r.correspondence_views
    assert set(np.unique(views)) == {0, 1}
    # Both view pairs contribute inliers under the final transform.
    assert r.is_inlier[views == 1].sum() > 50
    assert r.is_inlier[views == 0].sum() > 50


def test_optional_point_cloud_is_accepted():
    view = frame_view_dict(20)
    pts = np.random.default_rng(0).uniform(-1, 1, size=(100, 3)).astype(np.float32)
    # Only the ICP refinement reads the cloud; without it the answer is the one without the cloud.
    no_icp = zeroreg.Pipeline({"refine": {"enabled": False}})
    with_cloud = no_icp.register({"views": [view], "points": pts}, frame_spec(0))
    without = no_icp.register({"views": [view]}, frame_spec(0))
    assert with_cloud.valid
    np.testing.assert_array_equal(with_cloud.T_target_source, without.T_target_source)


def test_result_fields_are_consistent(result_20_0_from_paths):
    r = result_20_0_from_paths
    n = r.counts["correspondences"]
    assert n > 100
    assert r.source_points.shape == (n, 3) and r.target_points.shape == (n, 3)
    assert r.source_pixels.shape == (n, 2) and r.target_pixels.shape == (n, 2)
    assert r.is_inlier.shape == (n,) and r.is_inlier.dtype == np.bool_
    assert r.scores.shape == (n,) and r.correspondence_views.shape == (n,)
    assert r.correspondence_target_views.shape == (n,)
    assert r.is_inlier.sum() == r.counts["inliers"]
    assert r.inlier_ratio == pytest.approx(r.counts["inliers"] / n)
    # Inliers agree with the transform within the RANSAC threshold (5 cm by default).
    T = r.T_target_source
    moved = r.source_points[r.is_inlier] @ T[:3, :3].T + T[:3, 3]
    assert np.linalg.norm(moved - r.target_points[r.is_inlier], axis=1).max() <= 0.05 + 1e-9
    # Pixels lie inside the 640x480 images (pixel centres at integers: pixel 0 spans -0.5..0.5).
    for pixels in (r.source_pixels, r.target_pixels):
        assert (pixels >= -0.5).all()
        assert (pixels[:, 0] < 639.5).all() and (pixels[:, 1] < 479.5).all()
    assert list(r.timings)[-1] == "total" and all(v >= 0 for v in r.timings.values())
    assert "valid" in repr(r)


def test_to_dict_is_the_cli_json(result_20_0_from_paths):
    r = result_20_0_from_paths
    d = r.to_dict()
    json.dumps(d)  # plain JSON types only
    assert d["valid"] is True and d["path"] == r.path and d["reason"] == r.reason
    np.testing.assert_array_equal(np.array(d["T_target_source"]), r.T_target_source)
    assert d["counts"] == r.counts
    assert "correspondences" not in d  # like the CLI without --with-correspondences
    full = r.to_dict(correspondences=True)
    assert len(full["correspondences"]) == r.counts["correspondences"]
    first = full["correspondences"][0]
    np.testing.assert_array_equal(first["source"], r.source_points[0])
    assert first["inlier"] == bool(r.is_inlier[0])


def test_determinism_same_seed_same_everything(pipeline):
    a = pipeline.register(frame_spec(20), frame_spec(0))
    b = zeroreg.register(frame_spec(20), frame_spec(0), seed=0)
    np.testing.assert_array_equal(a.T_target_source, b.T_target_source)
    np.testing.assert_array_equal(a.source_points, b.source_points)
    np.testing.assert_array_equal(a.is_inlier, b.is_inlier)
    assert a.to_dict()["counts"] == b.to_dict()["counts"]


def test_config_dict_and_seed(gt_20_0):
    config = {"features": {"backend": "sift", "max_keypoints": 2000}, "ransac": {"min_inliers": 12}}
    p = zeroreg.Pipeline(config, seed=7)
    assert p.config["features"]["backend"] == "sift"
    assert p.config["features"]["max_keypoints"] == 2000
    assert p.config["ransac"]["min_inliers"] == 12
    assert p.config["seed"] == 7
    # Untouched keys keep the defaults.
    assert p.config["match"] == zeroreg.default_config()["match"]
    r = p.register(frame_spec(20), frame_spec(0))
    assert r.counts["keypoints_source"] <= 2000
    assert_close_to_gt(r, gt_20_0)
    # numpy scalars in a config are plain numbers.
    p2 = zeroreg.Pipeline({"ransac": {"inlier_threshold_m": np.float64(0.03)}})
    assert p2.config["ransac"]["inlier_threshold_m"] == 0.03


def test_config_file_path(tmp_path):
    path = tmp_path / "config.json"
    path.write_text(json.dumps({"features": {"backend": "sift"}, "seed": 3}))
    p = zeroreg.Pipeline(path)
    assert p.config["features"]["backend"] == "sift" and p.config["seed"] == 3


def test_error_measures_on_exact_transforms():
    angle = np.radians(10.0)
    T_gt = np.eye(4)
    T = np.eye(4)
    T[:3, :3] = [[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]]
    T[:3, 3] = [0.03, 0.0, 0.04]
    assert zeroreg.rotation_error_deg(T, T_gt) == pytest.approx(10.0, abs=1e-9)
    assert zeroreg.translation_error_m(T, T_gt) == pytest.approx(0.05, abs=1e-12)
    with pytest.raises(ValueError, match=r"^T_gt: element \[0, 0\] is NaN"):
        zeroreg.rotation_error_deg(T, np.full((4, 4), np.nan))


def test_objects_and_matches_are_consistent(result_20_0_from_paths):
    # Object lists are empty when the pipeline ran the image path only; whatever is there must be
    # well formed and the matches must index into the object lists.
    r = result_20_0_from_paths
    for objects in (r.source_objects, r.target_objects):
        assert isinstance(objects, list)
        for o in objects:
            assert isinstance(o["label"], str) and o["centroid"].shape == (3,)
            for v in o["views"]:
                assert len(v["box"]) == 4 and v["outline"].shape[1:] == (2,)
    for m in r.object_matches:
        assert 0 <= m["source"] < len(r.source_objects)
        assert 0 <= m["target"] < len(r.target_objects)
        # Point support (object_match.min_point_support, default 4): every match has at least that
        # many rigidly consistent point matches. (They may exceed num_correspondences: where two
        # objects' masks overlap, a keypoint pair goes to the estimator once, counted by one pair.)
        assert m["point_support"] >= 4
    # One to one, whatever the checks dropped and object_match.complete_by_motion added (a dropped
    # match's object may get another partner, so kept + rejected can exceed the object lists).
    assert isinstance(r.rejected_object_matches, int) and r.rejected_object_matches >= 0
    assert len({m["source"] for m in r.object_matches}) == len(r.object_matches)
    assert len({m["target"] for m in r.object_matches}) == len(r.object_matches)


def test_default_config_is_accepted_back():
    # The whole default config, as Python returns it, must be a valid config: its unsigned 64-bit
    # settings (object_match.max_exact_assignments) arrive as Python ints, i.e. signed integers.
    config = zeroreg.default_config()
    assert isinstance(config["object_match"]["max_exact_assignments"], int)
    p = zeroreg.Pipeline(config)
    assert p.config == zeroreg.default_config()
    config["object_match"]["max_exact_assignments"] = -1
    with pytest.raises(ValueError, match="max_exact_assignments"):
        zeroreg.Pipeline(config)


def test_depth_noise_is_measured_from_the_depth():
    # Kinect v1: about its published 1.5 mm at 1 m. Adding sigma = 0.01 d^2 noise to the same
    # depth makes it measure about sqrt(0.01^2 + a^2).
    view = frame_view_dict(0)
    a = zeroreg.depth_noise_at_1m_m({"views": [view]})
    assert 0.0012 < a < 0.0022
    rng = np.random.default_rng(0)
    raw = view["depth"]
    valid = (raw > 0) & (raw < 65535)  # 7-Scenes marks missing depth with 0 and 65535
    depth_m = np.where(valid, raw.astype(np.float64) / view.get("depth_scale", 1000.0), 0.0)
    noisy = depth_m + 0.01 * depth_m**2 * rng.standard_normal(depth_m.shape)
    noisy_view = dict(view, depth=np.where(valid & (noisy > 0), noisy, 0.0).astype(np.float32))
    noisy_view.pop("depth_scale", None)
    b = zeroreg.depth_noise_at_1m_m({"views": [noisy_view]})
    assert abs(b - np.hypot(0.01, a)) < 0.001


def test_agree_with_result_only_filters_the_reported_matches():
    # object_match.agree_with_result (default on) judges the object matches against the valid
    # result's transform: on redkitchen 20 <- 80 it drops a wrong chair; the transform, verdict
    # and path stay bit for bit, and the dropped matches are counted as rejected.
    assert zeroreg.default_config()["object_match"]["agree_with_result"] is True
    off = zeroreg.Pipeline({"object_match": {"agree_with_result": False}})
    on = zeroreg.Pipeline({})
    a = off.register(frame_spec(80), frame_spec(20))
    b = on.register(frame_spec(80), frame_spec(20))
    assert b.valid
    np.testing.assert_array_equal(a.T_target_source, b.T_target_source)
    assert (a.valid, a.path) == (b.valid, b.path)
    kept = {(m["source"], m["target"]) for m in b.object_matches}
    assert kept < {(m["source"], m["target"]) for m in a.object_matches}
    dropped = len(a.object_matches) - len(b.object_matches)
    assert b.rejected_object_matches == a.rejected_object_matches + dropped


def test_motion_prior(pipeline, result_20_0_from_paths, gt_20_0):
    # A prior that holds the right pose changes nothing; one that does not makes the result
    # invalid and says why; a prior that is no rigid transform is refused by name.
    near = gt_20_0.copy()
    near[:3, 3] += [0.05, 0.0, 0.0]
    r = pipeline.register(frame_spec(20), frame_spec(0), prior=near)
    np.testing.assert_array_equal(r.T_target_source, result_20_0_from_paths.T_target_source)
    assert r.valid and not r.outside_prior and r.reason == result_20_0_from_paths.reason
    far = gt_20_0.copy()
    far[:3, 3] += [1.0, 0.0, 0.0]
    r = pipeline.register(frame_spec(20), frame_spec(0), prior=far, prior_max_translation_m=0.2)
    assert not r.valid and r.outside_prior  # the check passed; the prior refused it
    # The refusal as data: the translation from the prior (about the 1 m it is off) beyond 0.2 m.
    assert r.refusal["test"] == "outside_prior" and r.refusal["threshold"] == 0.2, r.refusal
    assert 0.8 < r.refusal["measured"] < 1.2, r.refusal
    # The prior refused the method's estimate, so the fallback and every hypothesis ran, each
    # passed by the check and refused by the prior, and ICP from the prior (1 m off) was judged
    # and not taken.
    candidates = r.to_dict()["candidates"]
    for source in ("image-fallback", "object clique", "geometry clique"):
        assert any(c["name"].startswith(source) and c["passed"] and c["outside_prior"]
                   for c in candidates), (source, candidates)
    assert any(c["name"] == "prior" and not c["chosen"] for c in candidates), candidates
    assert "hypothesis prior" in r.timings, r.timings
    with pytest.raises(ValueError) as error:
        pipeline.register(frame_spec(20), frame_spec(0), prior=2 * np.eye(4))
    assert "prior" in str(error.value)
    with pytest.raises(ValueError) as error:
        pipeline.register(frame_spec(20), frame_spec(0), prior=near, prior_max_rotation_deg=-1)
    assert "motion prior tolerance" in str(error.value)
    with pytest.raises(TypeError) as error:
        pipeline.register(frame_spec(20), frame_spec(0), prior=near, prior_max_translation_m=None)
    assert "prior_max_translation_m" in str(error.value)


def test_refusal_is_data_none_when_valid(result_20_0_from_paths):
    assert result_20_0_from_paths.valid and result_20_0_from_paths.refusal is None
    strict = zeroreg.Pipeline({"ransac": {"min_inliers": 100000}, "hypotheses": {"enabled": False}})
    r = strict.register(frame_spec(20), frame_spec(0))
    assert not r.valid
    assert r.refusal == {"test": "few_inliers", "measured": float(r.counts["inliers"]),
                         "threshold": 100000.0}


def test_ambiguous_result_lists_both_poses():
    # A TUM cabinet pair seen from opposite sides (co-visibility 0.26 under the ground truth): a
    # turned pose fits as well as the reported one, so the result is not valid but ambiguous,
    # both poses listed, the reported one first.
    cabinet = os.path.join(REPO, "..", "shared", "data", "tum-fr3-cabinet")
    # Its winner has image inliers (4 or more: decisive by default), so the search is asked to
    # look at winners with fewer than 50.
    pipeline = zeroreg.Pipeline({"ambiguity": {"decisive_inliers": 50}})
    r = pipeline.register(f"{cabinet}@31", f"{cabinet}@9")
    assert not r.valid and r.ambiguous, r.reason
    assert r.refusal["test"] == "ambiguous"
    assert len(r.alternatives) >= 2
    first, second = r.alternatives[0], r.alternatives[1]
    np.testing.assert_array_equal(first["T_target_source"], r.T_target_source)
    assert second["T_target_source"].shape == (4, 4)
    assert second["apart_m"] > r.refusal["threshold"]
    assert zeroreg.rotation_error_deg(first["T_target_source"], second["T_target_source"]) > 45
    d = r.to_dict()
    assert d["ambiguous"] is True and len(d["alternatives"]) == len(r.alternatives)


def test_unambiguous_result_has_no_alternatives(result_20_0_from_paths):
    assert result_20_0_from_paths.valid
    assert not result_20_0_from_paths.ambiguous
    assert result_20_0_from_paths.alternatives == []
