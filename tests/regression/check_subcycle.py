#!/usr/bin/env python3
"""Subcycling (&solver subcycle; doc/solver.md, "Subcycling"): the same runs with and without
it, against closed forms and against each other, and the work it saves.

A. An elastic bar striking a rigid wall (plane strain, nu = 0, 1 m/s; the 1D closed forms of
   check_bar_impact.py: contact stress rho c0 v, contact duration 2 L / c0, rebound at v
   with the kinetic energy returned) on a graded triangle mesh whose three bottom rows are
   1/8 as tall as the others (built here: a particle file with /mesh/triangles). Without
   subcycling those rows set the step of the whole bar; with it they take 8 sub-steps.
   - both runs meet the closed forms within the coarse tolerances of check_bar_impact.py
     (stress 5%, duration 3%, rebound and energy 4%: the same front smearing and exact
     enforcement losses, which subcycling does not touch);
   - the two runs agree on stress, rebound and energy to 0.5% and on the duration to 1%
     (the time integration differs only in the thin rows, where both are stable and
     second order; measured: stress 0.02%, rebound and energy 0.1%, duration 0.45%, which
     is read from history rows a whole step apart, 4 sub-steps with subcycling);
   - the energy balance: the residuals (-8.6e-4 of the energy scale, the losses of exact
     contact enforcement) differ by at most 1e-4 (measured 4.5e-5; a wrong interface
     trajectory or a force applied over the wrong step shows here first);
   - subcycling happened (at least 4 sub-steps in a step) and the point updates fell to at
     most 40% of the plain run's (measured 29%).
B. The coarse FEM Taylor bar (input/taylor_bar_fem_coarse.nml, viscoplastic, friction) to
   12 us, where the elements at the lip flatten and their critical step falls ~10-fold:
   length within 0.05%, foot radius within 1%, width within 1% of the plain run (measured
   0.0005 / 0.001 / 0.001%; the foot radius is read at the lip, whose one-point elements
   localise, so it gets the loosest bound), energy residuals within 1e-3 of each other
   (measured 2e-5), and at most 75% of the point updates (measured 63%: the lip only
   starts to flatten by 12 us; over the whole run to 24 us it is about 20%).
C. (given a third deck) The 3D Taylor quarter by linear tetrahedra with averaged nodal
   pressure (input/taylor_bar_3d_fem_coarse.nml: symmetry planes, viscoplastic, friction)
   to 24 us, the whole impact: the bounds of B on length, foot radius, width and the
   residuals (measured: length 0, foot radius +0.016%, width +0.012%; residuals 5.7e-5
   and 2.2e-4), and at most 60% of the point updates (measured 46.5%, 596 steps against
   1,516). Subcycling in 3D needs nothing of its own: the rates, the sub-steps' point lists
   and the nodal pressure average over the listed points are dimension-free.
Both runs use the default adaptive step (cfl 0.5).

Usage: check_subcycle.py /path/to/mfcd input/taylor_bar_fem_coarse.nml
                         [input/taylor_bar_3d_fem_coarse.nml]
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "post"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from mfcd_h5 import MfcdFile  # noqa: E402
from mesh_body import boundary_loops, dual_cells, write_body  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
TAYLOR = os.path.abspath(sys.argv[2])
TAYLOR_3D = os.path.abspath(sys.argv[3]) if len(sys.argv) > 3 else None
E, RHO, V, L, W = 211e9, 7800.0, 1.0, 0.06, 0.006
C0 = np.sqrt(E / RHO)
SIG, T_C = RHO * C0 * V, 2 * L / C0
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "subcycle." + name
          + ("" if cond else ": " + str(detail)[-2000:]), flush=True)


def graded_bar(path):
    """A 6 x 60 mm bar of triangles, 0.5 mm columns; rows 0.0625 mm tall for the bottom
    0.1875 mm, 0.5 mm above; each box split by a diagonal, alternating."""
    xs = np.linspace(0.0, W, 13)
    ys = np.concatenate([np.arange(4) * 0.0625e-3,
                         0.1875e-3 + np.arange(1, 120) * 0.5e-3])
    ys[-1] = L
    nx, ny = len(xs), len(ys)
    x = np.array([[a, b] for b in ys for a in xs])
    tri = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            n0, n1 = j * nx + i, j * nx + i + 1
            n2, n3 = n1 + nx, n0 + nx
            if (i + j) % 2 == 0:
                tri += [(n0, n1, n2), (n0, n2, n3)]
            else:
                tri += [(n0, n1, n3), (n1, n2, n3)]
    tri = np.array(tri)
    ptr, xy = dual_cells(x, tri)
    write_body(path, x, tri, boundary_loops(tri), ptr, xy, {"source": "check_subcycle.py"})


BAR_DECK = """&run
  title = 'Elastic bar on a graded mesh striking a rigid wall'
  mode = 'dynamic'
  ndim = 2
  geometry = 'plane'
/
&material
  name = 'steel_elastic'
  model = 'elastic'
  density = 7800.0
  youngs_modulus = 211.0e9
  poisson_ratio = 0.0
/
&body
  name = 'bar'
  shape = 'file'
  file = '{mesh}'
  material = 'steel_elastic'
  discretization = 'fem'
  velocity = 0.0, -1.0
/
&body
  name = 'wall'
  role = 'rigid'
  shape = 'rectangle'
  lo = -0.003, -0.003
  hi = 0.009, 0.0
  n = 25, 7
  support_factor = 2.0, 2.0
/
&contact
  master = 'wall'
  slave = 'bar'
  eps_cr = 5.0e-10
  mu = 0.0
/
&solver
  t_end = 40.0e-6
  history_every = 1
  snapshot_times = 0.0, 40.0e-6
  subcycle = {sub}
/
&output
  file = '{out}'
/
"""


def run(deck, work):
    p = subprocess.run([MFCD, deck], cwd=work, capture_output=True, text=True, timeout=1800)
    return p.returncode, p.stdout + p.stderr


def bar_case(work):
    mesh = os.path.join(work, "graded_bar.h5")
    graded_bar(mesh)
    m = {}
    for sub in (".false.", ".true."):
        tag = "on" if sub == ".true." else "off"
        deck = os.path.join(work, f"bar_{tag}.nml")
        with open(deck, "w") as fh:
            fh.write(BAR_DECK.format(mesh=mesh, sub=sub, out=f"bar_{tag}.h5"))
        rc, log = run(deck, work)
        check(f"graded bar, subcycle {tag}: exits 0", rc == 0, log)
        if rc:
            return
        with MfcdFile(os.path.join(work, f"bar_{tag}.h5")) as f:
            h = f.history()
            s = f.summary
            last = sorted(f.snapshot_labels())[-1]
            v = f.snapshot(last).bodies["bar"].v
            bar = f.body("bar")
            nq = f.body("bar").triangles.shape[0]
        t, n, fc = h["time"], h["n_contact"], h["f_contact"]
        on = np.nonzero(n > 0)[0]
        t0, t1 = t[on[0]], t[on[-1]]
        t_sep = t[min(on[-1] + 1, len(t) - 1)]
        mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
        mass = bar.volume * RHO
        m[tag] = {"stress": fc[mid].mean() / W / SIG - 1, "duration": (t_sep - t0) / T_C - 1,
                  "rebound": np.sum(mass * v[:, 1]) / mass.sum() / V - 1,
                  "energy": h["ke"][-1] / h["ke"][0] - 1,
                  "residual": s["energy_residual"] / s["energy_scale"],
                  "updates": float(s["steps"]) * nq + float(s["substep_point_updates"]),
                  "substeps_max": int(s["substeps_max"]), "steps": int(s["steps"])}
    print("| graded bar | stress | duration | rebound | energy | residual | steps | point "
          "updates |\n|---|---|---|---|---|---|---|---|")
    for tag, r in m.items():
        print(f"| subcycle {tag} | {r['stress']:+.4f} | {r['duration']:+.4f} | "
              f"{r['rebound']:+.4f} | {r['energy']:+.4f} | {r['residual']:+.2e} | "
              f"{r['steps']} | {r['updates']:.3e} |")
    for tag, r in m.items():
        for key, tol in (("stress", 0.05), ("duration", 0.03), ("rebound", 0.04),
                         ("energy", 0.04)):
            check(f"graded bar, subcycle {tag}: {key} error {r[key]:+.4f} within {tol}",
                  abs(r[key]) <= tol, r[key])
    a, b = m["off"], m["on"]
    for key, tol in (("stress", 0.005), ("rebound", 0.005), ("energy", 0.005),
                     ("duration", 0.01)):
        check(f"graded bar: {key} with and without subcycling agree within {tol} "
              f"({b[key] - a[key]:+.5f})", abs(b[key] - a[key]) <= tol, (a[key], b[key]))
    check(f"graded bar: energy residual with subcycling {b['residual']:+.2e}, plain "
          f"{a['residual']:+.2e}: within 1e-4 of each other",
          abs(b["residual"] - a["residual"]) <= 1e-4, (a["residual"], b["residual"]))
    check(f"graded bar: subcycled, at most {b['substeps_max']} sub-steps in a step (>= 4)",
          b["substeps_max"] >= 4, b["substeps_max"])
    ratio = b["updates"] / a["updates"]
    check(f"graded bar: point updates {ratio:.3f} of the plain run's (<= 0.4)", ratio <= 0.4,
          ratio)


def taylor_case(work, deck_path, label, t_end, max_updates):
    text = open(deck_path).read()
    text = re.sub(r"t_end\s*=\s*[0-9.eE+-]+", f"t_end = {t_end:.1e}", text)
    text = re.sub(r"snapshot_times\s*=\s*[^\n]*", f"snapshot_times = 0.0, {t_end:.1e}", text)
    text = re.sub(r"det_fields\s*=\s*\.true\.", "det_fields = .false.", text)
    m = {}
    for sub in (".false.", ".true."):
        tag = "on" if sub == ".true." else "off"
        t2 = re.sub(r"file\s*=\s*'[^']*\.h5'", f"file = '{label}_{tag}.h5'", text)
        t2 = t2.replace("&solver", f"&solver\n  subcycle = {sub}", 1)
        deck = os.path.join(work, f"{label}_{tag}.nml")
        with open(deck, "w") as fh:
            fh.write(t2)
        rc, log = run(deck, work)
        check(f"{label} to {t_end * 1e6:.0f} us, subcycle {tag}: exits 0", rc == 0, log)
        if rc:
            return
        with MfcdFile(os.path.join(work, f"{label}_{tag}.h5")) as f:
            s = f.summary
            b = f.summary_bodies()["bar"]
            g = f.h5["bodies/bar"]
            # (its elements: triangles in the plane, tetrahedra in 3D)
            nq = (g["tetrahedra"] if "tetrahedra" in g else g["triangles"]).shape[0]
        m[tag] = {"length": b["length"], "foot_radius": b["foot_radius"], "width": b["width"],
                  "residual": s["energy_residual"] / s["energy_scale"],
                  "updates": float(s["steps"]) * nq + float(s["substep_point_updates"]),
                  "steps": int(s["steps"])}
    a, b = m["off"], m["on"]
    print(f"| {label} {t_end * 1e6:.0f} us | length (mm) | foot radius (mm) | width (mm) | residual | steps | "
          "point updates |\n|---|---|---|---|---|---|---|")
    for tag, r in m.items():
        print(f"| subcycle {tag} | {r['length'] * 1e3:.4f} | {r['foot_radius'] * 1e3:.4f} | "
              f"{r['width'] * 1e3:.4f} | {r['residual']:+.2e} | {r['steps']} | "
              f"{r['updates']:.3e} |")
    for key, tol in (("length", 5e-4), ("foot_radius", 0.01), ("width", 0.01)):
        rel = b[key] / a[key] - 1
        check(f"{label}: {key} with subcycling {rel:+.5f} of the plain run's (within {tol})",
              abs(rel) <= tol, (a[key], b[key]))
    check(f"{label}: energy residuals {a['residual']:+.2e} and {b['residual']:+.2e} within 1e-3",
          abs(a["residual"] - b["residual"]) <= 1e-3, (a["residual"], b["residual"]))
    ratio = b["updates"] / a["updates"]
    check(f"{label}: point updates {ratio:.3f} of the plain run's (<= {max_updates})",
          ratio <= max_updates, ratio)


def main():
    work = tempfile.mkdtemp(prefix="mfcd_subcycle_")
    bar_case(work)
    taylor_case(work, TAYLOR, "taylor", 12.0e-6, 0.75)
    if TAYLOR_3D:
        taylor_case(work, TAYLOR_3D, "taylor_3d", 24.0e-6, 0.6)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if results and all(results) else 1)


if __name__ == "__main__":
    main()
