#!/usr/bin/env python3
"""Rigid bodies with a prescribed velocity as contact masters (issue 22, item 4; doc/deck.md,
`&body velocity`; doc/contact.md, "A moving rigid master").

A rigid master moving at v is met where it is (its det(M), box and surface looked up at
x - v t) and the slip of eq. (90) is taken relative to it. Two independent checks:

1. Galilean invariance. A run with the ram moving at +V and the deformable body at rest is the
   fixed-target run with the body moving at -V seen from the target. So each case is run
   twice, the deck as it is (a fixed rigid target, the body at -V) and its twin (the body at
   rest, the target at +V), and the twin must give the same motion shifted by V:
     u_twin(t) = u(t) + V t and v_twin = v + V at every snapshot, within 1e-9 of the largest
        displacement (resp. of |V|): the two runs differ only in the rounding of the shifted
        lookups (x - V t, about 1e-17 m against displacements of 1e-5 m and more), and an
        error of one step in the ram's position would be dt V, 1e-3 of them or more;
     the contact force of every history row equal within 1e-9 of its largest value, and the
        same steps in contact.
   Cases: the elastic bar of input/ram_push.nml against input/bar_impact_elastic_coarse.nml
   (RKPM, plane strain, skip_far on); the CST4 bar (input/bar_impact_elastic_fem_coarse.nml);
   the subcycled CST4 Taylor bar (input/taylor_bar_fem_coarse_subcycle.nml, cut to 6 us),
   whose sub-steps meet the ram at their own times; the axisymmetric viscoplastic RKPM Taylor
   bar with friction (input/taylor_bar_rkpm_coarse.nml, cut to 8 us). That last one amplifies
   round-off: the same deck with both bodies moved by 1 mm along the axis (&body translate, a
   perturbation of the rounding only) already differs from it by about 1e-3 of the contact
   force after 8 us (stick and slip switching under a rate exponent 1/m = 100). There the
   twin must lie within 4 x that envelope of the fixed run (it lies within 0.7-1 x; a ram a
   step off would put the gaps dt V = 5e-7 m off, 100 x the gaps themselves).
2. Closed forms for input/ram_push.nml (a ram at 1 m/s striking an elastic bar at rest,
   nu = 0, one-dimensional): the ram transmits the momentum 2 m V (the bar leaves at 2 V),
   within 4% (as the fixed-wall run's rebound at this spacing: the first rows' inelastic
   stop, check_bar_impact.py); the bar's momentum at the end equals the sum of the pair's
   force history x dt (every step) to 1e-12 (round-off of 300 sums), independent of
   w_contact; the mean contact stress over the middle 60% of the contact within 5% of
   rho c0 V and the contact lasts 2 L / c0 within 3% (check_bar_impact.py's coarse
   tolerances); the energy balance closes (|residual| below 1e-3 of the scale) with the
   ram's work counted in w_contact (> 0: the ram puts energy in).
3. Output: the ram in every snapshot at /bodies/ram/x + V t (to 1e-15 m), with u = V t and
   v = V; /bodies/ram has role 'rigid' and its velocity; the XDMF grid of the ram at each
   time points at that snapshot's positions (a fixed rigid body's at /bodies/<name>/x).

Usage: check_rigid_ram.py /path/to/mfcd /path/to/source [--quick]
(--quick: the two elastic bars only, for a Debug build.)
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
SRC = os.path.abspath(sys.argv[2])
QUICK = "--quick" in sys.argv[3:]
REL = 1e-9   # Galilean twins: rounding of the shifted lookups only (module docstring)
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "rigid_ram." + name
          + ("" if cond else ": " + str(detail)[:1500]))


def run(text, name, work):
    """Run deck text as work/name.nml writing output/name.h5; the file's path or None."""
    text = re.sub(r"(?m)^\s*file\s*=.*$", f"  file = 'output/{name}.h5'", text)
    deck = os.path.join(work, name + ".nml")
    with open(deck, "w") as f:
        f.write(text)
    p = subprocess.run([MFCD, deck], cwd=work, capture_output=True, text=True, timeout=1200)
    if p.returncode:
        print(p.stdout[-3000:], p.stderr[-3000:])
        return None
    return os.path.join(work, "output", name + ".h5")


def groups(text):
    """The deck's groups as (name, start line, end line) over text.splitlines()."""
    out, cur, start = [], None, 0
    for i, line in enumerate(text.splitlines()):
        s = line.split("!")[0].strip()
        if cur is None and s.startswith("&"):
            cur, start = s[1:].split()[0].lower() if s[1:].split() else "", i
        elif cur is not None and s == "/":
            out.append((cur, start, i))
            cur = None
    return out


def twin(text, t_end=None):
    """The deck seen from its rigid target: the deformable body's velocity (0, -V) removed,
    the rigid body given (0, +V); V returned too. Optionally a shorter t_end, with the
    snapshots cut to it."""
    lines = text.splitlines()
    vel, rigid_end = None, None
    for name, a, b in groups(text):
        if name != "body":
            continue
        body = "\n".join(lines[a:b + 1])
        if re.search(r"role\s*=\s*'rigid'", body):
            rigid_end = b
            continue
        for i in range(a, b + 1):
            m = re.match(r"\s*velocity\s*=\s*([-+0-9.eE]+)\s*,\s*([-+0-9.eE]+)", lines[i])
            if m:
                vel = np.array([float(m.group(1)), float(m.group(2))])
                lines[i] = "  ! (velocity moved to the rigid body: the twin's frame)"
    assert vel is not None and rigid_end is not None, "deck without a moving body and a target"
    lines.insert(rigid_end, f"  velocity = {-vel[0] + 0.0:.17g}, {-vel[1] + 0.0:.17g}")
    out = "\n".join(lines) + "\n"
    if t_end is not None:
        out = re.sub(r"(?m)^\s*t_end\s*=.*$", f"  t_end = {t_end:.17g}", out)
        out = re.sub(r"(?m)^\s*snapshot_times\s*=.*$",
                     f"  snapshot_times = 0.0, {t_end / 2:.17g}, {t_end:.17g}", out)
    return out, -vel


def cut(text, t_end):
    """The deck with t_end and its snapshots cut to t_end (twin's cut, frame unchanged)."""
    text = re.sub(r"(?m)^\s*t_end\s*=.*$", f"  t_end = {t_end:.17g}", text)
    return re.sub(r"(?m)^\s*snapshot_times\s*=.*$",
                  f"  snapshot_times = 0.0, {t_end / 2:.17g}, {t_end:.17g}", text)


def translated(text, dz):
    """The deck with every body moved by dz along y (z) and the tracked edge with them."""
    text = re.sub(r"(?m)^(\s*&body\b.*)$", rf"\1\n  translate = 0.0, {dz:.17g}", text)
    return re.sub(r"(?m)^(\s*edge_point\s*=\s*[-+0-9.eE]+\s*,\s*)([-+0-9.eE]+)",
                  lambda m: m.group(1) + f"{float(m.group(2)) + dz:.17g}", text)


def differences(fixed, moving, vram):
    """The largest differences of the moving-ram run from the fixed-target one shifted by
    vram: (contact force, u, v), and the scales (largest force, |u|)."""
    with MfcdFile(fixed) as a, MfcdFile(moving) as b:
        ha, hb = a.history(), b.history()
        fmax = np.max(np.abs(ha["f_contact"]))
        df = np.max(np.abs(ha["f_contact"] - hb["f_contact"]))
        du_max, dv_max, umax = 0.0, 0.0, 0.0
        for lab in a.snapshot_labels():
            sa, sb = a.snapshot(lab), b.snapshot(lab)
            for n, ba in sa.bodies.items():
                bb = sb.bodies[n]
                du_max = max(du_max, np.max(np.abs(bb.u - ba.u - vram * sa.time)))
                dv_max = max(dv_max, np.max(np.abs(bb.v - ba.v - vram)))
                umax = max(umax, np.max(np.abs(ba.u)), np.max(np.abs(bb.u)))
    return (df, du_max, dv_max), (fmax, umax)


def galilean(tag, fixed, moving, vram, envelope=None):
    """The moving-ram run against the fixed-target run shifted by vram; envelope: the
    differences of a rounding-perturbed fixed run (a case that amplifies round-off)."""
    with MfcdFile(fixed) as a, MfcdFile(moving) as b:
        ha, hb = a.history(), b.history()
        # (the adaptive step follows the deformed points, whose rounding differs)
        check(f"{tag}: the same history rows", ha["time"].shape == hb["time"].shape
              and np.allclose(ha["time"], hb["time"], rtol=REL, atol=0.0),
              (ha["time"].shape, hb["time"].shape))
        if ha["time"].shape != hb["time"].shape:
            return
        check(f"{tag}: the same steps in contact",
              np.array_equal(ha["n_contact"] > 0, hb["n_contact"] > 0))
        check(f"{tag}: contact took place", np.any(ha["n_contact"] > 0))
        check(f"{tag}: the same snapshots", a.snapshot_labels() == b.snapshot_labels())
    (df, du, dv), (fmax, umax) = differences(fixed, moving, vram)
    vmag = np.linalg.norm(vram)
    bounds = (REL * fmax, REL * umax, REL * vmag)
    what = "rounding"
    if envelope is not None:
        bounds = tuple(max(b, 4.0 * e) for b, e in zip(bounds, envelope))
        what = "4 x the rounding envelope"
    check(f"{tag}: contact force equal: {df:.3g} <= {bounds[0]:.3g} ({what}; largest "
          f"{fmax:.4g})", df <= bounds[0], df)
    check(f"{tag}: u_twin = u + V t: {du:.3g} <= {bounds[1]:.3g} m ({what}; largest "
          f"{umax:.4g} m)", du <= bounds[1], du)
    check(f"{tag}: v_twin = v + V: {dv:.3g} <= {bounds[2]:.3g} m/s ({what}; |V| {vmag:g})",
          dv <= bounds[2], dv)


def closed_forms(path, work):
    E, RHO, V, L, W = 211e9, 7800.0, 1.0, 0.06, 0.006
    c0 = np.sqrt(E / RHO)
    with MfcdFile(path) as f:
        h = f.history()
        bar = f.body("bar")
        mass = bar.volume.sum() * RHO
        p_end = h["bodies/bar/momentum_y"][-1]
        check(f"the ram transmits 2 m V: p = {p_end:.6g}, 2 m V = {2 * mass * V:.6g}",
              abs(p_end / (2 * mass * V) - 1) <= 0.04, p_end / (2 * mass * V))
        t = h["time"]
        dt = np.diff(t)
        fy = h["contacts/contact1/force_y"]
        impulse = np.sum(fy[1:] * dt)
        check(f"momentum = sum of the pair's force x dt: {p_end:.12g} vs {impulse:.12g}",
              abs(p_end - impulse) <= 1e-12 * abs(p_end), p_end - impulse)
        on = np.nonzero(h["n_contact"] > 0)[0]
        t0, t1 = t[on[0]], t[on[-1]]
        t_sep = t[min(on[-1] + 1, len(t) - 1)]
        mid = (t > t0 + 0.2 * (t1 - t0)) & (t < t0 + 0.8 * (t1 - t0))
        stress = h["f_contact"][mid].mean() / W
        check(f"contact stress {stress / 1e6:.3f} MPa within 5% of rho c0 V = "
              f"{RHO * c0 * V / 1e6:.3f} MPa", abs(stress / (RHO * c0 * V) - 1) <= 0.05)
        dur = t_sep - t0
        check(f"contact for {dur * 1e6:.3f} us within 3% of 2 L / c0 = {2 * L / c0 * 1e6:.3f} us",
              abs(dur / (2 * L / c0) - 1) <= 0.03)
        res, scale = h["residual"][-1], np.max(np.abs(h["w_contact"]))
        check(f"the ram's work is in w_contact: {h['w_contact'][-1]:.5g} J/m > 0",
              h["w_contact"][-1] > 0)
        check(f"energy balance with it: |residual| {abs(res):.3g} <= 1e-3 x {scale:.4g}",
              abs(res) <= 1e-3 * scale)
        # the ram in the output
        ram = f.body("ram")
        check("/bodies/ram: role 'rigid', velocity (0, 1)",
              f.is_rigid("ram") and np.allclose(ram.attrs.get("velocity"), [0.0, 1.0]),
              ram.attrs)
        vr = np.array([0.0, V])
        worst = 0.0
        labels = f.snapshot_labels()
        for lab in labels:
            s = f.snapshot(lab)
            r = s.rigid.get("ram")
            if r is None:
                worst = np.inf
                break
            worst = max(worst, np.max(np.abs(r.x - (ram.x + vr * s.time))),
                        np.max(np.abs(r.u - vr * s.time)), np.max(np.abs(r.v - vr)))
            if "ram" in s.bodies or "ram" in f.snapshot_body_names(lab):
                worst = np.inf
        check(f"the ram in every snapshot at x + V t, u = V t, v = V: {worst:.3g} <= 1e-15",
              worst <= 1e-15, worst)
    xdmf = path[:-3] + ".xdmf"
    text = open(xdmf).read()
    grids = re.findall(r'<Grid Name="ram".*?</Grid>', text, flags=re.S)
    want = [f":/snapshots/{lab}/ram/x<" for lab in labels]
    check(f"the XDMF's {len(grids)} ram grids point at their snapshots' positions",
          len(grids) == len(labels) and all(w in g for w, g in zip(want, grids)),
          grids[:1])


def main():
    work = tempfile.mkdtemp(prefix="mfcd_ram_")
    inp = os.path.join(SRC, "input")
    read = lambda n: open(os.path.join(inp, n)).read()  # noqa: E731

    # 1. the user's deck against the fixed-wall deck it mirrors
    fixed = run(read("bar_impact_elastic_coarse.nml"), "wall_rkpm", work)
    moving = run(read("ram_push.nml"), "ram_push", work)
    check("input/ram_push.nml and its fixed-wall twin run", fixed and moving)
    if fixed and moving:
        with MfcdFile(fixed) as a, MfcdFile(moving) as b:
            check("the same bar in both decks", np.array_equal(a.body("bar").x, b.body("bar").x)
                  and np.array_equal(a.body("wall").x, b.body("ram").x))
        galilean("rkpm bar", fixed, moving, np.array([0.0, 1.0]))
        closed_forms(moving, work)
    # the other cases: twins generated from the fixed-target decks
    cases = [("fem bar", "bar_impact_elastic_fem_coarse.nml", None, False),
             ("subcycled fem Taylor bar", "taylor_bar_fem_coarse_subcycle.nml", 6.0e-6, False),
             ("axisymmetric rkpm Taylor bar", "taylor_bar_rkpm_coarse.nml", 8.0e-6, True)]
    if QUICK:
        cases = cases[:1]
    for tag, name, t_end, sensitive in cases:
        text = read(name)
        base = text if t_end is None else cut(text, t_end)
        tw, vram = twin(text, t_end)
        stem = re.sub(r"\W+", "_", tag)
        fixed = run(base, stem + "_fixed", work)
        moving = run(tw, stem + "_ram", work)
        check(f"{tag}: both runs complete", fixed and moving)
        if not (fixed and moving):
            continue
        envelope = None
        if sensitive:
            moved = run(translated(base, 1.0e-3), stem + "_translated", work)
            check(f"{tag}: the translated run completes", moved)
            if not moved:
                continue
            envelope, _ = differences(fixed, moved, np.zeros(2))
            print(f"[ INFO ] rigid_ram.{tag}: rounding envelope (force, u, v) = "
                  + ", ".join(f"{e:.3g}" for e in envelope))
        galilean(tag, fixed, moving, vram, envelope)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
