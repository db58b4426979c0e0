#!/usr/bin/env python3
"""Figures of an mfcd 'detect' run, after Li, Qian, Liu, Belytschko (2001), Figs. 2-7 and 11.

    python post/plot_detection.py output/example_2_2.h5 [--out doc/figures] [--format png]

What is drawn depends on the dimension and on the query sets the deck asked for:

  1D (Example 2.1)
    <stem>_particles     particles in the computed region with the marked points (Fig. 2)
    <stem>_det_profile   det(M) along the line, linear and logarithmic, with the marked
                         points, the threshold and the buffer zone shaded (Fig. 3)
  2D (Example 2.2)
    <stem>_particles     particles and boundary polyline (Figs. 4, 6)
    <stem>_det_surface   det(M) over the grid as a surface (Figs. 5, 7)          [grid]
    <stem>_det_contour   det(M) filled contours, det = threshold, exact boundary  [grid]
    <stem>_buffer_zone   0 < distance < rho_buffer shaded, det = threshold, body  [grid]
                         outline, max_outside_inside vs rho_buffer (Fig. 11)
    <stem>_det_line      det(M) along the query line, linear and logarithmic      [line]
  3D (the box and the C-shaped block of input/example_3d_*.nml)
    <stem>_det_plane     det(M) filled contours on a plane grid (grid_n = 1 in one     [grid]
                         direction), det = threshold, the exact section of the body,
                         the particles within half a spacing of the plane
    <stem>_det_line      det(M) along the query line                               [line]

Several files may be given. Exit status: 0 when every figure was written, 1 otherwise.
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
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch, Rectangle  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_style import figure_style  # noqa: E402
from mfcd_h5 import MfcdFile  # noqa: E402


C_PART = "0.15"
C_BND = "tab:orange"
C_LOOP = "tab:blue"
C_THR = "tab:red"
C_EXACT = "black"
C_BUF = "#fdd49e"
C_DETBUF = "#e34a33"
C_PTS = "tab:purple"


# --------------------------------------------------------------------------- helpers
def fmt(v: float, digits: int = 4) -> str:
    """A number for a label: fixed for moderate magnitudes, else scientific."""
    if v == 0:
        return "0"
    a = abs(v)
    if 1e-3 <= a < 1e4:
        return f"{v:.{digits}g}"
    return f"{v:.{digits - 1}e}"


def vec(v) -> str:
    v = np.atleast_1d(v)
    return " x ".join(fmt(float(t), 4) for t in v)


def body_summary(body) -> str:
    a = body.attrs
    return (f"{body.np} particles, dx = {vec(a.get('spacing', []))} m, "
            f"rho = {vec(a.get('basis_scale', []))} m, {a.get('basis', '?')} basis, "
            f"{a.get('kernel', '?')} ({a.get('window', '?')})")


def runs(mask: np.ndarray):
    """(start, stop) index pairs of the True runs of a 1D boolean array (stop inclusive)."""
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    d = np.diff(m.astype(int))
    return list(zip(np.where(d == 1)[0], np.where(d == -1)[0] - 1))


def shade_runs(ax, coord, mask, **kw):
    """Shade the full height of ax over the coord ranges where mask holds."""
    first = True
    for i0, i1 in runs(mask):
        lo, hi = coord[i0], coord[i1]
        if hi < lo:
            lo, hi = hi, lo
        ax.axvspan(lo, hi, lw=0, **({**kw} if first else {k: v for k, v in kw.items()
                                                           if k != "label"}))
        first = False


def save(fig, out, stem, name, ext, dpi):
    path = os.path.join(out, f"{stem}_{name}.{ext}")
    fig.savefig(path, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {path}")
    return path


def run_name(f) -> str:
    """The run's title, or its file name when the deck gave none."""
    return f.title or os.path.basename(f.path)


def point_labels(n, ndim):
    return [f"P{k + 1}" for k in range(n)] if ndim == 1 else [f"Q{k + 1}" for k in range(n)]


# --------------------------------------------------------------------------- profiles
def line_coordinate(line, ndim):
    """The abscissa of a line query: the coordinate that varies when the line is parallel
    to an axis (with a note giving the fixed ones), else the arc length s."""
    x = line.x
    span = x.max(axis=0) - x.min(axis=0)
    names = "xyz"
    moving = np.flatnonzero(span > 0)
    if ndim == 1 or moving.size == 1:
        k = int(moving[0]) if moving.size else 0
        fixed = [f"{names[j]} = {fmt(x[0, j])} m" for j in range(ndim) if j != k]
        return x[:, k], f"{names[k]} [m]", (", ".join(fixed)), k
    a, b = x[0], x[-1]
    return line.s, (f"s along the line from ({', '.join(fmt(t) for t in a)}) "
                    f"to ({', '.join(fmt(t) for t in b)}) [m]"), "", None


def draw_profile(f, line, points, title):
    """Linear (as the paper) and logarithmic det(M) along the line, threshold, buffer zone."""
    det_attrs = f.detection
    thr = float(det_attrs["threshold"])
    rho = float(det_attrs["rho_buffer"])
    plateau = float(det_attrs["plateau"])
    coord, xlabel, note, axis_k = line_coordinate(line, f.ndim)
    dmax = max(float(line.det.max()), plateau)
    scale, ylab = det_scale(dmax)

    fig, (ax, axl) = plt.subplots(2, 1, figsize=(8.0, 7.0), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 2]})
    handles = []
    if line.distance is not None:
        for a in (ax, axl):
            shade_runs(a, coord, (line.distance > 0) & (line.distance < rho), color=C_BUF,
                       alpha=0.8, zorder=0)
            # exact boundary: sign changes of the signed distance
            sgn = np.sign(line.distance)
            for i in np.flatnonzero(sgn[:-1] * sgn[1:] <= 0):
                if sgn[i] == 0 and i > 0:
                    continue
                a.axvline(coord[i], color=C_EXACT, lw=0.8, ls=":", zorder=1)
        handles += [Patch(fc=C_BUF, alpha=0.8,
                          label=f"buffer zone, eq. (50): 0 < distance < rho = {fmt(rho)} m"),
                    Line2D([], [], color=C_EXACT, lw=0.8, ls=":",
                           label="exact boundary (distance = 0)")]
    ax.plot(coord, line.det / scale, color="tab:blue", lw=1.6, zorder=3)
    ax.axhline(plateau / scale, color="0.5", lw=0.8, ls="--", zorder=2)
    ax.axhline(thr / scale, color=C_THR, lw=1.0, zorder=2)
    handles += [Line2D([], [], color="tab:blue", lw=1.6, label="det(M)"),
                Line2D([], [], color="0.5", lw=0.8, ls="--",
                       label=f"interior plateau (/detection plateau) = {fmt(plateau)}"),
                Line2D([], [], color=C_THR, lw=1.2,
                       label=f"threshold = {fmt(thr)} (at 0 on the linear scale)")]
    ax.set_ylabel(ylab)
    ax.set_ylim(-0.04 * dmax / scale, 1.15 * dmax / scale)

    pos = line.det > 0
    axl.semilogy(np.where(pos, coord, np.nan), np.where(pos, line.det, np.nan),
                 color="tab:blue", lw=1.4, zorder=3)
    axl.axhline(thr, color=C_THR, lw=1.2, zorder=2)
    lo = min(thr, line.det[pos].min() if pos.any() else thr) / 30.0
    axl.set_ylim(max(lo, dmax * 1e-14), dmax * 10)
    axl.set_ylabel("det(M) [-], log scale")
    axl.set_xlabel(xlabel + (f"   ({note})" if note else ""))

    # marked points that lie on the line (all of them in 1D)
    if points is not None and points.n:
        labels = point_labels(points.n, f.ndim)
        for k in range(points.n):
            p = points.x[k]
            if axis_k is None:
                continue
            others = [j for j in range(f.ndim) if j != axis_k]
            if others and not np.allclose(p[others], line.x[0, others]):
                continue
            xp, dp = p[axis_k], points.det[k]
            ax.plot([xp], [dp / scale], "o", ms=7, mfc="white", mec=C_PTS, mew=2, zorder=5)
            txt = f"{labels[k]} = {fmt(xp)} m\ndet(M) = {fmt(dp)}"
            dy = 0.22 * dmax if dp < 0.5 * dmax else -0.32 * dmax
            ax.annotate(txt, (xp, dp / scale), (xp, (dp + dy) / scale), ha="center",
                        fontsize=9.5, color=C_PTS,
                        arrowprops=dict(arrowstyle="->", color=C_PTS, lw=1),
                        bbox=dict(boxstyle="round,pad=0.25", fc="white", ec=C_PTS, lw=0.8),
                        zorder=6)
            axl.axvline(xp, color=C_PTS, lw=0.9, ls="--")
            axl.annotate(labels[k], (xp, 0.96), xycoords=("data", "axes fraction"),
                         xytext=(3, 0), textcoords="offset points", color=C_PTS, ha="left",
                         va="top", fontsize=9)
        handles.append(Line2D([], [], ls="", marker="o", mfc="white", mec=C_PTS, mew=2,
                              label="marked points (/detection/points)"))

    mo = line.attrs.get("max_outside_inside")
    sub = (f"det(M) > threshold reaches {fmt(mo)} m outside the body "
           f"(rho_buffer = {fmt(rho)} m)") if mo is not None else ""
    ax.set_title(f"{title}\n{sub}")
    fig.legend(handles=handles, loc="lower center", ncol=2, framealpha=0.95,
               bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    return fig


# --------------------------------------------------------------------------- 1D
def fig_particles_1d(f, body, line, points):
    x = body.x[:, 0]
    if line is not None:
        region = (line.x[:, 0].min(), line.x[:, 0].max())
    else:
        L = x.max() - x.min()
        region = (x.min() - 0.5 * L, x.max() + 0.5 * L)
    fig, ax = plt.subplots(figsize=(8.0, 3.0))
    ax.plot(region, [0, 0], color="0.6", lw=1.2, zorder=1)
    for r in region:
        ax.plot([r, r], [-0.15, 0.15], color="0.6", lw=1.2)
    ax.text(region[0], -0.25, "computed region", ha="left", va="top", fontsize=9,
            color="0.4")
    ax.plot([x.min(), x.max()], [0, 0], color=C_LOOP, lw=3, zorder=2,
            label=f"discretized domain [{fmt(x.min())}, {fmt(x.max())}] m")
    ax.plot(x[~body.boundary], np.zeros((~body.boundary).sum()), "o", ms=4, color=C_PART,
            zorder=3, label=f"{body.np} particles")
    if body.boundary.any():
        ax.plot(x[body.boundary], np.zeros(body.boundary.sum()), "s", ms=5, color=C_BND,
                zorder=4, label="end particles (half volume)")
    # the support of one end particle
    rho = body.support[-1, 0]
    ax.annotate("", (x[-1] + rho, 0.28), (x[-1], 0.28),
                arrowprops=dict(arrowstyle="<->", color="0.3", lw=1))
    ax.text(x[-1] + 0.5 * rho, 0.36, f"rho = {fmt(rho)} m", ha="left", va="bottom",
            fontsize=9, color="0.3")
    if points is not None:
        for lab, p, d in zip(point_labels(points.n, 1), points.x[:, 0], points.det):
            ax.plot([p], [0], "v", ms=10, color=C_PTS, zorder=5)
            ax.text(p, 0.22, f"{lab} = {fmt(p)}", ha="center", va="bottom", color=C_PTS,
                    fontsize=10)
    ax.set_ylim(-0.7, 0.9)
    ax.set_xlim(region[0] - 0.03 * (region[1] - region[0]),
                region[1] + 0.03 * (region[1] - region[0]))
    ax.set_yticks([])
    for s in ("left", "right", "top"):
        ax.spines[s].set_visible(False)
    ax.set_xlabel("x [m]")
    ax.set_title(f"{run_name(f)}: particles in the computed region "
                 f"[{fmt(region[0])}, {fmt(region[1])}] m\n{body_summary(body)}",
                 fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=3, framealpha=0.9,
               bbox_to_anchor=(0.5, 0.0))
    fig.subplots_adjust(left=0.03, right=0.97, top=0.80, bottom=0.32)
    return fig


# --------------------------------------------------------------------------- 2D
def region_2d(f, body, grid):
    if grid is not None:
        return (grid.axes[0][0], grid.axes[0][-1]), (grid.axes[1][0], grid.axes[1][-1])
    r = float(f.detection.get("rho_buffer", 0.0))
    lo = body.x.min(axis=0) - 2 * r
    hi = body.x.max(axis=0) + 2 * r
    return (lo[0], hi[0]), (lo[1], hi[1])


def draw_polylines(ax, body, **kw):
    first = True
    for pl in body.polylines():
        ax.plot(pl[:, 0], pl[:, 1], **(kw if first else {k: v for k, v in kw.items()
                                                         if k != "label"}))
        first = False


def fig_particles_2d(f, body, grid, points):
    (x0, x1), (y0, y1) = region_2d(f, body, grid)
    w = 8.0
    h = max(3.0, min(9.0, w * (y1 - y0) / (x1 - x0))) + 0.6
    fig, ax = plt.subplots(figsize=(w, h))
    x = body.x
    # marker size from the particle spacing as it appears on the page (points)
    sp = np.atleast_1d(body.attrs.get("spacing", [0.0]))[0]
    ax_w_pt = 0.8 * w * 72.0
    sp_pt = sp / (x1 - x0) * ax_w_pt if sp > 0 else 4.0
    ms = max(1.2, min(4.5, 0.4 * sp_pt))
    ax.plot(x[~body.boundary, 0], x[~body.boundary, 1], "o", ms=ms, color=C_PART,
            label="interior particles", zorder=3)
    ax.plot(x[body.boundary, 0], x[body.boundary, 1], "s", ms=ms * 1.1, color=C_BND,
            label="boundary particles", zorder=4)
    draw_polylines(ax, body, color=C_LOOP, lw=1.2, label="boundary polyline (loop_idx)",
                   zorder=5)
    # the tensor-product support of one interior particle
    inner = np.flatnonzero(~body.boundary)
    if inner.size:
        c = np.median(x[inner], axis=0)
        i = inner[np.argmin(((x[inner] - c) ** 2).sum(axis=1))]
        r = body.support[i]
        win = body.attrs.get("window", "tensor")
        if win == "radial":
            from matplotlib.patches import Ellipse
            patch = Ellipse(x[i], 2 * r[0], 2 * r[1], fill=False, ls="--", color="tab:green",
                            lw=1.6, zorder=6)
        else:
            patch = Rectangle(x[i] - r, 2 * r[0], 2 * r[1], fill=False, ls="--",
                              color="tab:green", lw=1.6, zorder=6)
        ax.add_patch(patch)
        ax.plot(*x[i], "o", ms=ms * 1.4, color="tab:green", zorder=6)
        hand_support = Line2D([], [], color="tab:green", ls="--", lw=1.6,
                              label=f"support of one particle (rho = {vec(r)} m)")
    else:
        hand_support = None
    if points is not None and points.n:
        labs = point_labels(points.n, 2)
        for k in range(points.n):
            p = points.x[k]
            ax.plot(*p, "x", ms=9, mew=2.2, color=C_PTS, zorder=7)
            # labels centred above their points, every other one higher (no overlaps)
            ax.annotate(f"{labs[k]}: det = {fmt(points.det[k], 3)}", p, (0, 8 + 14 * (k % 2)),
                        textcoords="offset points", fontsize=8.5, color=C_PTS, zorder=8,
                        ha="center", va="bottom",
                        bbox=dict(boxstyle="round,pad=0.2", fc="white", ec=C_PTS, lw=0.6,
                                  alpha=0.9))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{run_name(f)}: particle distribution\n{body_summary(body)}", fontsize=10)
    h, l_ = ax.get_legend_handles_labels()
    if hand_support is not None:
        h.append(hand_support)
        l_.append(hand_support.get_label())
    if points is not None and points.n:
        h.append(Line2D([], [], ls="", marker="x", mew=2.2, ms=8, color=C_PTS))
        l_.append("query points (/detection/points)")
    ax.legend(h, l_, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2,
              framealpha=0.9)
    fig.tight_layout()
    return fig


def det_scale(zmax: float):
    """(factor, label) to show det(M) without an offset text: det / 10^k."""
    if not zmax > 0:
        return 1.0, "det(M) [-]"
    k = int(np.floor(np.log10(zmax)))
    if -2 <= k <= 2:
        return 1.0, "det(M) [-]"
    return 10.0 ** k, f"det(M) [$10^{{{k}}}$]"


def fig_det_surface(f, body, grid):
    X, Y = grid.mesh()
    Z = grid.det2d
    scale, zlab = det_scale(float(Z.max()))
    fig = plt.figure(figsize=(9.0, 6.2))
    ax = fig.add_subplot(111, projection="3d")
    ny, nx = Z.shape
    surf = ax.plot_surface(X, Y, Z / scale, cmap="viridis", rcount=min(ny, 200),
                           ccount=min(nx, 300), linewidth=0, antialiased=False,
                           rasterized=True, vmin=0.0,
                           vmax=Z.max() / scale)
    ax.set_xlabel("x [m]", labelpad=8)
    ax.set_ylabel("y [m]", labelpad=8)
    ax.zaxis.set_rotate_label(False)
    ax.set_zlabel(zlab, labelpad=10, rotation=90)
    ax.view_init(elev=45, azim=-40)
    xr = X.max() - X.min()
    yr = Y.max() - Y.min()
    ax.set_box_aspect((1.0, yr / xr, 0.5))
    cb = fig.colorbar(surf, ax=ax, shrink=0.5, pad=0.1, aspect=15)
    cb.set_label(zlab)
    det = f.detection
    ax.set_title(f"{run_name(f)}\ndet(M) as the height over the x-y plane; interior plateau = "
                 f"{fmt(float(det['plateau']))}, max = {fmt(float(Z.max()))}", fontsize=10,
                 y=0.98)
    fig.subplots_adjust(left=0.0, right=0.92, bottom=0.02, top=0.95)
    return fig


def fig_det_contour(f, body, grid):
    X, Y = grid.mesh()
    Z = grid.det2d
    det = f.detection
    thr = float(det["threshold"])
    (x0, x1), (y0, y1) = region_2d(f, body, grid)
    w = 8.6
    h = max(3.0, min(9.0, (w - 1.6) * (y1 - y0) / (x1 - x0))) + 1.0
    fig, ax = plt.subplots(figsize=(w, h))
    scale, zlab = det_scale(float(Z.max()))
    levels = MaxNLocator(nbins=20).tick_values(0.0, float(Z.max()) / scale)
    if levels[-1] < Z.max() / scale:
        levels = np.append(levels, 2 * levels[-1] - levels[-2])
    cf = ax.contourf(X, Y, Z / scale, levels=levels, cmap="viridis")
    cb = fig.colorbar(cf, ax=ax, shrink=0.9)
    cb.set_label(zlab)
    ax.contour(X, Y, Z, levels=[thr], colors=C_THR, linewidths=1.6)
    handles = [Line2D([], [], color=C_THR, lw=1.6, label=f"det(M) = threshold = {fmt(thr)}")]
    dist = grid.distance2d
    if dist is not None:
        ax.contour(X, Y, dist, levels=[0.0], colors="white", linewidths=1.3,
                   linestyles="--")
        handles.append(Line2D([], [], color="white", lw=1.3, ls="--",
                              label="exact boundary (distance = 0)"))
    else:
        draw_polylines(ax, body, color="white", lw=1.2, ls="--")
        handles.append(Line2D([], [], color="white", lw=1.2, ls="--",
                              label="boundary polyline"))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_facecolor("0.35")
    leg = ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12),
                    ncol=2, framealpha=1.0, facecolor="0.35", labelcolor="white")
    leg.get_frame().set_edgecolor("0.35")
    ax.set_title(f"{run_name(f)}\ndet(M) contours; inside = det(M) > {fmt(thr)} "
                 f"({int(grid.inside.sum())} of {grid.n} grid points)", fontsize=10)
    fig.tight_layout()
    return fig


def fig_buffer_zone(f, body, grid):
    X, Y = grid.mesh()
    Z = grid.det2d
    dist = grid.distance2d
    det = f.detection
    thr = float(det["threshold"])
    rho = float(det["rho_buffer"])
    mo = float(grid.attrs.get("max_outside_inside", np.nan))
    nb = int(grid.attrs.get("n_beyond_buffer", 0))
    nfo = int(grid.attrs.get("n_false_outside", 0))
    (x0, x1), (y0, y1) = region_2d(f, body, grid)
    w = 8.0
    h = max(3.0, min(9.0, w * (y1 - y0) / (x1 - x0))) + 1.2
    fig, ax = plt.subplots(figsize=(w, h))
    ax.contourf(X, Y, dist, levels=[0.0, rho], colors=[C_BUF])
    # where det > threshold outside the body: the part of the buffer the criterion claims
    claimed = np.where(grid.inside2d & (dist > 0), 1.0, 0.0)
    if claimed.any():
        ax.contourf(X, Y, claimed, levels=[0.5, 1.5], colors=[C_DETBUF], alpha=0.55)
    ax.contour(X, Y, dist, levels=[rho], colors="tab:orange", linewidths=1.0,
               linestyles="--")
    ax.contour(X, Y, Z, levels=[thr], colors=C_THR, linewidths=1.5)
    ax.contour(X, Y, dist, levels=[0.0], colors=C_EXACT, linewidths=1.5)
    ax.plot(body.x[:, 0], body.x[:, 1], ".", ms=2.0, color="0.55", zorder=1)
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    handles = [
        Patch(fc=C_BUF, label=f"buffer zone, eq. (50): 0 < distance < rho = {fmt(rho)} m"),
        Patch(fc=C_DETBUF, alpha=0.55, label="outside the body with det(M) > threshold"),
        Line2D([], [], color=C_THR, lw=1.5, label=f"det(M) = threshold = {fmt(thr)}"),
        Line2D([], [], color=C_EXACT, lw=1.5, label="body outline (exact geometry)"),
        Line2D([], [], color="tab:orange", lw=1.0, ls="--", label="distance = rho"),
        Line2D([], [], ls="", marker=".", color="0.55", label="particles"),
    ]
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2,
              framealpha=0.9)
    ok = "inside the buffer zone" if (nb == 0 and mo < rho) else "NOT inside the buffer zone"
    ax.set_title(f"{run_name(f)}: the buffer zone (Fig. 11)\n"
                 f"det(M) > threshold reaches {fmt(mo)} m outside (max_outside_inside) vs "
                 f"rho_buffer = {fmt(rho)} m: {ok}\n"
                 f"grid points beyond rho with det > threshold: {nb}; interior points with "
                 f"det <= threshold: {nfo}", fontsize=9.5)
    fig.tight_layout()
    return fig


def fig_det_plane_3d(f, body, grid):
    """det(M) on a 3D grid that is a plane (one direction with a single point)."""
    names = ["x", "y", "z"]
    flat = [k for k, a in enumerate(grid.axes) if a.size == 1]
    if len(flat) != 1:
        return None
    k0 = flat[0]
    ka, kb = [k for k in range(3) if k != k0]
    D = np.squeeze(grid.as_grid(grid.det))          # (n_kb, n_ka): the later axis first
    A, B = np.meshgrid(grid.axes[ka], grid.axes[kb])
    det = f.detection
    thr = float(det["threshold"])
    at = float(grid.axes[k0][0])
    w = 8.6
    ext_a = grid.axes[ka][-1] - grid.axes[ka][0]
    ext_b = grid.axes[kb][-1] - grid.axes[kb][0]
    h = max(3.0, min(9.0, (w - 1.6) * ext_b / ext_a)) + 1.0
    fig, ax = plt.subplots(figsize=(w, h))
    scale, zlab = det_scale(float(D.max()))
    levels = MaxNLocator(nbins=20).tick_values(0.0, float(D.max()) / scale)
    if levels[-1] < D.max() / scale:
        levels = np.append(levels, 2 * levels[-1] - levels[-2])
    cf = ax.contourf(A, B, D / scale, levels=levels, cmap="viridis")
    cb = fig.colorbar(cf, ax=ax, shrink=0.9)
    cb.set_label(zlab)
    ax.contour(A, B, D, levels=[thr], colors=C_THR, linewidths=1.6)
    handles = [Line2D([], [], color=C_THR, lw=1.6, label=f"det(M) = threshold = {fmt(thr)}")]
    if grid.distance is not None:
        dist = np.squeeze(grid.as_grid(grid.distance))
        ax.contour(A, B, dist, levels=[0.0], colors="white", linewidths=1.3, linestyles="--")
        handles.append(Line2D([], [], color="white", lw=1.3, ls="--",
                              label="exact section of the body (distance = 0)"))
    sp = body.spacing
    near = np.abs(body.x[:, k0] - at) <= 0.5 * (sp[k0] if sp is not None else 0.0)
    ax.plot(body.x[near, ka], body.x[near, kb], ".", ms=1.5, color="0.85", zorder=3)
    handles.append(Line2D([], [], ls="", marker=".", color="0.85",
                          label=f"particles within half a spacing of {names[k0]} = {fmt(at)}"))
    ax.set_xlim(grid.axes[ka][0], grid.axes[ka][-1])
    ax.set_ylim(grid.axes[kb][0], grid.axes[kb][-1])
    ax.set_aspect("equal")
    ax.set_xlabel(f"{names[ka]} [m]")
    ax.set_ylabel(f"{names[kb]} [m]")
    ax.set_facecolor("0.35")
    leg = ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12),
                    ncol=2, framealpha=1.0, facecolor="0.35", labelcolor="white")
    leg.get_frame().set_edgecolor("0.35")
    ax.set_title(f"{run_name(f)}\ndet(M) on the plane {names[k0]} = {fmt(at)} m; interior "
                 f"plateau {fmt(float(det['plateau']))}; inside = det(M) > {fmt(thr)} "
                 f"({int(grid.inside.sum())} of {grid.n} points)", fontsize=10)
    fig.tight_layout()
    return fig


# --------------------------------------------------------------------------- driver
def plot_file(path, out, ext, dpi):
    stem = os.path.splitext(os.path.basename(path))[0]
    written = []
    with MfcdFile(path) as f:
        if f.attrs.get("mode") != "detect" or not f.query_kinds():
            print(f"{path}: no /detection query sets (mode = {f.attrs.get('mode')}); "
                  "nothing to draw", file=sys.stderr)
            return written
        body = f.body()
        line, grid, points = f.query("line"), f.query("grid"), f.query("points")
        nd = f.ndim
        if nd == 1:
            written.append(save(fig_particles_1d(f, body, line, points), out, stem,
                                "particles", ext, dpi))
            if line is not None:
                written.append(save(draw_profile(f, line, points,
                                                 f"{run_name(f)}: det(M) profile (Fig. 3)"),
                                    out, stem, "det_profile", ext, dpi))
            else:
                print(f"{path}: no /detection/line: det_profile skipped", file=sys.stderr)
        elif nd == 2:
            written.append(save(fig_particles_2d(f, body, grid, points), out, stem,
                                "particles", ext, dpi))
            if grid is not None:
                written.append(save(fig_det_surface(f, body, grid), out, stem, "det_surface",
                                    ext, dpi))
                written.append(save(fig_det_contour(f, body, grid), out, stem, "det_contour",
                                    ext, dpi))
                if grid.distance is not None:
                    written.append(save(fig_buffer_zone(f, body, grid), out, stem,
                                        "buffer_zone", ext, dpi))
                else:
                    print(f"{path}: body has no exact geometry (no /detection/grid/distance):"
                          " buffer_zone skipped", file=sys.stderr)
            else:
                print(f"{path}: no /detection/grid: surface, contour and buffer-zone figures "
                      "skipped", file=sys.stderr)
            if line is not None:
                written.append(save(draw_profile(f, line, points,
                                                 f"{run_name(f)}: det(M) along the query line"),
                                    out, stem, "det_line", ext, dpi))
        else:
            if grid is not None:
                fig = fig_det_plane_3d(f, body, grid)
                if fig is not None:
                    written.append(save(fig, out, stem, "det_plane", ext, dpi))
                else:
                    print(f"{path}: the 3D grid is not a plane (grid_n = 1 in one direction): "
                          "det_plane skipped", file=sys.stderr)
            if line is not None:
                written.append(save(draw_profile(f, line, points,
                                                 f"{run_name(f)}: det(M) along the query line"),
                                    out, stem, "det_line", ext, dpi))
            elif grid is None:
                print(f"{path}: ndim = {nd}: no query line or plane to draw", file=sys.stderr)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(
        description="Draw det(M) figures (after Li et al. 2001, Figs. 2-7 and 11) from mfcd "
                    "detect-mode HDF5 output.")
    ap.add_argument("files", nargs="+", metavar="FILE.h5", help="mfcd output file(s)")
    ap.add_argument("--out", default=None,
                    help="output directory (created if missing; default: the directory of "
                         "each input file)")
    ap.add_argument("--format", default="png", choices=["png", "pdf", "svg"],
                    help="figure format (default png)")
    ap.add_argument("--dpi", type=int, default=150, help="resolution of raster figures "
                                                         "(default 150)")
    args = ap.parse_args(argv)
    plt.rcParams.update(figure_style(savefig_dpi=150, axes_grid=False))
    status = 0
    for path in args.files:
        out = args.out if args.out else (os.path.dirname(os.path.abspath(path)) or ".")
        try:
            os.makedirs(out, exist_ok=True)
            if not plot_file(path, out, args.format, args.dpi):
                status = 1
        except Exception as exc:  # report and go on with the next file
            traceback.print_exc()
            print(f"plot_detection: error: {path}: {exc}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
