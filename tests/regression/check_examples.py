#!/usr/bin/env python3
"""Regression runs of the paper's example decks (issue 2, item 9): run mfcd on a deck and
check the numbers in its HDF5 output against closed forms and a brute-force coverage count.

Closed forms: with rho = 2 dx the cubic B-spline window reproduces its moments on a uniform
lattice, so the interior plateau is det M = 1/12 (1D, P = (1, x)) and 1/20736 (2D bilinear,
M = diag(1, 1/12, 1/12, 1/144)); both hold to round-off. Where no particle's support covers
a point, M = 0 and det(M) is exactly 0 (Proposition 2.1, Theorem 3.1).
Usage: check_examples.py /path/to/mfcd /path/to/deck.nml
"""
import os
import subprocess
import sys
import tempfile

import h5py  # only for the raw layout check that every dataset carries units (common)
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD, DECK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
NAME = os.path.splitext(os.path.basename(DECK))[0]
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + f"{NAME}.{name}" + ("" if cond else ": " + str(detail)))


def common(f):
    with open(DECK) as fh:
        check("deck stored verbatim", f.deck == fh.read())
    for key in ("code", "code_version", "git_commit", "created", "deck_path"):
        check(f"root attribute {key}", key in f.attrs)
    missing = []
    # the raw layout itself: a units attribute on every dataset of the file, whatever it is
    with h5py.File(f.path, "r") as raw:
        raw.visititems(lambda n, o: missing.append(n) if isinstance(o, h5py.Dataset)
                       and "units" not in o.attrs else None)
    check("every dataset has units", not missing, missing)


def uncovered(x, rho, q):
    """Brute force: True where no particle's tensor support (|x_l - q| < rho) covers q."""
    cov = np.zeros(len(q), bool)
    for xl, rl in zip(x, rho):
        cov |= np.all(np.abs(q - xl) < rl, axis=1)
    return ~cov


def main():
    work = tempfile.mkdtemp(prefix=f"mfcd_{NAME}_")
    p = subprocess.run([MFCD, DECK], cwd=work, capture_output=True, text=True, timeout=600)
    check("run exits 0", p.returncode == 0, p.stderr)
    if p.returncode != 0:
        sys.exit(1)
    out = [l for l in open(DECK) if "file" in l and ".h5" in l][0].split("'")[1]
    f = MfcdFile(os.path.join(work, out))
    common(f)
    det_attrs = f.detection
    plateau = det_attrs["plateau"]
    body = det_attrs["body"]
    b = f.body(body)
    x, rho = b.x, b.support
    for g in ("line", "grid"):
        if g in f.query_kinds():
            qs = f.query(g)
            a = qs.attrs
            check(f"{g}: no interior point has det <= eps", a["n_false_outside"] == 0,
                  a["n_false_outside"])
            check(f"{g}: det > eps only inside the buffer zone (distance < rho)",
                  a["n_beyond_buffer"] == 0 and a["max_outside_inside"] < det_attrs["rho_buffer"],
                  (a["max_outside_inside"], det_attrs["rho_buffer"]))
            q = qs.x
            det = qs.det.ravel()
            free = uncovered(x, rho, q)
            check(f"{g}: det = 0 exactly where no support covers the point",
                  np.all(det[free] == 0.0) and free.any(), np.abs(det[free]).max())
    pdet = f.query("points").det
    if NAME == "example_2_1":
        check("np = 41", b.attrs["np"] == 41)
        check("plateau = 1/12", abs(plateau - 1 / 12) < 1e-14, plateau)
        check("det(P1 = -0.3) = 0", pdet[0] == 0.0, pdet[0])
        check("det(P2 = 0.5) = plateau", abs(pdet[1] - 1 / 12) < 1e-14, pdet[1])
        lx = f.query("line").x[:, 0]
        ld = f.query("line").det
        inner = (lx > 0.05) & (lx < 0.95)
        check("det = 1/12 on the interior of [0, 1]", np.allclose(ld[inner], 1 / 12, rtol=0, atol=1e-14))
    elif NAME == "example_2_2":
        check("np = 41 x 21 = 861", b.attrs["np"] == 861)
        check("plateau = 1/20736", abs(plateau - 1 / 20736) < 1e-17, plateau)
        check("det(15, 10) = plateau", abs(pdet[0] - 1 / 20736) < 1e-17, pdet[0])
        check("det(3, 10) = 0", pdet[1] == 0.0, pdet[1])
        check("0 < det(25.3, 10) < plateau (buffer zone)", 0.0 < pdet[2] < plateau, pdet[2])
        gd = f.query("grid").det.ravel()
        dist = f.query("grid").distance
        deep = dist <= -1.0
        check("det = plateau wherever the support lies inside the body",
              np.allclose(gd[deep], 1 / 20736, rtol=1e-12, atol=0))
    elif NAME == "example_2_2_concave":
        check("np = 265", b.attrs["np"] == 265)
        check("plateau = 1/20736", abs(plateau - 1 / 20736) < 1e-17, plateau)
        check("det(10, 10) = plateau (arm of the C)", abs(pdet[0] - 1 / 20736) < 1e-17, pdet[0])
        check("det(20, 10) = 0 (inside the notch)", pdet[1] == 0.0, pdet[1])
        check("det(20, 5) = plateau (lower arm)", abs(pdet[2] - 1 / 20736) < 1e-17, pdet[2])
    f.close()
    n = len(results)
    print(f"{sum(results)} passed, {n - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
