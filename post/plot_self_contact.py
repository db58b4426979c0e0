#!/usr/bin/env python3
"""Self-contact of a body (&contact master = slave) beside its control run without it: the
deformed shapes, the self-overlap the control is left with, and det(M) of the particles that
are not a point's reference neighbours where the faces meet (the paper's Sections 1 and 7).

    python post/plot_self_contact.py output/ring_crush.h5 output/ring_crush_free.h5
        --out doc/figures [--body ring] [--name ring_crush] [--snapshots 0004,0005,0006]
        [--det-snapshot 0006] [--vmax 1.5] [--step-fraction 0.05] [--format png]

Figures (in --out, default: the directory of the first file; <name> defaults to the first
file's stem):
  <name>_shapes.png    rows: snapshots; left column the run with self-contact, right the
                       control without it, on the same axes. The body's deformed boundary
                       (black), its effective plastic strain (per triangle for a finite-
                       element body, per particle for an RKPM body; one colour scale for all
                       panels), the other bodies as grey outlines (rigid ones at their
                       reference position), and in red the material covered twice: the
                       raster cells where the winding number of the deformed boundary loops
                       is 2 or more (post/self_overlap.py, overlap()). Each panel title gives
                       the overlap depth and area at that time; the run with self-contact is
                       shaded too where it has any, and a patch too small to see at the
                       figure's scale is circled (its title turns red).
  <name>_det_self.png  at one snapshot of the run with self-contact (--det-snapshot, default
                       the last one in which some particle has det_self above its threshold):
                       top, the contact zone (the box of those particles, padded by two
                       supports) with every particle or node coloured by
                       log10(det_self / threshold), grey where det_self <= threshold (no
                       other face of the body covers it), and the deformed boundary; bottom,
                       det_self at the boundary particles of the contact zone (each stretch
                       of a boundary loop above the threshold, with a support's worth of
                       particles either side) against position, with the threshold.

Default snapshots: from the first meeting of the faces (the first snapshot in which the run
with self-contact has a particle above its det_self threshold or the control overlaps
itself) to the end, at least 3 (earlier ones added) and at most 4 (the first meeting, the
last and evenly between). The two files should come from decks that differ only in the
self-contact group: snapshots are matched by label. The body (--body) defaults to the body of
the self-contact pair, the one with det_self in its snapshots.

Exit status: 0 when both figures were written, 1 when the files lack what is needed (no
self-contact body, no common snapshots), 2 for bad arguments.
File layout: doc/output.md; reader: post/mfcd_h5.py; overlap: post/self_overlap.py.
"""

from __future__ import annotations

import argparse
import logging
import math
import os
import sys
import textwrap
import traceback

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch, Polygon  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import negative_values, MfcdFile  # noqa: E402
from self_overlap import overlap  # noqa: E402

PROG = "plot_self_contact"
SC = 1e3                      # lengths in mm
C_OTHER_FACE = "0.88"         # other bodies: fill
C_OTHER_EDGE = "0.35"         # other bodies: outline
C_NEUTRAL = "0.80"            # det_self <= threshold
C_OVERLAP = (0.85, 0.0, 0.0)  # doubly covered material
CMAP_EPS = "YlGnBu"           # no red in it: the overlap stays unmistakable
CMAP_DET = "plasma"


class Fail(Exception):
    """A reason to stop with exit status 1 (the message says why)."""


def fmt_us(t: float) -> str:
    return f"{t * 1e6:.1f}".rstrip("0").rstrip(".")


# ------------------------------------------------------------------------------- reading
class Run:
    """One run of the pair: the file, the body, its snapshots (cached) and overlaps."""

    def __init__(self, f: MfcdFile, body: str, step: float):
        self.f = f
        self.body = f.body(body)
        self.step = step
        self.labels = f.snapshot_labels()
        self._snap = {}
        self._ovl = {}
        self.others = [n for n in f.body_names() if n != body]

    def snap(self, lab):
        if lab not in self._snap:
            self._snap[lab] = self.f.snapshot(lab)
        return self._snap[lab]

    def sbody(self, lab):
        return self.snap(lab).bodies[self.body.name]

    def outline(self, lab):
        return self.body.polylines(x=self.sbody(lab).x)

    def overlap(self, lab):
        """(area [m^2], depth [m], cell centres (k, 2)) of the body at snapshot lab."""
        if lab not in self._ovl:
            self._ovl[lab] = overlap(self.outline(lab), self.step)
        return self._ovl[lab]

    def covered(self, lab) -> int:
        """Particles with det_self above the threshold (0 when the run has no det_self)."""
        b = self.sbody(lab)
        if b.det_self is None:
            return 0
        return int(np.sum(b.det_self > b.det_self_threshold))

    def other_outlines(self, lab):
        """Closed outlines (k, 2) of the other bodies: deformed when the snapshot has them,
        else (rigid bodies) at their reference position."""
        out = []
        s = self.snap(lab)
        for n in self.others:
            b = self.f.body(n)
            x = s.bodies[n].x if n in s.bodies else None
            out += [p[:, :2] for p in b.polylines(x=x)]
        return out


def pick_body(fw: MfcdFile, fo: MfcdFile, name: str | None) -> str:
    selfb = fw.self_contact_bodies()
    if name is None:
        if not selfb:
            raise Fail(f"{fw.path} has no self-contact body (no det_self in its snapshots: "
                       "no &contact with master = slave); is it the run *with* self-contact?")
        if len(selfb) > 1:
            print(f"{PROG}: self-contact bodies {', '.join(selfb)}: drawing {selfb[0]} "
                  "(--body to choose)")
        name = selfb[0]
    for f in (fw, fo):
        if name not in f.body_names():
            raise Fail(f"no body {name!r} in {f.path} (bodies: {', '.join(f.body_names())})")
        labs = f.snapshot_labels()
        if not labs or name not in f.snapshot_body_names(labs[0]):
            raise Fail(f"body {name!r} is not in the snapshots of {f.path} (a rigid body?)")
    if name not in selfb:
        raise Fail(f"body {name!r} of {fw.path} has no det_self: it is not in self-contact")
    return name


def default_labels(rw: Run, ro: Run, common: list) -> tuple:
    """(labels, first meeting label or None): see the module docstring."""
    meet = None
    for lab in common:
        if rw.covered(lab) > 0 or ro.overlap(lab)[0] > 0:
            meet = lab
            break
    if meet is None:
        print(f"{PROG}: note: the faces never meet in the snapshots (no det_self above the "
              "threshold, no overlap in the control); drawing the last ones")
        i0 = len(common) - 1
    else:
        i0 = common.index(meet)
    sel = common[i0:]
    while len(sel) < 3 and i0 > 0:
        i0 -= 1
        sel = common[i0:]
    if len(sel) > 4:
        idx = np.unique(np.linspace(0, len(sel) - 1, 4).round().astype(int))
        sel = [sel[i] for i in idx]
    return sel, meet


# ------------------------------------------------------------------------------- drawing
def marker_sizes(fig, ax, colls):
    """Set scatter marker sizes to diameters given in data units (mm), once the layout is
    final: colls is [(collection, diameters (n,) in mm)]."""
    fig.canvas.draw()
    bb = ax.get_window_extent()
    x0, x1 = ax.get_xlim()
    ppu = bb.width * 72.0 / fig.dpi / abs(x1 - x0)   # points per mm
    for c, d in colls:
        dp = np.maximum(np.asarray(d) * ppu, 0.8)
        c.set_sizes(dp * dp)


def draw_others(ax, outlines):
    for p in outlines:
        ax.add_patch(Polygon(p * SC, closed=True, facecolor=C_OTHER_FACE,
                             edgecolor=C_OTHER_EDGE, lw=0.9, zorder=1))


def draw_overlap(ax, cells: np.ndarray, step: float):
    """The doubly covered raster cells as a red image (exact cells, no smoothing)."""
    if cells.shape[0] == 0:
        return
    c0 = cells.min(axis=0)
    ij = np.rint((cells - c0) / step).astype(int)
    img = np.zeros((ij[:, 1].max() + 1, ij[:, 0].max() + 1, 4))
    img[ij[:, 1], ij[:, 0]] = (*C_OVERLAP, 0.9)
    lo = (c0 - 0.5 * step) * SC
    hi = lo + np.array([img.shape[1], img.shape[0]]) * step * SC
    ax.imshow(img, extent=(lo[0], hi[0], lo[1], hi[1]), origin="lower",
              interpolation="nearest", zorder=4)


def small_overlaps(cells: np.ndarray, cluster: float, size: float) -> np.ndarray:
    """Centres (k, 2) of the patches of overlap cells (grouped on a grid of step cluster)
    that span less than size: too small to see at the figure's scale, so they are circled."""
    if cells.shape[0] == 0:
        return np.zeros((0, 2))
    key = np.floor(cells / cluster).astype(int)
    _, inv = np.unique(key, axis=0, return_inverse=True)
    out = []
    for k in range(inv.max() + 1):
        c = cells[inv.ravel() == k]
        m = c.mean(axis=0)
        # one circle for a patch that straddles a grid line
        if np.ptp(c, axis=0).max() < size and \
                all(np.hypot(*(m - o)) > cluster for o in out):
            out.append(m)
    return np.array(out).reshape(-1, 2)


def field_of(run: Run, lab):
    """(values, per_cell) of epsbar: element values for a finite-element body."""
    b = run.sbody(lab)
    if run.body.is_fem and b.epsbar_cells is not None:
        return b.epsbar_cells, True
    return b.epsbar, False


def colour_scale(values: list, vmax_user):
    allv = np.concatenate([v[np.isfinite(v)] for v in values])
    vmax = float(allv.max()) if allv.size else 1e-3
    if vmax_user is not None:
        vmax = vmax_user
    else:
        p999 = float(np.percentile(allv, 99.9)) if allv.size else 0.0
        if p999 > 0 and vmax > 1.5 * p999:        # a few outliers would wash the field out
            mag = 10.0 ** np.floor(np.log10(p999))
            vmax = float(np.ceil(p999 / mag * 10) * mag / 10)
            print(f"{PROG}: note: the largest epsbar ({allv.max():.3g}) is far above the "
                  f"99.9th percentile ({p999:.3g}); the colour scale ends at {vmax:.3g}")
    if vmax <= 0:
        vmax = 1e-3
    extend = "max" if allv.size and allv.max() > vmax * (1 + 1e-12) else "neither"
    return Normalize(0.0, vmax), extend


def spacing_of(body) -> float:
    sp = np.atleast_1d(body.attrs.get("spacing", [0.0]))[:2]
    s = float(np.min(sp)) if sp.size else 0.0
    return s if s > 0 else float(np.median(body.support[:, :2])) / 2.0


def draw_shapes(rw: Run, ro: Run, labels: list, vmax_user, out: str, name: str,
                fmt: str) -> str:
    axisym = rw.f.geometry == "axisymmetric"
    xl, yl = ("r", "z") if axisym else ("x", "y")
    body = rw.body
    h = spacing_of(body)
    runs = [rw, ro]

    vals = [field_of(r, lab)[0] for r in runs for lab in labels if field_of(r, lab)[0] is not None]
    if not vals:
        raise Fail(f"body {body.name!r} has no epsbar in the snapshots")
    norm, extend = colour_scale(vals, vmax_user)
    cmap = plt.get_cmap(CMAP_EPS)

    # one window for every panel: the body in all drawn snapshots of both runs, padded
    allx = np.concatenate([r.sbody(lab).x for r in runs for lab in labels])
    lo, hi = allx.min(axis=0), allx.max(axis=0)
    pad = np.maximum(0.04 * (hi - lo), 1.5 * float(body.support.max()))
    lo, hi = lo - pad, hi + pad
    ext = (hi - lo) * SC

    n = len(labels)
    pw = 6.5 if ext[0] > 2.5 * ext[1] else 5.2          # long flat bodies get wider panels
    ph = float(np.clip(pw * ext[1] / ext[0], 0.8, 6.5))
    fig, axes = plt.subplots(n, 2, figsize=(2 * pw + 1.7, n * (ph + 0.62) + 1.1),
                             sharex=True, sharey=True, squeeze=False, layout="constrained")
    colls = []
    circled = False
    for i, lab in enumerate(labels):
        for j, r in enumerate(runs):
            ax = axes[i, j]
            b = r.sbody(lab)
            v, per_cell = field_of(r, lab)
            draw_others(ax, r.other_outlines(lab))
            if per_cell:
                tr = Triangulation(b.x[:, 0] * SC, b.x[:, 1] * SC, triangles=body.triangles)
                ax.tripcolor(tr, facecolors=v, cmap=cmap, norm=norm, shading="flat",
                             edgecolors="face", linewidth=0.2, rasterized=True, zorder=2)
            else:
                d = h * SC * np.sqrt(np.clip(b.J if b.J is not None else 1.0, 0.05, 20.0))
                c = ax.scatter(b.x[:, 0] * SC, b.x[:, 1] * SC, c=v, cmap=cmap, norm=norm,
                               marker="s", s=4, linewidths=0, rasterized=True, zorder=2)
                colls.append((c, np.broadcast_to(d, (b.np,)) * 1.05))
            area, depth, cells = r.overlap(lab)
            draw_overlap(ax, cells, r.step)
            small = small_overlaps(cells, 4.0 * float(body.support.max()), 0.03 * ext[0] / SC)
            if small.size and j == 0:      # leftover interpenetration with self-contact
                ax.scatter(small[:, 0] * SC, small[:, 1] * SC, s=200, facecolors="none",
                           edgecolors=C_OVERLAP, linewidths=1.4, zorder=6)
                circled = True
            for p in r.outline(lab):
                ax.plot(p[:, 0] * SC, p[:, 1] * SC, color="k", lw=0.9, zorder=5)
            ax.set_xlim(lo[0] * SC, hi[0] * SC)
            ax.set_ylim(lo[1] * SC, hi[1] * SC)
            ax.set_aspect("equal")
            t = r.snap(lab).time
            ov = (f"overlap depth {depth * SC:.3g} mm, area {area * SC * SC:.3g} mm\u00b2"
                  if area > 0 else "no overlap")
            head = "with self-contact" if j == 0 else "without (control)"
            ax.set_title(f"{head}, t = {fmt_us(t)} \u00b5s\n{ov}",
                         color="firebrick" if (j == 0 and area > 0) else "black")
            if i == n - 1:
                ax.set_xlabel(f"{xl} [mm]")
            if j == 0:
                ax.set_ylabel(f"{yl} [mm]")
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes.ravel().tolist(),
                      shrink=min(0.9, 0.35 + 0.15 * n), aspect=30, extend=extend)
    cb.set_label("effective plastic strain [-]"
                 + (" (per element)" if body.is_fem else " (per particle)"))
    handles = [Line2D([], [], color="k", lw=0.9, label=f"boundary of '{body.name}'"),
               Patch(facecolor=C_OVERLAP, label="material covered twice (self-overlap)")]
    if circled:
        handles.append(Line2D([], [], ls="none", marker="o", ms=10, mfc="none",
                              mec=C_OVERLAP, mew=1.4, label="a small overlap, circled"))
    if rw.others:
        handles.append(Patch(facecolor=C_OTHER_FACE, edgecolor=C_OTHER_EDGE,
                             label="other bodies: " + ", ".join(rw.others)))
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), frameon=False)
    base = (rw.f.title or name).split(":")[0]
    fig.suptitle(f"{base}: with self-contact (left) and without (right)")
    if colls:
        marker_sizes(fig, axes[0, 0], colls)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, f"{name}_shapes.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    return path


def loop_runs(mask: np.ndarray) -> list:
    """Maximal stretches of True in a cyclic boolean array: [(start, length)]."""
    n = mask.size
    if mask.all():
        return [(0, n)]
    if not mask.any():
        return []
    s = int(np.argmin(mask))                 # a False entry: start scanning after it
    runs, k = [], 0
    while k < n:
        i = (s + k) % n
        if mask[i]:
            L = 0
            while k < n and mask[(s + k) % n]:
                L += 1
                k += 1
            runs.append((i, L))
        else:
            k += 1
    return runs


def draw_det(rw: Run, lab: str, out: str, name: str, fmt: str) -> str:
    axisym = rw.f.geometry == "axisymmetric"
    xl, yl = ("r", "z") if axisym else ("x", "y")
    body = rw.body
    s = rw.snap(lab)
    b = rw.sbody(lab)
    det, thr = b.det_self, float(b.det_self_threshold)
    cov = det > thr
    if not cov.any():
        raise Fail(f"snapshot {lab}: no particle of {body.name!r} has det_self above the "
                   f"threshold {thr:.3g}")
    supp = float(body.support.max())
    h = spacing_of(body)
    lo = b.x[cov].min(axis=0) - 2.0 * supp
    hi = b.x[cov].max(axis=0) + 2.0 * supp
    ext = (hi - lo) * SC
    wide = ext[0] >= ext[1]                  # the line plot runs along the longer side
    ratio = np.log10(np.where(cov, det, thr) / thr)
    rmax = max(float(ratio.max()), 0.5)
    cmap = plt.get_cmap(CMAP_DET)
    norm = Normalize(0.0, math.ceil(rmax * 2) / 2)

    if wide:
        mw = 11.0
        mh = float(np.clip(mw * ext[1] / ext[0], 2.0, 7.0))
        fig, (axm, axl) = plt.subplots(2, 1, figsize=(mw + 1.8, mh + 4.4), sharex=True,
                                       layout="constrained",
                                       gridspec_kw={"height_ratios": [mh, 3.2]})
    else:
        mh = 8.0
        mw = float(np.clip(mh * ext[0] / ext[1], 1.4, 7.0))
        fig, (axm, axl) = plt.subplots(1, 2, figsize=(mw + 6.0, mh + 1.4), sharey=True,
                                       layout="constrained",
                                       gridspec_kw={"width_ratios": [mw, 4.0]})

    # --- the map
    draw_others(axm, rw.other_outlines(lab))
    inw = np.all((b.x >= lo - supp) & (b.x <= hi + supp), axis=1)
    if body.is_fem:
        tr = Triangulation(b.x[:, 0] * SC, b.x[:, 1] * SC, triangles=body.triangles)
        axm.triplot(tr, color="0.55", lw=0.3, zorder=2)
    unc = inw & ~cov
    c0 = axm.scatter(b.x[unc, 0] * SC, b.x[unc, 1] * SC, s=9, c=C_NEUTRAL, marker="o",
                     edgecolors="0.5", linewidths=0.3, zorder=3)
    order = np.nonzero(cov)[0][np.argsort(ratio[cov])]
    c1 = axm.scatter(b.x[order, 0] * SC, b.x[order, 1] * SC, s=16, c=ratio[order], cmap=cmap,
                     norm=norm, marker="o", edgecolors="k", linewidths=0.3, zorder=4)
    for p in rw.outline(lab):
        axm.plot(p[:, 0] * SC, p[:, 1] * SC, color="k", lw=1.0, zorder=3)
    axm.set_xlim(lo[0] * SC, hi[0] * SC)
    axm.set_ylim(lo[1] * SC, hi[1] * SC)
    # the map fills its axes (more of the other direction shows), so that its axis lines up
    # with the line plot's
    axm.set_aspect("equal", adjustable="datalim")
    # (it logs that the fixed y limits give way: that is the intent)
    logging.getLogger("matplotlib.axes._base").setLevel(logging.ERROR)
    axm.set_ylabel(f"{yl} [mm]")
    if not wide:
        axm.set_xlabel(f"{xl} [mm]")
    what = "nodes" if body.is_fem else "particles"
    # the colour bar above the map (wide) or below both panels (tall), never beside one
    # panel only, which would shift the shared axis
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap),
                      ax=axm if wide else [axm, axl], location="top" if wide else "bottom",
                      shrink=0.6, aspect=40, pad=0.02,
                      extend="max" if ratio.max() > norm.vmax else "neither")
    cb.set_label(f"log10(det_self / threshold) at the {int(cov.sum())} of {b.np} {what} "
                 "above the threshold;\ngrey: det_self \u2264 threshold (no other face of the "
                 "body covers the point)")
    d = 0.45 * h * SC
    marker_sizes(fig, axm, [(c0, np.full(int(unc.sum()), 0.7 * d)),
                            (c1, np.full(order.size, d))])

    # --- det_self along the boundary particles of the contact zone
    floor = thr * 1e-4
    m = int(math.ceil(supp / max(h, 1e-300))) + 1
    lines = []                               # (median across, positions, values, count)
    for idx in body.loops:
        n = idx.size
        for start, L in loop_runs(cov[idx]):
            take = [(start + k) % n for k in range(-m, L + m)] if L < n - 2 * m else \
                [(start + k) % n for k in range(n + 1)]
            p = idx[take]
            core = idx[[(start + k) % n for k in range(L)]]
            across = body.x[core, 1 if wide else 0] * SC      # reference, mm
            lines.append((float(np.median(across)), float(across.min()),
                          float(across.max()), b.x[p, 0 if wide else 1] * SC, det[p], L))
    # faces in the order of their reference position across the zone (top first)
    lines.sort(key=lambda t: -t[0] if wide else t[0])
    if len(lines) == 2:
        names = ["upper face", "lower face"] if wide else ["left face", "right face"]
    else:
        names = [f"face {k + 1}" for k in range(len(lines))]
    styles = [("-", "o", None), ("--", "s", "none"), (":", "^", None), ("-.", "D", "none")]
    colours = plt.get_cmap("tab10")
    for k, ((med, amin, amax, pos, dv, L), nm) in enumerate(zip(lines, names)):
        ls, mk, mfc = styles[k % len(styles)]
        col = colours(k % 10)
        val = np.maximum(dv, floor)
        below = dv <= floor
        c = yl if wide else xl
        where = (f"{c} = {med:.1f} mm" if amax - amin < 0.1 else
                 f"{c} = {amin:.1f} to {amax:.1f} mm")
        lab_line = f"{nm} ({where} before the deformation): {L} above the threshold"
        xy = (pos, val) if wide else (val, pos)
        axl.plot(*xy, ls=ls, color=col, lw=1.3, label=lab_line)
        xy = (pos[~below], val[~below]) if wide else (val[~below], pos[~below])
        axl.plot(*xy, ls="none", marker=mk, color=col, ms=4.5 if mfc else 3.5, mfc=mfc)
        xy = (pos[below], val[below]) if wide else (val[below], pos[below])
        axl.plot(*xy, ls="none", marker="v" if wide else "<", mfc="none", color=col, ms=5)
    top = float(det.max()) * 5.0
    if wide:
        axl.set_yscale("log")
        axl.set_ylim(floor / 2, top)
        axl.axhspan(floor / 2, thr, color=C_NEUTRAL, alpha=0.35, lw=0)
        axl.axhline(thr, color="k", ls="--", lw=1.0, label=f"threshold {thr:.3g}")
        axl.set_xlabel(f"{xl} [mm]")
        axl.set_ylabel("det_self [-]")
    else:
        axl.set_xscale("log")
        axl.set_xlim(floor / 2, top)
        axl.axvspan(floor / 2, thr, color=C_NEUTRAL, alpha=0.35, lw=0)
        axl.axvline(thr, color="k", ls="--", lw=1.0, label=f"threshold {thr:.3g}")
        axl.set_ylabel(f"{yl} [mm]")
        axl.set_xlabel("det_self [-]")
    axl.grid(alpha=0.3, which="major")
    axl.legend(loc="lower center", fontsize=8, frameon=True, framealpha=0.85)
    axl.set_title("det_self at the boundary particles of the contact zone "
                  f"(open markers: below {floor:.0e}, drawn there)")
    base = (rw.f.title or name).split(":")[0]
    sub = ("det_self: det(M) at each point from the particles that are not its reference "
           "neighbours, above the threshold where another face of the body covers it")
    width = max(int(fig.get_figwidth() * 72 / 8.0), 40)       # ~8 pt per character
    fig.suptitle(f"{base}: det_self at t = {fmt_us(s.time)} \u00b5s, run with "
                 f"self-contact\n" + textwrap.fill(sub, width))
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, f"{name}_det_self.{fmt}")
    fig.savefig(path)
    plt.close(fig)
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("with_file", help="HDF5 output of the run with self-contact")
    ap.add_argument("without_file", help="HDF5 output of the control run without it")
    ap.add_argument("--out", default=None, help="output directory (default: the first file's)")
    ap.add_argument("--name", default=None,
                    help="figure name prefix (default: the first file's stem)")
    ap.add_argument("--body", default=None,
                    help="the body (default: the body of the self-contact pair)")
    ap.add_argument("--snapshots", default=None,
                    help="comma-separated labels for the shapes, e.g. 0004,0005,0006 "
                         "(default: from the first meeting of the faces to the end, 3-4)")
    ap.add_argument("--det-snapshot", default=None,
                    help="label for the det_self figure (default: the last snapshot of the "
                         "run with self-contact with det_self above the threshold)")
    ap.add_argument("--vmax", type=float, default=None,
                    help="upper end of the effective plastic strain colour scale")
    ap.add_argument("--step-fraction", type=float, default=0.05,
                    help="overlap raster step as a fraction of the body's spacing "
                         "(default 0.05, as post/self_overlap.py)")
    ap.add_argument("--format", default="png", help="image format (default png)")
    a = ap.parse_args(negative_values(argv))
    plt.rcParams.update(figure_style(savefig_dpi=130))
    out = a.out or os.path.dirname(os.path.abspath(a.with_file))
    name = a.name or os.path.splitext(os.path.basename(a.with_file))[0]
    try:
        with MfcdFile(a.with_file) as fw, MfcdFile(a.without_file) as fo:
            body = pick_body(fw, fo, a.body)
            step = a.step_fraction * spacing_of(fw.body(body))
            rw, ro = Run(fw, body, step), Run(fo, body, step)
            common = [lab for lab in rw.labels if lab in ro.labels]
            if not common:
                raise Fail(f"{a.with_file} and {a.without_file} have no snapshot label in "
                           "common")
            for lab in common:
                tw, to = rw.snap(lab).time, ro.snap(lab).time
                if abs(tw - to) > 1e-3 * max(abs(tw), 1e-12):
                    print(f"{PROG}: note: snapshot {lab} is at t = {fmt_us(tw)} us with "
                          f"self-contact and {fmt_us(to)} us without")
            if a.snapshots:
                req = [w.strip() for w in a.snapshots.split(",") if w.strip()]
                req = [w.zfill(4) if w.isdigit() else w for w in req]
                bad = [w for w in req if w not in common]
                if bad:
                    raise Fail(f"no snapshot {', '.join(bad)} in both files (common: "
                               f"{', '.join(common)})")
                labels = req
            else:
                labels, meet = default_labels(rw, ro, common)
                if meet:
                    print(f"{PROG}: the faces first meet in snapshot {meet} "
                          f"(t = {fmt_us(rw.snap(meet).time)} us)")
            print(f"{PROG}: body {body!r}, snapshots {', '.join(labels)}; overlap raster "
                  f"step {step * SC:.4g} mm")
            print(f"{PROG}: label  t [us]   with: covered, overlap area [mm^2], depth [mm]"
                  "   without: overlap area [mm^2], depth [mm]")
            for lab in labels:
                aw, dw, _ = rw.overlap(lab)
                ao, do, _ = ro.overlap(lab)
                print(f"{PROG}: {lab:6s} {rw.snap(lab).time * 1e6:7.1f}   {rw.covered(lab):5d} "
                      f"{aw * 1e6:10.4g} {dw * 1e3:10.4g}      {ao * 1e6:10.4g} {do * 1e3:10.4g}")
            print(f"{PROG}: wrote {draw_shapes(rw, ro, labels, a.vmax, out, name, a.format)}")
            if a.det_snapshot:
                dl = a.det_snapshot.zfill(4) if a.det_snapshot.isdigit() else a.det_snapshot
                if dl not in rw.labels:
                    raise Fail(f"no snapshot {dl} in {a.with_file}")
            else:
                met = [lab for lab in rw.labels if rw.covered(lab) > 0]
                if not met:
                    raise Fail(f"no snapshot of {a.with_file} has det_self above the threshold "
                               "(the faces never meet): no det_self figure")
                dl = met[-1]
            print(f"{PROG}: wrote {draw_det(rw, dl, out, name, a.format)}")
    except Fail as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    except (OSError, ValueError, KeyError) as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 1
    except Exception:  # noqa: BLE001
        traceback.print_exc()
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
