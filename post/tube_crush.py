#!/usr/bin/env python3
"""The tube crush (issue 24, the paper's Fig. 1 case): a quarter tube of tetrahedra crushed
axially between a rigid floor and a rigid ram, with self-contact, beside its control run
without it. Measures, prints, checks and draws:

- the crush force P against the ram's displacement d: the ram pair's resultant contact
  force on the tube along z (/history/contacts/contact<k>/force_z), times 4 for the whole
  tube; d = |v_ram| t (the ram is rigid and moves at its &body velocity);
- the mean crush force over the stroke, P_m = int P dd / d (the energy the tube took
  over the ram's displacement: the crashworthiness definition), against Abramowicz &
  Jones (1984), "Dynamic axial crushing of circular tubes", Int. J. Impact Eng. 2(3)
  263-281, axisymmetric (concertina) mode, in the form their summary reports agreeing with
  their tests, with the effective crushing distance (coefficients as Jones, Structural
  Impact, 1989, ch. 7, quotes them):
      P_m / M_0 = (25.23 sqrt(D/t) + 15.09) / (0.86 - 0.568 sqrt(t/D)),
      M_0 = (2/sqrt 3) sigma_0 t^2 / 4
  (D the mean diameter, t the wall; von Mises plane strain); printed beside it, their
  form without it, P_m / M_0 = 20.79 sqrt(D/t) + 11.90, and Alexander's (1960) model
  (Q. J. Mech. Appl. Math. 13, 10-15) worked out in doc/self_contact.md: P_m = 2 pi
  sigma_0' t sqrt(pi R t / 2), H = sqrt(pi R t / 2), sigma_0' = 2 sigma_0 / sqrt 3.
  sigma_0, the flow stress, is the run's own plastic-work-weighted mean flow stress:
  sigma_0 = sum V_e int sigma_y deps / sum V_e epsbar_e over the tetrahedra at the end
  (for the linear hardening sigma_y0 + H epsbar: sigma_y0 + H <epsbar^2> / (2 <epsbar>));
  its sum V_e int sigma_y deps is checked against /history/w_plastic;
- the folds: the outer generator of the wall in the symmetry plane y = 0 (its nodes sorted
  by reference z), its radial excursion dr(Z) = r - R_ref; a lobe is an extreme of dr
  (outwards or inwards) more than a wall thickness beyond the extremes either side, its
  arms the generator from it to those (or to the tube's ends); a fold is closed when both
  arms have shortened along z to less than half their length (rotated past 60 degrees
  from the axis: a fold, not a wave); the mode: the generators in y = 0 and in x = 0
  differ by at most 25% of the largest excursion (axisymmetric, the estimates' mode);
- the material left covering itself (post/self_overlap.py's raster and rule, as in
  overlap_3d: the winding number of the deformed facet surface on a raster of a quarter
  of the mesh size; the depth from the deepest cells only, overlap() below), with and
  without self-contact: with it at most a tenth of the control's, at most h/2 deep;
- the energy balance: /summary's residual against its scale and the largest of the
  /history residual; the kinetic energy against the plastic work (inertia).

    python post/tube_crush.py output/tube_crush.h5 output/tube_crush_free.h5
        [--out output/figures] [--name tube_crush] [--min-folds 2] [--force-tol 0.25]
        [--no-force-check] [--overlap-last 3] [--control-folds N] [--energy-tol 1e-2]
    python post/tube_crush.py output/tube_crush_coarse.h5 --control-only --min-folds 1

Exit status 0 when every check holds, 1 when one fails (each printed with FAIL), 2 for bad
arguments. Figures (only with --out): <name>_shapes.png (the deformed surface, a half tube, at four
times), <name>_section.png (the wall in the plane y = 0, with and without self-contact),
<name>_force.png (P against d, the mean and the estimates).
File layout: doc/output.md; reader: post/mfcd_h5.py.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_h5 import MfcdFile, deck_group  # noqa: E402
from self_overlap import (distance_to_facets, facet_cells, raster_axes,  # noqa: E402
                          raster_winding)

SQ3 = np.sqrt(3.0)


class Fail(Exception):
    pass


# ------------------------------------------------------------------------------- reading
class Run:
    """One run: its tube, ram, history and snapshots."""

    def __init__(self, path: str):
        self.path = path
        self.f = MfcdFile(path)
        deck = self.f.deck
        groups = self.f.deck_groups()
        bodies = [v for g, v in groups if g == "body"]
        contacts = [v for g, v in groups if g == "contact"]
        self.tube = next(b["name"] for b in bodies if b.get("role", "deformable")
                         == "deformable")
        rams = [b for b in bodies if b.get("role") == "rigid"
                and np.any(np.asarray(b.get("velocity", [0.0]), dtype=float) != 0.0)]
        if len(rams) != 1:
            raise Fail(f"{path}: one moving rigid body (the ram) expected, {len(rams)} found")
        self.ram = rams[0]["name"]
        self.v_ram = abs(float(np.asarray(rams[0]["velocity"], dtype=float)[2]))
        self.k_ram = 1 + next(k for k, c in enumerate(contacts) if c["master"] == self.ram)
        self.k_floor = 1 + next(k for k, c in enumerate(contacts)
                                if c["master"] not in (self.ram, self.tube))
        self.self_contact = any(c["master"] == c["slave"] == self.tube for c in contacts)
        tb = deck_group(deck, "body", name=self.tube)
        geo = dict(zip([str(n).strip() for n in np.atleast_1d(tb["geo_names"])],
                       np.atleast_1d(tb["geo_values"]).astype(float)))
        self.R, self.t, self.L = geo["R"], geo["t"], geo["L"]
        self.H, self.a, self.h = geo["H"], geo["a"], geo["h"]
        mat = deck_group(deck, "material", name=tb["material"])
        self.sy0 = float(mat["yield_stress"])
        self.Hp = float(mat.get("hardening_modulus", 0.0))
        self.body = self.f.body(self.tube)
        g = self.f.h5["bodies"][self.tube]
        self.tets = np.asarray(g["tetrahedra"][()], dtype=int).reshape(-1, 4)
        X = self.body.x
        e = X[self.tets]
        self.vol = np.abs(np.einsum("ij,ij->i", np.cross(e[:, 1] - e[:, 0],
                                                         e[:, 2] - e[:, 0]),
                                    e[:, 3] - e[:, 0])) / 6.0
        self.hist = self.f.history()
        c = self.f.h5["history"]["contacts"]
        self.fz_ram = np.asarray(c[f"contact{self.k_ram}"]["force_z"][()], dtype=float)
        self.fz_floor = np.asarray(c[f"contact{self.k_floor}"]["force_z"][()], dtype=float)
        self.labels = self.f.snapshot_labels()
        self.summary = self.f.summary
        self._snap = {}

    def snap(self, lab):
        if lab not in self._snap:
            self._snap[lab] = self.f.snapshot(lab)
        return self._snap[lab]

    def x(self, lab):
        return self.snap(lab).bodies[self.tube].x

    def epsbar_cells(self, lab):
        return self.snap(lab).bodies[self.tube].epsbar_cells

    def wall_mid(self, z):
        """The reference mid-surface radius at height z (the trigger bulge, input/tube_crush
        .geo)."""
        s = self.L - z
        w = np.where(s < 2.0 * self.H, self.a * (1.0 - np.cos(np.pi * s / self.H)) / 2.0,
                     0.0)
        return self.R + w


# ----------------------------------------------------------------------------- measures
def crush_curve(r: Run):
    """(d [m], P [N] whole tube, P_floor [N] whole tube, t [s]) on the history rows."""
    t = r.hist["time"]
    return r.v_ram * t, -4.0 * r.fz_ram, 4.0 * r.fz_floor, t


def mean_force(d, P, i0):
    """int P dd / (d[-1] - d[i0]) by the trapezoid rule on the history rows from i0."""
    dd, pp = d[i0:], P[i0:]
    return float(np.sum(0.5 * (pp[1:] + pp[:-1]) * np.diff(dd)) / (dd[-1] - dd[0]))


def flow_stress(r: Run, lab):
    """(sigma_0 [Pa], sum V int sigma_y deps [J, quarter], mean epsbar of the plastic
    material): the plastic-work-weighted flow stress at snapshot lab."""
    e = np.asarray(r.epsbar_cells(lab), dtype=float)
    V = r.vol
    wp = np.sum(V * (r.sy0 * e + 0.5 * r.Hp * e * e))
    se = np.sum(V * e)
    plastic = e > 1e-3
    return wp / se, wp, float(np.sum(V[plastic] * e[plastic]) / np.sum(V[plastic]))


def estimates(r: Run, s0: float):
    """The mean crush force estimates [N] for flow stress s0."""
    D, t, R = 2.0 * r.R, r.t, r.R
    M0 = (2.0 / SQ3) * s0 * t * t / 4.0
    aj = M0 * (20.79 * np.sqrt(D / t) + 11.90)
    aj_eff = M0 * (25.23 * np.sqrt(D / t) + 15.09) / (0.86 - 0.568 * np.sqrt(t / D))
    alex = 2.0 * np.pi * (2.0 * s0 / SQ3) * t * np.sqrt(np.pi * R * t / 2.0)
    return {"AJ": aj, "AJ_eff": aj_eff, "Alexander": alex, "M0": M0}


def generator(r: Run, plane: int = 1):
    """Node indices of the outer generator in the plane y = 0 (plane 1; x = 0: plane 0),
    sorted by reference z."""
    X = r.body.x
    on = np.abs(X[:, plane]) < 1e-9
    outer = np.abs(X[:, 1 - plane] - (r.wall_mid(X[:, 2]) + r.t / 2.0)) < 0.05 * r.t
    idx = np.nonzero(on & outer)[0]
    return idx[np.argsort(X[idx, 2])]


def extrema(dr, prom):
    """Alternating extrema of dr [(index, +1 maximum | -1 minimum)], each standing more
    than prom above (below) the extrema either side (a hysteresis scan)."""
    ext = []
    hi = lo = 0
    kind = 0                       # 0: undecided, +1: looking for a maximum, -1: minimum
    for i in range(1, dr.size):
        if dr[i] > dr[hi]:
            hi = i
        if dr[i] < dr[lo]:
            lo = i
        if kind >= 0 and dr[hi] - dr[i] > prom:
            ext.append((hi, 1))
            kind, lo = -1, i
        elif kind <= 0 and dr[i] - dr[lo] > prom:
            ext.append((lo, -1))
            kind, hi = 1, i
    if kind == 1 and dr[hi] - dr[lo] > prom:
        ext.append((hi, 1))
    elif kind == -1 and dr[hi] - dr[lo] > prom:
        ext.append((lo, -1))
    return ext


def folds(r: Run, lab):
    """The lobes of the outer generator in the plane y = 0 at snapshot lab, [(Z [m], dr [m],
    shortening of the arm below, of the arm above)], and the profile (Z, dr, z). A lobe is
    an extreme of the radial excursion dr(Z) = r - R_ref (outwards or inwards) standing
    more than a wall thickness above (below) its neighbours; its arms run from it to the
    neighbouring extremes (or to the tube's ends), and an arm's shortening is its deformed
    axial length over its reference length."""
    g = generator(r)
    X, x = r.body.x[g], r.x(lab)[g]
    Z = X[:, 2]
    dr = np.hypot(x[:, 0], x[:, 1]) - np.hypot(X[:, 0], X[:, 1])
    z = x[:, 2]
    ext = extrema(dr, r.t)
    bounds = [0] + [i for i, _ in ext] + [dr.size - 1]
    out = []
    for j, (i, k) in enumerate(ext):
        if i in (0, dr.size - 1):
            continue
        a, b = bounds[j], bounds[j + 2]
        lo = abs(z[i] - z[a]) / max(Z[i] - Z[a], 1e-30)
        up = abs(z[b] - z[i]) / max(Z[b] - Z[i], 1e-30)
        out.append((Z[i], dr[i], lo, up))
    return out, (Z, dr, z)


def overlap(x, facets, step):
    """(volume [m^3], depth [m], centres of the doubly covered cells (k, 3)) of the closed
    facet surface at x: post/self_overlap.py's overlap_3d (the same raster, shifted the same
    way, and the same winding number along vertical columns), except for the depth, which
    overlap_3d measures from every covered cell (minutes for the control's thousands of
    cells): here the covered cells are eroded layer by layer (6 neighbours) and only those
    of the last two layers, the deepest within a raster step, are measured exactly (the
    depth is twice their largest distance to the surface)."""
    xs, ys, zs = raster_axes(x, step)
    m = raster_winding(x, facets, xs, ys, zs) >= 2
    ii, jj, kk = np.nonzero(m)
    if ii.size == 0:
        return 0.0, 0.0, np.zeros((0, 3))
    hit = np.column_stack([xs[ii], ys[jj], zs[kk]])
    prev2, prev, cur = m, m, m
    while cur.any():
        nxt = cur.copy()
        nxt[1:] &= cur[:-1]
        nxt[:-1] &= cur[1:]
        nxt[:, 1:] &= cur[:, :-1]
        nxt[:, :-1] &= cur[:, 1:]
        nxt[:, :, 1:] &= cur[:, :, :-1]
        nxt[:, :, :-1] &= cur[:, :, 1:]
        prev2, prev, cur = prev, cur, nxt
    a, b, c = np.nonzero(prev | prev2)
    pts = np.column_stack([xs[a], ys[b], zs[c]])[:2000]
    depth = 2.0 * float(distance_to_facets(x, facets, pts).max())
    return hit.shape[0] * step ** 3, depth, hit


def closed_folds(fl):
    """The lobes whose two arms have both shortened to less than half their length (each
    arm rotated past 60 degrees from the axis: a closed fold, not a wave)."""
    return [f for f in fl if max(f[2], f[3]) < 0.5]


# -------------------------------------------------------------------------------- figures
def draw(rw: Run, ro: Run | None, out: str, name: str, d, P, Pf, i0, Pm, est, ovl,
         what_w="self-contact"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from mfcd_style import figure_style

    plt.rcParams.update(figure_style())
    mm = 1e3
    os.makedirs(out, exist_ok=True)
    paths = []
    # ---- the force curve
    fig, ax = plt.subplots(figsize=(7.0, 4.2))
    ax.plot(d * mm, P / 1e3, color="C0", lw=1.0, label="ram force, self-contact")
    if ro is not None:
        do, Po, _, _ = crush_curve(ro)
        ax.plot(do * mm, Po / 1e3, color="C1", lw=0.8, alpha=0.8,
                label="ram force, no self-contact")
    ax.plot(d * mm, Pf / 1e3, color="0.6", lw=0.6, label="floor force, self-contact")
    ax.hlines(Pm / 1e3, d[i0] * mm, d[-1] * mm, color="C0", lw=2.0, ls="--",
              label=f"mean {Pm / 1e3:.1f} kN")
    for key, c, lab in (("AJ_eff", "k", "Abramowicz & Jones (1984), eff. crushing distance"),
                        ("AJ", "0.5", "A & J without it"),
                        ("Alexander", "C2", "Alexander (1960)")):
        ax.axhline(est[key] / 1e3, color=c, lw=1.0, ls=":",
                   label=f"{lab}: {est[key] / 1e3:.1f} kN")
    ax.set_xlabel("ram displacement [mm]")
    ax.set_ylabel("crush force, whole tube [kN]")
    ax.set_xlim(0, d[-1] * mm)
    ax.set_ylim(0, None)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(f"{name}: crush force (D/t = {2 * rw.R / rw.t:.0f}, ram {rw.v_ram:.0f} m/s)")
    fig.tight_layout()
    p = os.path.join(out, f"{name}_force.png")
    fig.savefig(p)
    plt.close(fig)
    paths.append(p)
    # ---- the deformed surface: a half tube (the quarter and its mirror in x = 0)
    fac = rw.body.facets
    labs = rw.labels
    pick = [labs[int(round(k * (len(labs) - 1) / 3))] for k in range(4)]
    cells = facet_cells(fac, rw.tets, rw.body.np)
    emax = max(float(np.max(rw.epsbar_cells(lab))) for lab in pick)
    norm = Normalize(0.0, min(emax, 1.0))
    cmap = plt.get_cmap("YlGnBu")
    fig = plt.figure(figsize=(12.0, 4.6))
    for j, lab in enumerate(pick):
        ax = fig.add_subplot(1, 4, j + 1, projection="3d")
        x = rw.x(lab) * mm
        col = cmap(norm(np.asarray(rw.epsbar_cells(lab))[np.maximum(cells, 0)]))
        for sx in (1.0, -1.0):
            xx = x * np.array([sx, 1.0, 1.0])
            pc = Poly3DCollection(xx[fac], facecolors=col, edgecolors="none",
                                  linewidths=0.0)
            ax.add_collection3d(pc)
        lim = (rw.R + rw.H) * mm
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_zlim(0, rw.L * mm)
        ax.set_box_aspect((2 * lim, 2 * lim, rw.L * mm), zoom=1.35)
        ax.view_init(elev=12, azim=70)
        ax.set_axis_off()
        dd = rw.v_ram * rw.snap(lab).time * mm
        ax.set_title(f"t = {rw.snap(lab).time * 1e6:.0f} us, d = {dd:.1f} mm")
    sm = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    fig.subplots_adjust(left=0.0, right=0.9, bottom=0.0, top=0.88, wspace=0.0)
    fig.colorbar(sm, ax=fig.axes, shrink=0.6, label="effective plastic strain")
    fig.suptitle(f"{name}: {what_w}, seen from outside (the quarter and its mirror "
                 "in x = 0)")
    p = os.path.join(out, f"{name}_shapes.png")
    fig.savefig(p)
    plt.close(fig)
    paths.append(p)
    # ---- the section y = 0: the facets of the symmetry face, at the end
    runs = [(rw, what_w)] + ([(ro, "no self-contact")] if ro is not None else [])
    fig, axes = plt.subplots(1, len(runs), figsize=(4.2 * len(runs), 5.2), squeeze=False)
    from matplotlib.collections import PolyCollection

    for ax, (r, what) in zip(axes[0], runs):
        lab = r.labels[-1]
        fac = r.body.facets
        X = r.body.x
        face = fac[np.all(np.abs(X[fac, 1]) < 1e-9, axis=1)]
        cf = facet_cells(face, r.tets, r.body.np)
        x = r.x(lab) * mm
        col = cmap(norm(np.asarray(r.epsbar_cells(lab))[np.maximum(cf, 0)]))
        ax.add_collection(PolyCollection(x[face][:, :, [0, 2]], facecolors=col,
                                         edgecolors=col, linewidths=0.2))
        vol, dep, pts = ovl[what][lab]
        near = pts[np.abs(pts[:, 1]) < 0.5 * r.t] if pts.size else pts
        if near.size:
            ax.plot(near[:, 0] * mm, near[:, 2] * mm, ".", color=(0.85, 0, 0), ms=2,
                    label="covered twice (|y| < t/2)")
            ax.legend(loc="upper left", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlim((r.R - r.H) * mm, (r.R + r.H) * mm)
        ax.set_ylim(0, min(r.L, float(r.x(lab)[:, 2].max()) + r.t) * mm)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("z [mm]")
        ax.set_title(f"{what}, t = {r.snap(lab).time * 1e6:.0f} us\n"
                     f"overlap {vol * 1e9 * 4:.2f} mm^3 (tube), depth {dep * mm:.3f} mm")
    fig.suptitle(f"{name}: the wall in y = 0")
    fig.tight_layout()
    p = os.path.join(out, f"{name}_section.png")
    fig.savefig(p)
    plt.close(fig)
    paths.append(p)
    return paths


# ----------------------------------------------------------------------------------- main
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="the run with self-contact (.h5)")
    ap.add_argument("free", nargs="?", help="the control without self-contact (.h5)")
    ap.add_argument("--out", default=None, help="figures' directory (default: no figures)")
    ap.add_argument("--name", default="tube_crush")
    ap.add_argument("--min-folds", type=int, default=2,
                    help="closed folds required in the run with self-contact")
    ap.add_argument("--control-folds", type=int, default=0,
                    help="closed folds required in the control too (0: printed only)")
    ap.add_argument("--force-tol", type=float, default=0.25,
                    help="largest relative difference of the mean force from Abramowicz & "
                    "Jones's estimate with the effective crushing distance")
    ap.add_argument("--no-force-check", action="store_true")
    ap.add_argument("--overlap-ratio", type=float, default=0.1,
                    help="largest overlap volume with self-contact over the control's")
    ap.add_argument("--overlap-last", type=int, default=3,
                    help="the overlap is measured on this many last snapshots (each costs a "
                    "few seconds to a minute)")
    ap.add_argument("--control-only", action="store_true",
                    help="one run, without self-contact (the CI's coarse control): the force, "
                    "folds, mode and energy checks; its overlap printed")
    ap.add_argument("--energy-tol", type=float, default=1e-2,
                    help="largest relative energy residual")
    a = ap.parse_args(argv)
    fails = []

    def check(ok, msg):
        print(("ok   " if ok else "FAIL ") + msg)
        if not ok:
            fails.append(msg)

    try:
        rw = Run(a.run)
        ro = Run(a.free) if a.free else None
    except (Fail, OSError, KeyError, StopIteration) as e:
        print(f"tube_crush: cannot read the runs: {e!r}", file=sys.stderr)
        return 1
    if rw.self_contact == a.control_only:
        print(f"tube_crush: {a.run} " + ("has a self-contact pair (--control-only)"
                                         if a.control_only else "has no self-contact pair"),
              file=sys.stderr)
        return 1
    what_w = "no self-contact" if a.control_only else "self-contact"
    if ro is not None and ro.self_contact:
        print(f"tube_crush: {a.free} has a self-contact pair (the control must not)",
              file=sys.stderr)
        return 1
    print(f"# tube: R = {rw.R * 1e3:.3g} mm, t = {rw.t * 1e3:.3g} mm, D/t = "
          f"{2 * rw.R / rw.t:.1f}, L = {rw.L * 1e3:.3g} mm, mesh h = {rw.h * 1e3:.3g} mm "
          f"({rw.tets.shape[0]} tetrahedra, {rw.body.np} nodes, a quarter); ram "
          f"{rw.v_ram:.3g} m/s")
    # ---- force
    d, P, Pf, t = crush_curve(rw)
    i0 = 0
    Pm = mean_force(d, P, i0)
    last = rw.labels[-1]
    s0, wp_cells, emean = flow_stress(rw, last)
    wp_hist = float(rw.hist["w_plastic"][-1])
    est = estimates(rw, s0)
    print(f"# stroke {d[-1] * 1e3:.2f} mm; mean crush force {Pm / 1e3:.3f} kN (whole tube); "
          f"largest {P.max() / 1e3:.2f} kN")
    if ro is not None:
        do, Po, _, _ = crush_curve(ro)
        print(f"# control: mean crush force over the same stroke "
              f"{mean_force(do, Po, i0) / 1e3:.3f} kN")
    print(f"# flow stress sigma_0 = {s0 / 1e6:.1f} MPa (plastic-work-weighted; yield "
          f"{rw.sy0 / 1e6:.0f} MPa, mean epsbar of the plastic material {emean:.3f}); "
          f"sum V int sigma_y deps = {wp_cells:.4g} J, /history/w_plastic = {wp_hist:.4g} J")
    check(abs(wp_cells / wp_hist - 1.0) < 0.05,
          f"the plastic work from the strains ({wp_cells:.4g} J) matches /history/w_plastic "
          f"({wp_hist:.4g} J) within 5% (the strains are element values, the work a sum "
          f"over steps in the current volume)")
    for key, what in (("AJ_eff", "Abramowicz & Jones 1984, axisymmetric, effective crushing "
                       "distance"),
                      ("AJ", "the same without the effective crushing distance"),
                      ("Alexander", "Alexander 1960")):
        print(f"# estimate {what}: {est[key] / 1e3:.3f} kN; measured/estimate "
              f"{Pm / est[key]:.3f}")
    if not a.no_force_check:
        rel = Pm / est["AJ_eff"] - 1.0
        check(abs(rel) <= a.force_tol,
              f"mean crush force {Pm / 1e3:.2f} kN within {a.force_tol:.0%} of Abramowicz & "
              f"Jones's {est['AJ_eff'] / 1e3:.2f} kN (effective crushing distance; {rel:+.1%})")
    # ---- folds
    fl, _ = folds(rw, last)
    closed = closed_folds(fl)
    for Zp, drp, lo, up in fl:
        print(f"# lobe at Z = {Zp * 1e3:.2f} mm: dr = {drp * 1e3:+.2f} mm = {drp / rw.H:+.2f} H;"
              f" its arms shortened to {lo:.2f} (below), {up:.2f} (above)")
    # the mode: the radial profiles of the two generators, in y = 0 and in x = 0, 90 degrees
    # apart, against reference z (a diamond mode of the quarter differs between them)
    prof = []
    for plane in (1, 0):
        g = generator(rw, plane)
        X, x = rw.body.x[g], rw.x(last)[g]
        prof.append((X[:, 2], np.hypot(x[:, 0], x[:, 1]) - np.hypot(X[:, 0], X[:, 1])))
    zz = np.linspace(0.0, rw.L, 200)
    diff = np.abs(np.interp(zz, *prof[0]) - np.interp(zz, *prof[1])).max()
    big = np.abs(prof[0][1]).max()
    print(f"# mode: the radial excursions of the generators in y = 0 and x = 0 differ by at "
          f"most {diff * 1e3:.3f} mm, {diff / big:.1%} of the largest ({big * 1e3:.2f} mm)")
    check(diff <= 0.25 * big,
          f"axisymmetric (concertina) mode, the estimates' mode: the two generators' "
          f"profiles differ by {diff / big:.1%} of the largest excursion, at most 25% (a "
          f"diamond mode's lobes and valleys alternate around the tube)")
    check(len(closed) >= a.min_folds,
          f"{len(closed)} closed folds (lobes whose arms both shortened to < 0.5 of their "
          f"length) at t = {rw.snap(last).time * 1e6:.0f} us, at least {a.min_folds}")
    if ro is not None:
        flo, _ = folds(ro, ro.labels[-1])
        nco = len(closed_folds(flo))
        print(f"# control: {nco} closed folds ({len(flo)} lobes)")
        if a.control_folds:
            check(nco >= a.control_folds,
                  f"{nco} closed folds in the control, at least {a.control_folds}")
    # ---- overlap
    step = 0.25 * rw.h
    ovl = {"self-contact": {}, "no self-contact": {}}
    for r, what in ((rw, what_w), (ro, "no self-contact")):
        if r is None:
            continue
        for lab in r.labels[-a.overlap_last:]:
            ovl[what][lab] = overlap(r.x(lab), r.body.facets, step)
        vmax = max(v[0] for v in ovl[what].values())
        dmax = max(v[1] for v in ovl[what].values())
        print(f"# overlap, {what}: largest over the last {a.overlap_last} snapshots "
              f"{4 * vmax * 1e9:.3f} mm^3 "
              f"(whole tube), depth {dmax * 1e3:.3f} mm = {dmax / rw.t:.2f} t "
              f"(raster step {step * 1e3:.3f} mm)")
    vw = max(v[0] for v in ovl[what_w].values())
    dw = max(v[1] for v in ovl[what_w].values())
    if ro is not None:
        vo = max(v[0] for v in ovl["no self-contact"].values())
        check(vo > 0.0, f"the control overlaps itself ({4 * vo * 1e9:.3f} mm^3): the folds "
              "touch, so self-contact has something to stop")
        check(vw <= a.overlap_ratio * vo,
              f"overlap with self-contact {4 * vw * 1e9:.4f} mm^3 at most "
              f"{a.overlap_ratio:g} of the control's")
    if not a.control_only:
        check(dw <= 0.5 * rw.h,
              f"overlap depth with self-contact {dw * 1e3:.3f} mm at most half a mesh size "
              f"({0.5 * rw.h * 1e3:.3f} mm)")
    # ---- energy
    for r, what in ((rw, what_w), (ro, "no self-contact")):
        if r is None:
            continue
        s, h = r.summary, r.hist
        # /summary's scale (doc/output.md); a run cut short has no /summary: the same scale
        # from /history
        scale = float(s["energy_scale"]) if "energy_scale" in s else float(max(
            h["ke"][0], np.max(h["ke"]), np.max(np.abs(h["w_int"])),
            np.max(np.abs(h["w_ext"])), np.max(np.abs(h["w_contact"]))))
        if "energy_residual" not in s:
            print(f"# {what}: no /summary (a run cut short): its /history up to the last "
                  "snapshot")
        res = float(s.get("energy_residual", h["residual"][-1]))
        rel = abs(res) / scale
        hist = float(np.max(np.abs(h["residual"]))) / scale
        ke = float(r.hist["ke"][-1])
        wp = float(r.hist["w_plastic"][-1])
        wram = float(np.sum(0.5 * (P[1:] + P[:-1]) * np.diff(d))) / 4.0 if r is rw else None
        print(f"# energy, {what}: residual {rel:.2e} of the scale {scale:.4g}"
              f" J at the end, largest {hist:.2e}; plastic work {wp:.4g} J, kinetic "
              f"{ke:.4g} J = {ke / wp:.3f} of it (a quarter)"
              + (f"; ram work int P dd / 4 = {wram:.4g} J" if wram else ""))
        check(max(rel, hist) <= a.energy_tol,
              f"energy residual ({what}) {max(rel, hist):.2e} <= {a.energy_tol:g}")
    if a.out:
        for p in draw(rw, ro, a.out, a.name, d, P, Pf, i0, Pm, est, ovl, what_w):
            print(f"wrote {p}")
    if fails:
        print(f"tube_crush: {len(fails)} check(s) failed", file=sys.stderr)
        return 1
    print("tube_crush: all checks hold")
    return 0


if __name__ == "__main__":
    sys.exit(main())
