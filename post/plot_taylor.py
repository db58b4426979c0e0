#!/usr/bin/env python3
"""Figures of a contact run of mfcd (the Taylor bar of the paper, Section 6).

  <stem>_det_fields.png   Figs. 9-10: det(M) of the target (master) and of the bar (slave)
                          over the contact region before impact and at a later snapshot,
                          and det(M_master) at the bar's particles (the "dark region moves
                          up" where the bar meets the target); needs &output det_fields.
  <stem>_contact.png      histories: contact force, contact radius, bar length, foot radius.

Usage: python post/plot_taylor.py output/taylor_bar_rkpm.h5 [--out doc/figures]
       [--after 0002]
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mfcd_h5 import MfcdFile  # noqa: E402


def det_panels(f, out, stem, after):
    snaps = {lab: f.snapshot(lab) for lab in sorted(f.snapshot_labels())}
    labels = [lab for lab, s in snaps.items() if s.det]
    if not labels:
        print("no det(M) fields in the file (&output det_fields = .true.)")
        return None
    before = labels[0]
    after = after or (labels[1] if len(labels) > 1 else labels[0])
    slave = list(snaps[before].bodies)[0]
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), constrained_layout=True)
    for row, lab in enumerate((before, after)):
        g = snaps[lab].det[1]
        a1, a2 = g.axis1 * 1e3, g.axis2 * 1e3
        dm, ds = g.master, g.slave
        thr = g.threshold
        plateau = g.master_plateau
        t_us = snaps[lab].time * 1e6
        ax = axes[row, 0]
        cm = ax.pcolormesh(a1, a2, dm / plateau, shading="auto", cmap="Blues", vmin=0, vmax=1.2)
        ax.contour(a1, a2, ds, levels=[thr], colors="red", linewidths=1.0)
        ax.contour(a1, a2, dm, levels=[thr], colors="navy", linewidths=1.0, linestyles="--")
        ax.set_title(f"t = {t_us:.1f} us: det(M_target)/plateau (colour)\n"
                     "det(M_bar) = eps (red), det(M_target) = eps (dashed)", fontsize=9)
        ax.set_xlabel("r [mm]")
        ax.set_ylabel("z [mm]")
        ax.set_aspect("equal")
        fig.colorbar(cm, ax=ax, label="det(M_target) / plateau")
        ax = axes[row, 1]
        x = snaps[lab].bodies[slave].x * 1e3
        dms = g.master_at_slave
        near = x[:, 1] < a2.max()
        logd = np.log10(np.maximum(dms[near] / plateau, 1e-12))
        sc = ax.scatter(x[near, 0], x[near, 1], c=logd, s=4, cmap="viridis", vmin=-12, vmax=0)
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlim(a1.min(), a1.max())
        ax.set_ylim(a2.min() if row else -0.5, a2.max())
        n_det = int(np.sum(dms > thr))
        ax.set_title(f"t = {t_us:.1f} us: det(M_target) at the bar's particles\n"
                     f"{n_det} above eps = {thr:.1e} (the gap decides contact)", fontsize=9)
        ax.set_xlabel("r [mm]")
        ax.set_ylabel("z [mm]")
        ax.set_aspect("equal")
        fig.colorbar(sc, ax=ax, label="log10 det(M_target)/plateau at the particle")
    path = os.path.join(out, f"{stem}_det_fields.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def histories(f, out, stem):
    h = f.history()
    t = h["time"] * 1e6
    plane = f.geometry != "axisymmetric"
    fig, axes = plt.subplots(2, 2, figsize=(11, 7), constrained_layout=True, sharex=True)
    unit = "kN/m" if plane else "kN"
    axes[0, 0].plot(t, h["f_contact"] / 1e3)
    axes[0, 0].set_ylabel(f"contact force [{unit}]")
    axes[0, 1].plot(t, h["contact_radius"] * 1e3)
    axes[0, 1].set_ylabel("contact radius [mm]")
    axes[1, 0].plot(t, h["length"] * 1e3)
    axes[1, 0].set_ylabel("bar length [mm]")
    axes[1, 1].plot(t, h["foot_radius"] * 1e3)
    axes[1, 1].set_ylabel("foot radius [mm]")
    t_sep = float(f.summary["edge_separation_time"]) * 1e6
    for ax in axes.ravel():
        ax.grid(alpha=0.3)
        if t_sep > 0:
            ax.axvline(t_sep, color="r", lw=0.8, ls="--")
    for ax in axes[1]:
        ax.set_xlabel("time [us]")
    axes[0, 1].text(0.98, 0.05, f"edge separates at {t_sep:.2f} us (red)", ha="right",
                    transform=axes[0, 1].transAxes, fontsize=9, color="r")
    fig.suptitle(f.title.strip(), fontsize=11)
    path = os.path.join(out, f"{stem}_contact.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("--out", default=None)
    ap.add_argument("--after", default=None, help="snapshot label for 'after penetration'")
    a = ap.parse_args(argv)
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    os.makedirs(out, exist_ok=True)
    stem = os.path.splitext(os.path.basename(a.file))[0]
    with MfcdFile(a.file) as f:
        for p in (det_panels(f, out, stem, a.after), histories(f, out, stem)):
            if p:
                print("wrote", p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
