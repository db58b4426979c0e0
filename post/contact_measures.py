"""Contact measures from mfcd snapshots: interface pressure, gap, Hertz line contact.

Used by bench/contact_patch.py (the convergence study) and tests/regression/
check_patch_test.py. The pressure on a surface particle is its mean contact force since
the previous snapshot (`/snapshots/<label>/<body>/f_contact`, doc/output.md) divided by
its tributary length along the surface: half the distance between its neighbours, half
the distance to its one neighbour at an end.

    import sys; sys.path.insert(0, "post")
    from contact_measures import surface_row, pressure, vertical_gap, hertz_line
"""

from __future__ import annotations

import numpy as np

__all__ = ["surface_row", "tributary", "pressure", "vertical_gap", "hertz_line",
           "edge_half_width", "fit_half_width", "observed_order"]


def surface_row(f, label, body, y0=0.0):
    """The particles of `body` whose reference y is y0 (a flat surface row), sorted by x:
    (indices, physical positions (n, 2) in m, f_contact (n, 2) in N/m) at snapshot label.
    f: an open mfcd_h5.MfcdFile."""
    X = f.body(body).x
    tol = 1e-9 * max(1.0, float(np.abs(X).max()))     # round-off of the generated lattice
    idx = np.nonzero(np.abs(X[:, 1] - y0) <= tol)[0]
    s = f.snapshot(label).bodies[body]
    x, fc = s.x[idx], s.f_contact[idx]
    o = np.argsort(x[:, 0])
    return idx[o], x[o], fc[o]


def tributary(xs):
    """Tributary lengths (m) of points at the sorted abscissae xs."""
    t = np.empty_like(xs)
    t[1:-1] = 0.5 * (xs[2:] - xs[:-2])
    t[0] = 0.5 * (xs[1] - xs[0])
    t[-1] = 0.5 * (xs[-1] - xs[-2])
    return t


def pressure(x, fc, sign=1.0):
    """Contact pressure (Pa) at the surface particles x (n, 2) with forces fc (n, 2):
    sign * f_y / tributary length (sign = +1 for a body pushed up, -1 pushed down)."""
    return sign * fc[:, 1] / tributary(x[:, 0])


def vertical_gap(points, surface):
    """Signed vertical gap (m) of points (n, 2) above the polyline through surface (k, 2),
    sorted by x: > 0 separated, < 0 penetrated (for a body lying above the surface)."""
    return points[:, 1] - np.interp(points[:, 0], surface[:, 0], surface[:, 1])


def hertz_line(P, R, Estar):
    """Hertz line contact (Johnson, Contact Mechanics, 1985, Sec. 4.3): half-width
    a = sqrt(4 P R / (pi E*)) and peak pressure p0 = 2 P / (pi a) for the load P per unit
    length (N/m), radius R (m) and contact modulus E* (1/E* = sum (1 - nu^2)/E)."""
    a = np.sqrt(4.0 * P * R / (np.pi * Estar))
    return a, 2.0 * P / (np.pi * a)


def edge_half_width(xs, p):
    """Contact half-width from the outermost loaded particles (xs >= 0 sorted, p their
    pressures): near the edge of an elliptic profile p^2 is linear in (a - x), so p^2 of the
    last two loaded particles is extrapolated to zero."""
    on = np.nonzero(p > 1e-6 * p.max())[0]      # loaded: above round-off of the peak
    k = on[-1]
    if k == 0 or not p[k - 1] > p[k]:
        return xs[k]
    return xs[k] + p[k] ** 2 * (xs[k] - xs[k - 1]) / (p[k - 1] ** 2 - p[k] ** 2)


def fit_half_width(xs, p):
    """Contact half-width from a least-squares fit of p^2 = p0^2 (1 - x^2/a^2) over the
    loaded particles (the Hertz shape assumed, every loaded particle used)."""
    on = p > 1e-6 * p.max()
    A = np.c_[np.ones(on.sum()), xs[on] ** 2]
    c = np.linalg.lstsq(A, p[on] ** 2, rcond=None)[0]
    return float(np.sqrt(-c[0] / c[1])) if c[1] < 0 and c[0] > 0 else float("nan")


def observed_order(e1, e2, h1, h2):
    """log(e1/e2) / log(h1/h2): the observed order of an error e ~ h^q."""
    if not (e1 > 0 and e2 > 0):
        return float("nan")
    return float(np.log(e1 / e2) / np.log(h1 / h2))
