#!/usr/bin/env python3
"""Deformed finite-element (CST4) shapes of an mfcd run coloured by element values: the
paper's Fig. 15 (Li, Qian, Liu, Belytschko 2001: the Taylor bar by FEM at 12, 16, 20, 24 us
coloured by effective plastic strain).

    python post/plot_fem.py output/taylor_bar_fem.h5 --out doc/figures
        [--snapshots 0002,0003,0004,0005] [--body bar] [--mirror | --no-mirror]
        [--vmax 3] [--field epsbar] [--foot-height 6] [--format png]

Figures (in --out, default: the directory of the .h5 file; <stem> is the file's stem):
  <stem>_fig15.png       one panel per snapshot: the body's triangles at the snapshot's node
                         positions (/snapshots/<label>/<body>/x on /bodies/<body>/triangles),
                         each triangle one colour, its element value (epsbar_cells; flat
                         shading: no smoothing across elements); a common colour scale
                         (--vmax; by default the largest value, or the 99.9th percentile of
                         the elements when a few lie far above it), the snapshot time in
                         microseconds and the panel's largest value in each title
  <stem>_fig15_foot.png  the same zoomed on the foot (the bottom --foot-height mm of the
                         window, default from the widest radius) with the element edges
                         drawn, so the mesh is visible

By default the snapshots after t = 0 are drawn ('0002', '0003', ... in the Taylor decks); when
the run failed (/summary status 'failed') its 'failure' snapshot is added, and the snapshot
times of the deck (&solver snapshot_times) that the file lacks are named on stdout and in the
figure. --mirror (default for axisymmetric runs) reflects the body about r = 0 like
plot_snapshots.py --mirror. Rigid bodies (only in /bodies) are drawn grey at their reference
position. The field is the element value of --field (default epsbar; J, stress_11 ..
stress_12, von_mises); nodal fields are not drawn here (post/plot_snapshots.py draws them).

A requested snapshot that the file lacks is named and skipped; when it has none of them, the
default choice is drawn instead. Exit status: 0 when both figures were written, 1 when the
file has no snapshots or no finite-element body, 2 for bad arguments.
File layout: doc/output.md; reader: post/mfcd_h5.py.
"""

from __future__ import annotations

import argparse
import os
import sys
import textwrap
import traceback

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from matplotlib.patches import Polygon  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import (CELL_FIELDS, FIELDS, MfcdFile, cell_field_values, negative_values,  # noqa: E402
                     deck_group)

C_RIGID = "0.65"
PROG = "plot_fem"


class Fail(Exception):
    """A reason to stop with exit status 1 (the message says why)."""


def fmt_us(t: float) -> str:
    return f"{t * 1e6:.2f}".rstrip("0").rstrip(".")


def deck_times(f: MfcdFile) -> list:
    """&solver snapshot_times of the stored deck (s), [] when it gives none."""
    sol = deck_group(f.deck, "solver") or {}
    t = sol.get("snapshot_times", [])
    return [float(v) for v in (t if isinstance(t, list) else [t])]


def snapshot_times(f: MfcdFile) -> dict:
    return {lab: f.snapshot_time(lab) for lab in f.snapshot_labels()}


def missing_times(f: MfcdFile, times: dict) -> list:
    """Deck snapshot times after t = 0 that no snapshot of the file (failure excluded)
    matches within 1% of the time (a snapshot is written at the nearest step)."""
    have = [t for lab, t in times.items() if lab != "failure"]
    out = []
    for t in deck_times(f):
        if t <= 0:
            continue
        if not any(abs(h - t) <= 0.01 * t for h in have):
            out.append(t)
    return out


def pick_labels(f: MfcdFile, wanted: str | None, times: dict) -> list:
    labels = list(times)
    if not labels:
        raise Fail(f"{f.path} has no snapshots (mode '{f.mode}'; &solver snapshot_times)")
    if wanted:
        req = [w.strip() for w in wanted.split(",") if w.strip()]
        req = [w.zfill(4) if w.isdigit() else w for w in req]
        absent = [w for w in req if w not in labels]
        sel = [w for w in req if w in labels]
        if absent:
            print(f"{PROG}: no snapshot {', '.join(absent)} in {f.path} (it has "
                  f"{', '.join(labels)}); "
                  + ("drawing the others" if sel else "drawing those after t = 0 instead"))
        if sel:
            return sel
        # none of them (a run that stopped early): draw what there is rather than nothing
    sel = [lab for lab in labels if lab != "failure" and times[lab] > 0]
    if "failure" in labels:
        sel.append("failure")
    if not sel:                        # only t = 0: draw it rather than nothing
        sel = labels
    return sel


def pick_body(f: MfcdFile, name: str | None, label: str) -> str:
    snap_bodies = f.snapshot_body_names(label)
    if name:
        if name not in f.body_names():
            raise Fail(f"no body {name!r} in {f.path} (bodies: {', '.join(f.body_names())})")
        if f.triangles(name) is None:
            raise Fail(f"body {name!r} is not a finite-element body (discretization "
                       f"'{f.discretization(name)}': no /bodies/{name}/triangles)")
        return name
    fem = [n for n in snap_bodies if f.triangles(n) is not None]
    if not fem:
        raise Fail(f"{f.path} has no deformable finite-element body (no "
                   "/bodies/<name>/triangles); for particle bodies use plot_snapshots.py")
    return fem[0]


def rigid_outlines(f: MfcdFile, skip) -> list:
    """Closed reference outlines (k, 2) of the bodies that are not in the snapshots."""
    out = []
    for n in f.body_names():
        if n in skip:
            continue
        try:
            out += [p[:, :2] for p in f.body(n).polylines()]
        except Exception:  # noqa: BLE001  (a body without polylines)
            continue
    return out


def signed_areas(x: np.ndarray, tri: np.ndarray) -> np.ndarray:
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))


def draw(f: MfcdFile, body: str, labels: list, field: str, mirror: bool,
         vmax_user: float | None, out: str, fmt: str, foot_height: float | None,
         missing: list) -> list:
    axisym = f.geometry == "axisymmetric"
    tri = f.triangles(body)
    snaps = []
    for lab in labels:
        s = f.snapshot(lab)
        if body not in s.bodies:
            print(f"{PROG}: snapshot {lab} has no body {body!r}; skipped")
            continue
        b = s.bodies[body]
        v = cell_field_values(b, field)
        if v is None or v.shape[0] != tri.shape[0]:
            print(f"{PROG}: snapshot {lab}: body {body!r} has no element values of {field} "
                  f"({tri.shape[0]} triangles); skipped")
            continue
        snaps.append((s, b, v))
    if not snaps:
        raise Fail(f"no snapshot to draw for body {body!r}")

    label, funit, _ = FIELDS[field]
    for s, b, v in snaps:
        area = signed_areas(b.x, tri)
        jc = b.J_cells
        fin = np.isfinite(v)
        print(f"{PROG}: {s.label} t = {fmt_us(s.time)} us: {field} max {np.nanmax(v[fin]):.4g}"
              f" (element {int(np.nanargmax(np.where(fin, v, -np.inf)))}), 99th percentile "
              f"{np.percentile(v[fin], 99):.4g}"
              + (f"; J_cells {jc.min():.3f} .. {jc.max():.3f}" if jc is not None else "")
              + f"; {int(np.sum(area <= 0))} inverted triangles"
              + (f"; {int(np.sum(~fin))} non-finite values" if not fin.all() else ""))

    allv = np.concatenate([v[np.isfinite(v)] for _, _, v in snaps])
    vmin, vmax = float(allv.min()), float(allv.max())
    signed_field = field.startswith("stress_")
    if signed_field and vmin < 0 < vmax:
        m = max(-vmin, vmax)
        vmin, vmax = -m, m
    elif field == "epsbar":
        vmin = 0.0
    if vmax_user is not None:
        vmax = vmax_user
    elif not signed_field:
        # a few elements far above the rest (localisation at the contact surface) would
        # leave the whole field dark: then the scale ends at the 99.9th percentile, rounded
        # up, and the colour bar shows the saturation (every panel title gives its max)
        p999 = float(np.percentile(allv, 99.9))
        if p999 > 0 and vmax > 1.5 * p999:
            mag = 10.0 ** np.floor(np.log10(p999))
            vmax = float(np.ceil(p999 / mag * 10) * mag / 10)
            print(f"{PROG}: note: the largest {field} ({allv.max():.3g}) is far above the "
                  f"99.9th percentile of the elements ({p999:.3g}); the colour scale ends at "
                  f"{vmax:.3g} (--vmax to choose)")
    if vmax - vmin <= 1e-12 * max(abs(vmax), 1.0):       # a constant field
        if field == "epsbar" and vmin == 0.0:
            print(f"{PROG}: note: {field} is 0 in every element (no plastic flow)")
            vmax = 1e-3
        else:
            pad = max(abs(vmax) * 0.05, 1e-6)
            vmin, vmax = vmin - pad, vmax + pad
    extend = "max" if allv.max() > vmax * (1 + 1e-12) else "neither"
    print(f"{PROG}: colour scale {vmin:.3g} .. {vmax:.3g}")
    cmap = plt.get_cmap("RdBu_r" if signed_field and vmin < 0 < vmax else "turbo")
    norm = Normalize(vmin, vmax)

    rigid = rigid_outlines(f, {body} | set(snaps[0][0].bodies))
    allx = np.concatenate([b.x for _, b, _ in snaps] + rigid)
    mm = float(np.ptp(allx, axis=0).max()) <= 0.1 * (1 + 1e-9)
    sc, unit = (1e3, "mm") if mm else (1.0, "m")
    xl, yl = ("r", "z") if axisym else ("x", "y")
    if mirror and not axisym:
        print(f"{PROG}: --mirror ignored: the run is not axisymmetric")
        mirror = False
    sides = [1.0, -1.0] if mirror else [1.0]

    status = str(f.summary.get("status", ""))
    fail_t = float(f.summary.get("time", np.nan)) if status == "failed" else None
    notes = []
    if fail_t is not None:
        notes.append(f"run FAILED at t = {fmt_us(fail_t)} \u00b5s")
    if missing:
        notes.append("no snapshot at t = " + ", ".join(fmt_us(t) for t in missing) + " \u00b5s")

    def suptitle(fig, lines):
        """The figure title, its lines wrapped to the figure's width."""
        width = max(int(fig.get_figwidth() * 72 / 7.0), 30)      # ~7 pt per character
        text = "\n".join(textwrap.fill(l, width) for l in lines)
        fig.suptitle(text, color="firebrick" if notes else "black")

    edge_lw = [0.3]

    def panel(ax, s, b, v, edges: bool):
        for sg in sides:
            tr = Triangulation(sg * b.x[:, 0] * sc, b.x[:, 1] * sc, triangles=tri)
            # edgecolors 'face' with a hairline closes the pixel gaps between triangles
            ax.tripcolor(tr, facecolors=v, cmap=cmap, norm=norm, shading="flat",
                         edgecolors="face", linewidth=0.25, rasterized=True)
            if edges:
                ax.triplot(tr, color="0.45", lw=edge_lw[0], alpha=0.8, rasterized=True)
        for p in rigid:
            for sg in sides:
                ax.add_patch(Polygon(np.c_[sg * p[:, 0], p[:, 1]] * sc, closed=True,
                                     facecolor=C_RIGID, edgecolor="none", zorder=0))
        if mirror:
            ax.axvline(0.0, color="0.3", lw=0.6, ls=":")
        ax.set_aspect("equal")
        tag = " (failure)" if s.label == "failure" else ""
        ax.set_title(f"t = {s.time * 1e6:.1f} \u00b5s{tag}\nmax {np.nanmax(v):.3g}")

    # extents: the bodies in the chosen snapshots, mirrored, and the rigid bodies
    bx = np.concatenate([b.x for _, b, _ in snaps])
    rmax = float(np.abs(bx[:, 0]).max())
    lo = np.array([-rmax if mirror else bx[:, 0].min(), bx[:, 1].min()])
    hi = np.array([rmax, bx[:, 1].max()])
    if rigid:
        rx = np.concatenate(rigid)
        lo = np.minimum(lo, [-np.abs(rx[:, 0]).max() if mirror else rx[:, 0].min(),
                             rx[:, 1].min()])
        hi = np.maximum(hi, [np.abs(rx[:, 0]).max(), hi[1]])
    pad = 0.03 * (hi - lo)
    lo, hi = lo - pad, hi + pad

    stem = os.path.splitext(os.path.basename(f.path))[0]
    title = f.title or os.path.basename(f.path)
    paths = []

    # --- the whole bodies, one panel per snapshot side by side
    n = len(snaps)
    ext = hi - lo
    ph = 7.0
    pw = min(max(ph * ext[0] / ext[1], 1.6), 6.0)
    fig, axes = plt.subplots(1, n, figsize=(pw * n + 1.8, ph + 1.4), squeeze=False,
                             sharey=True, layout="constrained")
    axes = axes[0]
    for k, (ax, (s, b, v)) in enumerate(zip(axes, snaps)):
        panel(ax, s, b, v, edges=False)
        ax.set_xlim(lo[0] * sc, hi[0] * sc)
        ax.set_ylim(lo[1] * sc, hi[1] * sc)
        ax.set_xlabel(f"{xl} [{unit}]")
        if k == 0:
            ax.set_ylabel(f"{yl} [{unit}]")
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=list(axes), shrink=0.9,
                      aspect=30, extend=extend)
    cb.set_label(f"{label} [{funit}]")
    suptitle(fig, [title, f"element values of {label} (flat per triangle)"
                   + (", mirrored about r = 0" if mirror else "")] + (["; ".join(notes)]
                                                                      if notes else []))
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, f"{stem}_fig15.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    paths.append(path)

    # --- the foot: the bottom of the window with the element edges
    near = bx[:, 1] < bx[:, 1].min() + 0.3 * np.ptp(bx[:, 1])
    rfoot = float(np.abs(bx[near, 0]).max())
    h = 0.6 * rfoot if foot_height is None else foot_height / sc   # [m]
    zb = float(bx[:, 1].min())
    padr = 0.06 * rfoot
    flo = np.array([-(rfoot + padr) if mirror else -padr, zb - 0.12 * h])
    fhi = np.array([rfoot + padr, zb + h])
    fext = fhi - flo
    pw = 11.0 if mirror else 8.0
    ph = min(max(pw * fext[1] / fext[0], 1.5), 6.0)
    ncol = 1
    fig, axes = plt.subplots(n, ncol, figsize=(pw + 1.8, (ph + 0.75) * n + 1.2), squeeze=False,
                             sharex=True, layout="constrained")
    # element edges about 4% of the median edge length on the page, 0.08 to 0.3 pt
    x0 = snaps[-1][1].x
    elen = np.median(np.linalg.norm(x0[tri[:, 0]] - x0[tri[:, 1]], axis=1))
    edge_lw[0] = float(np.clip(0.04 * elen * pw * 72.0 / fext[0], 0.08, 0.3))
    axes = axes[:, 0]
    for k, (ax, (s, b, v)) in enumerate(zip(axes, snaps)):
        panel(ax, s, b, v, edges=True)
        ax.set_title(ax.get_title().replace("\n", ", "))
        ax.set_xlim(flo[0] * sc, fhi[0] * sc)
        ax.set_ylim(flo[1] * sc, fhi[1] * sc)
        ax.set_ylabel(f"{yl} [{unit}]")
        if k == n - 1:
            ax.set_xlabel(f"{xl} [{unit}]")
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=list(axes), shrink=0.8,
                      aspect=30, extend=extend)
    cb.set_label(f"{label} [{funit}]")
    suptitle(fig, [title, f"the foot: {label} per element, with the element edges"
                   + (", mirrored about r = 0" if mirror else "")] + (["; ".join(notes)]
                                                                      if notes else []))
    path = os.path.join(out, f"{stem}_fig15_foot.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    paths.append(path)
    return paths


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("file", help="HDF5 output of a dynamic run with a finite-element body")
    ap.add_argument("--out", default=None, help="output directory (default: the file's)")
    ap.add_argument("--snapshots", default=None,
                    help="comma-separated labels, e.g. 0002,0003,0004,0005 or failure "
                         "(default: every snapshot after t = 0, and 'failure' if written)")
    ap.add_argument("--body", default=None,
                    help="the finite-element body (default: the first one in the snapshots)")
    ap.add_argument("--mirror", action=argparse.BooleanOptionalAction, default=None,
                    help="reflect the bodies about r = 0 (default: on for axisymmetric runs)")
    ap.add_argument("--vmax", type=float, default=None,
                    help="upper end of the common colour scale (default: the largest value, "
                         "or the 99.9th percentile of the elements, rounded up, when the "
                         "largest is more than 1.5 times that: a few outliers)")
    ap.add_argument("--field", default="epsbar", choices=list(CELL_FIELDS),
                    help="element field (default epsbar: epsbar_cells)")
    ap.add_argument("--foot-height", type=float, default=None,
                    help="height of the foot window above the bar's lowest point, in the "
                         "figure's length unit (mm for the Taylor bar; default 0.6 x the "
                         "foot's widest radius)")
    ap.add_argument("--format", default="png", help="image format (default png)")
    a = ap.parse_args(negative_values(argv))
    plt.rcParams.update(figure_style(savefig_dpi=130))
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    try:
        with MfcdFile(a.file) as f:
            times = snapshot_times(f)
            labels = pick_labels(f, a.snapshots, times)
            body = pick_body(f, a.body, labels[0])
            summ = f.summary
            missing = missing_times(f, times)
            if str(summ.get("status", "")) == "failed":
                print(f"{PROG}: {a.file}: the run FAILED at t = "
                      f"{fmt_us(float(summ.get('time', 0.0)))} us: {summ.get('failure', '')}")
            if missing:
                print(f"{PROG}: {a.file}: missing snapshots of the deck at t = "
                      + ", ".join(fmt_us(t) for t in missing) + " us")
            mirror = a.mirror if a.mirror is not None else f.geometry == "axisymmetric"
            for p in draw(f, body, labels, a.field, mirror, a.vmax, out, a.format,
                          a.foot_height, missing):
                print(f"{PROG}: wrote {p}")
    except Fail as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    except (OSError, ValueError, KeyError) as e:
        print(f"{PROG}: {a.file}: {e}", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001
        traceback.print_exc()
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
