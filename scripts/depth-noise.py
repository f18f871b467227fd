#!/usr/bin/env python3
"""How noisy each scene's depth is: a of sigma(d) = a d^2 (mm at 1 m), measured per frame.

    PYTHONPATH=build/python /usr/bin/python3 scripts/depth-noise.py DATA [DATA ...] [--step N]

DATA is a scene folder (3DMatch layout, e.g. ../shared/data/7scenes-redkitchen, or a noisy copy
made by scripts/bench-resolution.sh under cache/resized/). Every N-th frame (default 7) is
measured with zeroreg.depth_noise_at_1m_m (src/estimate/depth_noise.hpp) and the minimum,
median, 95th percentile and maximum are printed: the figures docs/CONFIG.md "Depth noise" quotes,
and what to set depth.noise_at_1m_m from for a new sensor.
"""
import argparse
import os
import statistics
import sys

import zeroreg


def frames(data):
    folder = os.path.join(data, "frames") if os.path.isdir(os.path.join(data, "frames")) else data
    ids = sorted(int(name[6:12]) for name in os.listdir(folder)
                 if name.startswith("frame-") and name.endswith(".depth.png"))
    if not ids:
        sys.exit(f"depth-noise: {folder}: no frame-XXXXXX.depth.png here")
    return ids


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data", nargs="+")
    parser.add_argument("--step", type=int, default=7)
    args = parser.parse_args()
    print("| scene | frames | min | median | p95 | max (mm at 1 m) |")
    print("|---|---|---|---|---|---|")
    for data in args.data:
        values = []
        for frame in frames(data)[::max(1, args.step)]:
            a = zeroreg.depth_noise_at_1m_m(f"{data}@{frame}")
            if a is not None:
                values.append(1000.0 * a)
        if not values:
            print(f"| {data} | 0 | | | | |")
            continue
        values.sort()
        p95 = values[min(len(values) - 1, int(round(0.95 * (len(values) - 1))))]
        print(f"| {data} | {len(values)} | {values[0]:.2f} | {statistics.median(values):.2f} | "
              f"{p95:.2f} | {values[-1]:.2f} |")


if __name__ == "__main__":
    main()
