"""Finds the module under test and provides the real frames the tests use.

The tests import the `zeroreg` installed in the running Python (pip install ./python, as
scripts/test.sh does into a venv), or the build tree's when $ZEROREG_PYTHONPATH is set, e.g.
ZEROREG_PYTHONPATH=build/python. Data: ../shared/data/7scenes-redkitchen beside the repository
this file is in (see its MANIFEST.md): 640x480 frames, depth in millimetres, camera-to-world poses.
"""

import os
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.environ.get("ZEROREG_PYTHONPATH"):
    sys.path.insert(0, os.environ["ZEROREG_PYTHONPATH"])

try:
    import zeroreg  # noqa: E402  (may need the path above)
except ImportError as e:
    raise ImportError(
        f"{e}; install the module (pip install --no-build-isolation ./python, docs/PYTHON.md) or "
        "set ZEROREG_PYTHONPATH=build/python, and run pytest from outside python/"
    ) from e

KITCHEN = os.path.join(REPO, "..", "shared", "data", "7scenes-redkitchen")


def frame_spec(n):
    return f"{KITCHEN}@{n}"


def frame_file(n, suffix):
    return os.path.join(KITCHEN, "frames", f"frame-{n:06d}.{suffix}")


def frame_pose(n):
    """Ground-truth camera -> world of frame n."""
    return np.loadtxt(frame_file(n, "pose.txt"))


def frame_view_dict(n, T_scan_camera=None):
    """Frame n as a view dict built from the files: RGB uint8, raw uint16 depth with scale."""
    view = {
        "color": zeroreg.read_color(frame_file(n, "color.jpg")),
        "depth": zeroreg.read_depth(frame_file(n, "depth.png")),
        "depth_scale": 1000.0,
        "intrinsics": np.loadtxt(os.path.join(KITCHEN, "camera-intrinsics.txt")),
        "name": f"frame {n}",
    }
    if T_scan_camera is not None:
        view["T_scan_camera"] = T_scan_camera
    return view


@pytest.fixture(scope="session")
def pipeline():
    """Default pipeline (XFeat), models loaded once for all tests."""
    return zeroreg.Pipeline()


@pytest.fixture(scope="session")
def gt_20_0():
    """Ground-truth T_target_source for source frame 20, target frame 0."""
    return np.linalg.inv(frame_pose(0)) @ frame_pose(20)


@pytest.fixture(scope="session")
def result_20_0_from_paths(pipeline):
    return pipeline.register(frame_spec(20), frame_spec(0))
