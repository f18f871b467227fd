"""zeroreg: register two RGB-D scans (ZeroReg, CVPR 2025) from Python.

    import zeroreg
    r = zeroreg.register("../shared/data/7scenes-redkitchen@20",
                         "../shared/data/7scenes-redkitchen@0")
    if r.valid:
        print(r.T_target_source)      # 4x4 numpy float64, maps source points into the target frame

A scan is a path specification (anything the CLI accepts: "DIR@N", a scan.json or its folder, a
3DMatch frame-XXXXXX.color.{jpg,png}), a `Scan`, or a dict with the same fields as `Scan` and
`View`. Arrays follow Python conventions: colour is RGB. All bad input raises ValueError whose
message starts with the offending argument, e.g. "source.views[0].depth: ...". See docs/PYTHON.md.
"""

import dataclasses
import os
from dataclasses import dataclass, field
from typing import Any, List, Optional, Union

import numpy as np

from . import _zeroreg
from ._zeroreg import (
    PreparedScan,
    Result,
    default_config,
    open3d_module_path,
    read_color,
    read_depth,
    rotation_error_deg,
    translation_error_m,
)
from ._zeroreg import depth_noise_at_1m_m as _depth_noise_at_1m_m
from ._zeroreg import refine as _refine
from ._zeroreg import verify as _verify

# The project version (CMakeLists.txt), compiled into the module: the same as `zeroreg --version`.
__version__ = _zeroreg.__version__

__all__ = [
    "Pipeline",
    "PreparedScan",
    "Result",
    "Scan",
    "View",
    "close_loops",
    "default_config",
    "depth_noise_at_1m_m",
    "load_scan",
    "merge",
    "open3d_module_path",
    "read_color",
    "read_depth",
    "refine",
    "register",
    "rotation_error_deg",
    "translation_error_m",
    "verify",
]


@dataclass
class View:
    """One posed RGB-D image.

    color: (H, W, 3) uint8, RGB order.
    depth: (H, W) uint16 raw sensor units together with depth_scale (raw units per metre: 1000
        for millimetres, 5000 for TUM; 0 and 65535 mean "no measurement"), or (H, W) float32
        metres with depth_scale None (0 means "no measurement"; NaN is an error).
    intrinsics: 3x3 camera matrix [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] in pixels.
    T_scan_camera: 4x4 rigid transform camera -> scan frame (identity for a single frame).
    T_world_camera_gt: optional ground-truth camera -> world, used only for evaluation.
    """

    color: np.ndarray
    depth: np.ndarray
    intrinsics: Any
    T_scan_camera: Any = field(default_factory=lambda: np.eye(4))
    depth_scale: Optional[float] = None
    name: str = ""
    T_world_camera_gt: Any = None


@dataclass
class Scan:
    """What is registered: one or more posed views plus an optional point cloud.

    points: optional (N, 3) float array in the scan frame, metres.
    colors: optional (N, 3) float RGB in [0, 1], one per point.
    T_world_scan_gt: optional ground-truth scan -> world, used only for evaluation.
    """

    views: List[View]
    points: Any = None
    colors: Any = None
    name: str = ""
    T_world_scan_gt: Any = None


ScanLike = Union[str, "os.PathLike[str]", Scan, dict]


def _fields(obj: Any) -> dict:
    """A dataclass as a shallow dict (dataclasses.asdict would deep-copy the arrays)."""
    return {f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)}


def _number(value: Any, where: str) -> float:
    """A real number argument as a float; anything else (None, a string) is a TypeError naming it."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{where}: got {type(value).__name__}; expected a number")
    return float(value)


def _native(scan: Any, where: str) -> Union[str, dict, PreparedScan]:
    """A scan as the compiled module takes it: a path string, a dict of dicts or a PreparedScan."""
    if isinstance(scan, PreparedScan):
        return scan
    if isinstance(scan, (str, bytes, os.PathLike)):
        return os.fspath(scan)
    if isinstance(scan, Scan):
        scan = _fields(scan)
    if not isinstance(scan, dict):
        raise ValueError(
            f"{where}: got {type(scan).__name__}; expected a path string, a zeroreg.Scan "
            "or a dict with 'views'"
        )
    views = scan.get("views")
    if isinstance(views, (list, tuple)):
        scan = dict(scan)
        scan["views"] = [_fields(v) if isinstance(v, View) else v for v in views]
    return scan


def load_scan(
    spec: Union[str, bytes, "os.PathLike[str]"], depth_scale: Optional[float] = None
) -> Scan:
    """Loads a scan from disk like the CLI does and returns it as arrays.

    spec: "DIR@N" (frame N of a 3DMatch / TUM / ScanNet folder), a scan.json or its folder, or a
        3DMatch frame-XXXXXX.color.{jpg,png}.
    depth_scale: raw depth units per metre; None = the layout's default (1000, TUM 5000).
    The returned views hold RGB colour and float32 depth in metres (depth_scale None).
    """
    # The compiled module takes str, bytes and os.PathLike itself (TypeError naming `spec` else).
    d = _zeroreg.load_scan(spec, 0.0 if depth_scale is None else float(depth_scale))
    d["views"] = [View(**v) for v in d["views"]]
    return Scan(**d)


class Pipeline:
    """Loads the models once; call register() for each pair.

    config: None (defaults), a dict with the keys of the JSON config (docs/CONFIG.md, e.g.
        {"features": {"backend": "sift"}, "ransac": {"inlier_threshold_m": 0.05}}), or the path
        of a JSON config file. Unknown keys raise ValueError.
    seed: overrides config["seed"] when not None.
    """

    def __init__(self, config: Union[None, dict, str] = None, seed: Optional[int] = None):
        self._impl = _zeroreg.Pipeline(config, seed)

    @property
    def config(self) -> dict:
        """The effective config, as the JSON config dict."""
        return self._impl.config

    def register(
        self,
        source: Union[ScanLike, PreparedScan],
        target: Union[ScanLike, PreparedScan],
        prior: Any = None,
        prior_max_rotation_deg: float = 15.0,
        prior_max_translation_m: float = 0.30,
    ) -> Result:
        """Registers source to target; the result's T_target_source maps source into target.

        Either may be a PreparedScan from prepare(): the result is the same, bit for bit, and what
        depends on that scan alone is not computed again.

        prior: what is already known of T_target_source (4x4, e.g. from odometry), or None. With
        it, only a pose within prior_max_rotation_deg and prior_max_translation_m of it can be
        valid, and ICP from the prior itself is tried when no source gives one (path "prior icp").
        Scans of symmetric content agree under a flipped pose as well as under the true one; the
        prior tells them apart (README "Symmetric scenes").
        """
        return self._impl.register(
            _native(source, "source"),
            _native(target, "target"),
            prior,
            _number(prior_max_rotation_deg, "prior_max_rotation_deg"),
            _number(prior_max_translation_m, "prior_max_translation_m"),
        )

    def prepare(self, scan: ScanLike, as_target: bool = True) -> PreparedScan:
        """Everything of the pipeline that depends on one scan alone (features, detections, masks,
        objects, the clouds of verification and ICP), done once. Pass the result to register() as
        often as needed, with this Pipeline only; it is immutable and may be shared by threads.
        as_target=False for a scan that will only be a source: ICP's target geometry (normals,
        k-d tree) is then made the first time it is a target, if ever; results are the same."""
        return self._impl.prepare(_native(scan, "scan"), bool(as_target))


def register(
    source: ScanLike,
    target: ScanLike,
    config: Union[None, dict, str] = None,
    seed: Optional[int] = None,
    prior: Any = None,
    prior_max_rotation_deg: float = 15.0,
    prior_max_translation_m: float = 0.30,
) -> Result:
    """One-call registration: Pipeline(config, seed).register(source, target, prior, ...)."""
    return Pipeline(config, seed).register(
        source, target, prior, prior_max_rotation_deg, prior_max_translation_m
    )


def refine(
    source: ScanLike,
    target: ScanLike,
    T_target_source: Any,
    config: Union[None, dict, str] = None,
) -> dict:
    """The pipeline's ICP refinement (config "refine", docs/CONFIG.md) from any initial transform.

    Coarse-to-fine point-to-plane ICP on every other depth pixel of both scans (refine.pixel_stride;
    every 4th where the depth is noisy, see depth_noise_at_1m_m), starting from
    T_target_source (4x4, e.g. odometry). Nothing anchors it and nothing checks it: pass the result
    to verify() before trusting it. Returns a dict: T_target_source (4x4 array), fitness (fraction
    of source points with a target point within the last stage's gate), rmse_m, iterations.
    """
    return _refine(
        _native(source, "source"), _native(target, "target"), np.asarray(T_target_source), config
    )


def depth_noise_at_1m_m(scan: ScanLike) -> Optional[float]:
    """How noisy the scan's depth is: a of sigma(d) = a d^2, in metres at 1 m, measured from its
    depth images (second differences of 1/d on the pixel grid, median absolute deviation; the
    median over its views). Kinect v1 frames measure about 0.0017. None when the scan has no
    measurable depth image. docs/CONFIG.md, "Depth noise"."""
    return _depth_noise_at_1m_m(_native(scan, "scan"))


def verify(
    source: ScanLike,
    target: ScanLike,
    T_target_source: Any,
    config: Union[None, dict, str] = None,
) -> dict:
    """Geometric check of a transform (the check behind Result.valid, docs/CONFIG.md "verify").

    Each scan's depth is rendered into the other scan's views under T_target_source (4x4, maps
    source points into the target frame). Returns a dict: passed, reason, overlap, overlap_max,
    violation, residual_rms_m, score, probe_contradicted, degenerate, source_samples, target_samples.
    """
    return _verify(
        _native(source, "source"), _native(target, "target"), np.asarray(T_target_source), config
    )


def _recordings_result(result: dict) -> dict:
    """Transforms of a recordings result as 4x4 float64 arrays; trajectories keyed by int id."""
    result["T_A_B"] = np.asarray(result["T_A_B"], dtype=np.float64)
    for k in result["keyframes"]:
        k["T_before"] = np.asarray(k["T_before"], dtype=np.float64)
        k["T_after"] = np.asarray(k["T_after"], dtype=np.float64)
    for c in result["candidates"]:
        c["T_u_v"] = np.asarray(c["T_u_v"], dtype=np.float64)
    result["trajectories"] = [
        {int(i): np.asarray(T, dtype=np.float64) for i, T in t.items()}
        for t in result["trajectories"]
    ]
    return result


def merge(
    a: Union[str, os.PathLike],
    b: Union[str, os.PathLike],
    out: Union[None, str, os.PathLike] = None,
    poses_a: Any = "auto",
    poses_b: Any = "auto",
    config: Union[None, dict, str] = None,
    seed: Optional[int] = None,
    **options: Any,
) -> dict:
    """Recording B placed in recording A's frame, as `zeroreg merge A B --out OUT` (same result).

    a, b: "DIR" or "DIR@FIRST-LAST" (frame ids). poses_*: "auto" (the dataset's own poses when it
    has them), "gt", "none", a TUM trajectory file (first column the frame id), or a dict
    {frame id: 4x4 camera-to-recording pose}. options: RecordingsConfig fields
    (docs/RECORDINGS.md), e.g. candidates_per_keyframe=5, progress=False. Returns a dict: found,
    reason, T_A_B (4x4, maps B's frame into A's), keyframes, candidates (with their verdicts),
    trajectories ([A, B] in A's frame, {frame id: 4x4}), stages (seconds, peak RSS)."""
    return _recordings_result(
        _zeroreg.merge(a, b, poses_a, poses_b, out, config, seed, dict(options))
    )


def close_loops(
    sequence: Union[str, os.PathLike],
    odometry: Any = "auto",
    out: Union[None, str, os.PathLike] = None,
    config: Union[None, dict, str] = None,
    seed: Optional[int] = None,
    **options: Any,
) -> dict:
    """Loop closures of one sequence and its optimised trajectory, as `zeroreg loops SEQ
    --odometry ODOMETRY --out OUT`; arguments and result as merge() (trajectories: [sequence])."""
    return _recordings_result(
        _zeroreg.close_loops(sequence, odometry, out, config, seed, dict(options))
    )
