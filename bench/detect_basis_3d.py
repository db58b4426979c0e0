#!/usr/bin/env python3
"""Which basis detects in 3D: linear (1, x, y, z) against trilinear (1, x, y, z, xy, yz, zx,
xyz), measured on the box of input/example_3d_box.nml (41 x 21 x 21 particles, rho = 2 dx,
cubic spline tensor window) with the same relative threshold, eps_rel = 1e-5 of each
basis' plateau (the paper's 2D eps_cr = 5e-10 is 1.0e-5 of the bilinear plateau 1/20736),
on the deck's plane y = 10 (x-z: faces and edges of the box) refined to 301 x 201 points
and its line refined to 30001 points.

For each basis it prints the plateau, how far det(M) > threshold reaches outside the box
(the buffer zone actually claimed, from the run's max_outside_inside), the points inside or
on the box with det <= threshold (misses: n_false_outside, on its edges), and the query
rate of the plane (mfcd's log; a benchmark, not a test: machines differ, compare within
one run).

Usage: bench/detect_basis_3d.py /path/to/mfcd [input/example_3d_box.nml]
"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
DECK = os.path.abspath(sys.argv[2] if len(sys.argv) > 2 else os.path.join(
    os.path.dirname(os.path.abspath(__file__)), "..", "input", "example_3d_box.nml"))


def variant(text, basis):
    text = re.sub(r"basis = '\w+'", f"basis = '{basis}'", text)
    text = re.sub(r"eps_cr = [-+0-9.eE]+", "eps_rel = 1.0e-5", text)
    text = re.sub(r"grid_n = [0-9, ]+", "grid_n = 301, 1, 201", text)
    text = re.sub(r"line_n = \d+", "line_n = 30001", text)
    return re.sub(r"file = '[^']*'", f"file = 'basis_{basis}.h5'", text)


def main():
    text = open(DECK).read()
    work = tempfile.mkdtemp(prefix="mfcd_basis3d_")
    print("| basis | plateau | det > threshold reaches outside (m) | misses inside (plane) | "
          "plane queries / s |")
    print("|---|---|---|---|---|")
    for basis in ("linear", "trilinear"):
        deck = os.path.join(work, f"{basis}.nml")
        open(deck, "w").write(variant(text, basis))
        p = subprocess.run([MFCD, deck], cwd=work, capture_output=True, text=True)
        if p.returncode:
            print(p.stderr[-2000:])
            sys.exit(1)
        rate = re.search(r"/detection/grid: \d+ points in +[0-9.]+ s \( *([0-9.]+) M/s\)",
                         p.stdout).group(1)
        with MfcdFile(os.path.join(work, f"basis_{basis}.h5")) as f:
            plateau = float(f.detection["plateau"])
            g, ln = f.query("grid").attrs, f.query("line").attrs
            reach = max(float(g["max_outside_inside"]), float(ln["max_outside_inside"]))
            miss = int(g["n_false_outside"])
        print(f"| {basis} | {plateau:.4e} | {reach:.3f} | {miss} | {rate} M |")


if __name__ == "__main__":
    main()
