#!/usr/bin/env python3
"""Benchmark sweeps (not tests): run time against error, and stress tests that push
a numerical parameter until the method fails, recording where and how.

  accuracy   the elastic bar on a rigid wall (input/bar_impact_elastic*.nml) at four spacings,
             2, 1, 0.5, 0.25 mm: errors of contact stress, duration, rebound and energy against
             the closed forms, with wall time and particle-steps/s; draws run time against
             error into doc/figures/sweep_time_vs_error.png.

Stability stress tests (issue 9, item 7; doc/stability.md). Each point is one run of mfcd,
one thread, recording its outcome: completed, exit 1 (a run-health guard stopped it, its
message), exit 2 (the deck was refused, its message), or a FINDING (anything else: a signal,
another exit code, a run past the time limit, non-finite numbers in a completed run's
output); with wall time, steps, the smallest dt, the energy residual over its scale, the
largest remaining penetration and, for the bars, shortening, foot radius and largest plastic
strain. Taylor bars run to 24 us, on the adaptive step (dt = 0, cfl 0.5) unless said.

  cfl        the elastic wave deck at a fixed dt of 0.5 ... 2 times the estimated critical
             step (where the run stops, and how), then the adaptive step at cfl = 0.1 ... 1.2
             on the coarse RKPM Taylor bar, the coarse bilinear-J2 bar (bar_impact_j2_coarse)
             and the coarse FEM Taylor bar.
  eps        the coarse RKPM Taylor bar at eps_cr = 1e-14 ... 1e-4 (decades, and the deck's
             5e-10): detections, contacts, the penetration left; at and above the target's
             det(M) plateau the deck is refused (exit 2) on purpose.
  support    support_factor 1.0 ... 3.5 (steps of 0.25) of the coarse Taylor bar's particles
             (the target keeps the deck's) and of the elastic wave's (plateau stress error).
  perturb    the interior particles of the coarse Taylor bar and of the coarse J2 bar moved
             at random by up to 0 ... 45% of the spacing (&body perturbation), three seeds at
             30%.
  speed      impact speed 50 ... 600 m/s, coarse Taylor bar by RKPM and by FEM.
  stability  all five stress tests above (figures doc/figures/stability_*.png).

Usage: .venv/bin/python bench/sweeps.py [accuracy cfl eps support perturb speed stability]
       (default: accuracy and the five stress tests)
       .venv/bin/python bench/sweeps.py --plot bench/results/stability_<date>.json
       (redraw the stability figures from a saved run)
Writes bench/results/sweeps_<date>.md and, for the stress tests, stability_<date>.json
(git-ignored); doc/benchmarks.md and doc/stability.md quote them.
"""
import datetime
import json
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


def run(text, name, threads=1, limit=3600):
    path = os.path.join(WORK, name + ".nml")
    text = re.sub(r"file = '[^']*\.h5'", f"file = 'out/{name}.h5'", text)
    open(path, "w").write(text)
    t0 = time.time()
    try:
        p = subprocess.run([MFCD, path], cwd=WORK, capture_output=True, text=True,
                           env=dict(os.environ, OMP_NUM_THREADS=str(threads)), timeout=limit)
    except subprocess.TimeoutExpired as e:
        p = subprocess.CompletedProcess(e.cmd, None, e.stdout or "", e.stderr or "")
    wall = time.time() - t0
    f = None
    for h5 in (os.path.join(WORK, "out", name + ".h5"),
               os.path.join(WORK, "out", name + ".failed.h5")):
        if os.path.exists(h5):
            f = h5py.File(h5, "r")
            break
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


def cfl_fixed():
    emit("## Stress test: time step (elastic wave, fixed dt as a multiple of the estimated critical step)")
    emit("")
    emit("| dt / dt_crit | outcome | energy residual / scale |")
    emit("|---|---|---|")
    base = deck("elastic_wave.nml")
    _, _, f = run(base, "cfl_probe")
    dtc = float(f["summary"].attrs["dt_critical"][0])   # 2/omega_max at t = 0
    for k in (0.5, 0.9, 1.0, 1.05, 1.1, 1.2, 1.5, 2.0):
        p, wall, f = run(base.replace("cfl = 0.5", f"dt = {k * dtc:.6e}"), f"cfl_{k}")
        res = ""
        if f is not None and "summary" in f:
            s = f["summary"].attrs
            res = f"{s['energy_residual'][0] / s['energy_scale'][0]:.2e}"
        emit(f"| {k} | {outcome(p, f)} | {res} |")
    emit(f"(dt_crit = 2/omega_max = {dtc:.4e} s from the power iteration)")
    emit("")


# ---------------------------------------------------------------------------------------
# Stability stress tests (issue 9, item 7): every point a run, its outcome classified.

RESULTS = {}        # part -> list of records (dicts), saved as JSON for the figures
RUN_LIMIT = 600     # s: a run still going after this is a hang, reported as a FINDING
L0 = 0.06           # m, length of the Taylor and J2 bars
TAYLOR = "taylor_bar_rkpm_coarse.nml"
TAYLOR_FEM = "taylor_bar_fem_coarse.nml"
J2BAR = "bar_impact_j2_coarse.nml"
WAVE = "elastic_wave.nml"
SPACING = {TAYLOR: 1 / 3 * 1e-3, TAYLOR_FEM: 1 / 3 * 1e-3, J2BAR: 0.5e-3, WAVE: 0.5e-3}
LABEL = {TAYLOR: "Taylor bar, RKPM", TAYLOR_FEM: "Taylor bar, FEM (CST4)",
         J2BAR: "J2 bar at 400 m/s, RKPM", WAVE: "elastic wave, RKPM"}


def setvar(text, group, var, value, name=None):
    """The deck text with `var = value` in the first &group (with name = 'name' when given),
    replacing the variable's line if the group has one."""
    lines = text.splitlines()
    start = None
    for k, line in enumerate(lines):
        st = line.strip()
        if start is None and re.match(rf"&{group}\b", st, re.I):
            start = k
        elif start is not None and st.startswith("/"):
            block = lines[start + 1:k]
            if name is None or any(re.match(rf"\s*name\s*=\s*'{name}'", b) for b in block):
                keep = [b for b in block if not re.match(rf"\s*{var}\s*=", b, re.I)]
                lines[start + 1:k] = keep + [f"  {var} = {value}"]
                return "\n".join(lines) + "\n"
            start = None
    raise ValueError(f"no &{group} {name or ''} in the deck")


def stress_deck(name, cfl=0.5, t_end=None):
    """A deck of input/ for the stress tests: adaptive step at cfl (dt = 0), one snapshot at
    the end (t_end, or the deck's), no det(M) fields."""
    text = deck(name)
    if t_end is None:
        t_end = float(re.search(r"^\s*t_end\s*=\s*([0-9.eE+-]+)", text, re.M).group(1))
    text = setvar(text, "solver", "t_end", f"{t_end:.6e}")
    text = setvar(text, "solver", "snapshot_times", f"{t_end:.6e}")
    text = setvar(text, "solver", "dt", "0.0")
    text = setvar(text, "solver", "cfl", f"{cfl:g}")
    if re.search(r"det_fields", text):
        text = setvar(text, "output", "det_fields", ".false.")
    return text


def finite_output(f):
    """False if a completed run wrote a non-finite number to /history, /summary or its last
    snapshot (a failure the guards let through)."""
    for key in f.get("history", {}):
        if not np.all(np.isfinite(f["history"][key][:])):
            return False
    groups = [f["summary"]]
    f["summary"].visit(lambda k: groups.append(f["summary"][k]))
    for g in groups:
        for v in g.attrs.values():
            if isinstance(v, np.ndarray) and v.dtype.kind == "f" and not np.all(np.isfinite(v)):
                return False
    snaps = sorted(k for k in f.get("snapshots", {}) if k != "failure")
    if snaps:
        for body in f["snapshots"][snaps[-1]].values():
            for ds in body.values():
                if ds.dtype.kind == "f" and not np.all(np.isfinite(ds[:])):
                    return False
    return True


def short_message(err):
    """The guard's or the deck check's message, without the file names at its end."""
    line = next((ln for ln in err.splitlines() if "mfcd: error:" in ln), "")
    line = line.replace("mfcd: error: ", "").strip()
    m = re.search(r"run failed at step \d+.*", line)
    if m:
        line = m.group(0)
    else:
        m = re.search(r"variable .*", line)
        line = m.group(0) if m else line
    line = re.split(r"; diagnostic snapshot|; the files", line)[0]
    return line


def stress_run(part, deckname, text, param, label, **extra):
    """One point: run it, classify the outcome, record the measures."""
    tag = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{part}_{deckname[:-4]}_{label}")
    p, wall, f = run(text, tag, limit=RUN_LIMIT)
    rec = dict(part=part, deck=deckname, param=param, label=label, wall=wall, rc=p.returncode,
               message="", steps=None, time=None, dt_min=None, residual=None, penetration=None,
               length=None, foot=None, epsbar=None, **extra)
    if f is not None and "summary" in f:
        a = f["summary"].attrs
        rec["steps"] = int(a["steps"]) if "steps" in a else None

        def first(key):
            return float(a[key][0]) if key in a else None

        rec["dt_min"] = first("dt_min")
        rec["time"] = first("time")
        if "energy_residual" in a and a["energy_scale"][0] > 0:
            rec["residual"] = float(a["energy_residual"][0] / a["energy_scale"][0])
        rec["penetration"] = first("max_remaining_penetration")
        if "bodies/bar" in f["summary"]:
            b = f["summary/bodies/bar"].attrs
            rec["length"], rec["foot"], rec["epsbar"] = (float(b[k][0]) for k in (
                "length", "foot_radius", "max_epsbar"))
        if "contacts/contact1" in f["summary"]:
            c = f["summary/contacts/contact1"].attrs
            rec["counts"] = [float(c[k][0]) for k in ("screened", "evaluated", "detected",
                                                      "contacts")]
    if p.returncode == 0:
        if f is not None and "summary" in f and finite_output(f):
            rec["outcome"] = "completed"
        else:
            rec["outcome"] = "FINDING"
            rec["message"] = "exit 0 but non-finite numbers (or no summary) in the output"
    elif p.returncode in (1, 2) and p.stderr.count("mfcd: error:") == 1:
        rec["outcome"] = f"exit {p.returncode}"
        rec["message"] = short_message(p.stderr)
    elif p.returncode is None:
        rec["outcome"] = "FINDING"
        rec["message"] = f"no answer in {RUN_LIMIT} s (killed)"
    else:
        rec["outcome"] = "FINDING"
        tail = p.stderr.strip()[-300:].replace("\n", " ")
        rec["message"] = f"exit code {p.returncode}: {tail}"
    if part == "support" and deckname == WAVE and rec["outcome"] == "completed":
        rec["plateau_error"] = wave_plateau_error(f)
    if f is not None:
        f.close()
    RESULTS.setdefault(part, []).append(rec)
    print(f"  {part} {deckname} {label}: {rec['outcome']} {rec['message'][:100]} ({wall:.1f} s)",
          flush=True)
    return rec


def wave_plateau_error(f):
    """Relative error of the stress behind the elastic wave's front against -rho c0 v."""
    c0 = np.sqrt(211e9 / 7800)
    last = sorted(k for k in f["snapshots"] if k != "failure")[-1]
    g = f["snapshots/" + last + "/bar"]
    x, sig = g["x"][:], g["stress"][:]
    mid = np.abs(x[:, 1] - 0.0025) < 1e-4
    t = f["snapshots/" + last].attrs["time"][0]
    behind = mid & (x[:, 0] > 0.002) & (x[:, 0] < 0.6 * c0 * t)
    return float(abs(sig[behind, 0].mean() / (-7800 * c0 * 10) - 1))


def fmt(v, spec):
    return "" if v is None else format(v, spec)


def stress_table(part, deckname, pname, extra_cols=()):
    """Markdown table of one part's points on one deck."""
    recs = [r for r in RESULTS.get(part, []) if r["deck"] == deckname]
    if not recs:
        return
    bar = deckname != WAVE
    cols = [pname, "outcome", "wall (s)", "steps", "dt min (s)", "energy residual / scale"]
    if bar:
        cols += ["penetration left (m)", "shortening (mm)", "foot radius (mm)", "max epsbar"]
    cols += [c[0] for c in extra_cols]
    emit(f"{LABEL[deckname]} (`input/{deckname}`)")
    emit("")
    emit("| " + " | ".join(cols) + " |")
    emit("|" + "---|" * len(cols))
    for r in recs:
        when = ""
        if r["outcome"] == "exit 1" and r.get("time") is not None:
            when = f" (t = {r['time'] * 1e6:.2f} us)"
        out = r["outcome"] + when + (": " + r["message"][:240] if r["message"] else "")
        row = [r["label"], out, fmt(r["wall"], ".1f"), fmt(r["steps"], "d"),
               fmt(r["dt_min"], ".2e"), fmt(r["residual"], ".2e")]
        if bar:
            row += [fmt(r["penetration"], ".2e"),
                    fmt(None if r["length"] is None else (L0 - r["length"]) * 1e3, ".3f"),
                    fmt(None if r["foot"] is None else r["foot"] * 1e3, ".3f"),
                    fmt(r["epsbar"], ".2f")]
        row += [c[1](r) for c in extra_cols]
        emit("| " + " | ".join(row) + " |")
    emit("")


EPS_COUNTS = (
    ("det(M) evaluations", lambda r: fmt(r.get("counts", [None] * 4)[1], ".3g")),
    ("detections", lambda r: fmt(r.get("counts", [None] * 4)[2], ".3g")),
    ("contact forces", lambda r: fmt(r.get("counts", [None] * 4)[3], ".3g")))
WAVE_ERROR = (("plateau stress error", lambda r: fmt(r.get("plateau_error"), ".2e")),)
TABLES = {  # part: (parameter column, {deck: extra columns})
    "cfl": ("cfl", {}),
    "eps": ("eps_cr", {TAYLOR: EPS_COUNTS}),
    "support": ("support_factor", {WAVE: WAVE_ERROR}),
    "perturb": ("perturbation (seed)", {}),
    "speed": ("v (m/s)", {}),
}


def report(part):
    """The tables of one part, deck by deck, and its figure."""
    pname, extra = TABLES[part]
    for name in dict.fromkeys(r["deck"] for r in RESULTS.get(part, [])):
        stress_table(part, name, pname, extra.get(name, ()))
    plot_part(part)


def cfl():
    cfl_fixed()
    emit("## Stress test: adaptive time step (dt = 0, cfl x the critical step re-estimated "
         "every step)")
    emit("")
    values = (0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 1.0, 1.1, 1.2)
    for name, t_end in ((TAYLOR, 24e-6), (J2BAR, None), (TAYLOR_FEM, 24e-6)):
        for c in values:
            text = stress_deck(name, t_end=t_end)
            text = setvar(text, "solver", "cfl", f"{c:g}")
            stress_run("cfl", name, text, c, f"{c:g}")
    report("cfl")


def eps():
    emit("## Stress test: detection threshold eps_cr (coarse Taylor bar, RKPM slave, 24 us, "
         "adaptive step)")
    emit("")
    values = [10.0 ** k for k in range(-14, -3)] + [5e-10]
    for v in sorted(values):
        text = setvar(stress_deck(TAYLOR, t_end=24e-6), "contact", "eps_cr", f"{v:.3e}")
        stress_run("eps", TAYLOR, text, v, f"{v:.0e}")
    report("eps")


def support():
    emit("## Stress test: support size (support_factor of the deformable body)")
    emit("")
    values = [1.0 + 0.25 * k for k in range(11)]
    for sf in values:
        text = setvar(stress_deck(TAYLOR, t_end=24e-6), "body", "support_factor",
                      f"{sf:g}, {sf:g}", name="bar")
        stress_run("support", TAYLOR, text, sf, f"{sf:g}")
    for sf in values:
        text = setvar(deck(WAVE), "body", "support_factor", f"{sf:g}, {sf:g}", name="bar")
        stress_run("support", WAVE, text, sf, f"{sf:g}")
    report("support")


def perturb():
    emit("## Stress test: random particle perturbation (&body perturbation, interior particles "
         "of the bar)")
    emit("")
    points = [(p, 1) for p in (0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.45)] + [(0.3, 2), (0.3, 3)]
    for name, t_end in ((TAYLOR, 24e-6), (J2BAR, None)):
        for frac, seed in points:
            text = stress_deck(name, t_end=t_end)
            text = setvar(text, "body", "perturbation", f"{frac:g}", name="bar")
            text = setvar(text, "body", "perturbation_seed", f"{seed}", name="bar")
            stress_run("perturb", name, text, frac, f"{frac:g} (seed {seed})", seed=seed)
    report("perturb")


def speed():
    emit("## Stress test: impact speed (coarse Taylor bar, 24 us, adaptive step)")
    emit("")
    for name in (TAYLOR, TAYLOR_FEM):
        for v in (50, 100, 200, 300, 400, 500, 600):
            text = setvar(stress_deck(name, t_end=24e-6), "body", "velocity",
                          f"0.0, -{v:.1f}", name="bar")
            stress_run("speed", name, text, v, f"{v}")
    report("speed")


PLOTS = {  # part: x label, log x, third panel (key, label)
    "cfl": ("cfl (adaptive step)", False),
    "eps": ("eps_cr", True),
    "support": ("support_factor of the bar", False),
    "perturb": ("perturbation (fraction of the spacing)", False),
    "speed": ("impact speed (m/s)", False),
}


def plot_part(part):
    """doc/figures/stability_<part>.png: energy residual, penetration and the bar's foot
    radius (and the wave's plateau error) against the parameter; completed points filled,
    exit 1 (guard) as crosses at the values of the failed run, exit 2 (refused) as triangles
    on the lower edge, FINDINGs as red stars."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        sys.path.insert(0, os.path.join(ROOT, "post"))
        from mfcd_style import figure_style
    except ImportError:
        return
    plt.rcParams.update(figure_style(savefig_dpi=110))
    recs = RESULTS.get(part, [])
    if not recs:
        return
    xlabel, logx = PLOTS[part]
    decks = list(dict.fromkeys(r["deck"] for r in recs))
    panels = [("|energy residual| / energy scale",
               lambda r: None if r["residual"] is None else abs(r["residual"])),
              ("largest penetration left / bar spacing\n(below 1e-12 drawn at 1e-12)",
               lambda r: None if r["penetration"] is None or r["deck"] == WAVE
               else max(r["penetration"] / SPACING[r["deck"]], 1e-12)),
              ("foot radius of the bar (mm)",
               lambda r: None if r["foot"] is None or r["deck"] == WAVE else r["foot"] * 1e3)]
    if any(r["deck"] == WAVE for r in recs):
        panels.append(("elastic wave: plateau stress error", lambda r: r.get("plateau_error")))
    logy = (True, True, False, True)
    fig, axes = plt.subplots(1, len(panels), figsize=(4.4 * len(panels), 4.0),
                             constrained_layout=True)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, (ylabel, get), ly in zip(axes, panels, logy):
        for k, name in enumerate(decks):
            c = colours[k % len(colours)]
            rs = sorted((r for r in recs if r["deck"] == name and r.get("seed", 1) == 1),
                        key=lambda r: r["param"])
            ok = [(r["param"], get(r)) for r in rs if r["outcome"] == "completed"
                  and get(r) is not None]
            if ok:
                ax.plot(*zip(*ok), "o-", color=c, label=LABEL[name], ms=5)
            extra = [(r["param"], get(r)) for r in recs if r["deck"] == name
                     and r.get("seed", 1) != 1 and r["outcome"] == "completed"
                     and get(r) is not None]
            if extra:
                ax.plot(*zip(*extra), "o", mfc="none", color=c, ms=7,
                        label=LABEL[name] + ", other seeds")
            bad = [(r["param"], get(r)) for r in rs if r["outcome"] == "exit 1"
                   and get(r) is not None]
            if bad:
                ax.plot(*zip(*bad), "x", color=c, ms=9, mew=2, label=LABEL[name] +
                        ", exit 1 (guard), at failure")
            refused = [r["param"] for r in rs if r["outcome"] == "exit 2"]
            if refused:
                ax.plot(refused, [0.02 + 0.03 * k] * len(refused), "v", color=c, ms=8,
                        transform=ax.get_xaxis_transform(), clip_on=False,
                        label=LABEL[name] + ", exit 2 (refused)")
            found = [r["param"] for r in rs if r["outcome"] == "FINDING"]
            if found:
                ax.plot(found, [0.95] * len(found), "*", color="red", ms=12,
                        transform=ax.get_xaxis_transform(), label="FINDING")
        if logx:
            ax.set_xscale("log")
        if ly:
            ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    fig.suptitle(f"Stability stress test: {xlabel}")
    os.makedirs(os.path.join(ROOT, "doc", "figures"), exist_ok=True)
    out = os.path.join(ROOT, "doc", "figures", f"stability_{part}.png")
    fig.savefig(out)
    plt.close(fig)
    emit(f"Figure: doc/figures/stability_{part}.png")
    emit("")


def machine():
    """CPU model, cores and load average, for the record."""
    model = ""
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = re.search(r"Model name:\s*(.*)", out).group(1).strip()
    except (OSError, AttributeError):
        pass
    return f"{model}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}"


def main():
    if sys.argv[1:2] == ["--plot"]:
        RESULTS.update(json.load(open(sys.argv[2]))["results"])
        for part in RESULTS:
            report(part)
        print("\n".join(OUT))
        return
    parts = sys.argv[1:] or ["accuracy", "stability"]
    if "stability" in parts:
        i = parts.index("stability")
        parts[i:i + 1] = ["cfl", "eps", "support", "perturb", "speed"]
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                            capture_output=True, text=True).stdout.strip()
    started = datetime.datetime.now(datetime.timezone.utc)
    emit(f"# mfcd sweeps {started.isoformat(timespec='seconds')}, commit {commit}, "
         f"{machine()} at the start")
    emit("")
    emit("Command: `" + " ".join(["nice -n 10", ".venv/bin/python", "bench/sweeps.py"] +
                                 sys.argv[1:]) + "`, one thread per run")
    emit("")
    for part in parts:
        t0 = time.time()
        {"accuracy": accuracy, "cfl": cfl, "eps": eps, "speed": speed, "support": support,
         "perturb": perturb}[part]()
        emit(f"({part}: {time.time() - t0:.0f} s wall, load {os.getloadavg()[0]:.2f} at the end)")
        emit("")
    stamp = f"{datetime.datetime.now():%Y-%m-%d_%H%M%S}"
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    out = os.path.join(ROOT, "bench", "results", f"sweeps_{stamp}.md")
    open(out, "w").write("\n".join(OUT) + "\n")
    print("wrote", out)
    if RESULTS:
        js = os.path.join(ROOT, "bench", "results", f"stability_{stamp}.json")
        json.dump({"commit": commit, "started": started.isoformat(timespec="seconds"),
                   "machine": machine(), "results": RESULTS}, open(js, "w"), indent=1)
        print("wrote", js)


if __name__ == "__main__":
    main()
