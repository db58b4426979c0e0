#!/usr/bin/env python3
"""Run time against error for the Taylor bar, RKPM and FEM (issue 9, item 3).

    .venv/bin/python bench/convergence.py [--threads 2] [--m 2,3,4,6] [--fem-m 2,3,4,6]
    .venv/bin/python bench/convergence.py --plot bench/results/convergence_<date>.json

The paper's Taylor bar (input/taylor_bar_rkpm.nml, input/taylor_bar_fem_cfl.nml: steel at
200 m/s on a rigid target, 24 us) at m particles (nodes) per mm: the bar 5 x 60 mm with
(5m + 1) x (60m + 1) nodes, the rigid target's lattice refined with it (25m + 1 across,
round(5m/3) + 1 through its height, as the decks' 3, 6 and 12 per mm). Every run takes the
adaptive step (cfl 0.5 of the estimated critical step, dt unset), so the step shrinks with
the spacing as it must for a convergence study. Measured per run: wall time of the whole
run, steps, and four results: the final length L and foot radius R_f (/summary), the
largest contact radius R_c over the run and the plastic work W_p at the end (/history).

For each method and result, a Richardson extrapolation from the three finest runs:
f(h) = f0 + C h^p with p from (f1 - f2)/(f2 - f3) = (h1^p - h2^p)/(h2^p - h3^p) (bisection;
the ratios of h need not be equal), then the error of every run against f0 and the order
between neighbours. Where the three finest are not monotone there is no asymptotic range:
the script says so and measures against the finest run instead. Writes Markdown and JSON
to bench/results/ and the figure doc/figures/convergence_time_vs_error.png (wall time
against relative error, log axes, one panel per result, RKPM and FEM).
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

from bench_record import ROOT, load_row, record_head, write_results
from mfcd_h5 import MfcdFile

MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
DECKS = {"RKPM": "taylor_bar_rkpm.nml", "FEM": "taylor_bar_fem_cfl.nml"}
RESULTS = [("L", "length (mm)"), ("Rf", "foot radius (mm)"), ("Rc", "contact radius (mm)"),
           ("Wp", "plastic work (J)")]


def deck_text(method, m, out):
    text = open(os.path.join(ROOT, "input", DECKS[method])).read()
    text = re.sub(r"file\s*=\s*'[^']*\.h5'", "file = '%s'" % out, text)
    text = re.sub(r"det_fields\s*=\s*\.true\.", "det_fields = .false.", text)
    text = re.sub(r"\n\s*dt\s*=[^\n]*", "\n", text)              # the adaptive step
    text = re.sub(r"\n\s*snapshot_times\s*=[^\n]*", "\n  snapshot_times = 0.0, 24.0e-6",
                  text)
    head, sep, rest = text.partition("name = 'bar'")
    rest = re.sub(r"\bn\s*=\s*\d+\s*,\s*\d+", "n = %d, %d" % (5 * m + 1, 60 * m + 1), rest,
                  count=1)
    head2, sep2, rest2 = rest.partition("name = 'target'")
    rest2 = re.sub(r"\bn\s*=\s*\d+\s*,\s*\d+",
                   "n = %d, %d" % (25 * m + 1, round(5 * m / 3) + 1), rest2, count=1)
    return head + sep + head2 + sep2 + rest2


def run(method, m, threads, tmp):
    out = os.path.join(tmp, "%s_%d.h5" % (method, m))
    deck = os.path.join(tmp, "%s_%d.nml" % (method, m))
    open(deck, "w").write(deck_text(method, m, out))
    t0 = time.time()
    p = subprocess.run([MFCD, deck], capture_output=True, text=True, cwd=tmp,
                       env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    wall = time.time() - t0
    res = {"method": method, "m": m, "h_mm": 1.0 / m, "wall": wall, "rc": p.returncode}
    if p.returncode != 0:
        res["error"] = (p.stdout + p.stderr)[-600:]
        return res
    with MfcdFile(out) as f:
        bar = f.summary_bodies()["bar"]
        hist = f.history()
    res.update(L=1e3 * bar["length"], Rf=1e3 * bar["foot_radius"],
               maxeps=float(bar["max_epsbar"]),
               Rc=1e3 * float(np.max(hist["contact_radius"])),
               Wp=float(hist["w_plastic"][-1]), steps=int(hist["step"][-1])
               if "step" in hist else None)
    return res


def richardson(h, f):
    """f0, p from the three finest (h descending order given); None if not monotone."""
    (h1, f1), (h2, f2), (h3, f3) = list(zip(h, f))[-3:]
    d12, d23 = f1 - f2, f2 - f3
    if d23 == 0.0 or d12 / d23 <= 0.0:
        return None
    ratio = d12 / d23

    def g(p):
        return (h1 ** p - h2 ** p) / (h2 ** p - h3 ** p) - ratio
    lo, hi = 0.05, 8.0
    if g(lo) * g(hi) > 0.0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if g(lo) * g(mid) <= 0.0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    c = d23 / (h2 ** p - h3 ** p)
    return f3 - c * h3 ** p, p


def analyse(runs):
    lines = []
    fig = {}
    for method in ("RKPM", "FEM"):
        rs = sorted([r for r in runs if r["method"] == method and r["rc"] == 0],
                    key=lambda r: -r["h_mm"])
        bad = [r for r in runs if r["method"] == method and r["rc"] != 0]
        if not rs:
            continue
        lines += ["", "### %s" % method, "",
                  "| per mm | h (mm) | steps | wall (s) | L (mm) | R_f (mm) | R_c (mm) | "
                  "W_p (J) | max epsbar |", "|---|---|---|---|---|---|---|---|---|"]
        for r in rs:
            lines.append("| %d | %.4f | %s | %.1f | %.4f | %.4f | %.4f | %.2f | %.2f |" % (
                r["m"], r["h_mm"], r["steps"], r["wall"], r["L"], r["Rf"], r["Rc"], r["Wp"],
                r["maxeps"]))
        for r in bad:
            lines.append("| %d | %.4f | failed (exit %d): %s |||||||" % (
                r["m"], r["h_mm"], r["rc"], r["error"].strip().splitlines()[-1][:120]))
        lines += ["", "| result | extrapolated f0 | order p (3 finest) | relative error of "
                  "each run (coarse to fine) | observed order between neighbours |",
                  "|---|---|---|---|---|"]
        h = [r["h_mm"] for r in rs]
        for key, label in RESULTS:
            f = [r[key] for r in rs]
            rx = richardson(h, f) if len(rs) >= 3 else None
            if rx is None:
                f0, p, how = f[-1], None, "not monotone: against the finest run"
            else:
                f0, p = rx
                how = "%.2f" % p
            err = [abs(x - f0) / abs(f0) for x in f]
            orders = []
            for k in range(len(f) - 1):
                if err[k] > 0 and err[k + 1] > 0:
                    orders.append("%.2f" % (math.log(err[k] / err[k + 1]) /
                                            math.log(h[k] / h[k + 1])))
                else:
                    orders.append("-")
            lines.append("| %s | %.5g | %s | %s | %s |" % (
                label, f0, how, ", ".join("%.2e" % e for e in err), ", ".join(orders)))
            fig.setdefault(key, {})[method] = {"wall": [r["wall"] for r in rs], "err": err,
                                               "m": [r["m"] for r in rs],
                                               "extrapolated": rx is not None}
    return lines, fig


def plot(fig, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sys.path.insert(0, os.path.join(ROOT, "post"))
    from mfcd_style import figure_style
    plt.rcParams.update(figure_style(savefig_dpi=130))
    axes = plt.subplots(1, len(RESULTS), figsize=(4.0 * len(RESULTS), 3.6))[1]
    for ax, (key, label) in zip(axes, RESULTS):
        for method, mk in (("RKPM", "o-"), ("FEM", "s--")):
            d = fig.get(key, {}).get(method)
            if not d:
                continue
            pts = [(w, e, m) for w, e, m in zip(d["wall"], d["err"], d["m"]) if e > 0]
            if not pts:
                continue
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], mk,
                      label=method + ("" if d["extrapolated"] else " (vs finest)"))
            for w, e, m in pts:
                ax.annotate("%d/mm" % m, (w, e), fontsize=7, xytext=(3, 3),
                            textcoords="offset points")
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("relative error")
        ax.set_title(label)
        ax.legend(fontsize=8)
    plt.tight_layout()
    plt.savefig(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--m", default="2,3,4,6")
    ap.add_argument("--fem-m", default="2,3,4,6")
    ap.add_argument("--plot", help="redraw from a JSON file of an earlier run")
    a = ap.parse_args()
    figpath = os.path.join(ROOT, "doc", "figures", "convergence_time_vs_error.png")
    if a.plot:
        data = json.load(open(a.plot))
        lines, fig = analyse(data["runs"])
        print("\n".join(data["head"] + lines))
        plot(fig, figpath)
        return
    head = record_head("# Taylor bar convergence (bench/convergence.py)",
                       ".venv/bin/python bench/convergence.py --threads %d --m %s --fem-m %s"
                       % (a.threads, a.m, a.fem_m))
    print("\n".join(head), flush=True)
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for method, ms in (("RKPM", a.m), ("FEM", a.fem_m)):
            for m in [int(x) for x in ms.split(",") if x]:
                r = run(method, m, a.threads, tmp)
                runs.append(r)
                print("%s m=%d: exit %d, %.1f s%s" % (method, m, r["rc"], r["wall"],
                      "" if r["rc"] == 0 else ": " + r["error"][-200:]), file=sys.stderr,
                      flush=True)
    head.append(load_row("after"))
    lines, fig = analyse(runs)
    print("\n".join(lines))
    md = write_results("convergence", head + lines)
    js = write_results("convergence", [json.dumps({"head": head, "runs": runs}, indent=1)],
                       ".json")
    plot(fig, figpath)
    print("written: %s, %s and %s" % (os.path.relpath(md, ROOT), os.path.relpath(js, ROOT),
                                       os.path.relpath(figpath, ROOT)), file=sys.stderr)


if __name__ == "__main__":
    main()
