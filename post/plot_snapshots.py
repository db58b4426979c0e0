#!/usr/bin/env python3
"""Deformed shapes and energy history of an mfcd 'dynamic' run (after Figs. 14-15 of
Li, Qian, Liu, Belytschko 2001: deformed Taylor bars coloured by effective plastic strain).

    python post/plot_snapshots.py output/run.h5 [--field epsbar] [--out DIR]
                                  [--snapshots 0001,0003] [--mirror] [--history]
                                  [--style surface|points] [--layout auto|row|column]

Figures (in --out, default: the directory of the .h5 file):
  <stem>_<field>.png   one panel per snapshot, the particles at their physical positions
                       (/snapshots/<label>/<body>/x) coloured by the field, a shared colour
                       bar, the snapshot time in microseconds in each title
  <stem>_energy.png    with --history: kinetic energy, internal work, plastic dissipation,
                       external and contact work against time, and the energy residual

By default the field is drawn as a surface: interpolated (Gouraud) over triangles of the
reference particle lattice, placed at the physical positions, so the deformed outline passes
through the outer particles; --style points draws one square marker per particle instead,
sized by the particle's spacing and its current area stretch.

Fields: epsbar, J, stress_11, stress_22, stress_33, stress_12 (Cauchy; in axisymmetry
11 = rr, 22 = zz, 33 = hoop), von_mises, v_mag, u_mag. Every body in a snapshot is drawn;
bodies without the field are grey. Bodies of the deck that are not in the snapshots (rigid
bodies: the solver writes only deformable ones) are drawn grey at their reference position
(they do not move). --mirror reflects the bodies of an axisymmetric run
about r = 0 to show the whole section. Lengths are in mm when the bodies span 0.1 m or
less. Panels stand side by side for tall bodies and one above the other for long ones
(--layout to choose).

Exit status: 0 when every figure was written, 1 otherwise, 2 for bad arguments.
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
from matplotlib.colors import ListedColormap, Normalize  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import negative_values, FIELDS, MfcdFile, field_values  # noqa: E402

C_OTHER = "0.6"        # bodies without the field
C_RIGID = "0.45"       # rigid bodies not in the snapshots
MAX_DEFAULT_PANELS = 6


def signed(field: str) -> bool:
    return field.startswith("stress_")


def pick_labels(f: MfcdFile, wanted: str | None) -> list:
    labels = f.snapshot_labels()
    if not labels:
        why = ("its deck gives no &solver snapshot_times (--history --no-snapshots draws "
               "the energies only)" if f.mode == "dynamic"
               else f"it is a '{f.mode}' run, not 'dynamic'")
        raise SystemExit(f"plot_snapshots: {f.path} has no snapshots: {why}")
    if wanted:
        req = [w.strip() for w in wanted.split(",") if w.strip()]
        # accept 1 for 0001
        req = [w.zfill(4) if w.isdigit() else w for w in req]
        bad = [w for w in req if w not in labels]
        if bad:
            raise SystemExit(f"plot_snapshots: no snapshot {', '.join(bad)} in {f.path}; "
                             f"it has {', '.join(labels)}")
        return req
    if len(labels) > MAX_DEFAULT_PANELS:
        idx = np.unique(np.linspace(0, len(labels) - 1, MAX_DEFAULT_PANELS).round().astype(int))
        sel = [labels[i] for i in idx]
        print(f"plot_snapshots: {len(labels)} snapshots; drawing {', '.join(sel)} "
              "(choose with --snapshots)")
        return sel
    return labels


def rigid_extras(f: MfcdFile, snap_bodies) -> list:
    """(name, x (np, 2)) of the rigid bodies, at their reference positions (a moving one is
    drawn where each snapshot has it: Snapshot.rigid)."""
    out = []
    for name in f.body_names():
        if name in snap_bodies or not f.is_rigid(name):
            continue
        out.append((name, f.body(name).x[:, :2]))
    return out


def body_spacing(f: MfcdFile, name: str) -> float:
    try:
        sp = np.atleast_1d(f.body(name).attrs.get("spacing", [0.0]))
        return float(np.min(sp))
    except Exception:  # noqa: BLE001
        return 0.0


def area_stretch(b, axisym: bool) -> np.ndarray:
    """Per-particle ratio of current to reference in-plane area: J in plane strain, J over
    the hoop stretch r/R in axisymmetry (1 on the axis); clipped to [0.05, 20]."""
    if b.J is None:
        return np.ones(b.np)
    a = b.J.copy()
    if axisym and b.u is not None:
        r0 = b.x[:, 0] - b.u[:, 0]
        ok = r0 > 1e-9 * max(np.abs(b.x[:, 0]).max(), 1e-30)
        a[ok] = a[ok] / (b.x[ok, 0] / r0[ok])
    return np.clip(np.where(np.isfinite(a), a, 1.0), 0.05, 20.0)


def reference_triangles(f: MfcdFile, name: str, npart: int):
    """Triangles (k, 3) over the body's reference particles (Delaunay), without the ones
    that bridge a gap of the body (an edge longer than 1.6 x the largest spacing), or None
    when the body's reference particles are not in the file or do not match."""
    try:
        body = f.body(name)
    except Exception:  # noqa: BLE001
        return None
    if body.x.shape[0] != npart or body.x.shape[1] < 2 or npart < 3:
        return None
    X = body.x[:, :2]
    try:
        tri = Triangulation(X[:, 0], X[:, 1])
    except Exception:  # noqa: BLE001  (collinear particles)
        return None
    t = tri.triangles
    e = np.stack([np.linalg.norm(X[t[:, i]] - X[t[:, (i + 1) % 3]], axis=1) for i in range(3)])
    sp = np.atleast_1d(body.attrs.get("spacing", [0.0]))
    lim = 1.6 * float(np.hypot(*np.resize(sp, 2)))
    if lim <= 0:
        lim = 3.0 * np.median(e)
    keep = e.max(axis=0) <= lim
    return t[keep] if keep.any() else None


def draw_snapshots(f: MfcdFile, field: str, labels: list, mirror: bool, out: str,
                   layout: str, fmt: str, cmap_name: str | None, style: str = "surface",
                   vmax_user: float | None = None, window: list | None = None,
                   suffix: str = "") -> str:
    axisym = f.geometry == "axisymmetric"
    if mirror and not axisym:
        print("plot_snapshots: --mirror ignored: the run is not axisymmetric")
        mirror = False
    snaps = [f.snapshot(l) for l in labels]
    names = sorted({n for s in snaps for n in s.bodies})
    extras = rigid_extras(f, names)
    spacing = {n: body_spacing(f, n) for n in names + [e[0] for e in extras]}

    # what each panel draws: (snapshot, list of (name, x, values or None, marker size h,
    # triangles of the reference configuration or None))
    tris = {}
    panels = []
    for s in snaps:
        items = []
        for n, b in s.bodies.items():
            h = spacing.get(n, 0.0) * np.sqrt(area_stretch(b, axisym))
            if n not in tris:
                tris[n] = reference_triangles(f, n, b.np)
            items.append((n, b.x.copy(), field_values(b, field), h, tris[n]))
        for n, x0 in extras:
            if n not in tris:
                tris[n] = reference_triangles(f, n, x0.shape[0])
            if n in s.rigid:   # a moving rigid body (a ram) where this snapshot has it
                x0 = s.rigid[n].x
            items.append((n + " (rigid)", x0.copy(), None,
                          np.full(x0.shape[0], spacing.get(n, 0.0)), tris[n]))
        if mirror:
            items = items + [(n, x * np.array([-1.0, 1.0]), v, h, t)
                             for n, x, v, h, t in items]
        panels.append((s, items))

    vals = [it[2] for _, its in panels for it in its if it[2] is not None and it[2].size]
    if not vals:
        raise SystemExit(f"plot_snapshots: no body in the chosen snapshots has field {field}")
    allv = np.concatenate(vals)
    allv = allv[np.isfinite(allv)]
    vmin, vmax = float(allv.min()), float(allv.max())
    if signed(field) and vmin < 0 < vmax:
        m = max(-vmin, vmax)
        vmin, vmax = -m, m
    if vmax_user is not None:
        vmax = vmax_user
    if vmax - vmin <= 1e-12 * max(abs(vmax), 1.0):      # a constant field
        pad = max(abs(vmax) * 0.05, 1e-6)
        vmin, vmax = vmin - pad, vmax + pad
    cmap = plt.get_cmap(cmap_name or ("RdBu_r" if signed(field) and vmin < 0 < vmax
                                      else "turbo"))
    norm = Normalize(vmin, vmax)

    allx = np.concatenate([it[1] for _, its in panels for it in its])
    lo, hi = allx.min(axis=0), allx.max(axis=0)
    mm = max(hi - lo) <= 0.1 * (1 + 1e-9)        # the bodies, before padding
    hmax = max(spacing.values()) if spacing else 0.0
    pad = np.maximum(0.03 * (hi - lo), 1.5 * hmax)
    lo, hi = lo - pad, hi + pad
    if window is not None:                             # x0, x1, y0, y1 in the file's units (m)
        lo, hi = np.array(window[0::2], float), np.array(window[1::2], float)
    ext = hi - lo
    sc = 1e3 if mm else 1.0
    unit = "mm" if mm else "m"

    n = len(panels)
    aspect = ext[0] / max(ext[1], 1e-300)
    if layout == "auto":
        layout = "column" if aspect > 1.5 else "row"
    if layout == "row":
        ph = 6.0 if aspect < 0.5 else 4.5
        pw = min(max(ph * aspect, 1.3), 6.0)
        fig, axes = plt.subplots(1, n, figsize=(pw * n + 1.6, ph + 1.0), squeeze=False,
                                 sharey=True, layout="constrained")
        axes = axes[0]
    else:
        pw = 9.0
        ph = min(max(pw / aspect, 0.35), 4.5)
        fig, axes = plt.subplots(n, 1, figsize=(pw + 1.8, (ph + 0.6) * n + 0.9),
                                 squeeze=False, sharex=True, layout="constrained")
        axes = axes[:, 0]

    xl, yl = ("r", "z") if axisym else ("x", "y")
    colls = []
    for k, (ax, (s, items)) in enumerate(zip(axes, panels)):
        for name, x, v, h, tri in items:
            grey = C_RIGID if "(rigid)" in name else C_OTHER
            if style == "surface" and tri is not None:
                tr = Triangulation(x[:, 0] * sc, x[:, 1] * sc, triangles=tri)
                if v is None:
                    ax.tripcolor(tr, np.zeros(x.shape[0]), cmap=ListedColormap([grey]),
                                 shading="gouraud", rasterized=True)
                else:
                    ax.tripcolor(tr, v, cmap=cmap, norm=norm, shading="gouraud",
                                 rasterized=True)
                continue
            if v is None:
                c = ax.scatter(x[:, 0] * sc, x[:, 1] * sc, s=1, c=grey, marker="s",
                               linewidths=0, rasterized=True)
                colls.append((ax, c, np.broadcast_to(h, (x.shape[0],))))
            else:
                order = np.argsort(v) if not signed(field) else np.argsort(np.abs(v))
                c = ax.scatter(x[order, 0] * sc, x[order, 1] * sc, s=1, c=v[order], cmap=cmap,
                               norm=norm, marker="s", linewidths=0, rasterized=True)
                colls.append((ax, c, np.broadcast_to(h, v.shape)[order]))
        ax.set_xlim(lo[0] * sc, hi[0] * sc)
        ax.set_ylim(lo[1] * sc, hi[1] * sc)
        ax.set_aspect("equal")
        tag = " (failure)" if s.label == "failure" else ""
        ax.set_title(f"t = {s.time * 1e6:.2f} \u00b5s{tag}")
        if layout == "row" or k == n - 1:
            ax.set_xlabel(f"{xl} [{unit}]")
        if layout == "column" or k == 0:
            ax.set_ylabel(f"{yl} [{unit}]")
        if mirror:
            ax.axvline(0.0, color="0.3", lw=0.6, ls=":")
    label, funit, _ = FIELDS[field]
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=list(axes),
                      shrink=0.9 if layout == "row" else 0.7, aspect=30)
    cb.set_label(f"{label} [{funit}]")
    title = f.title or os.path.basename(f.path)
    sup = f"{title}: {label}" + (" (mirrored about r = 0)" if mirror else "")
    if len(sup) * 7.5 > fig.get_figwidth() * 72:
        sup = f"{title}\n{label}" + (" (mirrored about r = 0)" if mirror else "")
    fig.suptitle(sup)
    # markers about one particle spacing wide, in points, now that the layout is fixed
    fig.canvas.draw()
    for ax, c, h in colls:
        bb = ax.get_window_extent()
        ppm = bb.width * 72.0 / fig.dpi / ((hi[0] - lo[0]))      # points per metre
        d = np.maximum(np.atleast_1d(h) * ppm * 1.1, 0.6)
        d[~(np.atleast_1d(h) > 0)] = 1.5
        c.set_sizes(d * d)
    os.makedirs(out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(f.path))[0]
    path = os.path.join(out, f"{stem}_{field}{'_mirror' if mirror else ''}{suffix}.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    return path


def draw_history(f: MfcdFile, out: str, fmt: str) -> str:
    h = f.history()
    if not h or "time" not in h:
        raise SystemExit(f"plot_snapshots: {f.path} has no /history")
    u = f.history_units()
    t = h["time"] * 1e6
    eu = u.get("ke", "J")
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(7.5, 6.2), sharex=True, layout="constrained",
                                  gridspec_kw={"height_ratios": [3, 1.3]})
    series = [("ke", "kinetic energy", "tab:blue", "-"),
              ("w_int", "internal work", "tab:orange", (0, (5, 3))),
              ("w_plastic", "plastic dissipation", "tab:red", "--"),
              ("w_ext", "external work", "tab:green", "-"),
              ("w_contact", "contact work", "tab:purple", ":")]
    for key, lab, col, ls in series:
        if key in h:
            ax.plot(t, h[key], color=col, ls=ls, lw=2.4 if key == "ke" else 1.6, label=lab)
    if all(k in h for k in ("ke", "w_int")):
        ax.plot(t, h["ke"] + h["w_int"], color="0.2", lw=0.9, ls="-.",
                label="kinetic + internal")
    ax.set_ylabel(f"energy [{eu}]")
    ax.legend(loc="best", ncol=2, frameon=False)
    ax.grid(alpha=0.3)
    summ = f.summary
    title = f.title or os.path.basename(f.path)
    ax.set_title(f"{title}: energy balance")
    axr.plot(t, h.get("residual", np.zeros_like(t)), color="k", lw=1.2)
    axr.axhline(0.0, color="0.5", lw=0.6)
    axr.set_ylabel(f"residual [{eu}]")
    axr.set_xlabel("time [\u00b5s]")
    axr.grid(alpha=0.3)
    note = "residual = KE + W_int - KE0 - W_ext - W_contact"
    if summ.get("energy_scale"):
        rel = float(summ.get("energy_residual", 0.0)) / float(summ["energy_scale"])
        note += f"; at the end {rel:.2e} of the energy scale"
    if str(summ.get("status", "")) == "failed":
        note += " (run FAILED)"
    axr.set_title(note, fontsize=9)
    os.makedirs(out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(f.path))[0]
    path = os.path.join(out, f"{stem}_energy.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("file", help="HDF5 output of a dynamic run")
    ap.add_argument("--field", default="epsbar", choices=list(FIELDS),
                    help="colour field (default epsbar)")
    ap.add_argument("--out", default=None, help="output directory (default: the file's)")
    ap.add_argument("--snapshots", default=None,
                    help="comma-separated labels, e.g. 0001,0003 or failure (default: all, "
                         f"at most {MAX_DEFAULT_PANELS} evenly chosen)")
    ap.add_argument("--mirror", action="store_true",
                    help="reflect axisymmetric bodies about r = 0")
    ap.add_argument("--history", action="store_true",
                    help="also draw the energy history into <stem>_energy")
    ap.add_argument("--no-snapshots", action="store_true",
                    help="skip the deformed shapes (with --history)")
    ap.add_argument("--layout", default="auto", choices=("auto", "row", "column"),
                    help="panels side by side (row) or stacked (column); auto by shape")
    ap.add_argument("--style", default="surface", choices=("surface", "points"),
                    help="surface: the field interpolated over triangles of the reference "
                         "particle lattice, drawn at the physical positions (default); "
                         "points: one square marker per particle")
    ap.add_argument("--cmap", default=None, help="matplotlib colour map")
    ap.add_argument("--vmax", type=float, default=None,
                    help="upper end of the colour scale (default: the largest value)")
    ap.add_argument("--window", default=None,
                    help="x0,x1,y0,y1 (m): zoom to this window, e.g. the Taylor bar's foot")
    ap.add_argument("--suffix", default="", help="added to the figure's file name")
    ap.add_argument("--format", default="png", help="image format (default png)")
    a = ap.parse_args(negative_values(argv))
    plt.rcParams.update(figure_style())
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    ok = True
    try:
        with MfcdFile(a.file) as f:
            if not a.no_snapshots:
                try:
                    labels = pick_labels(f, a.snapshots)
                    win = [float(v) for v in a.window.split(",")] if a.window else None
                    p = draw_snapshots(f, a.field, labels, a.mirror, out, a.layout, a.format,
                                       a.cmap, a.style, a.vmax, win, a.suffix)
                    print(f"plot_snapshots: wrote {p}")
                except SystemExit as e:
                    print(e, file=sys.stderr)
                    ok = False
            if a.history:
                try:
                    p = draw_history(f, out, a.format)
                    print(f"plot_snapshots: wrote {p}")
                except SystemExit as e:
                    print(e, file=sys.stderr)
                    ok = False
    except (OSError, ValueError) as e:
        print(f"plot_snapshots: {a.file}: {e}", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001
        traceback.print_exc()
        return 1
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
