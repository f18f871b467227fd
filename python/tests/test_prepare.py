"""Pipeline.prepare (issue 13): a prepared scan registers exactly like the scan itself, can be
reused across pairs and threads, and is refused by another Pipeline.

Real 7-Scenes redkitchen frames 20 -> 0 and 40 -> 20; the result must also be right (within 5 deg
and 10 cm of the dataset poses), so that two equally broken results cannot pass.
"""

import threading

import numpy as np
import pytest
import zeroreg
from conftest import frame_pose, frame_spec


def gt(source, target):
    return np.linalg.inv(frame_pose(target)) @ frame_pose(source)


def test_prepared_scans_register_bit_for_bit_like_scans(pipeline, result_20_0_from_paths):
    a = pipeline.prepare(frame_spec(20))
    b = pipeline.prepare(frame_spec(0))
    assert isinstance(a, zeroreg.PreparedScan) and a.num_views == 1
    assert a.memory_bytes > 1 << 20 and "features" in a.timings
    r = pipeline.register(a, b)
    np.testing.assert_array_equal(r.T_target_source, result_20_0_from_paths.T_target_source)
    assert r.valid == result_20_0_from_paths.valid
    assert r.counts == result_20_0_from_paths.counts
    assert r.inlier_rmse == result_20_0_from_paths.inlier_rmse
    assert zeroreg.rotation_error_deg(r.T_target_source, gt(20, 0)) < 5.0
    assert zeroreg.translation_error_m(r.T_target_source, gt(20, 0)) < 0.10
    # Only the pair's stages ran: perception was done by prepare().
    assert "features" not in r.timings and "estimate" in r.timings
    # A prepared scan mixes with a plain one.
    mixed = pipeline.register(a, frame_spec(0))
    np.testing.assert_array_equal(mixed.T_target_source, r.T_target_source)


def test_a_prepared_scan_is_reused_across_pairs_and_threads(pipeline):
    frame_20 = pipeline.prepare(frame_spec(20))
    expected = pipeline.register(frame_spec(40), frame_spec(20))
    as_target = {}

    def run():
        as_target["r"] = pipeline.register(frame_spec(40), frame_20)

    worker = threading.Thread(target=run)
    worker.start()
    as_source = pipeline.register(frame_20, frame_spec(0))
    worker.join()
    np.testing.assert_array_equal(as_target["r"].T_target_source, expected.T_target_source)
    assert zeroreg.translation_error_m(as_source.T_target_source, gt(20, 0)) < 0.10


def test_a_scan_prepared_as_source_only_can_still_be_a_target(pipeline, result_20_0_from_paths):
    a = pipeline.prepare(frame_spec(20), as_target=False)
    b = pipeline.prepare(frame_spec(0), as_target=False)
    r = pipeline.register(a, b)
    np.testing.assert_array_equal(r.T_target_source, result_20_0_from_paths.T_target_source)
    assert r.valid == result_20_0_from_paths.valid


def test_prepared_scan_of_another_pipeline_is_refused(pipeline):
    other = zeroreg.Pipeline()
    a = other.prepare(frame_spec(20))
    with pytest.raises(ValueError, match="prepared by another Pipeline"):
        pipeline.register(a, frame_spec(0))
