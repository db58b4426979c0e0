#!/usr/bin/env python3
"""Work skipped where a scene does not need it gives the same results (issue 9, item 6).

Each switch is exact by construction, so each case runs twice, with the switch on (the
default) and off, and every dataset of the two output files must be equal bit for bit
(the same floating-point operations on the same values: a skipped particle would have
been found outside the master's box anyway), the /summary attributes too apart from the
timings and the counter of the skipped work itself, which must be > 0 with the switch on
and 0 with it off (so the test fails if the skip silently stopped skipping).

- &contact skip_far: the coarse RKPM Taylor bar (axisymmetric, viscoplastic, friction,
  rigid target), shortened to 6 us, and the coarse FEM elastic bar on a rigid wall; and
  the self-contact of the C-shape (input/c_shape_fold.nml), where it skips the surface
  particles that no non-neighbour can have reached; and a rigid ram moving at a prescribed
  velocity onto a bar at rest (input/ram_push.nml), whose box moves towards the particles;
  and the self-contact of a 3D C closing its slot (tests/mpi/c_clamp_3d.nml: its 5 mm slot
  beyond the default neighbour radius, to 42 us; its tips meet at 33 us and are pressed
  together), where the second pass of a step also skips the candidates the first
  pass's correction cannot have brought under a non-neighbour's support.
- &solver skip_quiet: the elastic wave (a bar pushed at one end) bit for bit; the elastic
  RKPM bar on a rigid wall to a relative 1e-9 of each dataset's largest value. A quiet
  point keeps F = I exactly where the full computation gives I + O(1e-16) (the gradients
  of a uniform translation sum to round-off), so the two runs differ by round-off seeds;
  an elastic run carries them at ~1e-11 (measured 2e-11 at most), and a disturbance the
  skip dropped would change the stresses by O(1). (A plastic impact amplifies the seeds:
  the coarse Taylor bar differs by up to 7 MPa in stress at single points either way, as
  much as a change of the impact speed by 1e-16 does; doc/benchmarks.md.)

Usage: check_skip_work.py /path/to/mfcd input/taylor_bar_rkpm_coarse.nml
       input/bar_impact_elastic_fem_coarse.nml input/elastic_wave.nml
       input/bar_impact_elastic_coarse.nml input/c_shape_fold.nml input/ram_push.nml
       tests/mpi/c_clamp_3d.nml
"""
import os
import re
import subprocess
import sys
import tempfile

import h5py  # compare() walks every dataset of two files, whatever the reader knows of
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile, is_timing  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
TAYLOR, FEM_BAR, WAVE, RKPM_BAR, C_SHAPE, RAM, CLAMP_3D = (
    os.path.abspath(p) for p in sys.argv[2:9])
RTOL_QUIET = 1e-9   # round-off seeds carried by an elastic run: measured <= 2e-11
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "skip_work." + name
          + ("" if cond else ": " + str(detail)[-1500:]), flush=True)


def run(tmp, src, name, edits):
    text = open(src).read()
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = 'out/%s.h5'" % name, text)
    for pattern, repl in edits:
        if pattern.startswith("&"):   # a new line at the start of the group
            text = re.sub(r"(%s\b[^\n]*\n)" % pattern, r"\1  %s\n" % repl, text, count=1)
        else:                         # a variable's value replaced
            text, n = re.subn(r"\b%s\s*=[^\n!]*" % pattern, repl, text, count=1)
            assert n == 1, pattern
    deck = os.path.join(tmp, name + ".nml")
    open(deck, "w").write(text)
    p = subprocess.run([MFCD, deck], cwd=tmp, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    check(name + " completes", p.returncode == 0, p.stdout[-800:] + p.stderr[-800:])
    return os.path.join(tmp, "out", name + ".h5"), p.stdout


def compare(name, on, off, counter, rtol=0.0, evaluated=None):
    diffs = []
    # bit for bit: every dataset of the two files (visititems), known to mfcd_h5 or not
    with h5py.File(on, "r") as a, h5py.File(off, "r") as b:
        def visit(key, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            if key not in b:
                diffs.append("missing " + key)
                return
            x, y = obj[()], b[key][()]
            if x.dtype.kind not in "fiu" or np.array_equal(x, y, equal_nan=True):
                return
            if rtol > 0.0 and x.shape == y.shape and x.dtype.kind == "f":
                scale = np.nanmax(np.abs(y)) if y.size else 0.0
                if key.startswith("history/bodies/") and not key.endswith("/ke"):
                    # a momentum component that stays ~0 (the bar's x) has no scale of its
                    # own: the body's momentum is its scale, times its size for the
                    # angular momentum (L about the centre: differences of M x v terms)
                    g = key.rsplit("/", 1)[0]
                    scale = max(np.nanmax(np.abs(b[g + "/" + c][()]))
                                for c in ("momentum_x", "momentum_y") if g + "/" + c in b)
                    if key.endswith("angular_momentum"):
                        scale *= np.nanmax(np.abs(b["bodies"][g.split("/")[2]]["x"][()]))
                if np.nanmax(np.abs(x - y)) <= rtol * scale:
                    return
            diffs.append(key)
        a.visititems(visit)
    with MfcdFile(on) as fa, MfcdFile(off) as fb:
        sa, sb = fa.summary_flat(), fb.summary_flat()
    for k in sa:
        if is_timing(k) or k == counter or k not in sb:
            continue
        if k == evaluated:   # the skipped evaluations are fewer, by design
            if not sa[k] < sb[k]:
                diffs.append("summary " + k)
            continue
        x, y = np.asarray(sa[k]), np.asarray(sb[k])
        if x.dtype.kind in "fiu" and not np.array_equal(x, y):
            if rtol > 0.0 and x.shape == y.shape and np.all(
                    np.abs(x - y) <= rtol * np.maximum(np.abs(y), 1e-300)):
                continue
            diffs.append("summary " + k)
    n_on = float(sa[counter])
    n_off = float(sb[counter])
    how = "bit for bit" if rtol == 0.0 else "to %g of each one's largest value" % rtol
    check(name + ": every dataset and summary value equal " + how, not diffs, diffs[:10])
    check(name + ": work skipped with the switch on (%d), none off (%d)" % (n_on, n_off),
          n_on > 0 and n_off == 0)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        taylor = [("t_end", "t_end = 6.0e-6"), ("snapshot_times", "snapshot_times = 0.0, 6.0e-6")]
        for name, src, edits in [("taylor_rkpm", TAYLOR, taylor), ("bar_fem", FEM_BAR, []),
                                 ("c_shape_self", C_SHAPE, []), ("ram", RAM, []),
                                 ("c_clamp_3d_self", CLAMP_3D, [])]:
            on, _ = run(tmp, src, name + "_far_on", edits)
            off, _ = run(tmp, src, name + "_far_off",
                         edits + [("&contact", "skip_far = .false.")])
            if os.path.exists(on) and os.path.exists(off):
                # self-contact: a skipped candidate is one whose det(M) would have been
                # evaluated (to 0), so fewer evaluations; screened, detected, contacts equal
                compare(name + " skip_far", on, off, "contacts/contact1/skipped_far",
                        evaluated="contacts/contact1/evaluated"
                        if name.endswith("_self") else None)
        for name, src, rtol in [("wave", WAVE, 0.0), ("bar_rkpm", RKPM_BAR, RTOL_QUIET)]:
            on, _ = run(tmp, src, name + "_quiet_on", [])
            off, _ = run(tmp, src, name + "_quiet_off", [("&solver", "skip_quiet = .false.")])
            if os.path.exists(on) and os.path.exists(off):
                compare(name + " skip_quiet", on, off, "bodies/bar/quiet_point_steps_skipped",
                        rtol)
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
