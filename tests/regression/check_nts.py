#!/usr/bin/env python3
"""The node-to-segment detector against det(M) (issue 9, item 5; doc/contact.md, Detection).

Runs the elastic bar striking a rigid wall (1 mm spacing) and the two deformable bars
colliding (both detection passes of eq. 28, a moving master whose segment buckets are
re-sorted every step) once with &contact detector = 'det_m' and once with
'node_to_segment', both with compare_detectors = .true., and checks:

- the node-to-segment run against the closed forms of 1D impact: contact stress rho c0 v
  within 5% and duration 2 L / c0 within 3% for the bar (the coarse tolerances of
  check_bar_impact.py: the RK front smeared over a few supports; the collision at 0.5 mm:
  3% and 2%, as check_collision.py);
- the two runs agree: contact force, kinetic energy and contact count histories and the
  final velocities to 1e-12 relative to their largest value. Both detectors hand the
  particles with g < 0 to the same force code with the same gap (the same closest-segment
  rule), and det(M) misses none here (checked below), so the same particles get the same
  forces; what may differ is only a tie between two equally close segments taken in
  another order (the same gap to round-off, ~1e-16), far below 1e-12, while one particle
  more or less in contact changes the force by a whole row's share (~10%);
- the counters: the node-to-segment run flags exactly the penetrating particles (detected
  = contacts); det(M) flags more (its buffer zone: det > threshold with g >= 0, no force,
  all within one support of the surface); det(M) misses no penetrating particle; both runs
  screen the same particles and count the same disagreements.

Usage: check_nts.py /path/to/mfcd input/bar_impact_elastic_coarse.nml
       input/bars_collision_elastic.nml
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

COUNTS = ("screened", "evaluated", "detected", "contacts")
COMPARE = ("compare_det", "compare_gap", "compare_buffer", "compare_missed", "compare_det_max",
           "compare_gap_max")

MFCD = os.path.abspath(sys.argv[1])
DECKS = {"bar": os.path.abspath(sys.argv[2]), "collision": os.path.abspath(sys.argv[3])}
E, RHO, V, L, W = 211e9, 7800.0, 1.0, 0.06, 0.006
C0 = np.sqrt(E / RHO)
SIG, T_C = RHO * C0 * V, 2 * L / C0
TOL = {"bar": (0.05, 0.03), "collision": (0.03, 0.02)}   # stress, duration (see above)
AGREE = 1e-12                                            # relative (see above)
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "nts." + name
          + ("" if cond else ": " + str(detail)))


def variant(deck, detector, work):
    """A copy of deck with the detector chosen, both compared, output into work."""
    text = open(deck).read()
    text = re.sub(r"(&contact\b)", r"\1\n  detector = '%s'\n  compare_detectors = .true."
                  % detector, text, count=1)
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", f"file = '{detector}.h5'", text)
    path = os.path.join(work, f"{detector}.nml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(deck, work):
    p = subprocess.run([MFCD, deck], cwd=work, capture_output=True, text=True, timeout=600)
    if p.returncode:
        print(p.stdout[-3000:], p.stderr[-3000:])
        return None, p.stdout
    return MfcdFile(os.path.join(work, os.path.basename(deck)[:-4] + ".h5")), p.stdout


def closed_form_errors(f):
    h = f.history()
    t, n, fc = h["time"], h["n_contact"], h["f_contact"]
    on = np.nonzero(n > 0)[0]
    t0, t1 = t[on[0]], t[on[-1]]
    t_sep = t[min(on[-1] + 1, len(t) - 1)]
    mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
    return fc[mid].mean() / W / SIG - 1, (t_sep - t0) / T_C - 1


def final_velocities(f):
    last = sorted(f.snapshot_labels())[-1]
    g = f.snapshot(last).bodies
    return np.concatenate([g[b].v.ravel() for b in sorted(g) if g[b].v is not None])


def main():
    for case, deck in DECKS.items():
        work = tempfile.mkdtemp(prefix=f"mfcd_nts_{case}_")
        out = {}
        for det in ("det_m", "node_to_segment"):
            f, log = run(variant(deck, det, work), work)
            check(f"{case}: {det} run exits 0", f is not None)
            if f is None:
                sys.exit(1)
            check(f"{case}: {det}: log names the detector",
                  f"detector {det}" in log and "detectors compared" in log)
            out[det] = f
        a, b = out["det_m"], out["node_to_segment"]
        pa, pb = a.summary_contacts()[1], b.summary_contacts()[1]
        ta, tb = a.summary_timing, b.summary_timing
        check(f"{case}: /summary names the detector",
              pb["detector"] == "node_to_segment" and pa["detector"] == "det_m")
        es, ed = closed_form_errors(b)
        ts, td = TOL[case]
        check(f"{case}: node_to_segment contact stress = rho c0 v ({es:+.4f})", abs(es) <= ts, es)
        check(f"{case}: node_to_segment duration = 2 L / c0 ({ed:+.4f})", abs(ed) <= td, ed)
        ha, hb = a.history(), b.history()
        for key in ("f_contact", "ke", "n_contact"):
            x, y = ha[key], hb[key]
            ok = x.shape == y.shape and np.max(np.abs(x - y)) <= AGREE * np.max(np.abs(x))
            check(f"{case}: {key} histories agree", ok,
                  np.max(np.abs(x - y)) if x.shape == y.shape else (x.shape, y.shape))
        va, vb = final_velocities(a), final_velocities(b)
        check(f"{case}: final velocities agree",
              np.max(np.abs(va - vb)) <= AGREE * np.max(np.abs(va)), np.max(np.abs(va - vb)))
        ca, cb = (np.array([p[k] for k in COUNTS]) for p in (pa, pb))
        cmp_a, cmp_b = (np.array([p[k] for k in COMPARE]) for p in (pa, pb))
        check(f"{case}: same particles screened and evaluated", np.all(ca[:2] == cb[:2]),
              (ca, cb))
        check(f"{case}: node_to_segment flags exactly the contacts ({cb[2]:.0f})",
              cb[2] == cb[3] and cb[3] > 0, cb)
        check(f"{case}: det(M) flags more than it forces ({ca[2]:.0f} > {ca[3]:.0f})",
              ca[2] > ca[3], ca)
        check(f"{case}: det(M) misses no penetration", cmp_a[3] == 0 and cmp_b[3] == 0,
              (cmp_a, cmp_b))
        check(f"{case}: buffer zone = det(M) flags - contacts ({cmp_b[2]:.0f})",
              cmp_b[2] == ca[2] - ca[3] and cmp_b[0] == ca[2] and cmp_b[1] == cb[2],
              (cmp_b, ca, cb))
        check(f"{case}: both runs count the same disagreements", np.all(cmp_a == cmp_b),
              (cmp_a, cmp_b))
        gmean, gmax = pb["buffer_gap_mean"], pb["buffer_gap_max"]
        # the buffer zone lies outside the surface, within the master's support reach
        # (support_factor 2 x the 1 mm or 0.5 mm spacing)
        dx = min(b.body(n).spacing[0] for n in b.body_names())
        check(f"{case}: buffer zone outside the surface, within one support "
              f"(mean {gmean / dx:.3f} dx, largest {gmax / dx:.3f} dx)",
              0.0 <= gmean <= gmax <= 2.0 * dx, (gmean, gmax, dx))
        print(f"{case}: flagged det(M) {ca[2]:.0f}, node-to-segment {cb[2]:.0f}, "
              f"buffer {cmp_b[2]:.0f}, missed {cmp_b[3]:.0f}; contact phase "
              f"{ta['contact']:.3f} s vs {tb['contact']:.3f} s "
              "(with both compared)")
        a.close()
        b.close()
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
