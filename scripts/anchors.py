#!/usr/bin/python3
"""The anchors beside our fit, timed in one run on the same points: SciPy's LSQBivariateSpline with
our knots (32 x 32 bicubic, scattered points), SciPy's RectBivariateSpline and OpenCASCADE's
GeomAPI_PointsToBSplineSurface on a grid. Ratios are taken within one run because this machine is
shared and its timings drift from run to run. Usage: anchors.py BUILD_BIN_DIR"""
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.interpolate import LSQBivariateSpline, RectBivariateSpline

BIN = sys.argv[1] if len(sys.argv) > 1 else "build/release/bin"
SIGMA_MM = 0.002


def part(x, y):
    # The shape fit_bench fits: a bowl with a ripple, heights in mm over a 100 x 100 mm square.
    return 3.0 + 0.002 * ((x - 50) ** 2 + (y - 50) ** 2) + 0.3 * np.sin(x / 9.0) * np.sin(y / 11.0)


def ours(mode, path, *extra):
    out = subprocess.run([os.path.join(BIN, "anchor_fit"), mode, path, *map(str, extra)], check=True,
                         capture_output=True, text=True).stdout.split()
    return out


def write(points, path):
    points.astype("<f8").tofile(path)


def scattered(n, work):
    rng = np.random.default_rng(1)
    x = rng.uniform(0, 100, n)
    y = rng.uniform(0, 100, n)
    z = part(x, y) + rng.normal(0, SIGMA_MM, n)
    path = os.path.join(work, "scattered.f64")
    write(np.column_stack([x, y, z]), path)
    _, our_s, our_rms = ours("lsq", path)
    # Our clamped uniform net of 32 control points has 28 interior knots, evenly over the data's range.
    tx = np.linspace(x.min(), x.max(), 30)[1:-1]
    ty = np.linspace(y.min(), y.max(), 30)[1:-1]
    t0 = time.perf_counter()
    spline = LSQBivariateSpline(x, y, z, tx, ty, kx=3, ky=3)
    scipy_s = time.perf_counter() - t0
    scipy_rms = math.sqrt(np.mean((spline.ev(x, y) - z) ** 2))
    print(f"scattered {n:>8,} points, 32 x 32 bicubic: ours {float(our_s):.3f} s (rms {float(our_rms):.4f} mm), "
          f"SciPy LSQBivariateSpline {scipy_s:.3f} s (rms {scipy_rms:.4f} mm): SciPy / ours = {scipy_s / float(our_s):.1f}")


def grid(side, occ_side, work):
    rng = np.random.default_rng(2)
    xs = np.linspace(0, 100, side)
    ys = np.linspace(0, 100, side)
    X, Y = np.meshgrid(xs, ys)  # rows along y, x fastest
    Z = part(X, Y) + rng.normal(0, SIGMA_MM, X.shape)
    path = os.path.join(work, "grid.f64")
    write(np.column_stack([X.ravel(), Y.ravel(), Z.ravel()]), path)
    _, our_s, our_rms = ours("lsq", path)
    t0 = time.perf_counter()
    # Smoothing to the noise (s = n sigma^2): SciPy places its own knots until the residual gets there.
    spline = RectBivariateSpline(xs, ys, Z.T, kx=3, ky=3, s=Z.size * SIGMA_MM ** 2)
    scipy_s = time.perf_counter() - t0
    scipy_rms = math.sqrt(np.mean((spline(xs, ys).T - Z) ** 2))
    knots = f"{len(spline.get_knots()[0]) - 4} x {len(spline.get_knots()[1]) - 4}"
    print(f"grid {side} x {side}: ours 32 x 32 {float(our_s):.3f} s (rms {float(our_rms):.4f} mm), "
          f"SciPy RectBivariateSpline (s = n sigma^2, {knots} control points) {scipy_s:.3f} s (rms {scipy_rms:.4f} mm): "
          f"SciPy / ours = {scipy_s / float(our_s):.1f}")
    # OpenCASCADE's approximation to a tolerance of 3 sigma, on a coarser grid of the same shape.
    step = max(1, (side - 1) // (occ_side - 1))
    sub_x, sub_y = xs[::step], ys[::step]
    sub_z = Z[::step, ::step]
    SX, SY = np.meshgrid(sub_x, sub_y)
    occ_path = os.path.join(work, "occ.f64")
    write(np.column_stack([SX.ravel(), SY.ravel(), sub_z.ravel()]), occ_path)
    write_ours = os.path.join(work, "occ-ours.f64")
    write(np.column_stack([SX.ravel(), SY.ravel(), sub_z.ravel()]), write_ours)
    _, sub_our_s, sub_our_rms = ours("lsq", write_ours)
    result = ours("occ", occ_path, len(sub_x), len(sub_y), 3 * SIGMA_MM)
    if result[0] != "occ" or len(result) < 4:
        print(f"grid {len(sub_x)} x {len(sub_y)}: OpenCASCADE's approximation failed")
        return
    _, occ_s, occ_rms, occ_net = result
    print(f"grid {len(sub_x)} x {len(sub_y)}: ours 32 x 32 {float(sub_our_s):.3f} s (rms {float(sub_our_rms):.4f} mm), "
          f"OpenCASCADE GeomAPI_PointsToBSplineSurface (tolerance {3 * SIGMA_MM} mm, {occ_net} poles) {float(occ_s):.3f} s "
          f"(rms {float(occ_rms):.4f} mm): OpenCASCADE / ours = {float(occ_s) / float(sub_our_s):.1f}")


def main():
    with tempfile.TemporaryDirectory() as work:
        for n in (10_000, 100_000, 1_000_000):
            scattered(n, work)
        grid(1000, int(os.environ.get("ANCHOR_OCC_SIDE", "200")), work)


if __name__ == "__main__":
    main()
