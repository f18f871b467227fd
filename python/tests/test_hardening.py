"""Issue 15: NaN config values, paths that are not UTF-8, and one Pipeline shared by threads."""

import os
import shutil
import threading

import numpy as np
import pytest
import zeroreg
from conftest import KITCHEN, frame_spec


def test_nan_thresholds_are_refused():
    # They used to switch the verdict off (valid with a 131 degree error).
    config = {"ransac": {"min_inlier_spread_m": float("nan"), "min_inlier_ratio": float("nan"),
                         "min_inliers": 3}}
    with pytest.raises(ValueError, match=r"config: ransac\.min_inlier_ratio is NaN"):
        zeroreg.Pipeline(config)


def test_integers_do_not_wrap():
    with pytest.raises(ValueError, match=r"ransac\.max_iterations is 4294967297"):
        zeroreg.Pipeline({"ransac": {"max_iterations": 4294967297}})


def odd_folder(tmp_path):
    """A copy of redkitchen frame 0 in a folder whose name is not UTF-8, as Python names it."""
    folder = os.path.join(os.fsencode(str(tmp_path)), b"bad\xffname")
    os.makedirs(folder)
    frames = os.path.join(KITCHEN, "frames")
    for name in ("frame-000000.color.jpg", "frame-000000.depth.png", "frame-000000.pose.txt"):
        shutil.copy(os.path.join(frames, name), os.path.join(os.fsdecode(folder), name))
    shutil.copy(os.path.join(KITCHEN, "camera-intrinsics.txt"), os.fsdecode(folder))
    return os.fsdecode(folder)  # str with a surrogate escape for the 0xff byte


def test_non_utf8_paths_load(tmp_path):
    folder = odd_folder(tmp_path)
    scan = zeroreg.load_scan(folder + "@0")
    assert "bad\udcffname" in scan.name  # the name round-trips as os.fsdecode gives it
    as_bytes = zeroreg.load_scan(os.fsencode(folder) + b"@0")
    assert as_bytes.views[0].color.shape == (480, 640, 3)
    assert zeroreg.read_color(os.path.join(folder, "frame-000000.color.jpg")).shape == (480, 640, 3)


def test_non_utf8_path_errors_are_value_errors_naming_the_file(tmp_path):
    missing = os.fsdecode(os.path.join(os.fsencode(str(tmp_path)), b"gone\xff"))
    with pytest.raises(ValueError, match="gone"):
        zeroreg.read_depth(missing)
    with pytest.raises(ValueError, match="gone"):
        zeroreg.load_scan(missing + "@0")


def test_wrong_path_type_is_a_type_error_naming_the_argument():
    with pytest.raises(TypeError, match="^path: got int"):
        zeroreg.read_color(3)


def test_threads_sharing_one_pipeline_get_the_single_threaded_result():
    pipeline = zeroreg.Pipeline()
    source, target = zeroreg.load_scan(frame_spec(20)), zeroreg.load_scan(frame_spec(0))
    reference = pipeline.register(source, target)
    results = []
    lock = threading.Lock()

    def work():
        for _ in range(2):
            r = pipeline.register(source, target)  # releases the GIL
            with lock:
                results.append(r)

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 6
    for r in results:
        np.testing.assert_array_equal(r.T_target_source, reference.T_target_source)
        assert r.valid == reference.valid
        assert len(r.source_objects) == len(reference.source_objects)
        assert len(r.target_objects) == len(reference.target_objects)
