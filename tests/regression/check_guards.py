#!/usr/bin/env python3
"""A run that goes unstable stops cleanly (issue 3, item 7): the elastic-wave deck with a
fixed time step five times the critical one must stop with exit code 1 and a message naming
the step, the body and the quantity, keep the output written so far under the failed-run
name out/unstable.failed.h5 (never under the result's name out/unstable.h5), and add a
diagnostic snapshot /snapshots/failure and a /summary whose status is 'failed'. A bad
deck for the dynamic mode (unknown material, a detection threshold above the master's
det(M) plateau) exits 2 and writes nothing, not even the output directory.
Usage: check_guards.py /path/to/mfcd /path/to/input/elastic_wave.nml
"""
import os
import re
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
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "guards." + name
          + ("" if cond else ": " + str(detail)))


def main():
    work = tempfile.mkdtemp(prefix="mfcd_guard_")
    text = open(DECK).read()
    text = re.sub(r"cfl = 0\.5", "dt = 7.0e-7", text)
    text = text.replace("output/elastic_wave.h5", "out/unstable.h5")
    path = os.path.join(work, "unstable.nml")
    open(path, "w").write(text)
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True, timeout=300)
    check("unstable run exits 1", p.returncode == 1, (p.returncode, p.stderr[-500:]))
    check("message names the step and the body", re.search(r"step \d+", p.stderr) is not None
          and "bar" in p.stderr, p.stderr[-500:])
    check("log warns that dt exceeds the critical step", "exceeds the estimated critical" in
          p.stdout)
    out = os.path.join(work, "out", "unstable.failed.h5")
    check("output kept under the failed-run name", os.path.exists(out)
          and os.path.exists(os.path.join(work, "out", "unstable.failed.xdmf")),
          os.listdir(work))
    check("nothing under the result's name", not os.path.exists(
        os.path.join(work, "out", "unstable.h5")))
    if os.path.exists(out):
        with MfcdFile(out) as f:
            check("diagnostic snapshot written", "failure" in f.snapshot_labels())
            check("summary says failed", f.summary["status"].startswith("failed"))
            check("summary names the failure", len(f.summary["failure"].strip()) > 10)
            check("history kept up to the failure", f.history()["time"].shape[0] > 1)
            ok = True
            for k in f.snapshot_labels():
                if k != "failure":
                    ok &= bool(np.all(np.isfinite(f.snapshot(k).bodies["bar"].x)))
            check("snapshots before the failure are finite", ok)
    bad = open(DECK).read().replace("material = 'steel_elastic'", "material = 'steal'")
    bad = bad.replace("output/elastic_wave.h5", "out2/bad.h5")
    path = os.path.join(work, "bad.nml")
    open(path, "w").write(bad)
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True, timeout=60)
    check("unknown material: exit 2 naming the valid ones", p.returncode == 2 and "'steal'" in
          p.stderr and "steel_elastic" in p.stderr, p.stderr)
    check("unknown material: nothing written", not os.path.exists(os.path.join(work, "out2")))
    # a detection threshold at or above the master's plateau would let the slave pass
    # through the master silently (bench/sweeps.py): refused before any output
    taylor = os.path.join(os.path.dirname(DECK), "taylor_bar_rkpm_coarse.nml")
    text = open(taylor).read().replace("eps_cr = 5.0e-10", "eps_cr = 1.0e-4")
    text = text.replace("output/taylor_bar_rkpm_coarse.h5", "out3/t.h5")
    path = os.path.join(work, "eps.nml")
    open(path, "w").write(text)
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True, timeout=120)
    check("threshold above the plateau: exit 2 naming &contact eps_cr and the plateau",
          p.returncode == 2 and "&contact" in p.stderr and "eps_cr" in p.stderr and
          "plateau" in p.stderr, p.stderr)
    check("threshold above the plateau: nothing written, not even the directory",
          not os.path.exists(os.path.join(work, "out3")))
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
