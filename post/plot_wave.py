#!/usr/bin/env python3
"""Stress-wave profiles of the elastic bar (input/elastic_wave.nml) against the closed form.

    python post/plot_wave.py output/elastic_wave.h5 [--out DIR] [--body bar]

A bar whose end is pushed at velocity v from t = 0 carries a step front at c0 = sqrt(E/rho)
(plane strain with nu = 0 makes it one-dimensional), with sigma_xx = -rho c0 v and particle
velocity v behind it, nothing ahead. E and rho are read from the file
(/materials, the constants the run used; for a file written before mfcd kept them, the deck
stored in /deck), v and the loaded end from the body's &bc with kind = 'velocity' on component 1. With
nu /= 0 the long-wave bar speed sqrt(E/((1 - nu^2) rho)) of a plane-strain strip is used
instead (noted in the figure).

Draws sigma_xx and v_x of the particles on the bar's mid-line (the reference row nearest to
half the height) at every snapshot against the reference coordinate X, with the closed form
dashed, into <stem>_profiles.png, and prints per snapshot the plateau errors of stress and
velocity (mean over 4 dx < distance from the loaded end < 0.6 c0 t, as
tests/regression/check_elastic_wave.py), the front position (where sigma_xx crosses half
the plateau, interpolated between particles) against c0 t, and the largest overshoot of the
ringing behind it.

Exit status: 0 when the figure was written, 1 otherwise.
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
from mfcd_h5 import MfcdFile, deck_default, deck_group, parse_deck  # noqa: E402

# the material constants the wave speed needs (every model uses them)
MATERIAL_CONSTANTS = ("density", "youngs_modulus", "poisson_ratio")


def wave_parameters(f: MfcdFile, body: str) -> dict:
    """rho, E, nu, c, v, the loaded end X0 and the direction d (+1: the wave runs to +x)."""
    spec = deck_group(f.deck, "body", name=body)
    if spec is None:
        raise SystemExit(f"plot_wave: no &body name = '{body}' in the deck stored in {f.path}")
    # the constants in use (/materials); a file written before mfcd kept them: the deck's
    mat = f.materials().get(spec.get("material", "")) or \
        deck_group(f.deck, "material", name=spec.get("material", "")) or {}
    prm = {k: float(mat.get(k, deck_default("material", k))) for k in MATERIAL_CONSTANTS}
    bc = None
    for g, vals in parse_deck(f.deck):
        if g == "bc" and vals.get("body") == body and \
                str(vals.get("kind", "fixed")).lower() == "velocity" and \
                int(vals.get("component", 0)) == 1:
            bc = vals
            break
    if bc is None:
        raise SystemExit(f"plot_wave: the deck has no &bc kind = 'velocity', component = 1 on "
                         f"body '{body}': not a pushed-bar run")
    X = f.body(body).x
    lo = np.resize(np.atleast_1d(np.asarray(bc.get("region_lo", -np.inf), dtype=float)), 2)
    hi = np.resize(np.atleast_1d(np.asarray(bc.get("region_hi", np.inf), dtype=float)), 2)
    sel = np.all((X[:, :2] >= lo) & (X[:, :2] <= hi), axis=1)
    if not sel.any():
        raise SystemExit("plot_wave: the velocity &bc region holds no particle")
    x0 = float(X[sel, 0].mean())
    d = 1.0 if x0 - X[:, 0].min() <= X[:, 0].max() - x0 else -1.0
    v = float(bc.get("value", 0.0))
    nu = prm["poisson_ratio"]
    e_eff = prm["youngs_modulus"] / (1.0 - nu * nu)
    c = np.sqrt(e_eff / prm["density"])
    return dict(rho=prm["density"], E=prm["youngs_modulus"], nu=nu, c=c, v=v, x0=x0, d=d,
                dx=float(np.atleast_1d(f.body(body).attrs.get("spacing", [0.0]))[0]))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split("\n\n", 1)[1])
    ap.add_argument("file", help="HDF5 output of the elastic wave run")
    ap.add_argument("--out", default=None, help="output directory (default: the file's)")
    ap.add_argument("--body", default=None, help="body name (default: the first body)")
    ap.add_argument("--format", default="png")
    a = ap.parse_args(argv)
    out = a.out or os.path.dirname(os.path.abspath(a.file))
    try:
        f = MfcdFile(a.file)
    except (OSError, ValueError) as e:
        print(f"plot_wave: {a.file}: {e}", file=sys.stderr)
        return 1
    try:
        with f:
            body = a.body or f.body_names()[0]
            p = wave_parameters(f, body)
            X = f.body(body).x[:, :2]
            ymid = 0.5 * (X[:, 1].min() + X[:, 1].max())
            yrow = X[np.argmin(np.abs(X[:, 1] - ymid)), 1]
            row = np.where(np.abs(X[:, 1] - yrow) < 1e-9 * max(1.0, abs(yrow)) + 1e-12)[0]
            row = row[np.argsort(X[row, 0])]
            Xr = X[row, 0]
            s_exact = -p["rho"] * p["c"] * p["v"] * p["d"]
            labels = [l for l in f.snapshot_labels()]
            plt.rcParams.update({"font.size": 11, "legend.fontsize": 9, "savefig.dpi": 120})
            fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8.5, 7.0), sharex=True,
                                           layout="constrained")
            colors = plt.cm.viridis(np.linspace(0.0, 0.85, max(len(labels), 1)))
            xs = 1e3 * (Xr - Xr.min()) if p["d"] > 0 else 1e3 * (Xr.max() - Xr)
            dist = p["d"] * (Xr - p["x0"])         # distance from the loaded end (m)
            print(f"plot_wave: rho = {p['rho']:g} kg/m^3, E = {p['E']:.4g} Pa, nu = {p['nu']:g},"
                  f" c = {p['c']:.1f} m/s, v = {p['v']:g} m/s, sigma = {s_exact / 1e6:.2f} MPa;"
                  f" mid-line y = {yrow * 1e3:.3g} mm, {row.size} particles")
            notes = []
            for lab, col in zip(labels, colors):
                s = f.snapshot(lab)
                b = s.bodies.get(body)
                if b is None:
                    continue
                t = s.time
                sig = b.stress[row, 0]
                vx = b.v[row, 0]
                front = p["c"] * t
                behind = dist < front
                ex_s = np.where(behind, s_exact, 0.0)
                ex_v = np.where(behind, p["v"], 0.0)
                ax1.plot(xs, sig / 1e6, color=col, lw=1.5, label=f"t = {t * 1e6:.2f} \u00b5s")
                ax2.plot(xs, vx, color=col, lw=1.5, label=f"t = {t * 1e6:.2f} \u00b5s")
                if t > 0:
                    # closed form as a step: plot with a vertical front
                    fx = 1e3 * front
                    ax1.plot([0, fx, fx, xs.max()], np.array([s_exact, s_exact, 0, 0]) / 1e6,
                             color=col, lw=1.0, ls="--")
                    ax2.plot([0, fx, fx, xs.max()], [p["v"], p["v"], 0, 0], color=col, lw=1.0,
                             ls="--")
                    plat = (dist > 4 * p["dx"]) & (dist < 0.6 * front)
                    es = sig[plat].mean() / s_exact - 1.0 if plat.any() else np.nan
                    ev = vx[plat].mean() / p["v"] - 1.0 if plat.any() else np.nan
                    # the front: where sigma crosses half the plateau, interpolated between
                    # the last particle above and the first below (searching from the end)
                    ratio = sig * np.sign(s_exact) / abs(s_exact)
                    o = np.argsort(dist)
                    dd, rr = dist[o], ratio[o]
                    above = np.where(rr >= 0.5)[0]
                    fpos = np.nan
                    if above.size and above[-1] + 1 < dd.size:
                        k = above[-1]
                        fpos = dd[k] + (rr[k] - 0.5) / (rr[k] - rr[k + 1]) * (dd[k + 1] - dd[k])
                    over = np.max(sig * np.sign(s_exact)) / abs(s_exact) - 1.0
                    notes.append(f"t = {t * 1e6:.2f} \u00b5s: plateau {es:+.1e} (stress), "
                                 f"{ev:+.1e} (v)\n   front {(fpos - front) / p['dx']:+.2f} dx "
                                 f"from c t, overshoot {over:+.0%}")
                    print(f"plot_wave: {lab} t = {t * 1e6:.3f} us: plateau stress "
                          f"{sig[plat].mean() / 1e6:.2f} MPa (error {es:+.2e}), velocity "
                          f"{vx[plat].mean():.4f} m/s (error {ev:+.2e}), front "
                          f"{fpos * 1e3:.2f} mm vs c t = {front * 1e3:.2f} mm "
                          f"({(fpos - front) / p['dx']:+.2f} dx), overshoot {over:+.1%}")
            nu_note = "" if p["nu"] == 0 else f", nu = {p['nu']:g}: c = sqrt(E/((1-nu^2) rho))"
            ax1.set_ylabel("sigma_xx [MPa]")
            ax2.set_ylabel("v_x [m/s]")
            ax2.set_xlabel("distance from the loaded end, reference X [mm]")
            ax1.set_title(f"{f.title or body}: mid-line, y = {yrow * 1e3:.3g} mm\n"
                          f"closed form (dashed): front at c t, c = {p['c']:.0f} m/s, "
                          f"sigma = -rho c v = {s_exact / 1e6:.1f} MPa, v = {p['v']:g} m/s"
                          + nu_note, fontsize=10)
            for ax in (ax1, ax2):
                ax.grid(alpha=0.3)
                ax.axhline(0.0, color="0.5", lw=0.6)
            ax1.legend(loc="lower right", frameon=False)
            if notes:
                ax1.text(0.985, 0.5, "\n".join(notes), transform=ax1.transAxes, ha="right",
                         va="center", fontsize=8.5, family="monospace",
                         bbox=dict(boxstyle="round", fc="white", ec="0.7"))
            os.makedirs(out, exist_ok=True)
            stem = os.path.splitext(os.path.basename(a.file))[0]
            path = os.path.join(out, f"{stem}_profiles.{a.format}")
            fig.savefig(path)
            plt.close(fig)
            print(f"plot_wave: wrote {path}")
    except SystemExit as e:
        print(e, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
