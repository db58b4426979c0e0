#!/usr/bin/env python3
"""Gravity and an initial spin (issue 22, item 4) against closed forms, on a free elastic
steel block (20 x 10 mm, RKPM with SCNI and CST4 elements) and a free elastic steel disk
(&body shape = 'disk', radius 5 mm at spacing 0.5 mm: ten rings of particles, SCNI over
their annular-sector cells), no contact, no condition:

- free fall under &run gravity = 0, -9.81e6 m/s^2 (a large g, so the fall is many
  round-offs deep in 20 us): every particle's displacement is g t^2/2 and its velocity g t
  (velocity Verlet integrates a constant acceleration exactly: to 1e-9 of the fall, the
  round-off of the sums over 200 steps), the body's momentum M g t (/history/bodies) to
  1e-12, the block unstrained (stress below 1e-6 of rho g L, what round-off leaves), and
  the energy balance ke = w_ext (gravity's work) with the residual below 1e-9 of it;
- a spin, &body angular_velocity = 2000 rad/s: the angular momentum about the centre of
  mass constant to 1e-9 of its value over 20 us (the total-Lagrangian internal forces
  exert no moment; round-off), its value at t = 0 I omega with I = M (a^2 + b^2)/12 of the
  rectangle within 2%: the lumped masses' second moment exceeds the continuum's by O(h^2)
  (measured, RKPM: 5.5, 1.49, 0.39, 0.098% at h = 2, 1, 0.5, 0.25 mm; CST4: 1.6, 0.40,
  0.10, 0.025%; 21 x 11 particles here, h = 1 mm); the disk's I = M R^2/2 with its mass
  M = rho x the sum of the cell areas (the inscribed polygon's) within 2%: the last ring's
  particles sit on the circle with the mass of the half ring inside it, so the lumped
  second moment is high by O(h/R) (measured +1.21% at h/R = 0.1); the
  momentum 0 to 1e-12 of M omega a, and the energy residual below 1e-6 of ke(0);
- sliding with Coulomb friction (the block at 3 m/s along a rigid floor under gravity
  g = 1e5 m/s^2, mu = 0.3; issue 22, item 5): while every contact particle slides, each
  friction force is mu times its normal force, so p_x + mu p_y = M v0 - mu M g t exactly
  (the vertical momentum takes the normal impulse beyond M g t: the block rocks on the
  floor), checked to 1e-12 of M v0 over the first 50 us (local sticking starts at about
  65 us); the block stops near v0/(mu g) = 100 us (within 15%: it rocks, and its last
  particles stick); the pair's friction work /history/contacts/contact1/w_friction is
  negative, within 10% of -M v0^2/2 at the end (what it dissipates; the rest of the
  kinetic energy goes into vibration and the normal stops) and within 6% of -int F_t v dt
  (the mean friction force times the body's velocity: the bottom particles slip a little
  slower than the centre of mass as the block pitches); with mu = 0 the friction work is
  0 and p_x stays M v0 to round-off;
- a spin in axisymmetry, or on a rigid body, is refused (exit 2) naming angular_velocity;
  a radial gravity in axisymmetry is refused naming gravity.

Usage: check_body_motion.py MFCD
"""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
A, B, RHO = 0.02, 0.01, 7800.0
G, OMEGA, T_END = -9.81e6, 2000.0, 20.0e-6
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(f"[{'  OK  ' if cond else 'FAILED'}] {name}" + ("" if cond else f": {detail}"))


R_DISK, H_DISK = 0.005, 0.0005


def shape(disc, geometry):
    """The &body lines that make the body: the block (disc 'rkpm' or 'fem') or the disk."""
    if disc == "disk":
        return f"""  shape = 'disk'
  center = {0.006 if geometry == 'axisymmetric' else 0.0}, 0.0
  radius = {R_DISK}
  spacing = {H_DISK}
  discretization = 'rkpm'"""
    return f"""  shape = 'rectangle'
  lo = {0.001 if geometry == 'axisymmetric' else -A / 2}, {-B / 2}
  hi = {A / 2}, {B / 2}
  n = 21, 11
  discretization = '{disc}'"""


def deck(disc, gravity="0.0, 0.0", spin=0.0, geometry="plane", role="deformable"):
    return f"""&run
  mode = 'dynamic'
  ndim = 2
  geometry = '{geometry}'
  gravity = {gravity}
/
&material
  name = 'steel'
  model = 'elastic'
  density = {RHO}
  youngs_modulus = 200.0e9
  poisson_ratio = 0.3
/
&body
  name = 'block'
{shape(disc, geometry)}
  material = 'steel'
  role = '{role}'
  angular_velocity = {spin}
/
&solver
  t_end = {T_END}
  history_every = 1
  snapshot_times = 0.0, {T_END}
/
&output
  file = 'out.h5'
/
"""


def run(work, tag, text, code=0):
    d = os.path.join(work, tag)
    os.makedirs(d)
    open(os.path.join(d, "deck.nml"), "w").write(text)
    p = subprocess.run([MFCD, "deck.nml"], cwd=d, capture_output=True, text=True, timeout=600)
    check(f"{tag}: exit {code}", p.returncode == code, p.stdout[-800:] + p.stderr[-800:])
    return os.path.join(d, "out.h5"), p


def free_fall(work, disc):
    path, p = run(work, f"fall_{disc}", deck(disc, gravity=f"0.0, {G}"))
    if p.returncode:
        return
    with MfcdFile(path) as f:
        h, body = f.history(), f.body_history("block")
        lab = sorted(f.snapshot_labels())[-1]
        s = f.snapshot(lab)
        t = s.time
        b = s.bodies["block"]
    fall = 0.5 * G * t**2
    err_u = max(np.max(np.abs(b.u[:, 1] - fall)), np.max(np.abs(b.u[:, 0]))) / abs(fall)
    check(f"fall_{disc}: u = g t^2/2 at every particle ({err_u:.1e} of the fall)",
          err_u < 1e-9, err_u)
    err_v = max(np.max(np.abs(b.v[:, 1] - G * t)), np.max(np.abs(b.v[:, 0]))) / abs(G * t)
    check(f"fall_{disc}: v = g t ({err_v:.1e})", err_v < 1e-9, err_v)
    m = mass(path, disc)
    p_err = abs(body["momentum_y"][-1] - m * G * h["time"][-1]) / abs(m * G * h["time"][-1])
    check(f"fall_{disc}: momentum M g t ({p_err:.1e})", p_err < 1e-12, p_err)
    smax = np.max(np.abs(b.stress)) / (RHO * abs(G) * A)
    check(f"fall_{disc}: unstrained ({smax:.1e} of rho g L)", smax < 1e-6, smax)
    bal = abs(h["ke"][-1] - h["w_ext"][-1]) / h["w_ext"][-1]
    res = np.max(np.abs(h["residual"])) / h["w_ext"][-1]
    check(f"fall_{disc}: ke = w_ext ({bal:.1e}), residual {res:.1e} of it",
          bal < 1e-9 and res < 1e-9, (bal, res))


SLIDE_G, SLIDE_MU, SLIDE_V0, SLIDE_T = 1.0e5, 0.3, 3.0, 120.0e-6


def slide_deck(mu):
    return f"""&run
  mode = 'dynamic'
  ndim = 2
  geometry = 'plane'
  gravity = 0.0, {-SLIDE_G}
/
&material
  name = 'steel'
  model = 'elastic'
  density = {RHO}
  youngs_modulus = 200.0e9
  poisson_ratio = 0.3
/
&body
  name = 'block'
  shape = 'rectangle'
  lo = 0.0, 0.0
  hi = {A / 2}, {B / 2}
  n = 21, 11
  material = 'steel'
  velocity = {SLIDE_V0}, 0.0
/
&body
  name = 'floor'
  role = 'rigid'
  shape = 'rectangle'
  lo = -0.005, -0.003
  hi = 0.05, 0.0
  n = 111, 7
/
&contact
  master = 'floor'
  slave = 'block'
  mu = {mu}
/
&solver
  t_end = {SLIDE_T}
  history_every = 1
/
&output
  file = 'out.h5'
/
"""


def slide(work):
    m = RHO * (A / 2) * (B / 2)
    path, p = run(work, "slide", slide_deck(SLIDE_MU))
    if not p.returncode:
        with MfcdFile(path) as f:
            h, body = f.history(), f.body_history("block")
        t, px, py = h["time"], body["momentum_x"], body["momentum_y"]
        wf = h["contacts/contact1/w_friction"]
        early = t <= 50e-6
        ident = np.max(np.abs(px + SLIDE_MU * py - (m * SLIDE_V0 - SLIDE_MU * m * SLIDE_G * t))[
            early]) / (m * SLIDE_V0)
        check(f"slide: p_x + mu p_y = M v0 - mu M g t while sliding ({ident:.1e} < 1e-12)",
              ident < 1e-12, ident)
        vx = px / m
        stop = t[np.argmax(vx < 0.02 * SLIDE_V0)] if np.any(vx < 0.02 * SLIDE_V0) else np.inf
        t_s = SLIDE_V0 / (SLIDE_MU * SLIDE_G)
        check(f"slide: stops at {stop * 1e6:.1f} us, v0/(mu g) = {t_s * 1e6:.1f} us "
              "(within 15%)", abs(stop / t_s - 1) < 0.15, stop)
        ke0 = 0.5 * m * SLIDE_V0**2
        check(f"slide: friction work {wf[-1]:.4f} J/m within 10% of -M v0^2/2 = {-ke0:.4f}",
              wf[-1] < 0 and abs(wf[-1] / -ke0 - 1) < 0.10, wf[-1])
        check("slide: friction work never grows", np.all(np.diff(wf) <= 1e-12 * ke0),
              np.max(np.diff(wf)))
        ft = h["contacts/contact1/force_tangential"]
        approx = -np.sum(ft[1:] * 0.5 * (vx[1:] + vx[:-1]) * np.diff(t))
        check(f"slide: friction work within 6% of -int F_t v dt = {approx:.4f}",
              abs(wf[-1] / approx - 1) < 0.06, wf[-1] / approx)
    path, p = run(work, "slide_mu0", slide_deck(0.0))
    if not p.returncode:
        with MfcdFile(path) as f:
            h, body = f.history(), f.body_history("block")
        wf = h["contacts/contact1/w_friction"]
        dp = np.max(np.abs(body["momentum_x"] - m * SLIDE_V0)) / (m * SLIDE_V0)
        check(f"slide_mu0: no friction work, p_x = M v0 ({dp:.1e})",
              np.all(wf == 0.0) and dp < 1e-12, (wf[-1], dp))


def mass(path, disc):
    """The body's mass: rho A B for the block, rho x the disk's cell areas (the inscribed
    polygon's), which must be within 0.2% of pi R^2 at this spacing."""
    if disc != "disk":
        return RHO * A * B
    with MfcdFile(path) as f:
        area = f.body("block").volume.sum()
    e = area / (np.pi * R_DISK**2) - 1
    check(f"disk: cell areas sum to pi R^2 ({e:+.1e}, within 2e-3)", abs(e) < 2e-3, e)
    return RHO * area


def spin(work, disc):
    path, p = run(work, f"spin_{disc}", deck(disc, spin=OMEGA))
    if p.returncode:
        return
    with MfcdFile(path) as f:
        h, body = f.history(), f.body_history("block")
    L = body["angular_momentum"]
    m = mass(path, disc)
    i_closed = m * R_DISK**2 / 2.0 if disc == "disk" else m * (A**2 + B**2) / 12.0
    e0 = L[0] / (i_closed * OMEGA) - 1
    what = "disk" if disc == "disk" else "rectangle"
    check(f"spin_{disc}: L(0) = I omega of the {what} ({e0:+.2%}, within 2%)",
          abs(e0) < 0.02, e0)
    drift = np.max(np.abs(L - L[0])) / abs(L[0])
    check(f"spin_{disc}: angular momentum constant ({drift:.1e} < 1e-9)", drift < 1e-9,
          drift)
    pm = max(np.max(np.abs(body["momentum_x"])), np.max(np.abs(body["momentum_y"])))
    check(f"spin_{disc}: no momentum ({pm / (m * OMEGA * A):.1e} of M omega a)",
          pm < 1e-12 * m * OMEGA * A, pm)
    res = np.max(np.abs(h["residual"])) / h["ke"][0]
    check(f"spin_{disc}: energy residual {res:.1e} of ke(0) < 1e-6", res < 1e-6, res)


def main():
    with tempfile.TemporaryDirectory() as work:
        for disc in ("rkpm", "fem", "disk"):
            free_fall(work, disc)
            spin(work, disc)
        slide(work)
        _, p = run(work, "spin_axisymmetric", deck("fem", spin=OMEGA,
                                                    geometry="axisymmetric"), code=2)
        check("spin in axisymmetry: names angular_velocity",
              "angular_velocity" in p.stderr, p.stderr[-400:])
        _, p = run(work, "gravity_radial", deck("fem", gravity=f"{G}, 0.0",
                                                 geometry="axisymmetric"), code=2)
        check("radial gravity in axisymmetry: names gravity", "gravity" in p.stderr,
              p.stderr[-400:])
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
