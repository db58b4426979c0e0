#!/usr/bin/env python3
"""What self-contact costs (issue 10, item 5): each self-contact deck run with the pair's
skipping on (&contact skip_far, the default) and off, and its control without the pair.

    .venv/bin/python bench/self_contact.py [--threads 1] [--cases c_shape_fold,ring_crush,...]
        [--mfcd PATH]

Per run, from the log's summary and /summary: steps, wall time of the time loop, the
self-contact pair's own wall time (/summary/contacts/contact<k> pair_time: positions, re-binning, det(M) of
the non-neighbours, gaps, forces), its cost relative to the rest of the step
(t_pair / (t_loop - t_pair)), microseconds per step and nanoseconds per surface-particle
step, the share of surface-particle screenings skipped, and the same-run ratio of the loop
time with the pair to the control's; and the self-interpenetration left at the end
(post/self_overlap.py). Cases: c_shape_fold (RKPM), ring_crush (CST4, plane strain),
torus_crush (CST4, axisymmetric), bar_bend and bar_bend_fem (bent without folding: the
pair finds nothing; no control); in 3D c_shape_fold_3d (RKPM), c_shape_fold_3d_fem
(tetrahedra) and bar_bend_3d (the overlap depth is measured in 2D only: "-" in 3D).
--mfcd: another build's mfcd (an A/B against an older commit). Prints Markdown and writes
bench/results/self_contact_<date>.md (git-ignored). Never fails on a time.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

from bench_record import ROOT, load_row, record_head, write_results
from self_overlap import overlap
from mfcd_h5 import MfcdFile

MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
CASES = {"c_shape_fold": "c", "ring_crush": "ring", "torus_crush": "torus",
         "bar_bend": "bar", "bar_bend_fem": "bar", "c_shape_fold_3d": "c",
         "c_shape_fold_3d_fem": "c", "bar_bend_3d": "bar"}
LOOP = re.compile(r"time loop\s+([0-9.]+) s")


def run(tmp, deck, label, threads, skip=True):
    text = open(os.path.join(ROOT, "input", deck + ".nml")).read()
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = 'out/%s.h5'" % label, text)
    if not skip:   # skip_far off on the self-contact pair only
        text, n = re.subn(r"(&contact\s*\n\s*master\s*=\s*'(\w+)'\s*\n\s*slave\s*=\s*'\2'\s*\n)",
                          r"\1  skip_far = .false.\n", text)
        assert n == 1, deck
    path = os.path.join(tmp, label + ".nml")
    open(path, "w").write(text)
    p = subprocess.run([run.mfcd, path], cwd=tmp, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    if p.returncode != 0:
        sys.exit("bench/self_contact.py: %s failed:\n%s" % (label, p.stdout[-1500:] + p.stderr))
    h5 = os.path.join(tmp, "out", label + ".h5")
    out = {"loop": float(LOOP.search(p.stdout).group(1)), "h5": h5}
    with MfcdFile(h5) as f:
        out["steps"] = int(f.summary["steps"])
        out["t_pair"] = 0.0
        k = f.self_contact_pair()
        if k is not None:
            c = f.summary_contacts()[k]
            out.update(t_pair=float(c["pair_time"]), screened=c["screened"],
                       evaluated=c["evaluated"], contacts=c["contacts"],
                       skipped=float(c["skipped_far"]))
    return out


def depth(h5, body):
    with MfcdFile(h5) as f:
        b = f.body(body)
        if b.ndim == 3:
            return None, None, len(np.unique(b.facets))
        x = f.snapshot(f.snapshot_labels()[-1]).bodies[body].x
        step = 0.05 * float(np.min(np.atleast_1d(b.attrs["spacing"])[:2]))
        nsurf = len(np.unique(np.concatenate(b.loops)))
        return overlap(b.polylines(x=x), step)[1], float(np.max(b.support)), nsurf


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--mfcd", default=MFCD)
    a = ap.parse_args()
    run.mfcd = os.path.abspath(a.mfcd)
    cmd = ".venv/bin/python bench/self_contact.py --threads %d --cases %s --mfcd %s" % (
        a.threads, a.cases, a.mfcd)
    lines = record_head("# Self-contact cost (bench/self_contact.py)", cmd,
                        ["| threads | %d |" % a.threads]) + [
        "", "| case | run | steps | loop (s) | self pair (s) | pair / rest of step | "
        "us/step | ns/(surface particle step) | screenings skipped | loop / control | "
        "overlap depth at end (supports) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    if a.mfcd != MFCD:
        lines.insert(1, "mfcd: %s" % a.mfcd)
    with tempfile.TemporaryDirectory() as tmp:
        for case in a.cases.split(","):
            body = CASES[case]
            control = None
            if os.path.exists(os.path.join(ROOT, "input", case + "_free.nml")):
                control = run(tmp, case + "_free", case + "_free", a.threads)
            for label, skip in [("skip on", True), ("skip off", False)]:
                r = run(tmp, case, "%s_%s" % (case, label.split()[1]), a.threads, skip)
                d, rho, nsurf = depth(r["h5"], body)
                rest = r["loop"] - r["t_pair"]
                lines.append("| %s | self-contact, %s | %d | %.2f | %.3f | %.3f | %.1f | %.0f | "
                             "%.1f%% | %s | %s |" % (
                                 case, label, r["steps"], r["loop"], r["t_pair"],
                                 r["t_pair"] / rest, 1e6 * r["t_pair"] / r["steps"],
                                 1e9 * r["t_pair"] / (r["steps"] * nsurf),
                                 100.0 * r["skipped"] / max(r["screened"], 1),
                                 "%.3f" % (r["loop"] / control["loop"]) if control else "-",
                                 "%.3f" % (d / rho) if d is not None else "-"))
                print(lines[-1], flush=True)
            if control:
                d, rho, _ = depth(control["h5"], body)
                lines.append("| %s | control, no self-contact | %d | %.2f | - | - | - | - | - | "
                             "1 | %s |" % (case, control["steps"], control["loop"],
                                           "%.3f" % (d / rho) if d is not None else "-"))
                print(lines[-1], flush=True)
    lines.append(load_row("after"))
    print("\n".join(lines[:10]))
    print("wrote", write_results("self_contact", lines))


if __name__ == "__main__":
    main()
