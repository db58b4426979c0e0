#!/usr/bin/env python3
"""Self-contact (the paper's Sections 1 and 7): decks where a body folds onto itself, with
and without the self-contact pair, and bodies bent hard without folding.

The interpenetration is measured independently of anything mfcd computes for contact:
post/self_overlap.py counts the winding number of the deformed boundary loops on a raster
(1/20 of the spacing) and reports the depth of the doubly covered material. Each case:

- with self-contact (master = slave): the run completes, self-contact forces were applied,
  the overlap depth stays below TOL_DEPTH x the body's support radius at every snapshot,
  and the energy balance closes to ENERGY_TOL of its scale;
- without it (the _free control): the same run passes through itself, deeper than
  2 x TOL_DEPTH x the support at the last snapshot (so the measure can see what the
  self-contact run is checked for), and its energy balance closes too;
- a bar bent hard without folding (RKPM and CST4 elements alike; plastic strain above
  0.3, the free end swept by more than 30 mm): its self-contact pair flags no particle
  and applies no force: neighbours in the reference configuration never trigger it.

Tolerances. TOL_DEPTH = 0.25: contact stops the surface nodes on the other face, but the
straight segments between nodes can still cross where two faces' nodes do not match (at
corners), and at the tight ends of a fold the faces are reference neighbours, excluded
by design; measured 0.05 support (C-shape, corner of the tips), 0 (torus), 0.16 (ring,
fold ends; tools/self_contact.sh); the controls reach 0.64 (torus) to 3 (C-shape)
supports. ENERGY_TOL = 1e-3: measured 2.2e-4 (C-shape) and 7.5e-5 (torus) with
self-contact, below 4e-5 without; the run's own guard stops at 5e-2.

Usage: check_self_contact.py /path/to/mfcd DECK_WITH DECK_FREE [DECK_WITH DECK_FREE ...]
       [--bent DECK ...]
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "post"))
from mfcd_h5 import MfcdFile  # noqa: E402
from self_overlap import body_overlap  # noqa: E402

TOL_DEPTH = 0.25     # overlap depth allowed with self-contact, in supports (docstring)
ENERGY_TOL = 1.0e-3  # |energy residual| / energy scale (docstring)
STEP_FRACTION = 0.05  # raster step of the overlap measure, fraction of the spacing
# (3D: 1/4 of the spacing, a raster 125 times coarser in points; an overlap thinner than
# 0.25 spacing = 0.125 support reads as zero, half of TOL_DEPTH)
STEP_FRACTION_3D = 0.25
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "self_contact." + name
          + ("" if cond else ": " + str(detail)[-1500:]), flush=True)


def run(mfcd, tmp, src):
    name = os.path.splitext(os.path.basename(src))[0]
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = 'out/%s.h5'" % name, open(src).read())
    deck = os.path.join(tmp, name + ".nml")
    open(deck, "w").write(text)
    p = subprocess.run([mfcd, deck], cwd=tmp, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    check(name + " completes", p.returncode == 0, p.stdout[-800:] + p.stderr[-800:])
    return name, os.path.join(tmp, "out", name + ".h5")


def self_pair(f):
    """(k, [screened, evaluated, detected, contacts]) of the run's self-contact pair
    (/summary/contacts/contact<k> with self = 1), (None, None) without one."""
    k = f.self_contact_pair()
    if k is None:
        return None, None
    c = f.summary_contacts()[k]
    return k, np.array([c[n] for n in ("screened", "evaluated", "detected", "contacts")])


def self_body(f):
    """The body whose snapshots carry det_self (the self-contact body)."""
    snap = f.snapshot(f.snapshot_labels()[0])
    names = [name for name, b in snap.bodies.items() if b.det_self is not None]
    assert len(names) == 1, "expected one self-contact body, got %s" % names
    return names[0]


def energy_ok(name, summary):
    res = float(summary["energy_residual"])
    scale = float(summary["energy_scale"])
    check(name + ": energy balance closes (|residual|/scale %.2e < %g)"
          % (abs(res) / scale, ENERGY_TOL), abs(res) <= ENERGY_TOL * scale)


def depths(path, name=None, last_only=False):
    """Overlap depth at every snapshot (m) (last_only: at the last) of the body name
    (default: the self-contact body), its support radius (m), its name, the run's summary
    and its self-contact pair (self_pair). 2D: the boundary loops; 3D: the closed facet
    surface (post/self_overlap.py)."""
    with MfcdFile(path) as f:
        name = name or self_body(f)
        b = f.body(name)
        rho = float(np.max(b.support))
        frac = STEP_FRACTION_3D if b.ndim == 3 else STEP_FRACTION
        step = frac * float(np.min(np.atleast_1d(b.attrs["spacing"])[:2]))
        out = []
        labels = [lab for lab in f.snapshot_labels() if lab != "failure"]
        for lab in labels[-1:] if last_only else labels:
            _, d, _ = body_overlap(b, f.snapshot(lab).bodies[name].x, step)
            out.append(d)
        return np.array(out), rho, name, f.summary, self_pair(f)


def folding_case(mfcd, tmp, with_deck, free_deck):
    name, path = run(mfcd, tmp, with_deck)
    name_free, path_free = run(mfcd, tmp, free_deck)
    if not (os.path.exists(path) and os.path.exists(path_free)):
        return
    d, rho, body, summary, (k, counts) = depths(path)
    check(name + ": has a self-contact pair", k is not None)
    if k is not None:
        check(name + ": self-contact forces applied (%d)" % counts[3], counts[3] > 0)
    check(name + ": overlap depth at every snapshot <= %.2f support (largest %.3f mm = "
          "%.3f support)" % (TOL_DEPTH, 1e3 * d.max(), d.max() / rho),
          d.max() <= TOL_DEPTH * rho, d)
    energy_ok(name, summary)
    d_free, rho_free, _, summary_free, (k_free, _) = depths(path_free, body, last_only=True)
    check(name_free + ": no self-contact pair", k_free is None)
    check(name_free + ": passes through itself (overlap depth %.3f mm = %.2f support > %.2f)"
          % (1e3 * d_free[-1], d_free[-1] / rho_free, 2 * TOL_DEPTH),
          d_free[-1] > 2 * TOL_DEPTH * rho_free, d_free)
    energy_ok(name_free, summary_free)


def bent_case(mfcd, tmp, deck):
    name, path = run(mfcd, tmp, deck)
    if not os.path.exists(path):
        return
    with MfcdFile(path) as f:
        summary = f.summary
        k, counts = self_pair(f)
        body = self_body(f)
        last = f.snapshot(f.snapshot_labels()[-1]).bodies[body]
        sweep = float(np.max(np.abs(last.u[:, 1])))
        epsmax = float(np.max(last.epsbar))
    check(name + ": has a self-contact pair", k is not None)
    check(name + ": bent hard (max epsbar %.2f > 0.3, end swept %.1f mm > 30)"
          % (epsmax, 1e3 * sweep), epsmax > 0.3 and sweep > 0.030)
    if k is not None:
        check(name + ": no particle flagged, no force (detected %d, contacts %d; %d "
              "det(M) evaluations)" % (counts[2], counts[3], counts[1]),
              counts[2] == 0 and counts[3] == 0 and counts[1] > 0)
    energy_ok(name, summary)


def main():
    args = sys.argv[1:]
    mfcd = os.path.abspath(args.pop(0))
    bent = []
    if "--bent" in args:
        i = args.index("--bent")
        bent = args[i + 1:]
        args = args[:i]
    with tempfile.TemporaryDirectory() as tmp:
        for with_deck, free_deck in zip(args[0::2], args[1::2]):
            folding_case(mfcd, tmp, os.path.abspath(with_deck), os.path.abspath(free_deck))
        for deck in bent:
            bent_case(mfcd, tmp, os.path.abspath(deck))
    print("%d passed, %d failed" % (results.count(True), results.count(False)))
    sys.exit(0 if results and all(results) else 1)


if __name__ == "__main__":
    main()
