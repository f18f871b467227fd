#!/usr/bin/env python3
"""Are the object matches the same physical object? A diagnostic beside the centroid precision.

    PYTHONPATH=build/python /usr/bin/python3 scripts/object-overlap.py LIST DATA [OUT.json]

e.g. `... scripts/object-overlap.py hololens-gap5 ../shared/data/hololens-office`. Registers every
pair of ../shared/lists/LIST with the default pipeline (the Python module), and for each matched
object pair lifts both masks (their outlines, filled, every 2nd pixel) with depth, moves the
source object's points by the ground truth and measures the surface overlap: the larger of the
two fractions of one object's points (at most 600 / 2400 sampled, seed 0) within 5 cm of the
other's. Prints, for the matches the issue-11 metric calls right (centroids within 0.3 m under
the GT) and wrong, how many overlap (>= 0.2) and how many do not at all (< 0.05). A partly seen
large object can be centroid-wrong yet the same object; a match with no overlap is a different
one. Exploratory: thin objects and masks on missing depth show little overlap even when right.

Superseded by `zeroreg eval`'s `objects.same_surface` (docs/MATCHING.md "Two
measures of a match"), which tests the objects' own 3D points: the outline used here is the mask's
largest contour only, so a mask broken into pieces (a desk with things on it) loses most of itself
and its match is undercounted.
"""
import json
import sys

import numpy as np
import zeroreg

def inside(poly, xs, ys):
    # even-odd rule, vectorised over points
    res = np.zeros(xs.shape, bool)
    n = len(poly)
    for i in range(n):
        x1, y1 = poly[i]; x2, y2 = poly[(i + 1) % n]
        cond = ((y1 > ys) != (y2 > ys))
        with np.errstate(divide='ignore', invalid='ignore'):
            xint = (x2 - x1) * (ys - y1) / (y2 - y1 + 1e-12) + x1
        res ^= cond & (xs < xint)
    return res

def lift(view, poly):
    d = np.asarray(view.depth); K = np.asarray(view.intrinsics)
    x0, y0 = poly.min(0); x1, y1 = poly.max(0)
    ys, xs = np.mgrid[max(0, y0):min(d.shape[0], y1 + 1):2, max(0, x0):min(d.shape[1], x1 + 1):2]
    xs = xs.ravel(); ys = ys.ravel()
    m = inside(poly, xs + 0.5, ys + 0.5)
    xs, ys = xs[m], ys[m]; z = d[ys, xs]; ok = (z > 0.1) & (z < 6)
    xs, ys, z = xs[ok], ys[ok], z[ok]
    pts = np.stack([(xs - K[0, 2]) / K[0, 0] * z, (ys - K[1, 2]) / K[1, 1] * z, z], 1)
    T = np.asarray(view.T_scan_camera)
    return pts @ T[:3, :3].T + T[:3, 3]

def obj_points(scan, obj):
    parts = [lift(scan.views[v['view']], np.asarray(v['outline'])) for v in obj['views'] if len(v['outline']) >= 3]
    return np.concatenate(parts) if parts else np.zeros((0, 3))

def frac_near(a, b, r=0.05, cap=600):
    if len(a) == 0 or len(b) == 0: return 0.0
    rng = np.random.default_rng(0)
    a = a[rng.choice(len(a), min(cap, len(a)), replace=False)]
    b = b[rng.choice(len(b), min(4 * cap, len(b)), replace=False)]
    d2 = ((a[:, None, :] - b[None, :, :]) ** 2).sum(-1).min(1)
    return float((d2 < r * r).mean())

if len(sys.argv) not in (3, 4):
    sys.exit(__doc__)
lst, data = sys.argv[1], sys.argv[2]
out = sys.argv[3] if len(sys.argv) == 4 else None
pipe = zeroreg.Pipeline()
list_file = f'../shared/lists/{lst}/pairs.txt'
try:
    with open(list_file) as f:
        pairs = [l.split()[:2] for l in f if l.strip() and not l.startswith('#')]
except OSError as e:
    sys.exit(f'object-overlap: {list_file}: cannot read ({e}); expected a list of ../shared/lists')
rows = []
for i, j in pairs:
    tgt = zeroreg.load_scan(f'{data}@{i}'); src = zeroreg.load_scan(f'{data}@{j}')
    r = pipe.register(src, tgt)
    Tws = np.asarray(src.views[0].T_world_camera_gt); Twt = np.asarray(tgt.views[0].T_world_camera_gt)
    Tgt = np.linalg.inv(Twt) @ Tws
    so, to = r.source_objects, r.target_objects
    for m in r.object_matches:
        a, b = so[m['source']], to[m['target']]
        ca = Tgt[:3, :3] @ np.asarray(a['centroid']) + Tgt[:3, 3]
        cdist = float(np.linalg.norm(ca - np.asarray(b['centroid'])))
        pa = obj_points(src, a); pa = pa @ Tgt[:3, :3].T + Tgt[:3, 3]; pb = obj_points(tgt, b)
        ov = max(frac_near(pa, pb), frac_near(pb, pa))
        rows.append(dict(pair=f'{i}-{j}', label=a['label'], cdist=cdist, overlap=ov, path=r.path))
if out:
    with open(out, 'w') as f:
        json.dump(rows, f)
cw = [x for x in rows if x['cdist'] >= 0.3]; cr = [x for x in rows if x['cdist'] < 0.3]
for name, group in (('centroid-right', cr), ('centroid-wrong', cw)):
    ov = [x['overlap'] for x in group]
    print(lst, name, len(group), 'overlap>=0.2:', sum(o >= 0.2 for o in ov), 'overlap<0.05:', sum(o < 0.05 for o in ov))
