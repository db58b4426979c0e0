#!/usr/bin/env python3
"""An independent check of the plane-strain line-contact law that post/hertz_impact.py uses
for the cylinder: a static linear finite-element solution (numpy only, not mfcd) of the
disk of input/hertz_cylinder.geo loaded as in the impact, by the Hertz pressure
p0 sqrt(1 - x^2/b^2) on its lowest point and the uniform body force that balances it (the
inertia of a body decelerated by the contact force), with the approach of its centre of
mass to the contact point, delta = u_y(contact) - mean of u_y over the disk.

The closed form (doc/verification.md) gives delta pi E* / P - ln(pi E* R / P) =
-1/(4 (1 - nu)) (-0.357 at nu = 0.3); Johnson's diametral-compression law (ch. 5),
delta = P/(pi E*) (2 ln(4R/b) - 1), would give 2 ln 2 - 1 = +0.386. The script prints the
constant from the finite-element solution on each mesh asked for (linear triangles, dense
solve, the rigid motions removed by three Lagrange multipliers: zero mean displacement and
rotation), so its convergence can be seen:

    .venv/bin/python post/line_contact_static.py [--hc 0.04e-3 0.02e-3] [--hf 0.5e-3]

(b = 0.2 mm on R = 5 mm. The matrix is dense: hc = b/10 with hf = 0.25 mm has 4,700 nodes,
0.7 GB and about 10 s on two cores; hc = b/15, 7,400 nodes, 1.8 GB and 45 s.) Measured
(doc/verification.md): -0.390, -0.375 at b/5, b/10 with hf = 0.5 mm; -0.385, -0.369,
-0.367 at b/5, b/10, b/15 with hf = 0.25 mm.
"""
import argparse
import math
import os
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from mesh_body import boundary_loops, mesh_geo, signed_areas  # noqa: E402


def approach_constant(hc, hf, b, radius=5e-3, e=211e9, nu=0.3):
    """(nodes, delta pi E*/P - ln(pi E* R / P)) of the static solution on one mesh."""
    x, tri, _ = mesh_geo(os.path.join(ROOT, "input", "hertz_cylinder.geo"),
                         {"R": radius, "hc": hc, "hf": hf, "b": b})
    n = x.shape[0]
    es = e / (1 - nu * nu)
    lam, g = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
    d = np.array([[lam + 2 * g, lam, 0], [lam, lam + 2 * g, 0], [0, 0, g]])
    area = signed_areas(x, tri)
    p = x[tri]                                            # (ne, 3, 2)
    bb = (np.roll(p[:, :, 1], -1, axis=1) - np.roll(p[:, :, 1], -2, axis=1)) / (2 * area[:, None])
    cc = (np.roll(p[:, :, 0], -2, axis=1) - np.roll(p[:, :, 0], -1, axis=1)) / (2 * area[:, None])
    bm = np.zeros((tri.shape[0], 3, 6))
    bm[:, 0, 0::2], bm[:, 1, 1::2] = bb, cc
    bm[:, 2, 0::2], bm[:, 2, 1::2] = cc, bb
    ke = area[:, None, None] * np.einsum("eki,kl,elj->eij", bm, d, bm)
    dof = np.stack([2 * tri, 2 * tri + 1], axis=2).reshape(-1, 6)
    k = np.zeros((2 * n, 2 * n))
    np.add.at(k, (dof[:, :, None], dof[:, None, :]), ke)
    # Hertz pressure: a vertical traction per unit horizontal length on the lower edges
    load = math.pi * es * b * b / (4 * radius)
    p0 = 2 * load / (math.pi * b)
    f = np.zeros(2 * n)
    s = np.linspace(0.0, 1.0, 2001)
    loop = boundary_loops(tri)[0]
    for i, j in zip(loop, loop[1:] + loop[:1]):
        if x[i, 1] > radius or (abs(x[i, 0]) > b and abs(x[j, 0]) > b):
            continue
        xs = x[i, 0] + (x[j, 0] - x[i, 0]) * s
        pr = p0 * np.sqrt(np.clip(1 - xs ** 2 / b ** 2, 0, None)) * abs(x[j, 0] - x[i, 0])
        f[2 * i + 1] += np.trapezoid(pr * (1 - s), s)
        f[2 * j + 1] += np.trapezoid(pr * s, s)
    vol = np.zeros(n)
    for c in range(3):
        np.add.at(vol, tri[:, c], area / 3)
    f[1::2] -= f[1::2].sum() * vol / vol.sum()            # the balancing body force
    con = np.zeros((3, 2 * n))
    con[0, 0::2], con[1, 1::2] = vol, vol
    con[2, 0::2], con[2, 1::2] = -(x[:, 1] - radius) * vol, x[:, 0] * vol
    u = np.linalg.solve(np.block([[k, con.T], [con, np.zeros((3, 3))]]),
                        np.r_[f, 0.0, 0.0, 0.0])[:2 * n]
    uy = u[1::2]
    delta = uy[np.argmin(np.hypot(x[:, 0], x[:, 1]))] - np.sum(uy * vol) / vol.sum()
    return n, delta * math.pi * es / load - math.log(math.pi * es * radius / load)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--hc", type=float, nargs="+", default=[0.04e-3, 0.02e-3],
                    help="contact element sizes (m)")
    ap.add_argument("--hf", type=float, default=0.5e-3, help="element size far away (m)")
    ap.add_argument("--b", type=float, default=0.2e-3, help="contact half-width (m)")
    a = ap.parse_args(argv)
    nu = 0.3
    print("closed form -1/(4(1-nu)) = %+.4f; Johnson's diametral law 2 ln 2 - 1 = %+.4f"
          % (-0.25 / (1 - nu), 2 * math.log(2) - 1))
    for hc in a.hc:
        n, c = approach_constant(hc, a.hf, a.b, nu=nu)
        print("hc = b/%.1f, hf = %.3g mm: %d nodes, delta pi E*/P - ln(pi E* R/P) = %+.4f"
              % (a.b / hc, 1e3 * a.hf, n, c))
    return 0


if __name__ == "__main__":
    sys.exit(main())
