"""Arrays that are well formed but cannot describe a real scan are refused where they enter, as a
ValueError naming the argument: a depth scale that gives depths no sensor measures, intrinsics
that fit no camera for the image, more views than a scan may hold, images over the pixel limit."""

import re

import numpy as np
import pytest
import zeroreg

H, W = 48, 64


def valid_view():
    return {
        "color": np.zeros((H, W, 3), np.uint8),
        "depth": np.full((H, W), 1500, np.uint16),
        "depth_scale": 1000.0,
        "intrinsics": np.array([[60.0, 0, 32], [0, 60.0, 24], [0, 0, 1]]),
    }


@pytest.fixture(scope="module")
def sift_pipeline():
    # Scans are checked before any image work, so these tests need no model.
    return zeroreg.Pipeline({"features": {"backend": "sift"}})


def refused(pipeline, source, message):
    with pytest.raises(ValueError) as error:
        pipeline.register(source, {"views": [valid_view()]})
    assert re.search(message, str(error.value)), str(error.value)


@pytest.mark.parametrize(
    "depth_scale,message",
    [
        (1.0, r"^source\.views\[0\]\.depth: source\.views\[0\]\.depth_scale = 1 gives depths "
              r"from 1500 to 1500 m .*expected a depth sensor's range"),
        (100000.0, r"^source\.views\[0\]\.depth: .*depth_scale = 100000 gives depths from 0\.015"),
        (1e-300, r"^source\.views\[0\]\.depth: .*depth_scale = 1e-300 gives an infinite depth"),
    ],
)
def test_depth_scale_giving_impossible_depths(sift_pipeline, depth_scale, message):
    view = valid_view()
    view["depth_scale"] = depth_scale
    refused(sift_pipeline, {"views": [view]}, message)


def test_float_depth_not_in_metres(sift_pipeline):
    view = valid_view()
    view["depth"], view["depth_scale"] = np.full((H, W), 1500.0, np.float32), None
    refused(sift_pipeline, {"views": [view]}, r"^source\.views\[0\]\.depth: depth in metres gives "
                                              r"depths from 1500 .*is the depth in metres\?")


@pytest.mark.parametrize(
    "K,message",
    [
        ([[1e-300, 0, 32], [0, 60, 24], [0, 0, 1]], r"focal length fx = 1e-300 pixels is "
                                                    r"implausible for a 64x48 image"),
        ([[60, 0, 1e300], [0, 60, 24], [0, 0, 1]], r"principal point cx = 1e\+300 pixels"),
        ([[60, 0, 32], [0, 1e9, 24], [0, 0, 1]], r"focal length fy = 1e\+09"),
    ],
)
def test_absurd_intrinsics(sift_pipeline, K, message):
    view = valid_view()
    view["intrinsics"] = np.array(K, np.float64)
    refused(sift_pipeline, {"views": [view]}, r"^source\.views\[0\]\.intrinsics: " + message)


def test_views_per_scan_are_bounded(sift_pipeline, monkeypatch):
    monkeypatch.setenv("ZEROREG_MAX_VIEWS", "2")
    refused(sift_pipeline, {"views": [valid_view()] * 3},
            r"^source\.views: holds 3 views, more than the limit of 2 .*ZEROREG_MAX_VIEWS")
    # The default (64) holds: 65 views are refused before any image is converted.
    monkeypatch.delenv("ZEROREG_MAX_VIEWS")
    refused(sift_pipeline, {"views": [valid_view()] * 65}, r"more than the limit of 64")


def test_arrays_over_the_pixel_limit(sift_pipeline, monkeypatch):
    # The limit of image files (ZEROREG_MAX_IMAGE_PIXELS) holds for arrays too, checked on the
    # colour array before any copy (depth must have the colour's shape); lowered here so the test
    # does not need gigabytes.
    monkeypatch.setenv("ZEROREG_MAX_IMAGE_PIXELS", str(H * W - 1))
    refused(sift_pipeline, {"views": [valid_view()]},
            rf"^source\.views\[0\]\.color: shape \({H}, {W}.*is {H * W} pixels, more than the "
            rf"limit of {H * W - 1} \(set ZEROREG_MAX_IMAGE_PIXELS")
