#!/usr/bin/env python3
"""The Taylor bar by RKPM beside the same bar by FEM (CST4): a markdown table at the snapshot
times and one figure (paper Section 6: Figs. 14 and 15 side by side).

    python post/compare_taylor.py output/taylor_bar_rkpm.h5 output/taylor_bar_fem.h5 \\
        --out doc/figures [--table doc/figures/taylor_comparison.md] [--body bar]
        [--times 12,16,20,24] [--contact-rows 5]

Table (printed, and written to --table when given): one row per time and method with
  length, foot radius    /history 'length', 'foot_radius' interpolated linearly at the time [mm]
  contact radius         the largest /history 'contact_radius' of the --contact-rows history
                         rows nearest the time (the per-step value flickers as single nodes or
                         particles touch and leave) [mm]
  max epsbar             from the snapshot at the time: FEM the largest element value
                         (epsbar_cells), RKPM the largest particle value (epsbar)
  energy residual        /history 'residual' at the time over /summary energy_scale [%]
  penetration left       the largest /history 'penetration' up to the time [um]
  wall time              /summary wall_time of the whole run, on the row of the last time [s]
and, on the FEM rows, the relative differences (FEM - RKPM) / RKPM of length and foot radius.
The times are the deck's snapshot times after t = 0 (12, 16, 20, 24 us in the Taylor decks)
or --times (us). A run that stopped early (/summary status 'failed') or lacks a snapshot gets
'n/a' where it has no value: history values beyond its last row, snapshot values without a
snapshot at that time (within 1%).

Figure <out>/<name>.png (--name, default taylor_rkpm_vs_fem):
  (a) length and foot radius against time, both methods (the snapshot times dotted);
  (b) the deformed outlines of both at each snapshot time overlaid (the bodies' boundary
      polylines /bodies/<body>/loop_idx, 1-based, applied to the snapshot positions x: for
      the FE body they are node numbers), the whole bar and (c) zoomed on the foot.

Exit status: 0 when the table and the figure were written, 1 when a file cannot be read,
2 for bad arguments.
File layout: doc/output.md; reader: post/mfcd_h5.py.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import negative_values, MfcdFile, deck_group  # noqa: E402

PROG = "compare_taylor"
NA = "n/a"
METHOD_STYLE = {"RKPM": dict(color="tab:blue", ls="-"), "FEM": dict(color="tab:red", ls="--")}


def fmt_us(t: float) -> str:
    return f"{t * 1e6:.2f}".rstrip("0").rstrip(".")


class Run:
    """What the comparison needs of one output file, read once."""

    def __init__(self, path: str, method: str, body: str | None):
        self.path, self.method = path, method
        with MfcdFile(path) as f:
            self.title = f.title
            self.stem = os.path.splitext(os.path.basename(path))[0]
            self.h = f.history()
            if not self.h or "time" not in self.h:
                raise ValueError(f"{path}: no /history (not a dynamic run?)")
            self.summary = f.summary
            sol = deck_group(f.deck, "solver") or {}
            st = sol.get("snapshot_times", [])
            self.deck_times = [float(v) for v in (st if isinstance(st, list) else [st])]
            labels = f.snapshot_labels()
            if body is None:
                cand = [n for lab in labels for n in f.snapshot(lab).bodies][:1]
                body = cand[0] if cand else (f.body_names() or [None])[0]
            if body not in f.body_names():
                raise ValueError(f"{path}: no body {body!r} (bodies: "
                                 f"{', '.join(f.body_names())})")
            self.body = body
            self.ref = f.body(body)
            self.fem = self.ref.is_fem
            # snapshots of the body: label -> (time, x (np, 2), max epsbar or None)
            self.snaps = {}
            for lab in labels:
                s = f.snapshot(lab)
                if body not in s.bodies:
                    continue
                b = s.bodies[body]
                vals = b.epsbar_cells if (self.fem and b.epsbar_cells is not None) else b.epsbar
                emax = float(np.nanmax(vals)) if vals is not None and vals.size else None
                self.snaps[lab] = (s.time, b.x, emax)
        self.status = str(self.summary.get("status", "unknown"))
        self.t_end = float(self.h["time"][-1])
        self.scale = float(self.summary.get("energy_scale", 0.0)) or np.nan
        self.wall = float(self.summary.get("wall_time", np.nan))
        self.threads = int(self.summary.get("threads", 0) or 0)

    # history --------------------------------------------------------------------------
    def covers(self, t: float) -> bool:
        return t <= self.t_end * (1 + 1e-9) + 1e-15

    def interp(self, col: str, t: float):
        if col not in self.h or not self.covers(t):
            return None
        return float(np.interp(t, self.h["time"], self.h[col]))

    def contact_radius(self, t: float, rows: int):
        if "contact_radius" not in self.h or not self.covers(t):
            return None
        idx = np.argsort(np.abs(self.h["time"] - t), kind="stable")[:max(rows, 1)]
        return float(self.h["contact_radius"][idx].max())

    def penetration(self, t: float):
        if "penetration" not in self.h or not self.covers(t):
            return None
        tt = self.h["time"]
        upto = tt <= t * (1 + 1e-9)
        return float(self.h["penetration"][upto].max()) if upto.any() else None

    # snapshots ------------------------------------------------------------------------
    def snapshot_at(self, t: float):
        """(label, time, x, max epsbar) of the snapshot within 1% of t (failure excluded)."""
        best = None
        for lab, (ts, x, e) in self.snaps.items():
            if lab == "failure" or abs(ts - t) > 0.01 * max(t, 1e-12):
                continue
            if best is None or abs(ts - t) < abs(best[1] - t):
                best = (lab, ts, x, e)
        return best

    def outline(self, x: np.ndarray):
        return self.ref.polylines(x=x)

    def status_line(self) -> str:
        kind = "FE (CST4) body" if self.fem else "particle body"
        s = (f"{self.method}: `{os.path.basename(self.path)}` ({self.title}; {kind} "
             f"'{self.body}', {self.ref.np} {'nodes' if self.fem else 'particles'}"
             + (f", {self.ref.ne} triangles" if self.fem else "") + f"): status {self.status}")
        if self.status == "failed":
            s += (f" at t = {fmt_us(float(self.summary.get('time', self.t_end)))} us ("
                  f"{self.summary.get('failure', '')})")
        else:
            s += f", t_end = {fmt_us(float(self.summary.get('time', self.t_end)))} us"
        return s


def f2(v, fmt="{:.2f}"):
    return NA if v is None or not np.isfinite(v) else fmt.format(v)


def rel(a, b):
    if a is None or b is None or not np.isfinite(a) or not np.isfinite(b) or b == 0:
        return NA
    return f"{100.0 * (a - b) / b:+.2f}%"


ABOVE, BAND = 1.0e-3, 0.1e-3  # radius measured 1 mm above the impact face, in a 0.2 mm band


def radius_above(x):
    """Largest r of the points whose z lies within BAND of ABOVE over the lowest z: the
    bar's radius one millimetre above the impact face, clear of the bottom row's lip."""
    if x is None or len(x) == 0:
        return None
    z0 = float(np.min(x[:, 1]))
    band = np.abs(x[:, 1] - (z0 + ABOVE)) <= BAND
    return float(np.max(x[band, 0])) if band.any() else None


def table(runs: dict, times: list, rows: int) -> tuple:
    head = ["t (us)", "method", "length (mm)", "foot radius (mm)", "radius 1 mm up (mm)",
            "largest radius (mm)", "contact radius (mm)", "max epsbar [1]",
            "energy residual / scale", "penetration left (um)", "wall time (s)",
            "length FEM vs RKPM", "foot radius FEM vs RKPM", "radius 1 mm up FEM vs RKPM",
            "largest radius FEM vs RKPM"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    values = {}
    for i, t in enumerate(times):
        for m in ("RKPM", "FEM"):
            r = runs[m]
            L = r.interp("length", t)
            R = r.interp("foot_radius", t)
            snap = r.snapshot_at(t)
            R1 = None if snap is None else radius_above(snap[2])
            Rm = None if snap is None else float(np.max(snap[2][:, 0]))
            values[(m, t)] = (L, R, R1, Rm)
            res = r.interp("residual", t)
            pen = r.penetration(t)
            cr = r.contact_radius(t, rows)
            if i == len(times) - 1:
                wall = f2(r.wall, "{:.1f}") + (f" ({r.threads} thr.)" if r.threads else "")
                if r.status == "failed":
                    wall += f", failed at {fmt_us(r.t_end)} us"
            else:
                wall = ""
            cells = [fmt_us(t), m,
                     f2(None if L is None else L * 1e3, "{:.3f}"),
                     f2(None if R is None else R * 1e3, "{:.3f}"),
                     f2(None if R1 is None else R1 * 1e3, "{:.3f}"),
                     f2(None if Rm is None else Rm * 1e3, "{:.3f}"),
                     f2(None if cr is None else cr * 1e3, "{:.3f}"),
                     f2(None if snap is None else snap[3], "{:.3f}")
                     + (" (el.)" if r.fem and snap is not None else
                        " (part.)" if snap is not None else ""),
                     NA if res is None else f"{100.0 * res / r.scale:+.3f}%",
                     f2(None if pen is None else pen * 1e6, "{:.3g}"),
                     wall]
            if m == "FEM":
                (Lr, Rr, R1r, Rmr) = values[("RKPM", t)]
                cells += [rel(L, Lr), rel(R, Rr), rel(R1, R1r), rel(Rm, Rmr)]
            else:
                cells += ["", "", "", ""]
            lines.append("| " + " | ".join(cells) + " |")
    notes = [
        "",
        "- " + runs["RKPM"].status_line(),
        "- " + runs["FEM"].status_line(),
        "- length and foot radius: `/history` columns `length` (extent in z) and `foot_radius` "
        "(largest r within one spacing of the lowest point) interpolated linearly at t; the "
        "last four columns are (FEM - RKPM) / RKPM.",
        "- radius 1 mm up: the largest r of the nodes (particles) within 0.1 mm of 1 mm above "
        "the lowest point, from the snapshot at t: the foot's radius clear of the bottom row's "
        "lip, which the foot radius picks up; largest radius: the largest r of the body (the "
        "mushroom's widest point, the classical Taylor-test measure), from the snapshot.",
        f"- contact radius: the largest `/history/contact_radius` of the {rows} history rows "
        "nearest t (the per-step value flickers as single slave points touch and leave).",
        "- max epsbar: from the snapshot at t. **FEM: the largest element value "
        "(`epsbar_cells`, marked el.); RKPM: the largest particle value (`epsbar`, averaged "
        "over the particle's integration points, marked part.)**: not the same quantity, and "
        "the largest value sits in a few cells at the contact surface (localisation), so it "
        "depends on the discretisation more than any other column.",
        "- energy residual: `/history/residual` at t over the run's final "
        "`/summary energy_scale`.",
        "- penetration left: the largest `/history/penetration` (after the contact correction) "
        "from 0 to t.",
        "- wall time: `/summary wall_time` of the whole run (threads in brackets), on the row "
        "of the last time.",
        "- n/a: the run has no value at that time (it stopped earlier, or has no snapshot "
        "there).",
    ]
    return lines, notes


def draw(runs: dict, times: list, out: str, fmt: str, name="taylor_rkpm_vs_fem") -> str:
    fig = plt.figure(figsize=(15, 10.5), layout="constrained")
    gs = fig.add_gridspec(2, 3, width_ratios=[1, 1, 0.62], height_ratios=[1, 1.05])
    ax_len = fig.add_subplot(gs[0, 0])
    ax_foot = fig.add_subplot(gs[0, 1], sharex=ax_len)
    ax_bar = fig.add_subplot(gs[:, 2])
    ax_zoom = fig.add_subplot(gs[1, 0:2])

    # (a) histories
    for m, r in runs.items():
        st = METHOD_STYLE[m]
        t = r.h["time"] * 1e6
        lab = f"{m} ({r.stem})" + (f", FAILED at {fmt_us(r.t_end)} \u00b5s"
                                   if r.status == "failed" else "")
        ax_len.plot(t, r.h["length"] * 1e3, lw=1.6, label=lab, **st)
        ax_foot.plot(t, r.h["foot_radius"] * 1e3, lw=1.6, label=lab, **st)
        if r.status == "failed":
            for ax, col in ((ax_len, "length"), (ax_foot, "foot_radius")):
                ax.plot(t[-1], r.h[col][-1] * 1e3, "x", color=st["color"], ms=9, mew=2)
        for tt in times:
            v = r.interp("length", tt)
            if v is not None:
                ax_len.plot(tt * 1e6, v * 1e3, "o", color=st["color"], ms=4)
            v = r.interp("foot_radius", tt)
            if v is not None:
                ax_foot.plot(tt * 1e6, v * 1e3, "o", color=st["color"], ms=4)
    for ax, yl, ttl in ((ax_len, "bar length [mm]", "(a) bar length"),
                        (ax_foot, "foot radius [mm]", "(a) foot radius")):
        for tt in times:
            ax.axvline(tt * 1e6, color="0.6", lw=0.7, ls=":")
        ax.set_xlabel("time [\u00b5s]")
        ax.set_ylabel(yl)
        ax.set_title(ttl + " against time (dots: the snapshot times)")
        ax.grid(alpha=0.3)
        ax.legend(loc="best", frameon=False)

    # (b), (c) outlines
    cols = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, max(len(times), 1)))
    missing = {m: [] for m in runs}
    handles = []
    for k, tt in enumerate(times):
        for m, r in runs.items():
            snap = r.snapshot_at(tt)
            if snap is None:
                missing[m].append(tt)
                continue
            for ax in (ax_bar, ax_zoom):
                for p in r.outline(snap[2]):
                    ax.plot(p[:, 0] * 1e3, p[:, 1] * 1e3, color=cols[k],
                                  ls=METHOD_STYLE[m]["ls"], lw=1.3 if m == "RKPM" else 1.1)
        handles.append(plt.Line2D([], [], color=cols[k], lw=2, label=f"t = {fmt_us(tt)} \u00b5s"))
    handles += [plt.Line2D([], [], color="k", ls=METHOD_STYLE[m]["ls"], lw=1.3, label=m)
                for m in runs]
    xs, zs = [], []
    for m, r in runs.items():
        for tt in times:
            snap = r.snapshot_at(tt)
            if snap is not None:
                xs.append(snap[2][:, 0])
                zs.append(snap[2][:, 1])
    rmax = max((float(np.max(x)) for x in xs), default=0.012) * 1e3
    ztop = max((float(np.max(z)) for z in zs), default=0.06) * 1e3
    for ax in (ax_bar, ax_zoom):
        ax.axhline(0.0, color="0.35", lw=1.0)
        ax.axhspan(-1e3, 0.0, color="0.88", zorder=0)
        ax.set_aspect("equal")
        ax.set_xlabel("r [mm]")
        ax.set_ylabel("z [mm]")
    ax_bar.set_xlim(-0.5, rmax * 1.08 + 0.5)
    ax_bar.set_ylim(-2.0, ztop + 2.0)
    ax_bar.set_title("(b) deformed outlines\n(target surface z = 0, grey)")
    ax_bar.legend(handles=handles, loc="center right", frameon=True, fontsize=8)
    ax_zoom.set_xlim(-0.2, rmax * 1.05 + 0.2)
    ax_zoom.set_ylim(-0.4, max(0.45 * rmax, 2.0))
    ax_zoom.set_title("(c) the foot: outlines at the snapshot times (RKPM solid, FEM dashed)")
    ax_zoom.legend(handles=handles, loc="upper right", frameon=True, ncol=2)
    note = []
    for m, r in runs.items():
        if missing[m]:
            why = (f" (run failed at {fmt_us(r.t_end)} \u00b5s)" if r.status == "failed" else "")
            note.append(f"{m}: no snapshot at t = " + ", ".join(fmt_us(t) for t in missing[m])
                        + f" \u00b5s{why}")
    if note:
        ax_zoom.text(0.01, 0.97, "\n".join(note), transform=ax_zoom.transAxes, va="top",
                     ha="left", color="firebrick", fontsize=10,
                     bbox=dict(facecolor="white", edgecolor="firebrick", alpha=0.9))
    fig.suptitle("Taylor bar, RKPM vs FEM (CST4): "
                 f"{runs['RKPM'].stem} vs {runs['FEM'].stem}")
    path = os.path.join(out, f"{name}.{fmt}")
    os.makedirs(out, exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("rkpm", help="HDF5 output of the RKPM run")
    ap.add_argument("fem", help="HDF5 output of the FEM run")
    ap.add_argument("--out", default=None, help="figure directory (default: the FEM file's)")
    ap.add_argument("--table", default=None, help="also write the markdown table here")
    ap.add_argument("--body", default=None,
                    help="the bar's body name in both files (default: the first deformable)")
    ap.add_argument("--times", default=None,
                    help="comma-separated times in us (default: the decks' snapshot times "
                         "after t = 0)")
    ap.add_argument("--contact-rows", type=int, default=5,
                    help="history rows nearest each time whose largest contact radius is "
                         "taken (default 5)")
    ap.add_argument("--format", default="png", help="image format (default png)")
    ap.add_argument("--name", default="taylor_rkpm_vs_fem",
                    help="figure file name without extension (default taylor_rkpm_vs_fem)")
    a = ap.parse_args(negative_values(argv))
    plt.rcParams.update(figure_style())
    out = a.out or os.path.dirname(os.path.abspath(a.fem))
    try:
        runs = {"RKPM": Run(a.rkpm, "RKPM", a.body), "FEM": Run(a.fem, "FEM", a.body)}
    except (OSError, ValueError, KeyError) as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    for m, want in (("RKPM", False), ("FEM", True)):
        if runs[m].fem != want:
            print(f"{PROG}: warning: the {m} file's body '{runs[m].body}' is a "
                  f"{'finite-element' if runs[m].fem else 'particle'} body")
    if a.times:
        times = sorted(float(v) * 1e-6 for v in a.times.split(",") if v.strip())
    else:
        times = sorted({round(t, 12) for r in runs.values() for t in r.deck_times if t > 0})
        if not times:
            times = [12e-6, 16e-6, 20e-6, 24e-6]
    try:
        lines, notes = table(runs, times, a.contact_rows)
        text = "\n".join(lines + notes) + "\n"
        print(text, end="")
        if a.table:
            d = os.path.dirname(os.path.abspath(a.table))
            os.makedirs(d, exist_ok=True)
            with open(a.table, "w") as fh:
                fh.write(f"Taylor bar, RKPM vs FEM at the snapshot times (post/compare_taylor.py "
                         f"{os.path.basename(a.rkpm)} {os.path.basename(a.fem)})\n\n")
                fh.write(text)
            print(f"{PROG}: wrote {a.table}")
        print(f"{PROG}: wrote {draw(runs, times, out, a.format, a.name)}")
    except Exception:  # noqa: BLE001
        traceback.print_exc()
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
