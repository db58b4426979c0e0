"""Self-interpenetration of a deformed 2D body, measured from its boundary polylines alone.

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


def run_overlap(path: str, body: str | None = None, step_fraction: float = 0.05):
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
        step = step_fraction * float(np.min(np.atleast_1d(b.attrs["spacing"])[:2]))
        for lab in f.snapshot_labels():
            s = f.snapshot(lab)
            area, depth, _ = overlap(b.polylines(x=s.bodies[b.name].x), step)
            out.append((lab, s.time, area, depth))
    return out, step


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--body", default=None,
                    help="the body (default: the self-contact body, or the only deformable one)")
    ap.add_argument("--step-fraction", type=float, default=0.05,
                    help="raster step as a fraction of the body's spacing (default 0.05)")
    a = ap.parse_args(argv)
    rows, step = run_overlap(a.file, a.body, a.step_fraction)
    print(f"# raster step {step:.3e} m")
    print("# label  time [s]  overlap area [m^2]  overlap depth [m]")
    for lab, t, area, depth in rows:
        print(f"{lab:8s} {t:.4e} {area:.4e} {depth:.4e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
