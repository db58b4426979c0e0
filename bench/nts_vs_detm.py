#!/usr/bin/env python3
"""det(M) against a conventional node-to-segment search, head to head (issue 9, item 5).

For each case, the deck is copied (into the output folder, never into input/) three times:
with &contact detector = 'det_m' (the paper's screen, eqs. 25-28), with
'node_to_segment' (contact_nts_m: bucket-sorted master segments, closest-segment
projection, flagged when g < 0), and once more with compare_detectors = .true., which runs
both at every screened particle for the counters only (where they disagree). The first two
give the timings and the final results; the third the disagreements. Every run is on one
OpenMP thread; --repeat N runs each timing run N times and keeps the fastest.

Writes a Markdown report (printed and saved as <out>/nts_vs_detm.md) with, per case and
detector: particles flagged per step (mean, most), contacts per step, time per step of the
contact phase and of the whole time loop (from /summary's phase breakdown), and the final
results (shortening, foot radius, contact stress or impulse, energy residual); and from the
comparison run: the buffer zone (det(M) flags, g >= 0: no force) and its gaps in units of
the slave's spacing, and the penetrating particles det(M) missed.

Usage: .venv/bin/python bench/nts_vs_detm.py [--mfcd build/bin/mfcd] [--out DIR]
       [--repeat N] [--cases taylor,bar,collision] [--case NAME=DECK ...]
The patch test (issue 9, item 4) is added with --case patch=input/<its deck>.nml, or by
adding it to CASES below once its deck is in input/; a case needs one &contact group and
its slave body's &body spacing (read from the output).
"""
import argparse
import datetime
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# name: (deck, what it stands for). Add the patch test here when its deck exists.
CASES = {
    "taylor": ("input/taylor_bar_rkpm_coarse.nml", "Taylor bar, RKPM, coarse (1/3 mm)"),
    "bar": ("input/bar_impact_elastic.nml", "elastic bar on a rigid wall (0.5 mm)"),
    "collision": ("input/bars_collision_elastic.nml",
                  "two elastic bars colliding, both deformable (0.5 mm); stands in for "
                  "the patch test"),
}
DETECTORS = ("det_m", "node_to_segment")


def variant(deck, detector, compare, out, tag):
    """A copy of deck with the detector (and comparison) set and the output into out."""
    text = open(deck).read()
    text = re.sub(r"(&contact\b)", r"\1\n  detector = '%s'\n  compare_detectors = %s"
                  % (detector, ".true." if compare else ".false."), text, count=1,
                  flags=re.IGNORECASE)
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", f"file = '{tag}.h5'", text)
    path = os.path.join(out, f"{tag}.nml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(mfcd, deck, out):
    env = dict(os.environ, OMP_NUM_THREADS="1")
    t0 = time.time()
    p = subprocess.run([mfcd, deck], cwd=out, capture_output=True, text=True, env=env)
    if p.returncode:
        sys.exit(f"{deck}: mfcd exited {p.returncode}\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    with open(deck[:-4] + ".log", "w") as f:
        f.write(p.stdout)
    return os.path.join(out, os.path.basename(deck)[:-4] + ".h5"), time.time() - t0


def measure(path):
    with MfcdFile(path) as f:
        s = f.summary
        h = f.history()
        ph = f.summary_timing
        c = f.summary_contacts()[1]
        deck = f.deck
        slave = c["slave"]
        dx = float(min(np.atleast_1d(f.body(slave).attrs["spacing"])[:2]))
        t, n, fc = h["time"][:], h["n_contact"][:], h["f_contact"][:]
        cmp_ = [c[k] for k in ("compare_det", "compare_gap", "compare_buffer", "compare_missed",
                               "compare_det_max", "compare_gap_max")]
        r = {"steps": int(s["steps"]), "t_loop": ph["time_loop"], "t_contact": ph["contact"],
             "t_detect": float(c["detect_time"]),
             "evaluated": c["evaluated"], "flagged": c["detected"], "contacts": c["contacts"],
             "flag_max": float(c["detected_max_per_step"]),
             "cmp": cmp_, "gap_mean": c["buffer_gap_mean"], "gap_max": c["buffer_gap_max"],
             "dx": dx, "residual": float(s["energy_residual"] / s["energy_scale"]),
             "length0": h["length"][0], "length": h["length"][-1],
             "foot": float(f.summary_bodies()[slave]["foot_radius"]),
             "impulse": h["impulse"][-1] if "impulse" in h else np.nan}
        on = np.nonzero(n > 0)[0]
        r["stress"] = np.nan
        geometry = re.search(r"geometry\s*=\s*'([^']+)'", deck)
        if len(on) > 2 and not (geometry and geometry.group(1) == "axisymmetric"):
            # plane strain bars: mean force per unit thickness over the middle 60% of the
            # contact, over the bar's width (doc/contact.md, Verification)
            lo = [float(v) for v in re.search(r"name\s*=\s*'%s'.*?lo\s*=\s*([-\d.e, ]+)"
                                              % slave, deck, re.S).group(1).split(",")[:2]]
            hi = [float(v) for v in re.search(r"name\s*=\s*'%s'.*?hi\s*=\s*([-\d.e, ]+)"
                                              % slave, deck, re.S).group(1).split(",")[:2]]
            t0, t1 = t[on[0]], t[on[-1]]
            mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
            r["stress"] = fc[mid].mean() / (hi[0] - lo[0])
    return r


def machine():
    cpu = ""
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name"):
                cpu = line.split(":", 1)[1].strip()
    except OSError:
        pass
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    return cpu, commit + ("-dirty" if dirty else ""), os.getloadavg()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mfcd", default=os.path.join(ROOT, "build/bin/mfcd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench/results/nts_vs_detm"))
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--case", action="append", default=[],
                    help="NAME=DECK: another case (the patch test)")
    a = ap.parse_args()
    cases = {k: CASES[k] for k in a.cases.split(",") if k}
    for c in a.case:
        name, deck = c.split("=", 1)
        cases[name] = (deck, name)
    os.makedirs(a.out, exist_ok=True)
    mfcd = os.path.abspath(a.mfcd)
    cpu, commit, load0 = machine()
    res = {}
    for name, (deck, _) in cases.items():
        deck = os.path.join(ROOT, deck)
        for det in DETECTORS:
            best = None
            for k in range(a.repeat):
                path, wall = run(mfcd, variant(deck, det, False, a.out, f"{name}_{det}"), a.out)
                r = measure(path)
                if best is None or r["t_loop"] < best["t_loop"]:
                    best = r
                print(f"{name} {det} run {k + 1}: loop {r['t_loop']:.3f} s, contact "
                      f"{r['t_contact']:.3f} s ({wall:.1f} s wall)", flush=True)
            res[name, det] = best
        path, _ = run(mfcd, variant(deck, "det_m", True, a.out, f"{name}_compare"), a.out)
        res[name, "compare"] = measure(path)
    load1 = os.getloadavg()
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    L = [f"Date {now}, commit {commit}, CPU {cpu}, 1 OpenMP thread, best of {a.repeat}; "
         f"load average {load0[0]:.2f} before, {load1[0]:.2f} after.",
         f"Command: `.venv/bin/python bench/nts_vs_detm.py --repeat {a.repeat}"
         f"{' --cases ' + a.cases if a.cases != ','.join(CASES) else ''}`", ""]
    L += ["**Per step** (evaluated: particles in the master's grown box; flagged: det(M) > "
          "threshold, or g < 0 for node-to-segment; detection: the detector and, for det(M), "
          "the gap of the flagged; the contact phase adds screening, forces, redistribution "
          "(eq. 98) and moving a deformable master):", "",
          "| case | detector | steps | evaluated / step | flagged / step (mean, most) | "
          "contacts / step | detection / step (us) | per evaluation (ns) | "
          "contact phase / step (us) | time loop / step (us) | contact share |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in cases:
        for det in DETECTORS:
            r = res[name, det]
            n = r["steps"]
            L.append(f"| {name} | {det} | {n} | {r['evaluated'] / n:.1f} | "
                     f"{r['flagged'] / n:.1f}, {r['flag_max']:.0f} | {r['contacts'] / n:.1f} | "
                     f"{1e6 * r['t_detect'] / n:.2f} | "
                     f"{1e9 * r['t_detect'] / max(r['evaluated'], 1):.0f} | "
                     f"{1e6 * r['t_contact'] / n:.2f} | {1e6 * r['t_loop'] / n:.1f} | "
                     f"{100 * r['t_contact'] / r['t_loop']:.1f}% |")
    L += ["", "**Where they disagree** (compare_detectors: both at every screened particle "
          "and step; g from the closest segment at any distance):", "",
          "| case | det(M) flags | g < 0 | buffer zone: det(M) flags, g >= 0 | share of "
          "det(M)'s flags | buffer gap mean / largest (dx) | g < 0 missed by det(M) | "
          "dx (mm) |", "|---|---|---|---|---|---|---|---|"]
    for name in cases:
        r = res[name, "compare"]
        c = r["cmp"]
        L.append(f"| {name} | {c[0]:.0f} | {c[1]:.0f} | {c[2]:.0f} | "
                 f"{100 * c[2] / max(c[0], 1):.1f}% | {r['gap_mean'] / r['dx']:.3f} / "
                 f"{r['gap_max'] / r['dx']:.3f} | {c[3]:.0f} | {1e3 * r['dx']:.3g} |")
    L += ["", "**Final results**:", "",
          "| case | detector | shortening (mm) | foot radius (mm) | contact stress (MPa) | "
          "impulse (N s) | energy residual / scale |", "|---|---|---|---|---|---|---|"]
    for name in cases:
        for det in DETECTORS:
            r = res[name, det]
            L.append(f"| {name} | {det} | {1e3 * (r['length0'] - r['length']):.4f} | "
                     f"{1e3 * r['foot']:.4f} | "
                     + ("-" if np.isnan(r["stress"]) else f"{r['stress'] / 1e6:.3f}")
                     + f" | {r['impulse']:.5g} | {r['residual']:+.3e} |")
        a_, b_ = res[name, "det_m"], res[name, "node_to_segment"]
        same = all(a_[k] == b_[k] for k in ("length", "foot", "residual", "contacts"))
        L.append(f"| {name} | same? | " + ("identical" if same else "differ") + " | | | | |")
    text = "\n".join(L)
    print(text)
    with open(os.path.join(a.out, "nts_vs_detm.md"), "w") as f:
        f.write(text + "\n")


if __name__ == "__main__":
    main()
