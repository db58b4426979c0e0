#!/usr/bin/env python3
"""The checks a researcher makes on an impact run, on the tutorial's oblique disk
(doc/tutorial.md, input/disk_plate.nml), and its histories drawn.

    python post/disk_plate.py output/disk_plate.h5 [more.h5 ...] [--out DIR]
        [--striker disk] [--target plate] [--spacing 0.25e-3] [--mu 0.15]

For each file, from /history and /history/bodies (post/mfcd_h5.py), it prints:
  - the energy balance: the largest |residual| over the energy scale (a run that passes
    mfcd's guard has it below energy_tol; a sound one far below), and whether ke + w_int
    ever exceeds ke(0) (contact and friction can only take energy out; this reads no
    contact bookkeeping);
  - the momentum: of the striker before and after, and, for a free target, of both bodies
    together (constant to round-off; a held target takes momentum through its &bc);
  - the penetration left after the contact corrections, over the spacing;
  - the striker's rebound: its velocity after (momentum over mass), the normal restitution
    e = -v_y,out / v_y,in, and its spin against the Coulomb bound |L| <= mu R |dp_y| (the
    friction impulse at its rim cannot exceed mu times the normal impulse; R its radius,
    from its reference extent);
and draws <stem>_history.png: kinetic energies of both bodies, internal and plastic work,
contact work and residual; the striker's momentum and spin.
Several files (a convergence study in the spacing) print one line each of the rebound
measures to compare.

Exit status: 0 when every file was read and its figure written, 1 otherwise.
"""
from __future__ import annotations

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_h5 import MfcdFile, negative_values, parse_deck  # noqa: E402


def measures(path: str, striker: str, target: str, spacing: float, mu: float) -> dict:
    with MfcdFile(path) as f:
        h = f.history()
        s = f.body_history(striker)
        t = f.body_history(target)
        x = f.body(striker).x
        held = any(g == "bc" and v.get("body") == target for g, v in parse_deck(f.deck))
    if not s:
        raise SystemExit(f"disk_plate: no /history/bodies/{striker} in {path} (an mfcd "
                         "before the per-body history?)")
    ke0 = h["ke"][0]
    scale = np.maximum.reduce([np.full_like(h["ke"], ke0), h["ke"], np.abs(h["w_int"]),
                               np.abs(h["w_ext"]), np.abs(h["w_contact"])])
    m = {"time": h["time"], "h": h, "s": s, "t": t}
    m["residual"] = float(np.max(np.abs(h["residual"]) / scale))
    m["over"] = float(np.max(h["ke"] + h["w_int"] - h["w_ext"] - ke0) / ke0)
    m["pen"] = float(np.max(h["penetration"]) / spacing)
    vy0 = s["momentum_y"][0]
    v_in = np.array([s["momentum_x"][0], vy0])
    # the striker's mass from its initial momentum and kinetic energy: M = |p|^2 / (2 ke)
    mass = float(v_in @ v_in / (2.0 * s["ke"][0]))
    m["mass"] = mass
    m["v_in"] = v_in / mass
    m["v_out"] = np.array([s["momentum_x"][-1], s["momentum_y"][-1]]) / mass
    m["e"] = float(-m["v_out"][1] / m["v_in"][1])
    radius = 0.5 * float(np.max(x[:, 1]) - np.min(x[:, 1]))
    bound = mu * radius * abs(s["momentum_y"][-1] - vy0)
    m["spin"] = float(s["angular_momentum"][-1])
    m["coulomb"] = m["spin"] / bound if bound > 0 else 0.0
    m["held"] = held
    if t:
        p = np.array([s["momentum_x"] + t["momentum_x"], s["momentum_y"] + t["momentum_y"]])
        m["p_drift"] = float(np.max(np.abs(p - p[:, :1])) / np.linalg.norm(p[:, 0]))
    return m


def report(path: str, m: dict) -> None:
    print(f"disk_plate: {path}")
    print(f"  energy: largest |residual| {m['residual']:.2e} of the energy scale; "
          f"ke + w_int - w_ext - ke(0) at most {m['over']:+.2e} of ke(0) (<= 0: nothing "
          "created)")
    print(f"  striker: mass {m['mass']:.5g} (kg, or kg/m in plane strain); velocity in "
          f"({m['v_in'][0]:.2f}, {m['v_in'][1]:.2f}) m/s, out ({m['v_out'][0]:.2f}, "
          f"{m['v_out'][1]:.2f}) m/s; restitution e = {m['e']:.4f}")
    print(f"  spin: {m['spin']:+.4e} (J s/m), {m['coulomb']:+.3f} of the Coulomb bound "
          "mu R |dp_y| (negative: clockwise)")
    print(f"  penetration left: at most {m['pen']:.2%} of the spacing")
    if "p_drift" in m and not m["held"]:
        print(f"  momentum of both bodies: drift {m['p_drift']:.1e} of the initial (a free "
              "target keeps it to round-off)")
    elif "p_drift" in m:
        print("  momentum of both bodies: not kept, the target is held by &bc (its "
              "reactions take momentum; a free target keeps it to round-off)")


def draw(path: str, m: dict, out: str, striker: str, target: str) -> str:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    h, s, t = m["h"], m["s"], m["t"]
    tus = m["time"] * 1e6
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].plot(tus, s["ke"], label=f"ke {striker}")
    if t:
        ax[0].plot(tus, t["ke"], label=f"ke {target}")
    ax[0].plot(tus, h["w_int"], label="w_int")
    ax[0].plot(tus, h["w_plastic"], "--", label="w_plastic")
    ax[0].plot(tus, h["w_contact"], label="w_contact")
    ax[0].plot(tus, h["residual"], "k:", label="residual")
    ax[0].set_xlabel("t (us)")
    ax[0].set_ylabel("energy (J/m)")
    ax[0].legend(fontsize=8)
    ax[1].plot(tus, s["momentum_x"] / m["mass"], label="v_x (momentum / mass)")
    ax[1].plot(tus, s["momentum_y"] / m["mass"], label="v_y")
    ax[1].set_xlabel("t (us)")
    ax[1].set_ylabel("striker velocity (m/s)")
    a2 = ax[1].twinx()
    a2.plot(tus, s["angular_momentum"], "r--", label="spin L (right)")
    a2.set_ylabel("angular momentum about its centre (J s/m)", color="r")
    ax[1].legend(loc="center right", fontsize=8)
    fig.tight_layout()
    os.makedirs(out, exist_ok=True)
    name = os.path.join(out, os.path.splitext(os.path.basename(path))[0] + "_history.png")
    fig.savefig(name, dpi=110)
    plt.close(fig)
    return name


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--out", default="output/figures")
    ap.add_argument("--striker", default="disk")
    ap.add_argument("--target", default="plate")
    ap.add_argument("--spacing", type=float, default=0.25e-3, help="(m), for the penetration")
    ap.add_argument("--mu", type=float, default=0.15)
    a = ap.parse_args(negative_values(argv))
    rows = []
    for path in a.files:
        m = measures(path, a.striker, a.target, a.spacing, a.mu)
        report(path, m)
        print(f"disk_plate: wrote {draw(path, m, a.out, a.striker, a.target)}")
        rows.append((path, m))
    if len(rows) > 1:
        print("disk_plate: file, v_x out (m/s), v_y out (m/s), e, spin / Coulomb bound")
        for path, m in rows:
            print(f"  {path}: {m['v_out'][0]:.3f} {m['v_out'][1]:.3f} {m['e']:.4f} "
                  f"{m['coulomb']:+.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
