#!/usr/bin/env python3
"""Self-contact of a 3D body (&contact master = slave) beside its control run without it:
the deformed body seen along z and its mid-thickness section, with the material the control
is left covering twice (the 3D form of post/plot_self_contact.py).

    python post/plot_self_contact_3d.py output/c_shape_fold_3d.h5
        output/c_shape_fold_3d_free.h5 --out doc/figures [--body c]
        [--name c_shape_fold_3d] [--snapshots 0003,0004,0005] [--vmax 0.5]
        [--step-fraction 0.25] [--format png]

Figures (in --out, default: the directory of the first file; <name> defaults to the first
file's stem):
  <name>_shapes.png   rows: snapshots; left column the run with self-contact, right the
                      control without it, on the same axes. The body's deformed closed
                      boundary surface (its facets) seen along z, the nearer facets over the
                      farther ones, each coloured by effective plastic strain (the mean of
                      its three vertices' for an RKPM body, its tetrahedron's for a finite-
                      element body; one colour scale for all panels), the body's edges (the
                      facet edges where the reference surface folds by more than 30 degrees)
                      in black, other bodies as grey silhouettes; in red the x-y projection of
                      the material covered twice: the raster points where the winding number
                      of the deformed facet surface is 2 or more (post/self_overlap.py,
                      overlap_3d(); at any z). Each panel title gives the overlap depth and
                      volume at that time; the run with self-contact is shaded too where it
                      has any, and a patch too small to see at the figure's scale is circled
                      (its title turns red).
  <name>_section.png  the same for the mid-thickness section: the particles (nodes) whose
                      reference z is within half a spacing of the middle of the body's
                      reference z range, at their deformed x-y positions, coloured by their
                      effective plastic strain (a finite-element body: its node values, else
                      the mean of its tetrahedra's), the cut of the deformed facet surface by
                      the plane z = z_mid in black, and in red the doubly covered raster
                      points within half a spacing of that plane. The titles give the whole
                      body's overlap and, where it has any, the mean overlap area of the
                      raster planes in that slab.

Default snapshots: from the first meeting of the faces (the first snapshot in which the run
with self-contact has a particle above its det_self threshold or the control overlaps
itself) to the end, 3 of them (earlier ones added when fewer remain; the first meeting, the
last and the one closest to midway when more). The two files should come from decks that
differ only in the self-contact group: snapshots are matched by label. The body (--body)
defaults to the body of the self-contact pair, the one with det_self in its snapshots. The
overlap raster step is a quarter of the spacing (the measure of
tests/regression/check_self_contact.py); it costs up to a minute per snapshot of a control
that has passed deep through itself.

Exit status: 0 when both figures were written, 1 when the files lack what is needed (not 3D,
no facets, no self-contact body, no common snapshots, no effective plastic strain), 2 for
bad arguments. 2D runs: post/plot_self_contact.py.
File layout: doc/output.md; reader: post/mfcd_h5.py; overlap: post/self_overlap.py.
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
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.colors import Normalize  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import negative_values, MfcdFile  # noqa: E402
from self_overlap import default_step_fraction, facet_cells, overlap_3d  # noqa: E402
import plot_self_contact as plane  # noqa: E402  (the plane script's helpers)
from plot_self_contact import (Fail, colour_scale, fmt_us, marker_sizes,  # noqa: E402
                               small_overlaps, spacing_of)

PROG = "plot_self_contact_3d"
SC = 1e3                      # lengths in mm
C_OTHER_FACE = "0.88"         # other bodies: fill
C_OTHER_EDGE = "0.35"         # other bodies: outline
C_OVERLAP = (0.85, 0.0, 0.0)  # doubly covered material
CMAP_EPS = "YlGnBu"           # no red in it: the overlap stays unmistakable
FEATURE_DEG = 30.0            # a reference facet edge folding more than this is drawn
NROWS = 3                     # snapshots drawn by default


def facet_normals(x: np.ndarray, facets: np.ndarray) -> np.ndarray:
    """Unit normals (nf, 3) of the facets (counter-clockwise from outside: outward)."""
    n = np.cross(x[facets[:, 1]] - x[facets[:, 0]], x[facets[:, 2]] - x[facets[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]


def feature_edges(x: np.ndarray, facets: np.ndarray, deg: float = FEATURE_DEG) -> np.ndarray:
    """Vertex pairs (k, 2) of the facet edges where the surface at x folds by more than deg
    degrees (and the edges with one facet only: the surface is open there)."""
    nf = facets.shape[0]
    e = np.concatenate([facets[:, [0, 1]], facets[:, [1, 2]], facets[:, [2, 0]]])
    owner = np.tile(np.arange(nf), 3)
    e = np.sort(e, axis=1)
    key = e[:, 0].astype(np.int64) * (int(x.shape[0]) + 1) + e[:, 1]
    order = np.argsort(key, kind="stable")
    key, e, owner = key[order], e[order], owner[order]
    first = np.ones(key.size, dtype=bool)
    first[1:] = key[1:] != key[:-1]
    start = np.nonzero(first)[0]
    count = np.diff(np.append(start, key.size))
    nrm = facet_normals(x, facets)
    cos = np.cos(np.radians(deg))
    out = []
    two = count == 2
    if two.any():
        s = start[two]
        c = np.einsum("ij,ij->i", nrm[owner[s]], nrm[owner[s + 1]])
        out.append(e[s[c < cos]])
    if (count == 1).any():
        out.append(e[start[count == 1]])
    return np.concatenate(out) if out else np.zeros((0, 2), dtype=int)


def node_means(cells: np.ndarray, values: np.ndarray, nnode: int) -> np.ndarray:
    """The mean of the cell values over the cells each node belongs to (nnode,)."""
    s = np.bincount(cells.ravel(), weights=np.repeat(values, cells.shape[1]),
                    minlength=nnode)
    c = np.bincount(cells.ravel(), minlength=nnode)
    return np.where(c > 0, s / np.maximum(c, 1), np.nan)


def plane_cut(x: np.ndarray, facets: np.ndarray, z: float) -> np.ndarray:
    """Segments (k, 2, 2) in x-y where the plane at height z cuts the facets (a vertex on
    the plane counts as above it)."""
    d = x[facets, 2] - z                           # (nf, 3)
    above = d >= 0.0
    segs = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        cross = above[:, a] != above[:, b]
        da, db = d[:, a], d[:, b]
        t = np.where(cross, da / np.where(cross, da - db, 1.0), 0.0)
        pa, pb = x[facets[:, a], :2], x[facets[:, b], :2]
        segs.append((cross, pa + t[:, None] * (pb - pa)))
    # a facet the plane crosses has two crossing edges: join their points
    cnt = sum(s[0].astype(int) for s in segs)
    out = []
    for f in np.nonzero(cnt == 2)[0]:
        out.append([p[f] for c, p in segs if c[f]])
    return np.array(out).reshape(-1, 2, 2)


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
        g = f.h5["bodies"][body]
        self.tets = np.asarray(g["tetrahedra"][()], dtype=int).reshape(-1, 4) \
            if "tetrahedra" in g else None
        self.facet_tet = None if self.tets is None else \
            facet_cells(self.body.facets, self.tets, self.body.np)

    @property
    def is_fem(self) -> bool:
        return self.tets is not None

    def snap(self, lab):
        if lab not in self._snap:
            self._snap[lab] = self.f.snapshot(lab)
        return self._snap[lab]

    def sbody(self, lab):
        return self.snap(lab).bodies[self.body.name]

    def overlap(self, lab):
        """(volume [m^3], depth [m], raster points (k, 3)) of the body at snapshot lab."""
        if lab not in self._ovl:
            self._ovl[lab] = overlap_3d(self.sbody(lab).x, self.body.facets, self.step)
        return self._ovl[lab]

    def covered(self, lab) -> int:
        """Particles with det_self above the threshold (0 when the run has no det_self)."""
        b = self.sbody(lab)
        if b.det_self is None:
            return 0
        return int(np.sum(b.det_self > b.det_self_threshold))

    def node_field(self, lab):
        """epsbar per particle (node) (np,), None when the snapshot has none: a finite-
        element body's node values, else the mean of its tetrahedra's."""
        b = self.sbody(lab)
        if b.epsbar is not None and b.epsbar.size == self.body.np:
            return b.epsbar
        if self.is_fem and b.epsbar_cells is not None \
                and b.epsbar_cells.size == self.tets.shape[0]:
            return node_means(self.tets, b.epsbar_cells, self.body.np)
        return None

    def facet_field(self, lab):
        """epsbar per facet (nf,), None when the snapshot has none: the facet's tetrahedron's
        value, else the mean of its vertices'."""
        b = self.sbody(lab)
        fac = self.body.facets
        nodal = self.node_field(lab)
        out = None if nodal is None else nodal[fac].mean(axis=1)
        if self.is_fem and b.epsbar_cells is not None \
                and b.epsbar_cells.size == self.tets.shape[0]:
            t = self.facet_tet
            cell = np.where(t >= 0, b.epsbar_cells[np.maximum(t, 0)], np.nan)
            out = cell if out is None else np.where(t >= 0, cell, out)
        return out

    def other_surfaces(self, lab):
        """[(x (n, 3), facets)] of the other bodies that have facets: deformed when the
        snapshot has them, else (rigid bodies) at their reference position."""
        out = []
        s = self.snap(lab)
        for n in self.others:
            b = self.f.body(n)
            if b.facets is None:
                continue
            x = s.bodies[n].x if n in s.bodies else \
                s.rigid[n].x if n in s.rigid else b.x
            out.append((x, b.facets))
        return out


def pick_body(fw: MfcdFile, fo: MfcdFile, name: str | None) -> str:
    """The plane script's choice of the self-contact body, for two 3D runs whose body has
    its facets."""
    for f in (fw, fo):
        if f.ndim != 3:
            raise Fail(f"{f.path} is a {f.ndim}D run: use post/plot_self_contact.py")
    name = plane.pick_body(fw, fo, name)
    for f in (fw, fo):
        if "facets" not in f.h5["bodies"][name]:
            raise Fail(f"body {name!r} of {f.path} has no facets (its closed boundary "
                       "surface; written by mfcd since its 3D self-contact)")
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
    i0 = min(i0, max(len(common) - NROWS, 0))
    sel = common[i0:]
    if len(sel) > NROWS:
        idx = np.unique(np.linspace(0, len(sel) - 1, NROWS).round().astype(int))
        sel = [sel[i] for i in idx]
    return sel, meet


# ------------------------------------------------------------------------------- drawing
def draw_others(ax, surfaces):
    for x, fac in surfaces:
        ax.add_collection(PolyCollection(x[fac][:, :, :2] * SC, facecolors=C_OTHER_FACE,
                                         edgecolors=C_OTHER_FACE, linewidths=0.3,
                                         rasterized=True, zorder=1))
        e = feature_edges(x, fac)
        ax.add_collection(LineCollection(x[e][:, :, :2] * SC, colors=C_OTHER_EDGE, lw=0.8,
                                         zorder=1.5))


def draw_overlap(ax, pts: np.ndarray, step: float):
    """The x-y projection of the doubly covered raster points as a red image of the raster's
    columns (exact cells, no smoothing)."""
    if pts.shape[0] == 0:
        return
    xy = pts[:, :2]
    c0 = xy.min(axis=0)
    ij = np.rint((xy - c0) / step).astype(int)
    img = np.zeros((ij[:, 1].max() + 1, ij[:, 0].max() + 1, 4))
    img[ij[:, 1], ij[:, 0]] = (*C_OVERLAP, 0.9)
    lo = (c0 - 0.5 * step) * SC
    hi = lo + np.array([img.shape[1], img.shape[0]]) * step * SC
    ax.imshow(img, extent=(lo[0], hi[0], lo[1], hi[1]), origin="lower",
              interpolation="nearest", zorder=4)


def section_of(body):
    """(indices of the mid-thickness particles, z_mid [m], half-width [m]): the particles
    whose reference z is within half a spacing of the middle of the reference z range."""
    sp = body.spacing
    hz = float(sp[2]) if sp is not None and sp.size >= 3 and sp[2] > 0 else spacing_of(body)
    z = body.x[:, 2]
    zmid = 0.5 * (float(z.min()) + float(z.max()))
    idx = np.nonzero(np.abs(z - zmid) < 0.5 * hz * (1 + 1e-9))[0]
    return idx, zmid, 0.5 * hz


def panels(rw: Run, ro: Run, labels: list, extra: float = 0.0):
    """(figure, axes (n, 2), x-y window lo, hi [m], extent [mm]) for the labels."""
    runs = [rw, ro]
    allx = np.concatenate([r.sbody(lab).x[:, :2] for r in runs for lab in labels])
    lo, hi = allx.min(axis=0), allx.max(axis=0)
    pad = np.maximum(0.04 * (hi - lo), 1.5 * float(rw.body.support[:, :2].max()))
    lo, hi = lo - pad, hi + pad
    ext = (hi - lo) * SC
    n = len(labels)
    pw = 5.6 if ext[0] > 2.5 * ext[1] else 4.4          # long flat bodies get wider panels
    ph = float(np.clip(pw * ext[1] / ext[0], 0.8, 5.5))
    fig, axes = plt.subplots(n, 2, figsize=(2 * pw + 1.6, n * (ph + 0.62) + 1.1 + extra),
                             sharex=True, sharey=True, squeeze=False, layout="constrained")
    return fig, axes, lo, hi, ext


def title_panel(ax, r: Run, lab, j: int, note: str = ""):
    """Title: the run, the time, the whole body's overlap, and note (a third line) if any."""
    vol, depth, _ = r.overlap(lab)
    t = r.snap(lab).time
    ov = (f"overlap depth {depth * SC:.3g} mm, volume {vol * SC ** 3:.3g} mm\u00b3"
          if vol > 0 else "no overlap")
    head = "with self-contact" if j == 0 else "without (control)"
    ax.set_title(f"{head}, t = {fmt_us(t)} \u00b5s\n{ov}" + (f"\n{note}" if note else ""),
                 color="firebrick" if (j == 0 and vol > 0) else "black")


def finish(fig, axes, rw: Run, norm, cmap, extend, cb_label, handles, title, path,
           circled):
    n = axes.shape[0]
    for i in range(n):
        axes[i, 0].set_ylabel("y [mm]")
    for j in range(2):
        axes[n - 1, j].set_xlabel("x [mm]")
    cb = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes.ravel().tolist(),
                      shrink=min(0.9, 0.35 + 0.15 * n), aspect=30, extend=extend)
    cb.set_label(f"effective plastic strain [-] ({cb_label})")
    if circled:
        handles.append(Line2D([], [], ls="none", marker="o", ms=10, mfc="none",
                              mec=C_OVERLAP, mew=1.4, label="a small overlap, circled"))
    if rw.others:
        handles.append(Patch(facecolor=C_OTHER_FACE, edgecolor=C_OTHER_EDGE,
                             label="other bodies: " + ", ".join(rw.others)))
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 2),
               frameon=False)
    fig.suptitle(title)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return path


def to_palette(path: str):
    """Rewrite the PNG at path with a palette of 256 colours (a third of the bytes, the
    colour scale's steps finer than its colour bar can show); unchanged without Pillow."""
    try:
        from PIL import Image
    except ImportError:
        return
    with Image.open(path) as im:
        q = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT,
                                       dither=Image.Dither.NONE)
    q.save(path, optimize=True)


def circle_small(ax, pts, rw: Run, ext) -> bool:
    small = small_overlaps(pts[:, :2], 4.0 * float(rw.body.support.max()),
                           0.03 * ext[0] / SC)
    if small.size:
        ax.scatter(small[:, 0] * SC, small[:, 1] * SC, s=200, facecolors="none",
                   edgecolors=C_OVERLAP, linewidths=1.4, zorder=6)
        return True
    return False


def base_title(rw: Run, name: str) -> str:
    return (rw.f.title or name).split(":")[0]


def draw_shapes(rw: Run, ro: Run, labels: list, norm, extend, out: str, name: str,
                fmt: str) -> str:
    body = rw.body
    runs = [rw, ro]
    cmap = plt.get_cmap(CMAP_EPS)
    fac = body.facets
    edges = feature_edges(body.x, fac)
    fig, axes, lo, hi, ext = panels(rw, ro, labels)
    circled = False
    for i, lab in enumerate(labels):
        for j, r in enumerate(runs):
            ax = axes[i, j]
            x = r.sbody(lab).x
            draw_others(ax, r.other_surfaces(lab))
            v = r.facet_field(lab)
            order = np.argsort(x[fac, 2].mean(axis=1), kind="stable")   # far (low z) first
            col = cmap(norm(np.nan_to_num(v[order], nan=0.0)))
            ax.add_collection(PolyCollection(x[fac[order]][:, :, :2] * SC, facecolors=col,
                                             edgecolors=col, linewidths=0.25,
                                             rasterized=True, zorder=2))
            ax.add_collection(LineCollection(x[edges][:, :, :2] * SC, colors="k", lw=0.7,
                                             zorder=5))
            _, _, pts = r.overlap(lab)
            draw_overlap(ax, pts, r.step)
            if j == 0 and circle_small(ax, pts, r, ext):   # leftover interpenetration
                circled = True
            ax.set_xlim(lo[0] * SC, hi[0] * SC)
            ax.set_ylim(lo[1] * SC, hi[1] * SC)
            ax.set_aspect("equal")
            title_panel(ax, r, lab, j)
    handles = [Line2D([], [], color="k", lw=0.7,
                      label=f"edges of '{body.name}' (surface seen along z)"),
               Patch(facecolor=C_OVERLAP,
                     label="material covered twice (self-overlap), at any z")]
    cb_label = ("per facet: its tetrahedron's" if rw.is_fem else
                "per facet: the mean of its particles'")
    return finish(fig, axes, rw, norm, cmap, extend, cb_label, handles,
                  f"{base_title(rw, name)}: with self-contact (left) and without (right),\n"
                  "seen along z", os.path.join(out, f"{name}_shapes.{fmt}"), circled)


def draw_section(rw: Run, ro: Run, labels: list, norm, extend, out: str, name: str,
                 fmt: str) -> str:
    body = rw.body
    runs = [rw, ro]
    cmap = plt.get_cmap(CMAP_EPS)
    idx, zmid, half = section_of(body)
    if idx.size == 0:
        raise Fail(f"body {body.name!r} has no particle within half a spacing of its "
                   f"mid-thickness z = {zmid * SC:.3g} mm")
    h = spacing_of(body)
    fig, axes, lo, hi, ext = panels(rw, ro, labels, extra=0.2 * len(labels))
    colls = []
    circled = False
    for i, lab in enumerate(labels):
        for j, r in enumerate(runs):
            ax = axes[i, j]
            b = r.sbody(lab)
            v = r.node_field(lab)[idx]
            jac = b.J[idx] if b.J is not None and b.J.size == body.np else 1.0
            d = h * SC * np.cbrt(np.clip(jac, 0.05, 20.0))
            c = ax.scatter(b.x[idx, 0] * SC, b.x[idx, 1] * SC, c=v, cmap=cmap, norm=norm,
                           marker="s", s=4, linewidths=0, rasterized=True, zorder=2)
            colls.append((c, np.broadcast_to(d, (idx.size,)) * 1.05))
            seg = plane_cut(b.x, body.facets, zmid)
            ax.add_collection(LineCollection(seg * SC, colors="k", lw=0.9, zorder=5))
            vol, _, pts = r.overlap(lab)
            pts = pts[np.abs(pts[:, 2] - zmid) < half]
            draw_overlap(ax, pts, r.step)
            if j == 0 and circle_small(ax, pts, r, ext):
                circled = True
            ax.set_xlim(lo[0] * SC, hi[0] * SC)
            ax.set_ylim(lo[1] * SC, hi[1] * SC)
            ax.set_aspect("equal")
            # the mean overlap area over the slab's raster planes
            area = pts.shape[0] * r.step ** 3 / (2.0 * half)
            note = "" if vol <= 0 else "none at mid-thickness" if area <= 0 else \
                f"at mid-thickness {area * SC * SC:.3g} mm\u00b2"
            title_panel(ax, r, lab, j, note)
    what = "nodes" if rw.is_fem else "particles"
    cb_label = "per node" if rw.is_fem else "per particle"
    handles = [Line2D([], [], color="k", lw=0.9,
                      label=f"the deformed surface cut at z = {zmid * SC:.3g} mm"),
               Patch(facecolor=C_OVERLAP, label="material covered twice (self-overlap), "
                     f"|z - {zmid * SC:.3g} mm| < {half * SC:.3g} mm")]
    if colls:
        marker_sizes(fig, axes[0, 0], colls)
    return finish(fig, axes, rw, norm, cmap, extend, cb_label, handles,
                  f"{base_title(rw, name)}: with self-contact (left) and without (right),\n"
                  f"mid-thickness section ({idx.size} {what} of {body.np})",
                  os.path.join(out, f"{name}_section.{fmt}"), circled)


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
                    help="comma-separated labels, e.g. 0003,0004,0005 (default: from the "
                         f"first meeting of the faces to the end, {NROWS})")
    ap.add_argument("--vmax", type=float, default=None,
                    help="upper end of the effective plastic strain colour scale")
    ap.add_argument("--step-fraction", type=float, default=default_step_fraction(3),
                    help="overlap raster step as a fraction of the body's spacing "
                         f"(default {default_step_fraction(3)}, as post/self_overlap.py)")
    ap.add_argument("--format", default="png", help="image format (default png)")
    ap.add_argument("--full-colour", action="store_true",
                    help="keep the PNGs in full colour (default: a palette of 256 colours, "
                         "a third of the size)")
    a = ap.parse_args(negative_values(argv))
    if not a.step_fraction > 0:
        ap.error("--step-fraction must be positive")
    if a.vmax is not None and not a.vmax > 0:
        ap.error("--vmax must be positive")
    for p in (a.with_file, a.without_file):
        if not os.path.isfile(p):
            ap.error(f"no file {p}")
    if a.format.lower() not in plt.figure().canvas.get_supported_filetypes():
        ap.error(f"--format {a.format}: not an image format matplotlib writes")
    plt.close("all")
    plt.rcParams.update(figure_style(savefig_dpi=100))
    out = a.out or os.path.dirname(os.path.abspath(a.with_file))
    name = a.name or os.path.splitext(os.path.basename(a.with_file))[0]
    for p in (a.with_file, a.without_file):
        try:
            MfcdFile(p).close()
        except (OSError, ValueError) as e:
            print(f"{PROG}: cannot read {p}: {e}", file=sys.stderr)
            return 1
    try:
        with MfcdFile(a.with_file) as fw, MfcdFile(a.without_file) as fo:
            body = pick_body(fw, fo, a.body)
            step = a.step_fraction * spacing_of(fw.body(body))
            rw, ro = Run(fw, body, step), Run(fo, body, step)
            if rw.body.np != ro.body.np or rw.body.facets.shape != ro.body.facets.shape:
                raise Fail(f"body {body!r} differs between the files ({rw.body.np} and "
                           f"{ro.body.np} particles): not a run and its control")
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
            print(f"{PROG}: body {body!r} ({'tetrahedra' if rw.is_fem else 'RKPM'}, "
                  f"{rw.body.np} particles, {rw.body.facets.shape[0]} facets), snapshots "
                  f"{', '.join(labels)}; overlap raster step {step * SC:.4g} mm")
            print(f"{PROG}: label  t [us]   with: covered, overlap volume [mm^3], depth [mm]"
                  "   without: overlap volume [mm^3], depth [mm]")
            for lab in labels:
                vw, dw, _ = rw.overlap(lab)
                vo, do, _ = ro.overlap(lab)
                print(f"{PROG}: {lab:6s} {rw.snap(lab).time * 1e6:7.1f}   {rw.covered(lab):5d} "
                      f"{vw * 1e9:10.4g} {dw * 1e3:10.4g}      {vo * 1e9:10.4g} {do * 1e3:10.4g}")
            runs = [rw, ro]
            fields = [r.facet_field(lab) for r in runs for lab in labels]
            nodal = [r.node_field(lab) for r in runs for lab in labels]
            if any(v is None for v in fields + nodal):
                raise Fail(f"body {body!r} has no epsbar in the snapshots")
            norm, extend = colour_scale(fields + nodal, a.vmax)
            for draw in (draw_shapes, draw_section):
                path = draw(rw, ro, labels, norm, extend, out, name, a.format)
                if a.format.lower() == "png" and not a.full_colour:
                    to_palette(path)
                print(f"{PROG}: wrote {path}")
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
