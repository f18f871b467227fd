"""zeroreg.verify: the geometric check behind Result.valid, on real redkitchen frames."""

import numpy as np
import pytest
import zeroreg
from conftest import frame_spec


def _shift(T, metres):
    D = np.eye(4)
    D[0, 3] = metres
    return D @ T


def test_ground_truth_passes_and_a_30cm_shift_fails(gt_20_0):
    source, target = frame_spec(20), frame_spec(0)
    good = zeroreg.verify(source, target, gt_20_0)
    assert good["passed"], good["reason"]
    assert good["overlap"] > 0.5 and good["violation"] < 0.05
    bad = zeroreg.verify(source, target, _shift(gt_20_0, 0.3))
    assert not bad["passed"], bad["reason"]
    assert bad["score"] < good["score"]


def test_result_carries_its_verification(result_20_0_from_paths):
    d = result_20_0_from_paths.to_dict()
    assert d["verification"]["passed"] == result_20_0_from_paths.valid
    assert any(c["chosen"] for c in d["candidates"])


def test_verify_rejects_a_bad_matrix():
    with pytest.raises(ValueError):
        zeroreg.verify(frame_spec(20), frame_spec(0), np.eye(3))


def test_refine_pulls_a_shifted_estimate_back(gt_20_0):
    # ICP from the ground truth moved 4 cm sideways converges back near it (redkitchen 20 -> 0 has
    # rich geometry), and the refined transform scores better than the shifted one.
    source, target = frame_spec(20), frame_spec(0)
    start = _shift(gt_20_0, 0.04)
    refined = zeroreg.refine(source, target, start)
    T = refined["T_target_source"]
    assert T.shape == (4, 4)
    assert zeroreg.translation_error_m(T, gt_20_0) < 0.02
    assert zeroreg.translation_error_m(start, gt_20_0) > 0.039
    assert 0.3 < refined["fitness"] <= 1.0 and refined["iterations"] > 0
    assert zeroreg.verify(source, target, T)["score"] > zeroreg.verify(source, target, start)["score"]


def test_refine_rejects_a_bad_matrix():
    with pytest.raises(ValueError):
        zeroreg.refine(frame_spec(20), frame_spec(0), np.eye(3))
