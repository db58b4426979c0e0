#!/usr/bin/env python3
"""Benchmark sweeps (not tests): run time against error, and stress tests that push
a numerical parameter until the method fails, recording where and how.

  accuracy   the elastic bar on a rigid wall (input/bar_impact_elastic*.nml) at four spacings,
             2, 1, 0.5, 0.25 mm: errors of contact stress, duration, rebound and energy against
             the closed forms, with wall time and particle-steps/s; draws run time against
             error into doc/figures/sweep_time_vs_error.png.
  cfl        the elastic wave deck at a fixed dt of 0.5 ... 2 times the estimated critical
             step: where the run stops, and how (exit code, the guard's message).
  eps        the coarse Taylor bar at eps_cr = 1e-12 ... 1e-3: detections, contacts and the
             penetration left (a threshold above the buffer-zone values misses contacts).
  speed      the coarse Taylor bar at 100 ... 500 m/s: does it finish, energy residual,
             penetration, largest plastic strain.
  support    the elastic wave at support_factor 1.2 ... 3.0: deck errors below Theorem 3.1's
             limit, then accuracy of the plateau stress.

Usage: .venv/bin/python bench/sweeps.py [accuracy cfl eps speed support] (default: all)
Writes bench/results/sweeps_<date>.md (git-ignored); doc/benchmarks.md quotes it.
"""
import datetime
import os
import re
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
WORK = tempfile.mkdtemp(prefix="mfcd_sweep_")
OUT = []


def emit(line=""):
    print(line)
    OUT.append(line)


def run(text, name, threads=1):
    path = os.path.join(WORK, name + ".nml")
    text = re.sub(r"file = '[^']*\.h5'", f"file = 'out/{name}.h5'", text)
    open(path, "w").write(text)
    t0 = time.time()
    p = subprocess.run([MFCD, path], cwd=WORK, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS=str(threads)), timeout=3600)
    wall = time.time() - t0
    h5 = os.path.join(WORK, "out", name + ".h5")
    f = h5py.File(h5, "r") if os.path.exists(h5) else None
    return p, wall, f


def deck(name):
    return open(os.path.join(ROOT, "input", name)).read()


def accuracy():
    emit("## Run time against error: elastic bar on a rigid wall")
    emit("")
    E, RHO, V, L, W = 211e9, 7800.0, 1.0, 0.06, 0.006
    c0 = np.sqrt(E / RHO)
    base = deck("bar_impact_elastic.nml")
    rows = []
    for dx, nbar, nwall in ((2e-3, (4, 31), (7, 3)), (1e-3, (7, 61), (13, 4)),
                            (5e-4, (13, 121), (25, 7)), (2.5e-4, (25, 241), (49, 13))):
        text = base.replace("n = 13, 121", f"n = {nbar[0]}, {nbar[1]}")
        text = text.replace("n = 25, 7", f"n = {nwall[0]}, {nwall[1]}")
        p, wall, f = run(text, f"impact_{dx * 1e3:g}mm")
        if p.returncode:
            emit(f"dx = {dx * 1e3:g} mm failed: {p.stderr.strip()[-200:]}")
            continue
        h = f["history"]
        t, n, fc = h["time"][:], h["n_contact"][:], h["f_contact"][:]
        on = np.nonzero(n > 0)[0]
        t0, t1 = t[on[0]], t[on[-1]]
        tsep = t[min(on[-1] + 1, len(t) - 1)]
        mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
        es = abs(fc[mid].mean() / W / (RHO * c0 * V) - 1)
        ed = abs((tsep - t0) / (2 * L / c0) - 1)
        ee = abs(h["ke"][-1] / h["ke"][0] - 1)
        pss = f["summary"].attrs["particle_steps_per_second"][0]
        rows.append((dx, wall, pss, es, ed, ee))
    emit("| dx (mm) | wall (s, 1 thread) | particle-steps/s | stress error | duration error | energy error |")
    emit("|---|---|---|---|---|---|")
    for dx, wall, pss, es, ed, ee in rows:
        emit(f"| {dx * 1e3:g} | {wall:.2f} | {pss:.3g} | {es:.2e} | {ed:.2e} | {ee:.2e} |")
    emit("")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4.2), constrained_layout=True)
        r = np.array([row[1:] for row in rows])
        for k, lab in ((2, "contact stress"), (3, "contact duration"), (4, "energy returned")):
            ax.loglog(r[:, 0], r[:, k], "o-", label=lab)
        for (dx, wall, *_r) in rows:
            ax.annotate(f"{dx * 1e3:g} mm", (wall, _r[3]), fontsize=8, xytext=(3, 3),
                        textcoords="offset points")
        ax.set_xlabel("wall time, 1 thread [s]")
        ax.set_ylabel("relative error against the closed form")
        ax.set_title("Elastic bar on a rigid wall: run time against error")
        ax.grid(alpha=0.3, which="both")
        ax.legend()
        os.makedirs(os.path.join(ROOT, "doc", "figures"), exist_ok=True)
        fig.savefig(os.path.join(ROOT, "doc", "figures", "sweep_time_vs_error.png"), dpi=110)
        emit("Figure: doc/figures/sweep_time_vs_error.png")
        emit("")
    except ImportError:
        pass


def outcome(p, f):
    if p.returncode == 0:
        return "completed"
    msg = (p.stderr.strip().splitlines() or [""])[-1]
    msg = msg.replace("mfcd: error: ", "")
    return f"exit {p.returncode}: {msg[:150]}"


def cfl():
    emit("## Stress test: time step (elastic wave, fixed dt as a multiple of the estimated critical step)")
    emit("")
    emit("| dt / dt_crit | outcome | energy residual / scale |")
    emit("|---|---|---|")
    base = deck("elastic_wave.nml")
    p, _, _ = run(base, "cfl_probe")
    dtc = float(re.search(r"critical step 2/omega_max = +([0-9.E+-]+)", p.stdout).group(1))
    for k in (0.5, 0.9, 1.0, 1.05, 1.1, 1.2, 1.5, 2.0):
        p, wall, f = run(base.replace("cfl = 0.5", f"dt = {k * dtc:.6e}"), f"cfl_{k}")
        res = ""
        if f is not None and "summary" in f:
            s = f["summary"].attrs
            res = f"{s['energy_residual'][0] / s['energy_scale'][0]:.2e}"
        emit(f"| {k} | {outcome(p, f)} | {res} |")
    emit(f"(dt_crit = 2/omega_max = {dtc:.4e} s from the power iteration)")
    emit("")


def taylor_sweep(kind):
    base = deck("taylor_bar_rkpm_coarse.nml").replace("snapshot_times = 0.0, 12.0e-6, 16.0e-6, 20.0e-6, 24.0e-6",
                                                      "snapshot_times = 24.0e-6")
    if kind == "eps":
        emit("## Stress test: detection threshold (coarse Taylor bar, 24 us)")
        emit("")
        emit("| eps_cr | outcome | det(M) evaluations | detections | contact forces | penetration left (m) | shortening (mm) |")
        emit("|---|---|---|---|---|---|---|")
        values = (1e-12, 1e-9, 5e-10, 1e-7, 1e-6, 1e-5, 1e-4)
    else:
        emit("## Stress test: impact speed (coarse Taylor bar, 24 us)")
        emit("")
        emit("| v (m/s) | outcome | energy residual / scale | penetration left (m) | max epsbar | shortening (mm) |")
        emit("|---|---|---|---|---|---|")
        values = (100, 200, 300, 400, 500)
    for v in values:
        if kind == "eps":
            text = base.replace("eps_cr = 5.0e-10", f"eps_cr = {v:g}")
        else:
            text = base.replace("velocity = 0.0, -200.0", f"velocity = 0.0, -{v:.1f}")
        p, wall, f = run(text, f"{kind}_{v:g}")
        if f is None or "summary" not in f:
            emit(f"| {v:g} | {outcome(p, f)} | | | | | |")
            continue
        s = f["summary"].attrs
        ext = s["bar_length_width_footradius_maxepsbar"]
        if kind == "eps":
            c = s["contact1_counts_screened_evaluated_detected_contacts"]
            emit(f"| {v:g} | {outcome(p, f)} | {c[1]:.3g} | {c[2]:.3g} | {c[3]:.3g} | "
                 f"{s['max_remaining_penetration'][0]:.2e} | {(0.06 - ext[0]) * 1e3:.2f} |")
        else:
            emit(f"| {v:g} | {outcome(p, f)} | {s['energy_residual'][0] / s['energy_scale'][0]:.2e} | "
                 f"{s['max_remaining_penetration'][0]:.2e} | {ext[3]:.2f} | {(0.06 - ext[0]) * 1e3:.2f} |")
    emit("")


def support():
    emit("## Stress test: support size (elastic wave, bilinear basis)")
    emit("")
    emit("| support_factor | outcome | plateau stress error |")
    emit("|---|---|---|")
    base = deck("elastic_wave.nml")
    c0 = np.sqrt(211e9 / 7800)
    for sf in (0.9, 1.0, 1.2, 1.5, 2.0, 2.5, 3.0):
        p, wall, f = run(base.replace("support_factor = 2.0, 2.0", f"support_factor = {sf}, {sf}"),
                         f"support_{sf}")
        err = ""
        if p.returncode == 0 and f is not None:
            g = f["snapshots/0003/bar"]
            x, sig = g["x"][:], g["stress"][:]
            mid = np.abs(x[:, 1] - 0.0025) < 1e-4
            t = f["snapshots/0003"].attrs["time"][0]
            behind = mid & (x[:, 0] > 0.002) & (x[:, 0] < 0.6 * c0 * t)
            err = f"{abs(sig[behind, 0].mean() / (-7800 * c0 * 10) - 1):.2e}"
        emit(f"| {sf} | {outcome(p, f)} | {err} |")
    emit("")


def main():
    parts = sys.argv[1:] or ["accuracy", "cfl", "eps", "speed", "support"]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    emit(f"# mfcd sweeps {datetime.datetime.now().isoformat(timespec='seconds')}, commit {commit}, "
         f"{os.cpu_count()} cores")
    emit("")
    for part in parts:
        {"accuracy": accuracy, "cfl": cfl, "eps": lambda: taylor_sweep("eps"),
         "speed": lambda: taylor_sweep("speed"), "support": support}[part]()
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    out = os.path.join(ROOT, "bench", "results",
                       f"sweeps_{datetime.datetime.now():%Y-%m-%d_%H%M%S}.md")
    open(out, "w").write("\n".join(OUT) + "\n")
    print("wrote", out)


if __name__ == "__main__":
    main()
