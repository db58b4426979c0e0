#!/usr/bin/env python3
"""Bodies read from particle files (issue 2, item 4): the Example 2.2 rectangle written as
plain columns and as HDF5 must give the same det(M) as the generator's body, to round-off,
and keep the boundary polyline given in the file; a malformed file exits 2 naming it.
Usage: check_particle_files.py /path/to/mfcd
"""
import os
import subprocess
import sys
import tempfile

import h5py  # only to write the HDF5 particle file (an input of mfcd, not its output)
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + name + ("" if cond else ": " + str(detail)))


def deck(shape_lines, out):
    return f"""&run ndim = 2 /
&body
  name = 'block'
{shape_lines}
  support_factor = 2.0, 2.0
/
&detection
  grid_lo = 0.0, 0.0
  grid_hi = 30.0, 20.0
  grid_n = 61, 41
/
&output file = '{out}' /
"""


def run(work, name, text):
    path = os.path.join(work, name + ".nml")
    with open(path, "w") as f:
        f.write(text)
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True, timeout=300)
    return p.returncode, p.stderr


def main():
    work = tempfile.mkdtemp(prefix="mfcd_pfile_")
    rc, err = run(work, "gen", deck("  shape = 'rectangle'\n  lo = 5, 5\n  hi = 25, 15\n"
                                    "  n = 41, 21", "gen.h5"))
    check("generator run", rc == 0, err)
    with MfcdFile(os.path.join(work, "gen.h5")) as g:
        b = g.body("block")
        ref = g.query("grid").det
    x, vol = b.x, b.volume
    # the file's loop_idx: the boundary loops, 1-based, one after the other
    idx = np.concatenate(b.loops) + 1
    loop = np.zeros(len(vol), int)
    order = np.zeros(len(vol), int)
    loop[idx - 1] = 1
    order[idx - 1] = np.arange(1, len(idx) + 1)
    # plain columns: x y volume loop order, with a comment line
    with open(os.path.join(work, "block.txt"), "w") as f:
        f.write("# x y volume loop order\n")
        for i in range(len(vol)):
            f.write(f"{x[i, 0]:.17g} {x[i, 1]:.17g} {vol[i]:.17g} {loop[i]} {order[i]}\n")
    with h5py.File(os.path.join(work, "block.h5"), "w") as f:
        f["particles/x"] = x
        f["particles/volume"] = vol
        f["particles/loop"] = loop.astype(np.int32)
        f["particles/order"] = order.astype(np.int32)
    for kind, fname in (("plain columns", "block.txt"), ("HDF5", "block.h5")):
        out = fname.replace(".", "_") + "_out.h5"
        text = deck(f"  shape = 'file'\n  file = '{fname}'\n  spacing = 0.5, 0.5", out)
        rc, err = run(work, "file_" + fname.replace(".", "_"), text)
        check(f"{kind}: run", rc == 0, err)
        if rc != 0:
            continue
        with MfcdFile(os.path.join(work, out)) as h:
            det = h.query("grid").det
            idx_h = np.concatenate(h.body("block").loops) + 1
            plateau = h.detection["plateau"]
        check(f"{kind}: det(M) equals the generator's", np.allclose(det, ref, rtol=1e-12,
                                                                     atol=1e-20),
              np.abs(det - ref).max())
        check(f"{kind}: boundary polyline kept", np.array_equal(idx_h, idx))
        check(f"{kind}: plateau 1/20736", abs(plateau - 1 / 20736) < 1e-17)
    with open(os.path.join(work, "bad.txt"), "w") as f:
        f.write("1.0 2.0\nnot a number here\n")
    rc, err = run(work, "bad", deck("  shape = 'file'\n  file = 'bad.txt'", "bad_out.h5"))
    check("malformed particle file: exit 2 naming file and line",
          rc == 2 and "bad.txt" in err and "line" in err and
          not os.path.exists(os.path.join(work, "bad_out.h5")), err)
    rc, err = run(work, "nofile", deck("  shape = 'file'\n  file = 'none.h5'", "no_out.h5"))
    check("missing particle file: exit 2", rc == 2 and "none.h5" in err, err)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
