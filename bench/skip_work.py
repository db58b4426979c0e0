#!/usr/bin/env python3
"""Work skipped where a scene does not need it (issue 9, item 6): the Taylor bar run with
&contact skip_far and &solver skip_quiet on (the defaults) and off, one at a time and both.

    .venv/bin/python bench/skip_work.py [--threads 2] [--cases paper,coarse,flight]

Cases: 'paper' (input/taylor_bar_rkpm.nml, the main job's run), 'coarse'
(input/taylor_bar_rkpm_coarse.nml) and 'flight' (the coarse deck with the bar starting
2 mm above the target: 10 us of flight before the impact, what skip_quiet is for).
Per run: wall time of the time loop, its contact and kinematics+material+force shares
(from the log's summary), the skip counters, and the final length, foot radius and largest
plastic strain, which must agree between the runs (skip_far bit for bit; skip_quiet to
round-off, which a plastic impact amplifies: see doc/benchmarks.md). Prints Markdown and
writes bench/results/skip_work_<date>.md (git-ignored). Never fails on a time.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import h5py

from bench_record import ROOT, load_row, record_head, write_results
from mfcd_h5 import MfcdFile

MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
CASES = {"paper": "taylor_bar_rkpm.nml", "coarse": "taylor_bar_rkpm_coarse.nml",
         "flight": "taylor_bar_rkpm_coarse.nml"}
VARIANTS = [("both on (default)", []),
            ("skip_far off", [("&contact", "skip_far = .false.")]),
            ("skip_quiet off", [("&solver", "skip_quiet = .false.")]),
            ("both off", [("&contact", "skip_far = .false."),
                          ("&solver", "skip_quiet = .false.")])]
LOOP = re.compile(r"time loop\s+([0-9.]+) s: kinematics\s+([0-9.]+)%, material\s+([0-9.]+)%, "
                  r"internal force\s+([0-9.]+)%, contact\s+([0-9.]+)%")


def deck_text(case, edits, out):
    text = open(os.path.join(ROOT, "input", CASES[case])).read()
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = '%s'" % out, text)
    if case == "flight":
        # the bar's particles 2 mm higher: lo and hi of the bar's rectangle
        def lift(m):
            return "%s = %s, %g" % (m.group(1), m.group(2), float(m.group(3)) + 0.002)
        head, sep, rest = text.partition("name = 'bar'")
        rest = re.sub(r"\b(lo|hi)\s*=\s*([-0-9.eE]+)\s*,\s*([-0-9.eE]+)", lift, rest, count=2)
        text = head + sep + rest
    for group, line in edits:
        text = re.sub(r"(%s\b[^\n]*\n)" % group, r"\1  %s\n" % line, text, count=1)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cases", default="paper,coarse,flight")
    a = ap.parse_args()
    lines = record_head("# Skipped work (bench/skip_work.py)",
                        ".venv/bin/python bench/skip_work.py --threads %d" % a.threads) + [
             "",
             "| case | switches | time loop (s) | contact (s) | solid passes (s) | "
             "screenings skipped | point-steps skipped | length (mm) | foot radius (mm) | "
             "max epsbar |", "|---|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        for case in a.cases.split(","):
            for k, (name, edits) in enumerate(VARIANTS):
                out = os.path.join(tmp, "%s_%d.h5" % (case, k))
                deck = os.path.join(tmp, "%s_%d.nml" % (case, k))
                open(deck, "w").write(deck_text(case, edits, out))
                p = subprocess.run([MFCD, deck], capture_output=True, text=True, cwd=tmp,
                                   env=dict(os.environ, OMP_NUM_THREADS=str(a.threads)))
                m = LOOP.search(p.stdout)
                if p.returncode != 0 or not m:
                    sys.exit("run failed: %s\n%s" % (deck, p.stdout[-2000:] + p.stderr))
                tl = float(m.group(1))
                shares = [float(m.group(i)) for i in range(2, 6)]
                with MfcdFile(out) as f:
                    bar = f.summary_bodies()["bar"]
                    far = float(f.summary_contacts()[1]["skipped_far"])
                    quiet = float(bar["quiet_point_steps_skipped"])
                row = "| %s | %s | %.2f | %.2f | %.2f | %.3g | %.3g | %.4f | %.4f | %.4f |" % (
                    case, name, tl, tl*shares[3]/100, tl*sum(shares[:3])/100, far, quiet,
                    1e3*bar["length"], 1e3*bar["foot_radius"], bar["max_epsbar"])
                lines.append(row)
                print(row, flush=True)
    lines.append("")
    lines.append(load_row("after"))
    path = write_results("skip_work", lines)
    print("written: " + os.path.relpath(path, ROOT), file=sys.stderr)


if __name__ == "__main__":
    main()
