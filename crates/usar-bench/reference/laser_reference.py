"""The laser reference of `usar bench --laser-reference`: the same work as usar's
`lidar_scans_per_s` done the way a Python user would, with the raycast2D package (a C Bresenham
raycaster on a NumPy image) and OpenCV.

One scan: 360 beams over the full circle, 20 m long, from a pose of the benchmark floor; then its
occupancy update on a log-odds grid: the polygon of the beam ends filled as seen free (cv2.fillPoly
on the scan's bounding box) and lowered with OpenCV's saturating arithmetic, the cells where a
beam hit raised.

    python laser_reference.py bench MAP.pgm POSES.csv RANGE_CELLS SCANS REPS   -> JSON on stdout
    python laser_reference.py ends  MAP.pgm POSES.csv RANGE_CELLS              -> one line per pose

MAP.pgm: 255 on free cells, 0 on obstacles, row 0 = the grid's row 0 (no flip).
POSES.csv: `col,row,theta` per line (theta in radians, counter-clockwise from +col).
"""

import json
import math
import sys
import time

import cv2
import numpy as np
from raycast2D import Lidar2D, raycaster

BEAMS = 360
L_FREE, L_OCC = 4, 9  # log-odds steps of a miss (down) and a hit (up)


def load(map_path, poses_path):
    img = cv2.imread(map_path, cv2.IMREAD_UNCHANGED)
    if img is None:
        sys.exit(f"{map_path}: not a readable PGM image")
    poses = np.loadtxt(poses_path, delimiter=",", ndmin=2)
    return img, poses


def bench(img, poses, range_cells, scans, reps):
    lidar = Lidar2D(num_rays=BEAMS, FOV=360, ray_length=range_cells, occupancy_grid=img)
    h, w = img.shape
    rates = []
    for _ in range(reps):
        # Log-odds as saturating bytes, 128 = unknown: OpenCV's arithmetic clamps for free.
        logodds = np.full((h, w), 128, np.uint8)
        start = time.perf_counter()
        for k in range(scans):
            col, row, theta = poses[k % len(poses)]
            x, y = int(col), int(row)
            # raycast2D turns yaw by -pi/2 (its yaw 0 points up the image).
            ends = lidar.scan((x, y, theta + math.pi / 2), only_true_collisions=False)
            ends = ends.astype(np.int32)
            np.clip(ends, 0, [w - 1, h - 1], out=ends)
            (ex0, ey0), (ex1, ey1) = ends.min(0), ends.max(0)
            x0, y0, x1, y1 = min(ex0, x), min(ey0, y), max(ex1, x) + 1, max(ey1, y) + 1
            roi = logodds[y0:y1, x0:x1]
            seen = np.zeros(roi.shape, np.uint8)
            cv2.fillPoly(seen, [ends - (x0, y0)], 255)
            cv2.subtract(roi, L_FREE, dst=roi, mask=seen)
            hit = img[ends[:, 1], ends[:, 0]] == 0
            hx, hy = ends[hit, 0], ends[hit, 1]
            logodds[hy, hx] = np.minimum(logodds[hy, hx].astype(np.int16) + L_OCC + L_FREE, 255)
        rates.append(scans / (time.perf_counter() - start))
    rates.sort()
    return {"scans_per_s": rates[len(rates) // 2], "scans": scans, "reps": reps}


def ends(img, poses, range_cells):
    """Each pose's beam ends (col row pairs) at usar's beam angles: -pi + i * 2 pi / 360."""
    free = (img > 0).astype(np.uint8)
    for col, row, theta in poses:
        x, y = int(col), int(row)
        a = theta - math.pi + np.arange(BEAMS) * (2 * math.pi / BEAMS)
        rays = np.zeros((BEAMS, 3), np.int64)
        rays[:, 0] = np.round(x + range_cells * np.cos(a))
        rays[:, 1] = np.round(y + range_cells * np.sin(a))
        rays = rays.astype(np.uint32)
        raycaster.raycast(free, rays, x, y)
        print(" ".join(f"{c} {r} {h}" for c, r, h in rays))


def main(argv):
    if len(argv) < 5 or argv[1] not in ("bench", "ends"):
        sys.exit(__doc__)
    img, poses = load(argv[2], argv[3])
    range_cells = int(argv[4])
    if argv[1] == "bench":
        print(json.dumps(bench(img, poses, range_cells, int(argv[5]), int(argv[6]))))
    else:
        ends(img, poses, range_cells)


if __name__ == "__main__":
    main(sys.argv)
