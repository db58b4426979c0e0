#!/usr/bin/env python3
"""Two deformable elastic bars colliding head-on (issue 4, item 1: detection both ways when
both bodies deform, eq. 28). By symmetry each bar meets a standing interface, as at a rigid
wall: contact stress rho c0 v, duration 2 L / c0, rebound at v. Tolerances are those of the
rigid-wall check at the same spacing (0.5 mm: 3% stress, 2% duration, 3% rebound and
energy, see check_bar_impact.py); the two bars must stay mirror images (momentum 1e-6 of
m v: forces act pairwise, action against reaction). The bars' length, section (width in
plane strain, area in 3D) and spacing come from their particles and the motion is along the
last axis, so the same checks serve two 3D bars (input/bars_collision_3d.nml, 3 x 3 x 30 mm
boxes at 0.5 mm); the duration, rebound and energy bounds scale with 60 mm / L as in
check_bar_impact.py (the front's delay is a support width over c0, the loss a few rows'
share of the bar: spacing over length; the 3D pair measured +0.2% stress, +2.8% duration,
-2.3% rebound, -3.1% energy), the penetration bound with the spacing.
Usage: check_collision.py /path/to/mfcd /path/to/input/bars_collision_elastic.nml
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD, DECK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
E, RHO, V = 211e9, 7800.0, 1.0
C0 = np.sqrt(E / RHO)
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "collision." + name
          + ("" if cond else ": " + str(detail)))


def main():
    work = tempfile.mkdtemp(prefix="mfcd_coll_")
    p = subprocess.run([MFCD, DECK], cwd=work, capture_output=True, text=True, timeout=600)
    check("run exits 0", p.returncode == 0, p.stderr[-2000:])
    if p.returncode:
        sys.exit(1)
    check("log states detection both ways", "both ways" in p.stdout)
    out = [l for l in open(DECK) if "file" in l and ".h5" in l][0].split("'")[1]
    with MfcdFile(os.path.join(work, out)) as f:
        h = f.history()
        last = f.snapshot(sorted(f.snapshot_labels())[-1])
        volume = {b: f.body(b).volume for b in ("upper", "lower")}
        x0 = f.body("upper").x
        dx = float(np.min(f.body("upper").spacing[:x0.shape[1]]))
        pen = f.summary["max_remaining_penetration"]
    nd = x0.shape[1]
    L = np.ptp(x0[:, -1])
    W = np.ptp(x0[:, 0]) * (np.ptp(x0[:, 1]) if nd == 3 else 1.0)
    scale = 0.06 / L
    t, n, fc = h["time"], h["n_contact"], h["f_contact"]
    on = np.nonzero(n > 0)[0]
    t0, t1 = t[on[0]], t[on[-1]]
    t_sep = t[min(on[-1] + 1, len(t) - 1)]
    mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
    e_stress = fc[mid].mean() / W / (RHO * C0 * V) - 1
    e_dur = (t_sep - t0) / (2 * L / C0) - 1
    check(f"contact stress = rho c0 v ({e_stress:+.4f})", abs(e_stress) < 0.03, e_stress)
    check(f"contact duration = 2 L / c0 ({e_dur:+.4f})", abs(e_dur) < 0.02 * scale, e_dur)
    check("no contact after separation", np.all(n[t > t_sep + 1e-6] == 0))
    vm = {}
    for b in ("upper", "lower"):
        m = volume[b] * RHO
        vm[b] = np.sum(m * last.bodies[b].v[:, -1]) / m.sum()
    check(f"upper bar rebounds at +v ({vm['upper']:.4f} m/s)",
          abs(vm["upper"] / V - 1) < 0.03 * scale, vm["upper"])
    check("mirror symmetry of the rebound", abs(vm["upper"] + vm["lower"]) < 1e-6 * V,
          vm["upper"] + vm["lower"])
    ke = h["ke"]
    check(f"kinetic energy returned ({ke[-1] / ke[0]:.4f})",
          abs(ke[-1] / ke[0] - 1) < 0.03 * scale)
    check(f"remaining penetration {pen:.2e} m < 1% of dx", pen < 0.01 * dx, pen)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
