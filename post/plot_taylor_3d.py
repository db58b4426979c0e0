#!/usr/bin/env python3
"""The Taylor bar in 3D beside mfcd's axisymmetric run (paper Section 6, Figs. 14/15): one
figure of three panels and a markdown table.

    python post/plot_taylor_3d.py output/taylor_bar_3d_rkpm_coarse.h5 \\
        output/taylor_bar_rkpm_1mm.h5 --out doc/figures [--name taylor_3d] [--body bar]

  (a) the section of the 3D bar in its symmetry plane y = 0 (the particles or nodes within
      a quarter spacing of it, x against z) over the axisymmetric run's (r against z) at
      the last snapshot, the effective plastic strain as colour;
  (b) the 3D bar's footprint seen from below (its particles within one spacing of its
      lowest z, x against y) with the axisymmetric foot radius as a circle;
  (c) length and foot radius against time, both runs (/history 'length', 'foot_radius':
      in 3D the reference rim's mean distance from the axis, doc/3d.md).
The table (printed): length and foot radius of both runs at each snapshot time and the
3D run's relative difference.
Exit status: 0 when written, 1 when a file cannot be read.
File layout: doc/output.md; reader: post/mfcd_h5.py.
"""

from __future__ import annotations

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_h5 import MfcdFile  # noqa: E402
from mfcd_style import figure_style  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run3d")
    ap.add_argument("axisym")
    ap.add_argument("--out", default="output/figures")
    ap.add_argument("--name", default="taylor_3d")
    ap.add_argument("--body", default="bar")
    a = ap.parse_args()
    plt.rcParams.update(figure_style(savefig_dpi=150))
    try:
        f3, f2 = MfcdFile(a.run3d), MfcdFile(a.axisym)
        h3, h2 = f3.history(), f2.history()
        lab3 = sorted(f3.snapshot_labels())
        lab2 = sorted(f2.snapshot_labels())
        s3, s2 = f3.snapshot(lab3[-1]), f2.snapshot(lab2[-1])
        b3 = f3.body(a.body)
        x0 = b3.x
        dx = float(np.min(b3.spacing))
    except (OSError, KeyError) as e:
        print(f"plot_taylor_3d: cannot read the runs: {e}", file=sys.stderr)
        return 1
    bar3, bar2 = s3.bodies[a.body], s2.bodies[a.body]
    fig, ax = plt.subplots(1, 3, figsize=(13, 5.2), gridspec_kw={"width_ratios": [1, 1, 1.3]})
    # (a) the section y = 0 against the axisymmetric r-z particles
    sec = np.abs(x0[:, 1] - np.min(np.abs(x0[:, 1]))) < 0.25 * dx
    eps3 = bar3.epsbar if bar3.epsbar is not None else np.zeros(len(x0))
    vmax = max(float(np.max(eps3)), float(np.max(bar2.epsbar)))
    ax[0].scatter(bar2.x[:, 0] * 1e3, bar2.x[:, 1] * 1e3, s=6, c="0.75", label="axisymmetric")
    sc = ax[0].scatter(bar3.x[sec, 0] * 1e3, bar3.x[sec, 2] * 1e3, s=8, c=eps3[sec],
                       cmap="viridis", vmin=0.0, vmax=vmax, label="3D, plane y = 0")
    ax[0].set_xlabel("x, r (mm)")
    ax[0].set_ylabel("z (mm)")
    ax[0].set_aspect("equal")
    ax[0].set_ylim(-1.0, 25.0)
    ax[0].legend(loc="upper right", fontsize=8)
    fig.colorbar(sc, ax=ax[0], shrink=0.7, label="effective plastic strain")
    ax[0].set_title(f"(a) section at t = {s3.time * 1e6:.0f} us")
    # (b) the footprint from below
    z = bar3.x[:, 2]
    foot = z <= z.min() + dx
    ax[1].scatter(bar3.x[foot, 0] * 1e3, bar3.x[foot, 1] * 1e3, s=8, c=eps3[foot],
                  cmap="viridis", vmin=0.0, vmax=vmax)
    r2 = h2["foot_radius"][-1] * 1e3
    th = np.linspace(0.0, 2.0 * np.pi, 200)
    ax[1].plot(r2 * np.cos(th), r2 * np.sin(th), "k--", lw=1, label="axisymmetric foot radius")
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("x (mm)")
    ax[1].set_ylabel("y (mm)")
    lim = 1.1 * max(r2, float(np.max(np.abs(bar3.x[foot, :2]))) * 1e3)
    ax[1].set_xlim(-0.05 * lim, lim)
    ax[1].set_ylim(-0.05 * lim, lim)
    ax[1].legend(loc="upper right", fontsize=8)
    ax[1].set_title("(b) footprint (z within one spacing)")
    # (c) length and foot radius against time
    for h, tag, ls in ((h3, "3D", "-"), (h2, "axisymmetric", "--")):
        ax[2].plot(h["time"] * 1e6, h["length"] * 1e3 - 45.0, "C0" + ls,
                   label=f"length - 45 mm, {tag}")
        ax[2].plot(h["time"] * 1e6, h["foot_radius"] * 1e3, "C1" + ls,
                   label=f"foot radius, {tag}")
    ax[2].set_xlabel("t (us)")
    ax[2].set_ylabel("mm")
    ax[2].legend(fontsize=8)
    ax[2].set_title("(c) length and foot radius")
    fig.tight_layout()
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, a.name + ".png")
    fig.savefig(path)
    print(f"wrote {path}")
    print("| t (us) | length 3D (mm) | axisymmetric | diff | foot radius 3D (mm) | "
          "axisymmetric | diff |")
    print("|---|---|---|---|---|---|---|")
    for lab in lab3[1:]:
        t = f3.snapshot_time(lab)
        l3, l2 = (np.interp(t, h["time"], h["length"]) for h in (h3, h2))
        r3, rr2 = (np.interp(t, h["time"], h["foot_radius"]) for h in (h3, h2))
        print(f"| {t * 1e6:.0f} | {l3 * 1e3:.3f} | {l2 * 1e3:.3f} | {l3 / l2 - 1:+.2%} | "
              f"{r3 * 1e3:.3f} | {rr2 * 1e3:.3f} | {r3 / rr2 - 1:+.2%} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
