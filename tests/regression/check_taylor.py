#!/usr/bin/env python3
"""The Taylor bar by RKPM with det(M) contact (issue 4, item 7) at the coarse resolution
(input/taylor_bar_rkpm_coarse.nml, about 10 s): checks against independent balances.

  impenetrability: no slave particle ends a step inside the target by more than 1% of the
     particle spacing (the eq. 98 redistribution spreads each correction, so a small
     penetration remains; the log's largest value is ~0.5% of dx), and no snapshot shows
     one below the target surface by more than that;
  momentum: the contact impulse (history 'impulse': the mean contact force times dt summed
     over every step) equals
     the bar's loss of axial momentum 2 pi int rho v_z r dA (they are computed independently:
     forces at the particles vs the final velocity field), within 1% of the initial momentum;
  energy: |residual| < 1% of the initial kinetic energy, the bar ends with less kinetic
     energy than it started with, plastic dissipation is positive and below the internal work;
  kinematics: the bar shortens by less than v t (it cannot shorten faster than it moves) and
     by more than half of it (the far end has not yet felt the plastic wave's full slowdown);
  the paper's claim: the bar's outer edge separates from the target (edge separation time
     recorded in /summary) while the centre stays in contact.
Usage: check_taylor.py /path/to/mfcd /path/to/deck.nml
"""
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD, DECK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "taylor." + name
          + ("" if cond else ": " + str(detail)))


def main():
    work = tempfile.mkdtemp(prefix="mfcd_taylor_")
    p = subprocess.run([MFCD, DECK], cwd=work, capture_output=True, text=True, timeout=1800)
    check("run exits 0", p.returncode == 0, p.stderr[-2000:])
    if p.returncode:
        sys.exit(1)
    check("log reports contact counters", "det(M) evaluations" in p.stdout)
    out = [l for l in open(DECK) if "file" in l and ".h5" in l][0].split("'")[1]
    with MfcdFile(os.path.join(work, out)) as f:
        s = f.summary
        b = f.body("bar")
        dx, vol, x0 = b.spacing[0], b.volume, b.x
        h = f.history()
        last = sorted(k for k in f.snapshot_labels() if k != "failure")[-1]
        v_end = f.snapshot(last).bodies["bar"].v
        zmin = min(f.snapshot(k).bodies["bar"].x[:, 1].min() for k in f.snapshot_labels())
        bar = f.summary_bodies()["bar"]
    check("status completed", s["status"].strip() == "completed")
    pen = s["max_remaining_penetration"]
    check(f"remaining penetration {pen:.3e} m < 1% of dx", pen < 0.01 * dx, pen)
    t, dt, fc, ke = h["time"], h["dt"], h["f_contact"], h["ke"]
    every = np.diff(h["step"])
    rho = 7800.0
    v0 = 200.0
    # axisymmetric masses of the particles (ring volume 2 pi r dA, cell centroid radius)
    r_c = np.maximum(x0[:, 0], 0.25 * dx)
    mass = 2 * np.pi * rho * vol * r_c
    m_total = mass.sum()
    p_end = np.sum(mass * v_end[:, 1])
    impulse = h["impulse"][-1]
    dp = p_end - (-v0 * m_total)
    check(f"contact impulse {impulse:.4g} N s = momentum change {dp:.4g} N s (1% of m v0)",
          abs(impulse - dp) < 0.01 * m_total * v0, (impulse, dp))
    res = s["energy_residual"]
    check("energy residual < 1% of the initial kinetic energy", abs(res) < 0.01 * ke[0], res)
    check("kinetic energy lost", ke[-1] < ke[0])
    check("plastic dissipation positive, below the internal work",
          0 < s["plastic_dissipation"] < s["internal_work"])
    check("no snapshot particle below the target surface by 1% of dx", zmin > -0.01 * dx, zmin)
    shortening = 0.06 - bar["length"]
    vt = v0 * t[-1]
    check(f"shortening {shortening * 1e3:.3f} mm within (v t / 2, v t) = ({vt * 500:.2f}, "
          f"{vt * 1e3:.2f}) mm", 0.5 * vt < shortening < vt, shortening)
    check("foot radius grows (mushroom)", bar["foot_radius"] > 0.005 * 1.2, bar["foot_radius"])
    t_sep = s["edge_separation_time"]
    check(f"outer edge separates from the target (t = {t_sep * 1e6:.2f} us)", t_sep > 0, t_sep)
    check("centre still in contact at the end", h["n_contact"][-1] > 0)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
