#!/usr/bin/env python3
"""Writes a many-view scan: a fused fragment's cloud with more of its frames as views.

    python3 scripts/make-multiview-scan.py FRAGMENT_DIR DATA_DIR OUT_DIR FIRST LAST STEP

FRAGMENT_DIR is a fragment of `zeroreg fuse` / `zeroreg eval 3dmatch` (its scan.json, cloud.ply);
DATA_DIR a 7-Scenes-style folder with frames/frame-NNNNNN.{color.jpg|color.png,depth.png,pose.txt};
the views are frames FIRST, FIRST+STEP, ..., <= LAST, each placed in the fragment's frame by the
ground-truth poses (T_scan_camera = T_world_scan^-1 T_world_camera). OUT_DIR/scan.json refers to
the fragment's cloud and the data's images by relative paths; nothing is copied. Used for the
memory and time of a 10-view scan pair (BENCHMARKS.md), e.g. for redkitchen fragments
0 and 1 (frames 0-49 and 50-99):

    python3 scripts/make-multiview-scan.py cache/fragments/7-scenes-redkitchen/fragment-0 \\
        ../shared/data/7scenes-redkitchen cache/multiview/fragment-0 0 49 5
"""
import json
import os
import sys


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def rigid_inverse(t):
    r = [[t[j][i] for j in range(3)] for i in range(3)]
    p = [-sum(r[i][k] * t[k][3] for k in range(3)) for i in range(3)]
    return [r[0] + [p[0]], r[1] + [p[1]], r[2] + [p[2]], [0.0, 0.0, 0.0, 1.0]]


def rows(flat, where):
    if len(flat) != 16:
        sys.exit(f"make-multiview-scan: {where}: expected 16 numbers, got {len(flat)}")
    return [flat[4 * i:4 * i + 4] for i in range(4)]


def read_pose(path):
    try:
        with open(path) as f:
            values = [float(v) for v in f.read().split()]
    except (OSError, ValueError) as e:
        sys.exit(f"make-multiview-scan: {path}: cannot read a 4x4 pose ({e})")
    return rows(values, path)


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    fragment, data, out = sys.argv[1:4]
    try:
        first, last, step = (int(v) for v in sys.argv[4:7])
    except ValueError:
        sys.exit("make-multiview-scan: FIRST LAST STEP must be integers")
    if step <= 0 or last < first:
        sys.exit("make-multiview-scan: expected FIRST <= LAST and STEP > 0")
    descriptor = os.path.join(fragment, "scan.json")
    try:
        with open(descriptor) as f:
            scan = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"make-multiview-scan: {descriptor}: cannot read ({e})")
    if "T_world_scan_gt" not in scan or "cloud" not in scan or not scan.get("views"):
        sys.exit(f"make-multiview-scan: {descriptor}: expected T_world_scan_gt, cloud and views")
    world_scan = rows(scan["T_world_scan_gt"], descriptor + " T_world_scan_gt")
    scan_world = rigid_inverse(world_scan)
    template = scan["views"][0]
    os.makedirs(out, exist_ok=True)
    rel = lambda p: os.path.relpath(p, out)
    views = []
    for frame in range(first, last + 1, step):
        stem = os.path.join(data, "frames", f"frame-{frame:06d}")
        color = next((stem + ext for ext in (".color.png", ".color.jpg") if os.path.isfile(stem + ext)),
                     None)
        if color is None or not os.path.isfile(stem + ".depth.png"):
            sys.exit(f"make-multiview-scan: {stem}.color.(png|jpg) or .depth.png not found")
        world_camera = read_pose(stem + ".pose.txt")
        scan_camera = matmul(scan_world, world_camera)
        view = {k: v for k, v in template.items() if k in ("intrinsics", "depth_scale")}
        view["color"] = rel(color)
        view["depth"] = rel(stem + ".depth.png")
        view["T_scan_camera"] = [v for row in scan_camera for v in row]
        view["T_world_camera_gt"] = [v for row in world_camera for v in row]
        views.append(view)
    out_scan = {
        "name": scan.get("name", os.path.basename(fragment.rstrip("/"))) + f"-{len(views)}-views",
        "T_world_scan_gt": scan["T_world_scan_gt"],
        "cloud": rel(os.path.join(fragment, scan["cloud"])),
        "views": views,
    }
    with open(os.path.join(out, "scan.json"), "w") as f:
        json.dump(out_scan, f, indent=2)
    print(f"make-multiview-scan: {len(views)} views -> {os.path.join(out, 'scan.json')}")


if __name__ == "__main__":
    main()
