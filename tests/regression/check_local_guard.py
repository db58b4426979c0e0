#!/usr/bin/env python3
"""A local blow-up is caught by the local guard (issue 8, item 3). The large-strain impact
input/bar_impact_j2.nml with dt fixed at cfl 0.5 of the undeformed bar's critical step
(2.92e-8 s; the default step follows the deformation and completes) goes unstable at a few
particles of the impact face near the axis, while the global energy residual is still
within energy_tol. The run must stop with exit 1 on a per-point check before the energy
guard trips, with a message naming the step, the body, the integration point and its
particle, the quantity and the likely fix; keep its output (under the failed run's own name,
out/local.failed.h5, doc/deck.md) with a /snapshots/failure and a
/summary whose status is 'failed' and whose energy residual is below energy_tol x scale.
Usage: check_local_guard.py /path/to/mfcd /path/to/input/bar_impact_j2.nml
"""
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD, DECK = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
ENERGY_TOL = 0.05  # the deck's (default) energy_tol
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "local_guard." + name
          + ("" if cond else ": " + str(detail)))


def main():
    work = tempfile.mkdtemp(prefix="mfcd_local_")
    text = open(DECK).read()
    text = text.replace("  t_end = 30.0e-6\n", "  t_end = 30.0e-6\n  dt = 2.92e-8\n")
    text = text.replace("output/bar_impact_j2.h5", "out/local.h5")
    path = os.path.join(work, "local.nml")
    open(path, "w").write(text)
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True, timeout=600)
    err = p.stderr
    check("run exits 1", p.returncode == 1, (p.returncode, err[-800:]))
    check("message names step, body, point and particle",
          re.search(r"step \d+, body 'bar', integration point \d+ \(particle \d+\)", err)
          is not None, err[-800:])
    check("message names a local quantity",
          any(w in err for w in ("plastic strain", "J = ", "speed")), err[-800:])
    check("message names the likely fix", "smaller cfl" in err, err[-800:])
    check("not the energy guard", "energy residual" not in err, err[-800:])
    check("no result under the final name", not os.path.exists(os.path.join(work, "out",
                                                                          "local.h5")))
    with MfcdFile(os.path.join(work, "out", "local.failed.h5")) as f:
        check("diagnostic snapshot written", "failure" in f.snapshot_labels())
        s = f.summary
    status = s["status"]
    check("summary status failed", status == "failed", status)
    rel = abs(s["energy_residual"]) / s["energy_scale"]
    check(f"energy residual {rel:.3e} of scale still within energy_tol", rel < ENERGY_TOL, rel)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
