#!/usr/bin/env python3
"""Hertz impact of an elastic sphere on a rigid wall: an mfcd run against the closed forms.

For a sphere of radius R and mass m striking a rigid wall at speed v, with E* = E/(1-nu^2)
(Johnson, Contact Mechanics, ch. 11; the quasi-static Hertz law F = 4/3 E* sqrt(R)
delta^(3/2) integrated over the impact):

    delta_max = (15 m v^2 / (16 E* sqrt(R)))^(2/5)     largest approach
    F_max     = 4/3 E* sqrt(R) delta_max^(3/2)         peak force
    a_max     = sqrt(R delta_max)                      largest contact radius
    t_c       = 2.9432 delta_max / v                   contact time

From the run's /history, read through post/mfcd_h5.py: the contact force f_contact (N, the
whole revolution in axisymmetry), the contacting particles n_contact and the largest radius
in contact contact_radius. The approach is the distance the sphere's centre of mass has
travelled towards the wall since first contact, from its momentum: m dv/dt = -F, so
delta(t) = v (t - t0) - int_t0^t (1/m) int_t0^s F dt ds. m comes from the run's initial
kinetic energy (the body's own mass, not the exact sphere's). Contact time: first to last
step with a contacting particle.

    .venv/bin/python post/hertz_impact.py output/hertz_sphere_fem.h5 [more.h5 ...] \\
        [--radius 5e-3] [--speed 5] [--table output/hertz_sphere.md]
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


def measure(path, radius, speed=None):
    """The run's measures (same keys as hertz()) and its Hertz values, mass, material."""
    with MfcdFile(path) as f:
        h = f.history()
        mat = deck_group(f.deck, "material") or {}
        body = deck_group(f.deck, "body", role="deformable") or deck_group(f.deck, "body") or {}
        title = f.title
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
    ref = hertz(m, radius, v, float(mat.get("youngs_modulus", 211e9)),
                float(mat.get("poisson_ratio", 0.3)))
    # the speed away from the wall at the end, from the momentum the contact gave back
    rebound = float(impulse[-1] / m - v)
    return {"title": title, "mass": m, "speed": v, "got": got, "hertz": ref,
            "energy": energy, "rebound": rebound}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--radius", type=float, default=5e-3, help="sphere radius (m)")
    ap.add_argument("--speed", type=float, default=None,
                    help="impact speed (m/s; default from the deck's &body velocity)")
    ap.add_argument("--table", default=None, help="also write the Markdown table here")
    a = ap.parse_args(argv)
    lines = ["| run | mass (g) | approach (um) | peak force (N) | contact radius (mm) | "
             "contact time (us) | energy residual |", "|---|---|---|---|---|---|---|"]
    for path in a.files:
        r = measure(path, a.radius, a.speed)
        g, z = r["got"], r["hertz"]

        def cell(k, scale, fmt):
            return (fmt % (g[k] * scale)) + " (%+.1f%%)" % (100.0 * (g[k] / z[k] - 1.0))
        lines.append("| %s | %.4f | %s | %s | %s | %s | %.1e |" % (
            path, 1e3 * r["mass"], cell("delta", 1e6, "%.2f"), cell("force", 1.0, "%.0f"),
            cell("radius", 1e3, "%.3f"), cell("time", 1e6, "%.2f"), r["energy"]))
    z = r["hertz"]
    lines.append("| Hertz (last run's mass) | | %.2f | %.0f | %.3f | %.2f | |" % (
        1e6 * z["delta"], z["force"], 1e3 * z["radius"], 1e6 * z["time"]))
    print("\n".join(lines))
    if a.table:
        with open(a.table, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
