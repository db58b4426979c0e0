#!/usr/bin/env python3
"""Hertz impact of an elastic sphere (axisymmetric or in full 3D) or cylinder (plane strain)
on a rigid wall: an mfcd run against the closed forms.

Sphere (the run's geometry 'axisymmetric', or a 3D run: ndim = 3).

For a sphere of radius R and mass m striking a rigid wall at speed v, with E* = E/(1-nu^2)
(Johnson, Contact Mechanics, ch. 11; the quasi-static Hertz law F = 4/3 E* sqrt(R)
delta^(3/2) integrated over the impact):

    delta_max = (15 m v^2 / (16 E* sqrt(R)))^(2/5)     largest approach
    F_max     = 4/3 E* sqrt(R) delta_max^(3/2)         peak force
    a_max     = sqrt(R delta_max)                      largest contact radius
    t_c       = 2.9432 delta_max / v                   contact time

From the run's /history, read through post/mfcd_h5.py: the contact force f_contact (N, the
whole revolution in axisymmetry), the contacting particles n_contact and the largest radius
in contact contact_radius (in 3D the largest x of a node in contact: the sphere's pole is
on the z axis). The approach is the distance the sphere's centre of mass has
travelled towards the wall since first contact, from its momentum: m dv/dt = -F, so
delta(t) = v (t - t0) - int_t0^t (1/m) int_t0^s F dt ds. m comes from the run's initial
kinetic energy (the body's own mass, not the exact sphere's). Contact time: first to last
step with a contacting particle.

Cylinder (the run's geometry 'plane': plane strain, everything per unit length; the
cross-section is the whole disk). Line contact of a cylinder of radius R on a rigid flat
under a force P per unit length (Johnson, Contact Mechanics, 1985, ch. 4 and 5): contact
half-width b = sqrt(4 P R / (pi E*)), pressure p0 sqrt(1 - x^2/b^2), p0 = 2 P / (pi b).
The approach in 2D is logarithmic and depends on where it is measured and on how the body
is held. Here the body is held by its own inertia
(a uniform body force -P/A balancing the contact force) and the approach is that of its
centre of mass, which is what the momentum measure above gives:

    delta(P) = P / (pi E*) * (2 ln(2 R / b) - 1 / (4 (1 - nu)))
             = P / (pi E*) * (ln(pi E* R / P) - 1 / (4 (1 - nu)))

derived in doc/verification.md (Flamant's point force at the contact point, a uniform
pressure and a linear stress field that takes the body force, the Hertz pressure for the
local correction; the same steps for a disk squeezed between two flats give Johnson's
approach of its centre, delta = P / (pi E*) (2 ln(4 R / b) - 1), ch. 5). The work of the
contact force, W(P) = int P d(delta) = P^2 / (2 pi E*) (ln(pi E* R / P) - c - 1/2) with
c = 1/(4 (1 - nu)), takes the kinetic energy: W(P_max) = m v^2 / 2 gives the peak force
(bisection); delta_max = delta(P_max), b_max = b(P_max), and the contact time
t_c = 2 int_0^P_max delta'(P) dP / sqrt(v^2 - 2 W(P) / m), by Gauss-Legendre in
theta with P = P_max sin(theta), theta = (pi/2) u^2 (smooth at both ends: the turning point
and the logarithm at P = 0). The measures are those of the sphere; contact_radius in
/history is the largest x of a particle in contact, so the half-width on the x > 0 side.

    .venv/bin/python post/hertz_impact.py output/hertz_sphere_fem.h5 [more.h5 ...] \\
        [--radius 5e-3] [--speed 5] [--table output/hertz_sphere.md] \\
        [--plot doc/figures/hertz.png --labels NAME ...]

--plot draws each run's contact force against the time since its first contact and, for
spheres, Hertz's quasi-static history (m delta'' = -K delta^(3/2) integrated by RK4 for the
first run's mass and speed).
"""
import argparse
import math
import sys

import numpy as np

from mfcd_h5 import MfcdFile, deck_group


def hertz(m, radius, v, e, nu):
    """The closed forms above for mass m (kg), radius (m), speed v (m/s), E (Pa), nu."""
    es = e / (1.0 - nu * nu)
    d = (15.0 * m * v * v / (16.0 * es * math.sqrt(radius))) ** 0.4
    return {"delta": d, "force": 4.0 / 3.0 * es * math.sqrt(radius) * d ** 1.5,
            "radius": math.sqrt(radius * d), "time": 2.9432 * d / v}


def line_contact(m, radius, v, e, nu, c=None, n=200):
    """The plane-strain closed forms above for mass m (kg/m), radius (m), speed v (m/s), E
    (Pa), nu: delta (m), force (N/m), radius (the half-width b, m), time (s). c: the
    constant of delta(P) = P / (pi E*) (ln(pi E* R / P) - c), 1/(4 (1 - nu)) by default
    (1 - 2 ln 2 gives Johnson's diametral compression, ch. 5: for comparison only)."""
    es = e / (1.0 - nu * nu)
    k = math.pi * es * radius
    c = 0.25 / (1.0 - nu) if c is None else c

    def work(p):
        return p * p / (2.0 * math.pi * es) * (np.log(k / p) - c - 0.5)
    ke = 0.5 * m * v * v
    lo, hi = 0.0, k * math.exp(-(c + 1.0))   # W(P) rises up to hi
    if work(hi) <= ke:
        raise ValueError("line_contact: the kinetic energy is beyond the closed form's range")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if work(mid) < ke else (lo, mid)
    p = 0.5 * (lo + hi)
    g, w = np.polynomial.legendre.leggauss(n)
    u, wu = 0.5 * (g + 1.0), 0.5 * w
    th, dth = 0.5 * math.pi * u * u, math.pi * u * wu
    q = p * np.sin(th)
    ddelta = (np.log(k / q) - 1.0 - c) / (math.pi * es)
    t = 2.0 * float(np.sum(ddelta * p * np.cos(th) * dth
                           / np.sqrt(np.maximum(v * v - 2.0 * work(q) / m, 0.0))))
    return {"delta": p / (math.pi * es) * (math.log(k / p) - c), "force": p,
            "radius": math.sqrt(4.0 * p * radius / (math.pi * es)), "time": t}


def measure(path, radius, speed=None):
    """The run's measures (same keys as hertz()) and its Hertz values, mass, material."""
    with MfcdFile(path) as f:
        h = f.history()
        mat = deck_group(f.deck, "material") or {}
        body = deck_group(f.deck, "body", role="deformable") or deck_group(f.deck, "body") or {}
        title = f.title
        # a 3D run (its geometry attribute says 'plane') is a whole sphere
        geometry = "3d" if int(f.attrs.get("ndim", 2)) == 3 else f.geometry
        energy = f.summary["energy_residual"] / f.summary["energy_scale"]
    v = speed if speed else abs(float(np.atleast_1d(body.get("velocity", [0, -5]))[-1]))
    t, force, n = h["time"], h["f_contact"], h["n_contact"]
    m = 2.0 * h["ke"][0] / v ** 2
    on = np.nonzero(n > 0)[0]
    t0, t1 = t[on[0]], t[on[-1]]
    dt = np.diff(t, prepend=t[0])
    impulse = np.cumsum(force * dt)
    travel = np.cumsum((v - impulse / m) * dt)
    delta = travel - np.interp(t0, t, travel)
    got = {"delta": float(delta.max()), "force": float(force.max()),
           "radius": float(np.max(h["contact_radius"])), "time": float(t1 - t0)}
    ref = (line_contact if geometry == "plane" else hertz)(
        m, radius, v, float(mat.get("youngs_modulus", 211e9)),
        float(mat.get("poisson_ratio", 0.3)))
    # the speed away from the wall at the end, from the momentum the contact gave back
    rebound = float(impulse[-1] / m - v)
    return {"title": title, "geometry": geometry, "mass": m, "speed": v, "got": got,
            "hertz": ref, "energy": energy, "rebound": rebound}


def hertz_history(m, radius, v, e, nu, n=4000):
    """Hertz's quasi-static impact as a history: m delta'' = -K delta^(3/2), K = 4/3 E*
    sqrt(R), from delta = 0 at speed v until delta returns to 0 (RK4 in n steps of the
    closed form's contact time, a little past it). Times (s) and forces (N)."""
    k = 4.0 / 3.0 * e / (1.0 - nu * nu) * math.sqrt(radius)
    tc = hertz(m, radius, v, e, nu)["time"]
    h = 1.02 * tc / n

    def acc(d):
        return -k * max(d, 0.0) ** 1.5 / m
    t, d, u = [0.0], 0.0, v
    f = [0.0]
    for _ in range(n):
        k1d, k1u = u, acc(d)
        k2d, k2u = u + 0.5 * h * k1u, acc(d + 0.5 * h * k1d)
        k3d, k3u = u + 0.5 * h * k2u, acc(d + 0.5 * h * k2d)
        k4d, k4u = u + h * k3u, acc(d + h * k3d)
        d += h / 6.0 * (k1d + 2 * k2d + 2 * k3d + k4d)
        u += h / 6.0 * (k1u + 2 * k2u + 2 * k3u + k4u)
        t.append(t[-1] + h)
        f.append(k * max(d, 0.0) ** 1.5)
        if d < 0.0:
            break
    return np.array(t), np.array(f)


def plot(runs, labels, path, radius):
    """The contact force of each run against the time since its first contact, and Hertz's
    quasi-static history for the first run's mass and speed (spheres)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mfcd_style import figure_style
    plt.rcParams.update(figure_style(savefig_dpi=150))
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for (p, r), label in zip(runs, labels):
        with MfcdFile(p) as f:
            h = f.history()
        on = np.nonzero(h["n_contact"] > 0)[0]
        t0 = h["time"][on[0]]
        ax.plot((h["time"] - t0) * 1e6, h["f_contact"] * 1e-3, lw=1.2, label=label)
    r0 = runs[0][1]
    if r0["geometry"] != "plane":
        with MfcdFile(runs[0][0]) as f:
            mat = deck_group(f.deck, "material") or {}
        th, fh = hertz_history(r0["mass"], radius, r0["speed"],
                               float(mat.get("youngs_modulus", 211e9)),
                               float(mat.get("poisson_ratio", 0.3)))
        ax.plot(th * 1e6, fh * 1e-3, "k--", lw=1.0, label="Hertz (quasi-static)")
    ax.set_xlim(left=-0.5)
    ax.set_xlabel("time since first contact (us)")
    ax.set_ylabel("contact force (kN)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def table(runs):
    """Markdown table of [(path, measure(...)), ...], one geometry."""
    def cell(r, k, scale, fmt):
        g, z = r["got"], r["hertz"]
        return (fmt % (g[k] * scale)) + " (%+.1f%%)" % (100.0 * (g[k] / z[k] - 1.0))
    if runs[0][1]["geometry"] == "plane":
        lines = ["| run | mass (kg/m) | approach (um) | peak force (kN/m) | contact half-width "
                 "(mm) | contact time (us) | rebound (m/s) | energy residual |",
                 "|---|---|---|---|---|---|---|---|"]
        for path, r in runs:
            lines.append("| %s | %.4f | %s | %s | %s | %s | %.3f | %.1e |" % (
                path, r["mass"], cell(r, "delta", 1e6, "%.2f"),
                cell(r, "force", 1e-3, "%.1f"), cell(r, "radius", 1e3, "%.4f"),
                cell(r, "time", 1e6, "%.2f"), r["rebound"], r["energy"]))
        z = runs[-1][1]["hertz"]
        lines.append("| line contact (last run's mass) | | %.2f | %.1f | %.4f | %.2f | | |" % (
            1e6 * z["delta"], 1e-3 * z["force"], 1e3 * z["radius"], 1e6 * z["time"]))
        return lines
    lines = ["| run | mass (g) | approach (um) | peak force (N) | contact radius (mm) | "
             "contact time (us) | energy residual |", "|---|---|---|---|---|---|---|"]
    for path, r in runs:
        lines.append("| %s | %.4f | %s | %s | %s | %s | %.1e |" % (
            path, 1e3 * r["mass"], cell(r, "delta", 1e6, "%.2f"), cell(r, "force", 1.0, "%.0f"),
            cell(r, "radius", 1e3, "%.3f"), cell(r, "time", 1e6, "%.2f"), r["energy"]))
    z = runs[-1][1]["hertz"]
    lines.append("| Hertz (last run's mass) | | %.2f | %.0f | %.3f | %.2f | |" % (
        1e6 * z["delta"], z["force"], 1e3 * z["radius"], 1e6 * z["time"]))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--radius", type=float, default=5e-3,
                    help="sphere or cylinder radius (m)")
    ap.add_argument("--speed", type=float, default=None,
                    help="impact speed (m/s; default from the deck's &body velocity)")
    ap.add_argument("--table", default=None, help="also write the Markdown table here")
    ap.add_argument("--plot", default=None,
                    help="also draw the contact forces against time (and Hertz's) here")
    ap.add_argument("--labels", nargs="+", default=None,
                    help="the runs' names in the plot (default: the file names)")
    a = ap.parse_args(argv)
    runs = [(path, measure(path, a.radius, a.speed)) for path in a.files]
    if len({r["geometry"] == "plane" for _, r in runs}) > 1:
        ap.error("give runs of one geometry: spheres (axisymmetric or 3D) or cylinders (plane)")
    lines = table(runs)
    print("\n".join(lines))
    if a.table:
        with open(a.table, "w") as f:
            f.write("\n".join(lines) + "\n")
    if a.plot:
        labels = a.labels or [p.rsplit("/", 1)[-1] for p in a.files]
        if len(labels) != len(runs):
            ap.error("give one label per file")
        plot(runs, labels, a.plot, a.radius)
    return 0


if __name__ == "__main__":
    sys.exit(main())
