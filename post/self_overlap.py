"""Self-interpenetration of a deformed body, measured from its boundary alone (2D: its
polylines; 3D: its closed facet surface, overlap_3d below).

A body that folds onto itself without self-contact passes through itself: its deformed
boundary loops then cover some points twice. The winding number of the loops (outer loops
counter-clockwise, holes clockwise, as mfcd writes them) is 1 inside the body, 0 outside,
and 2 or more where material overlaps material. This module counts it on a raster, so it
is independent of anything mfcd computes for contact (det(M), gaps, neighbour lists):

    overlap area  = area of the raster cells with winding >= 2            [m^2]
    overlap depth = 2 x the largest distance from such a cell's centre
                    to the nearest boundary segment                        [m]

(the depth of the thickest lens of doubly covered material). The raster step is a fraction
of the particle spacing (default 1/20), so both are resolved to that step: an overlap
thinner than about a raster step reads as zero, which sets the tolerance of the checks.

In 3D the same on a raster of 1/4 of the spacing: the winding number of the deformed facet
surface (counted along vertical columns), the overlap volume [m^3] in the area column and
the depth of the doubly covered material.

    python post/self_overlap.py output/c_shape_fold.h5 [--body c] [--step-fraction 0.05]
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Tuple

import numpy as np

from mfcd_h5 import MfcdFile


def winding_number(loops: List[np.ndarray], pts: np.ndarray) -> np.ndarray:
    """Winding number of the closed polylines loops (each (k+1, 2), first point repeated)
    around each of pts (n, 2) (Sunday's crossing rule: upward crossings with the point on
    the left count +1, downward ones with it on the right -1)."""
    w = np.zeros(pts.shape[0], dtype=int)
    px = pts[:, 0][:, None]
    py = pts[:, 1][:, None]
    for loop in loops:
        a = loop[:-1]
        b = loop[1:]
        for s in range(0, a.shape[0], 256):
            ax, ay = a[s:s + 256, 0][None, :], a[s:s + 256, 1][None, :]
            bx, by = b[s:s + 256, 0][None, :], b[s:s + 256, 1][None, :]
            side = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
            up = (ay <= py) & (by > py) & (side > 0)
            down = (ay > py) & (by <= py) & (side < 0)
            w += up.sum(axis=1) - down.sum(axis=1)
    return w


def distance_to_segments(loops: List[np.ndarray], pts: np.ndarray) -> np.ndarray:
    """Distance from each of pts (n, 2) to the nearest segment of the loops."""
    a = np.concatenate([l[:-1] for l in loops])
    b = np.concatenate([l[1:] for l in loops])
    d = np.full(pts.shape[0], np.inf)
    for s in range(0, a.shape[0], 256):
        aa, bb = a[s:s + 256][None, :, :], b[s:s + 256][None, :, :]
        e = bb - aa
        t = np.clip(((pts[:, None, :] - aa) * e).sum(-1) / np.maximum((e * e).sum(-1), 1e-300),
                    0.0, 1.0)
        q = aa + t[..., None] * e
        d = np.minimum(d, np.sqrt(((pts[:, None, :] - q) ** 2).sum(-1)).min(axis=1))
    return d


def row_winding(loops: List[np.ndarray], y: float, xs: np.ndarray) -> np.ndarray:
    """Winding number of the loops at the points (xs, y) of one raster row, xs ascending,
    by the same crossing rule as winding_number: every edge crossing the row to the right of
    a point counts +1 going up, -1 going down."""
    a = np.concatenate([l[:-1] for l in loops])
    b = np.concatenate([l[1:] for l in loops])
    up = (a[:, 1] <= y) & (b[:, 1] > y)
    down = (a[:, 1] > y) & (b[:, 1] <= y)
    sel = up | down
    if not sel.any():
        return np.zeros(xs.size, dtype=int)
    a, b, sign = a[sel], b[sel], np.where(up[sel], 1, -1)
    xc = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    order = np.argsort(xc)
    xc, sign = xc[order], sign[order]
    # sum of the signs of the crossings at xc > x: a suffix sum
    suffix = np.concatenate([np.cumsum(sign[::-1])[::-1], [0]])
    return suffix[np.searchsorted(xc, xs, side="right")]


def overlap(loops: List[np.ndarray], step: float) -> Tuple[float, float, np.ndarray]:
    """(overlap area [m^2], overlap depth [m], centres of the doubly covered cells (k, 2))
    of the closed loops on a raster of the given step over their bounding box."""
    allp = np.concatenate(loops)
    lo = allp.min(axis=0) - step
    hi = allp.max(axis=0) + step
    xs = np.arange(lo[0] + 0.5 * step, hi[0], step)
    ys = np.arange(lo[1] + 0.5 * step, hi[1], step)
    cells = []
    for y in ys:
        w = row_winding(loops, y, xs)
        if (w >= 2).any():
            hx = xs[w >= 2]
            cells.append(np.column_stack([hx, np.full(hx.size, y)]))
    if not cells:
        return 0.0, 0.0, np.zeros((0, 2))
    hit = np.concatenate(cells)
    area = hit.shape[0] * step * step
    depth = 2.0 * float(distance_to_segments(loops, hit).max())
    return area, depth, hit


def raster_winding(x: np.ndarray, facets: np.ndarray, xs: np.ndarray, ys: np.ndarray,
                   zs: np.ndarray) -> np.ndarray:
    """Winding number (len(xs), len(ys), len(zs)) of the closed triangle surface (x (np, 3),
    facets (nf, 3), counter-clockwise from outside) on the raster xs x ys x zs (each
    ascending, evenly spaced): along each vertical column, the signed crossings of the
    facets above a point (+1 where the outward normal points up: the ray leaves the
    material there), as Sunday's rule counts them in the plane. Each facet is tried only
    on the columns of its x-y box."""
    a, b, c = x[facets[:, 0]], x[facets[:, 1]], x[facets[:, 2]]
    dx, dy = xs[1] - xs[0], ys[1] - ys[0]
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    i0 = np.clip(np.ceil((lo[:, 0] - xs[0]) / dx).astype(int), 0, xs.size)
    i1 = np.clip(np.floor((hi[:, 0] - xs[0]) / dx).astype(int) + 1, 0, xs.size)
    j0 = np.clip(np.ceil((lo[:, 1] - ys[0]) / dy).astype(int), 0, ys.size)
    j1 = np.clip(np.floor((hi[:, 1] - ys[0]) / dy).astype(int) + 1, 0, ys.size)
    ni, nj = np.maximum(i1 - i0, 0), np.maximum(j1 - j0, 0)
    npair = ni * nj
    f = np.repeat(np.arange(facets.shape[0]), npair)
    k = np.arange(f.size) - np.repeat(np.cumsum(npair) - npair, npair)
    ix = i0[f] + k // np.maximum(nj[f], 1)
    iy = j0[f] + k % np.maximum(nj[f], 1)
    px, py = xs[ix], ys[iy]
    A, B, C = a[f], b[f], c[f]
    d = (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (C[:, 0] - A[:, 0]) * (B[:, 1] - A[:, 1])
    ok = d != 0.0
    dd = np.where(ok, d, 1.0)
    l1 = ((px - A[:, 0]) * (C[:, 1] - A[:, 1]) - (C[:, 0] - A[:, 0]) * (py - A[:, 1])) / dd
    l2 = ((B[:, 0] - A[:, 0]) * (py - A[:, 1]) - (px - A[:, 0]) * (B[:, 1] - A[:, 1])) / dd
    hit = ok & (l1 >= 0.0) & (l2 >= 0.0) & (l1 + l2 <= 1.0)
    zc = A[hit, 2] + l1[hit] * (B[hit, 2] - A[hit, 2]) + l2[hit] * (C[hit, 2] - A[hit, 2])
    sign = np.where(d[hit] > 0.0, 1, -1)     # the projection's orientation: n_z's sign
    # each crossing adds its sign at every z below it: a difference array along z
    kz = np.searchsorted(zs, zc)             # the number of raster points below zc
    diff = np.zeros((xs.size, ys.size, zs.size + 1), dtype=int)
    np.add.at(diff, (ix[hit], iy[hit], 0), sign)
    np.add.at(diff, (ix[hit], iy[hit], kz), -sign)
    return np.cumsum(diff, axis=2)[:, :, :zs.size]


def distance_to_facets(x: np.ndarray, facets: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Distance from each of pts (n, 3) to the nearest triangle of the surface: the
    nearer of the distance to the facet's plane (where the foot lies inside the facet) and
    the distances to its three edges."""
    a, b, c = x[facets[:, 0]], x[facets[:, 1]], x[facets[:, 2]]
    out = np.full(pts.shape[0], np.inf)
    for k0 in range(0, pts.shape[0], 256):
        p = pts[k0:k0 + 256][:, None, :]
        n = np.cross(b - a, c - a)
        n = n / np.linalg.norm(n, axis=1)[:, None]
        h = np.einsum("ijk,jk->ij", p - a[None], n)
        foot = p - h[..., None] * n[None]
        inside = np.ones(h.shape, dtype=bool)
        for u, v in ((a, b), (b, c), (c, a)):
            inside &= np.einsum("ijk,jk->ij", np.cross(v - u, foot - u[None]), n) >= 0.0
        best = np.where(inside, np.abs(h), np.inf)
        for u, v in ((a, b), (b, c), (c, a)):
            e = v - u
            t = np.clip(np.einsum("ijk,jk->ij", p - u[None], e) / np.einsum("jk,jk->j", e, e),
                        0.0, 1.0)
            best = np.minimum(best, np.linalg.norm(p - u[None] - t[..., None] * e[None],
                                                   axis=2))
        out[k0:k0 + 256] = best.min(axis=1)
    return out


def facet_cells(facets: np.ndarray, tets: np.ndarray, nnode: int) -> np.ndarray:
    """The tetrahedron (row of tets) each facet is a face of, -1 where none is."""
    faces = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]],
                            tets[:, [1, 2, 3]]])
    owner = np.tile(np.arange(tets.shape[0]), 4)
    n = int(nnode) + 1

    def code(t):
        t = np.sort(t, axis=1).astype(np.int64)
        return (t[:, 0] * n + t[:, 1]) * n + t[:, 2]

    fk = code(faces)
    order = np.argsort(fk)
    fk, owner = fk[order], owner[order]
    q = code(facets)
    i = np.clip(np.searchsorted(fk, q), 0, fk.size - 1)
    return np.where(fk[i] == q, owner[i], -1)


def raster_axes(x: np.ndarray, step: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The raster of overlap_3d for points x (n, 3): the bounding box grown by a step,
    shifted by irrational fractions of a step so that no column passes through a vertex or
    an edge of a lattice-aligned surface; its x, y and z coordinates."""
    lo = x.min(axis=0) - step
    hi = x.max(axis=0) + step
    shift = step * np.array([0.5 + 0.0618034, 0.5 + 0.0414214, 0.5 + 0.0732051])
    return tuple(np.arange(lo[k] + shift[k], hi[k], step) for k in range(3))


def overlap_3d(x: np.ndarray, facets: np.ndarray, step: float
               ) -> Tuple[float, float, np.ndarray]:
    """(overlap volume [m^3], overlap depth [m], centres of the doubly covered cells
    (k, 3)) of the closed triangle surface on a raster of the given step over its
    bounding box: the 3D form of overlap(), the winding number counted along vertical
    columns (raster_winding). The raster is shifted by irrational fractions of a step so
    that no column passes through a vertex or an edge of a lattice-aligned surface."""
    xs, ys, zs = raster_axes(x, step)
    w = raster_winding(x, facets, xs, ys, zs)
    ii, jj, kk = np.nonzero(w >= 2)
    if ii.size == 0:
        return 0.0, 0.0, np.zeros((0, 3))
    hit = np.column_stack([xs[ii], ys[jj], zs[kk]])
    volume = hit.shape[0] * step ** 3
    depth = 2.0 * float(distance_to_facets(x, facets, hit).max())
    return volume, depth, hit


def body_overlap(b, x: np.ndarray, step: float) -> Tuple[float, float, np.ndarray]:
    """overlap() of a 2D body's boundary loops, or overlap_3d() of a 3D body's facets, at
    the physical positions x (np, ndim)."""
    if b.ndim == 3:
        return overlap_3d(np.asarray(x, dtype=float), b.facets, step)
    return overlap(b.polylines(x=x), step)


def default_step_fraction(ndim: int) -> float:
    """The raster step as a fraction of the spacing: 1/20 in the plane, 1/4 in 3D (a raster
    125 times coarser in points; an overlap thinner than a quarter spacing reads as zero)."""
    return 0.25 if ndim == 3 else 0.05


def run_overlap(path: str, body: str | None = None, step_fraction: float | None = None):
    """[(label, time, area, depth)] for every snapshot of a body of an mfcd run."""
    out = []
    with MfcdFile(path) as f:
        if body is None:
            # the self-contact body, else the only body that has snapshots
            names = f.self_contact_bodies()
            if not names and f.snapshot_labels():
                names = list(f.snapshot(f.snapshot_labels()[0]).bodies)
            if len(names) != 1:
                raise SystemExit(f"{path}: give --body, one of {names}")
            body = names[0]
        b = f.body(body)
        frac = step_fraction or default_step_fraction(b.ndim)
        step = frac * float(np.min(np.atleast_1d(b.attrs["spacing"])[:2]))
        for lab in f.snapshot_labels():
            s = f.snapshot(lab)
            area, depth, _ = body_overlap(b, s.bodies[b.name].x, step)
            out.append((lab, s.time, area, depth))
    return out, step


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--body", default=None,
                    help="the body (default: the self-contact body, or the only deformable one)")
    ap.add_argument("--step-fraction", type=float, default=None,
                    help="raster step as a fraction of the body's spacing (default 0.05 in "
                    "2D, 0.25 in 3D)")
    a = ap.parse_args(argv)
    rows, step = run_overlap(a.file, a.body, a.step_fraction)
    print(f"# raster step {step:.3e} m")
    print("# label  time [s]  overlap area [m^2] (3D: volume [m^3])  overlap depth [m]")
    for lab, t, area, depth in rows:
        print(f"{lab:8s} {t:.4e} {area:.4e} {depth:.4e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
