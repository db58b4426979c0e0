#!/usr/bin/env python3
"""Contact patch test and Hertz line contact with measured orders (issue 9, item 4).

patch   Two elastic blocks (plane strain, 6 mm wide, 12 mm tall) with non-matching spacings
        (upper, the slave: 7m cells across; lower, the master: 5m - 1 cells, a ratio
        7m/(5m - 1) so no interior particles coincide) meet at y = 0 with v = -/+0.5 m/s.
        Equal impedances: the interface stays at rest and carries the uniform 1-D pressure
        p = rho c v_rel / 2 (c = sqrt(M/rho), M = E (1-nu)/((1+nu)(1-2nu)) the constrained
        modulus; nu = 0 gives M = E; nu = 0.3 with the sides held in x, uniaxial strain)
        until the release waves from the far ends return after 2 L / c. Measured: the mean
        contact force on each interface particle over [0.3, 0.8] 2L/c (snapshot f_contact)
        over its tributary length against p, and the gap of the particles to the other
        body's interface polyline. m = 2, 4, 8, 16; the segment gap with the default
        effective mass and with &contact shared_mass = .true.
hertz   A rigid half-cylinder (R = 10 mm, an annulus sector: its surface polyline lies on
        the circle) on an elastic block (2 x 5 a wide, 5 a deep, bottom pushed up at 5 m/s,
        the whole block moving at it from t = 0 so no wave starts at the bottom) in plane
        strain; contact grows to a half-width of about a = 0.2 mm = 0.02 R. At three
        instants (mean forces over the last 4% of the time before each): the load P per
        unit length, the half-width from the outermost loaded particles against
        a_H = sqrt(4 P R / (pi E*)), E* = E/(1 - nu^2) for a rigid cylinder, the pressure
        against p0 sqrt(1 - x^2/a_H^2), p0 = 2 P/(pi a_H), and the gap of the loaded
        particles to the circle. a_H = k h, k = 4, 8, 16, 32 spacings h.

Usage: .venv/bin/python bench/contact_patch.py [patch] [hertz] [--decks]
  (default: both studies). --decks writes input/patch_test.nml (m = 2) and
  input/hertz_cylinder.nml (k = 8) and exits.
Runs build/bin/mfcd (Release) with OMP_NUM_THREADS=1 in a temporary directory; prints
Markdown tables and writes bench/results/contact_patch_<date>.md (git-ignored) and the
figures doc/figures/patch_pressure.png, hertz_pressure.png, contact_orders.png.
"""
import datetime
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "post"))
from contact_measures import (surface_row, pressure, vertical_gap, hertz_line,  # noqa: E402
                              edge_half_width, fit_half_width, observed_order)
from mfcd_h5 import MfcdFile  # noqa: E402

MFCD = os.path.join(ROOT, "build", "bin", "mfcd")
FIGS = os.path.join(ROOT, "doc", "figures")
E, RHO = 211.0e9, 7800.0
OUT = []

# patch test geometry and load
W, L, V = 0.006, 0.012, 0.5            # m, m, m/s each way (v_rel = 1 m/s)
PATCH_M = (2, 4, 8, 16)
WINDOW = (0.3, 0.8)                    # fractions of 2 L / c: after the start, before release

# Hertz: rigid cylinder on an elastic block
NU_H, R_CYL, A_TARGET, SIZE, V_H = 0.3, 0.010, 0.2e-3, 5.0, 5.0
E_STAR = E / (1.0 - NU_H ** 2)         # rigid indenter: 1/E* = (1 - nu^2)/E
HERTZ_K = (4, 8, 16, 32)
HERTZ_AT = (0.5, 0.75, 1.0)            # instants, fractions of t_end
HERTZ_WIN = 0.04                       # mean forces over the last 4% before each instant


def emit(line=""):
    print(line, flush=True)
    OUT.append(line)


def p_exact(nu):
    """rho c v_rel / 2 with the constrained modulus (Pa): equal impedances share v_rel."""
    M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    return np.sqrt(M * RHO) * 2 * V / 2, np.sqrt(M / RHO)


def patch_geometry(m):
    nxu, nxl = 7 * m, 5 * m - 1
    hu, hl = W / nxu, W / nxl
    nyu, nyl = round(L / hu), round(L / hl)
    return nxu, nxl, hu, hl, nyu, nyl


def patch_deck(m, nu=0.0, shared=False, out="out/patch.h5"):
    nxu, nxl, hu, hl, nyu, nyl = patch_geometry(m)
    Lu, Ll = nyu * hu, nyl * hl
    _, c = p_exact(nu)
    T = 2 * min(Lu, Ll) / c
    bcs = ""
    if nu != 0.0:
        for b in ("upper", "lower"):
            for x0 in (0.0, W):
                bcs += (f"&bc\n  body = '{b}'\n  region_lo = {x0 - 1e-6 * W:.9e}, -1.0\n"
                        f"  region_hi = {x0 + 1e-6 * W:.9e}, 1.0\n  component = 1\n"
                        "  kind = 'fixed'    ! the sides held in x: uniaxial strain\n/\n")
    return f"""! mfcd deck: contact patch test (Taylor and Papadopoulos), dynamic form; written by
! bench/contact_patch.py (m = {m}, nu = {nu}). Two elastic blocks, 6 mm wide, with non-matching
! spacings ({nxu} and {nxl} cells across: no interior particles coincide) meet at y = 0 with
! v = -/+{V} m/s. Equal impedances: the interface stays at rest and carries the uniform
! pressure rho c v_rel / 2 (c from the constrained modulus) for 2 L / c = {T * 1e6:.3f} us.
! Snapshot 0003 holds the mean contact force of each particle over [0.3, 0.8] 2L/c.
! Units: SI (m, kg, s, Pa).
&run
  title = 'Contact patch test, non-matching spacings (m = {m})'
  mode = 'dynamic'
  ndim = 2
  geometry = 'plane'
/
&material
  name = 'steel_elastic'
  model = 'elastic'
  density = {RHO}
  youngs_modulus = {E}
  poisson_ratio = {nu}
/
&body
  name = 'upper'
  shape = 'rectangle'
  lo = 0.0, 0.0
  hi = {W}, {Lu:.9e}
  n = {nxu + 1}, {nyu + 1}
  material = 'steel_elastic'
  velocity = 0.0, {-V}
/
&body
  name = 'lower'
  shape = 'rectangle'
  lo = 0.0, {-Ll:.9e}
  hi = {W}, 0.0
  n = {nxl + 1}, {nyl + 1}
  material = 'steel_elastic'
  velocity = 0.0, {V}
/
{bcs}&contact
  master = 'lower'
  slave = 'upper'
  mu = 0.0
  shared_mass = {'.true.' if shared else '.false.'}
/
&solver
  t_end = {0.9 * T:.6e}
  cfl = 0.5
  snapshot_times = 0.0, {WINDOW[0] * T:.6e}, {WINDOW[1] * T:.6e}
/
&output
  file = '{out}'
/
"""


def hertz_setup(k):
    h = A_TARGET / k
    half, H = SIZE * A_TARGET, SIZE * A_TARGET
    nxh = int(round(half / h))
    ny = int(round(H / h)) + 1
    # indentation that brings the contact to about A_TARGET: the Hertz load for it and a
    # rough approach of a strip of depth H, delta = P/(pi E*) (2 ln(2H/a) - 1); it only
    # sets the run length
    P = np.pi * E_STAR * A_TARGET ** 2 / (4 * R_CYL)
    delta = P / (np.pi * E_STAR) * (2 * np.log(2 * H / A_TARGET) - 1)
    return h, nxh, ny, H, 1.2 * delta / V_H


def hertz_deck(k, out="out/hertz.h5"):
    h, nxh, ny, H, T = hertz_setup(k)
    dth = 0.5 * h / R_CYL                  # arc spacing h/2 at the surface
    nth = int(np.ceil(np.pi / dth)) + 1
    ring = 12                              # the ring's depth in h: det(M) and surface only
    snaps = [0.0]
    for s in HERTZ_AT:
        snaps += [s * T * (1 - HERTZ_WIN), s * T]
    snap = ", ".join(f"{t:.6e}" for t in snaps)
    return f"""! mfcd deck: Hertz line contact, written by bench/contact_patch.py (k = {k}:
! the target half-width a = {A_TARGET * 1e3} mm is k spacings). A rigid half-cylinder,
! R = {R_CYL * 1e3} mm (an annulus sector: its surface polyline lies on the circle, arc
! spacing h/2), on an elastic steel block in plane strain, 2 x {SIZE} a wide and
! {SIZE} a deep. The block moves up at {V_H} m/s from t = 0 (its bottom held at that
! speed), so contact starts at one point and grows without a wave from the bottom;
! v/c ~ 1e-3, quasi-static. Compare a and the pressure with a = sqrt(4 P R / (pi E*)),
! p0 sqrt(1 - x^2/a^2), E* = E/(1 - nu^2). Snapshot pairs: the second of each holds the
! mean contact forces over the 4% of the time before it.
! Units: SI (m, kg, s, Pa).
&run
  title = 'Hertz line contact, rigid cylinder on an elastic block (k = {k})'
  mode = 'dynamic'
  ndim = 2
  geometry = 'plane'
/
&material
  name = 'steel_elastic'
  model = 'elastic'
  density = {RHO}
  youngs_modulus = {E}
  poisson_ratio = {NU_H}
/
&body
  name = 'block'
  shape = 'rectangle'
  lo = {-nxh * h:.9e}, {-H:.9e}
  hi = {nxh * h:.9e}, 0.0
  n = {2 * nxh + 1}, {ny}
  material = 'steel_elastic'
  velocity = 0.0, {V_H}
/
&body
  name = 'cylinder'
  role = 'rigid'
  shape = 'annulus_sector'
  center = 0.0, {R_CYL}
  r_inner = {R_CYL - ring * h:.9e}
  r_outer = {R_CYL}
  theta_start = 180.0
  theta_end = 360.0
  n = {ring + 1}, {nth}
/
&bc
  body = 'block'
  region_hi = 1.0, {-H + 1e-6 * h:.9e}
  component = 2
  kind = 'velocity'
  value = {V_H}
/
&contact
  master = 'cylinder'
  slave = 'block'
  mu = 0.0
/
&solver
  t_end = {T:.6e}
  cfl = 0.5
  snapshot_times = {snap}
/
&output
  file = '{out}'
/
"""


def run(text, name, work):
    path = os.path.join(work, name + ".nml")
    open(path, "w").write(text)
    t0 = time.time()
    p = subprocess.run([MFCD, path], cwd=work, capture_output=True, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"), timeout=3600)
    wall = time.time() - t0
    h5 = os.path.join(work, "out", name + ".h5")
    last = p.stdout.strip().splitlines()[-1] if p.stdout.strip() else p.stderr[-300:]
    return (MfcdFile(h5) if p.returncode == 0 else None), wall, last


def patch_measures(f, m, nu):
    """Errors of one patch run (dict)."""
    pex, _ = p_exact(nu)
    lab = sorted(f.snapshot_labels())[-1]
    _, xu, fu = surface_row(f, lab, "upper")
    _, xl, fl = surface_row(f, lab, "lower")
    pu, pl = pressure(xu, fu, +1.0) / pex - 1, pressure(xl, fl, -1.0) / pex - 1
    hu = patch_geometry(m)[2]
    inner_u, inner_l = slice(1, -1), slice(1, -1)       # the corner particles apart
    mid_u = np.abs(xu[:, 0] - W / 2) <= W / 4
    mid_l = np.abs(xl[:, 0] - W / 2) <= W / 4
    gu = vertical_gap(xu, xl)                           # slave particles on the master
    gl = -vertical_gap(xl, xu)                          # master particles under the slave
    return dict(
        h=hu, n=len(xu), total=fu[:, 1].sum() / W / pex - 1,
        reaction=abs(fu[:, 1].sum() + fl[:, 1].sum()) / abs(fu[:, 1].sum()),
        s_rms=np.sqrt(np.mean(pu[inner_u] ** 2)), s_max=np.abs(pu[inner_u]).max(),
        s_mid=np.abs(pu[mid_u]).max(), m_rms=np.sqrt(np.mean(pl[inner_l] ** 2)),
        m_max=np.abs(pl[inner_l]).max(), m_mid=np.abs(pl[mid_l]).max(),
        g_max=np.abs(gu[inner_u]).max(), g_rms=np.sqrt(np.mean(gu[inner_u] ** 2)),
        gm_max=np.abs(gl[inner_l]).max(), corner_p=pu[0] + 1, corner_pm=pl[0] + 1,
        corner_g=gu[0] / hu, xu=xu[:, 0], pu=pu + 1, xl=xl[:, 0], pl=pl + 1)


def cell(res, i, key, fmt="{:.4f}"):
    v = res[i][key]
    s = fmt.format(v)
    if i > 0 and res[i - 1] is not None and "h" in res[i - 1]:
        q = observed_order(abs(res[i - 1][key]), abs(v), res[i - 1]["h"], res[i]["h"])
        s += f" ({q:.2f})"
    return s


def patch_study(work):
    results = {}
    for nu in (0.0, 0.3):
        for shared in (False, True):
            tag = f"nu = {nu}, " + ("shared_mass" if shared else "segment gap, own mass")
            emit(f"\n### Patch test, {tag}\n")
            emit("Pressure errors relative to p = rho c v_rel/2 over the interface particles "
                 "(the two corner particles apart: last column), gap of the slave's particles "
                 "to the master's interface polyline; in brackets the observed order against "
                 "the row above.\n")
            emit("| m | h (mm) | slave particles | wall (s) | total force | slave p RMS | "
                 "slave p max | slave p max, central half | master p RMS | "
                 "master p max, central half | gap max (m) | gap max / h | "
                 "corner p/p_ex (slave, master) |")
            emit("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
            res = []
            for m in PATCH_M:
                name = f"patch_m{m}_nu{nu}_{'shared' if shared else 'default'}"
                f, wall, last = run(patch_deck(m, nu, shared, f"out/{name}.h5"), name, work)
                if f is None:
                    emit(f"| {m} | {patch_geometry(m)[2] * 1e3:.4f} | {7 * m + 1} | {wall:.1f} "
                         f"| run stopped: {last[last.find('run failed'):][:90]} |")
                    res.append(None)
                    continue
                r = patch_measures(f, m, nu)
                r["wall"] = wall
                res.append(r)
                i = len(res) - 1
                emit(f"| {m} | {r['h'] * 1e3:.4f} | {r['n']} | {wall:.1f} | "
                     f"{r['total']:+.1e} | {cell(res, i, 's_rms')} | {cell(res, i, 's_max')} | "
                     f"{cell(res, i, 's_mid')} | {cell(res, i, 'm_rms')} | "
                     f"{cell(res, i, 'm_mid')} | {cell(res, i, 'g_max', '{:.2e}')} | "
                     f"{r['g_max'] / r['h']:.1e} | "
                     f"{r['corner_p']:.2f}, {r['corner_pm']:.2f} |")
                f.close()
            results[(nu, shared)] = res
    return results


def hertz_measures(f):
    rows = []
    labs = sorted(f.snapshot_labels())
    for lab in labs[2::2]:
        t = f.snapshot_time(lab)
        _, x, fc = surface_row(f, lab, "block")
        right = x[:, 0] >= -1e-9 * A_TARGET          # x >= 0 but for round-off
        xs, p = x[right, 0], pressure(x, fc, -1.0)[right]
        P = -fc[:, 1].sum()
        aH, p0 = hertz_line(P, R_CYL, E_STAR)
        pex = p0 * np.sqrt(np.clip(1 - xs ** 2 / aH ** 2, 0, None))
        near = xs <= 1.25 * aH                     # the contact and just beyond it
        err = (p - pex)[near] / p0
        a_e, a_f = edge_half_width(xs, p), fit_half_width(xs, p)
        on = p > 1e-6 * p.max()
        g = np.hypot(x[right, 0], x[right, 1] - R_CYL) - R_CYL   # to the exact circle
        rows.append(dict(t=t, P=P, aH=aH, p0=p0, a_edge=a_e / aH - 1, a_fit=a_f / aH - 1,
                         p_peak=p[0] / p0 - 1, p_rms=np.sqrt(np.mean(err ** 2)),
                         p_max=np.abs(err).max(), g_max=np.abs(g[on]).max(), n_on=int(on.sum()),
                         xs=xs, p=p))
    return rows


def hertz_study(work):
    emit("\n### Hertz line contact (rigid cylinder, R = 10 mm, on an elastic block)\n")
    emit("Final instant; a_H = sqrt(4 P R/(pi E*)) from the measured load P; errors of a "
         "relative to a_H, of the pressure relative to p0 = 2P/(pi a_H) over x <= 1.25 a_H; "
         "gap of the loaded particles to the circle; in brackets the observed "
         "order against the row above.\n")
    emit("| k = a/h | h (um) | particles | wall (s) | P (MN/m) | a_H (mm) | loaded (x >= 0) | "
         "a, edge | a, fit | p(0)/p0 - 1 | p RMS | p max | gap max (m) | gap max / h |")
    emit("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    res, allrows = [], {}
    for k in HERTZ_K:
        name = f"hertz_k{k}"
        h, nxh, ny, _, _ = hertz_setup(k)
        f, wall, last = run(hertz_deck(k, f"out/{name}.h5"), name, work)
        if f is None:
            emit(f"| {k} | run failed: {last[:120]} |")
            res.append(None)
            continue
        rows = hertz_measures(f)
        f.close()
        allrows[k] = rows
        r = dict(rows[-1])
        r["h"] = h
        for key in ("a_edge", "a_fit", "p_peak"):
            r[key] = abs(r[key])
        res.append(r)
        i = len(res) - 1
        emit(f"| {k} | {h * 1e6:.2f} | {(2 * nxh + 1) * ny} | {wall:.1f} | {r['P'] / 1e6:.4f} | "
             f"{r['aH'] * 1e3:.4f} | {r['n_on']} | {cell(res, i, 'a_edge')} | "
             f"{cell(res, i, 'a_fit')} | {cell(res, i, 'p_peak')} | {cell(res, i, 'p_rms')} | "
             f"{cell(res, i, 'p_max')} | {cell(res, i, 'g_max', '{:.2e}')} | "
             f"{r['g_max'] / h:.1e} |")
    emit("\nEvery instant (signed errors: a_edge/a_H - 1, a_fit/a_H - 1, p(0)/p0 - 1):\n")
    emit("| k | t (us) | P (MN/m) | a_H (mm) | a, edge | a, fit | p(0) | p RMS |")
    emit("|---|---|---|---|---|---|---|---|")
    for k, rows in allrows.items():
        for r in rows:
            emit(f"| {k} | {r['t'] * 1e6:.3f} | {r['P'] / 1e6:.4f} | {r['aH'] * 1e3:.4f} | "
                 f"{r['a_edge']:+.4f} | {r['a_fit']:+.4f} | {r['p_peak']:+.4f} | "
                 f"{r['p_rms']:.4f} |")
    return res, allrows


def figures(patch, hertz):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mfcd_style import figure_style
    plt.rcParams.update(figure_style(savefig_dpi=130))
    os.makedirs(FIGS, exist_ok=True)
    if patch:
        fig, axs = plt.subplots(1, 2, figsize=(11, 4), sharey=True)
        for ax, shared in zip(axs, (False, True)):
            for m, style in ((4, "o-"), (16, ".-"), (8, "s-")):
                r = patch[(0.0, shared)][PATCH_M.index(m)]
                if r is None:
                    continue
                ax.plot(r["xu"] * 1e3, r["pu"], style, ms=3, lw=0.8, label=f"slave, m = {m}")
                ax.plot(r["xl"] * 1e3, r["pl"], style, ms=3, lw=0.8, alpha=0.5,
                        label=f"master, m = {m}")
            ax.axhline(1.0, color="k", lw=0.8)
            ax.set_xlabel("x (mm)")
            ax.set_title("own effective mass (shared_mass = .false.)" if not shared else "shared_mass = .true.")
            ax.legend(ncol=2)
        axs[0].set_ylabel("p / (rho c v_rel / 2)")
        axs[0].set_ylim(-0.05, 1.5)
        fig.suptitle("Patch test, nu = 0: interface pressure (mean over [0.3, 0.8] 2L/c)")
        fig.tight_layout()
        fig.savefig(os.path.join(FIGS, "patch_pressure.png"))
        plt.close(fig)
    if hertz:
        res, allrows = hertz
        fig, axs = plt.subplots(1, 2, figsize=(11, 4))
        xx = np.linspace(0, 1, 200)
        axs[0].plot(xx, np.sqrt(1 - xx ** 2), "k-", lw=1.2, label="Hertz")
        axs[0].plot([1, 1.3], [0, 0], "k-", lw=1.2)
        for k, rows in allrows.items():
            r = rows[-1]
            axs[0].plot(r["xs"] / r["aH"], r["p"] / r["p0"], "o", ms=3, label=f"k = {k}")
        axs[0].set_xlim(0, 1.3)
        axs[0].set_xlabel("x / a_H")
        axs[0].set_ylabel("p / p0")
        axs[0].set_title("pressure at the final instant")
        axs[0].legend()
        for k, rows in allrows.items():
            P = np.array([r["P"] for r in rows])
            a = np.array([(1 + r["a_edge"]) * r["aH"] for r in rows])
            axs[1].plot(P / 1e6, a * 1e3, "o", label=f"k = {k}, edge")
        PP = np.linspace(1e-3, 1.05, 200) * max(r["P"] for rows in allrows.values() for r in rows)
        axs[1].plot(PP / 1e6, hertz_line(PP, R_CYL, E_STAR)[0] * 1e3, "k-",
                    label="sqrt(4 P R / (pi E*))")
        axs[1].set_xlabel("P (MN/m)")
        axs[1].set_ylabel("a (mm)")
        axs[1].set_title("half-width against load")
        axs[1].legend()
        fig.tight_layout()
        fig.savefig(os.path.join(FIGS, "hertz_pressure.png"))
        plt.close(fig)
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.2))
    if patch:
        for (nu, shared), res in patch.items():
            if nu != 0.0:
                continue
            ok = [r for r in res if r is not None]
            h = np.array([r["h"] for r in ok]) * 1e3
            lab = "shared" if shared else "default"
            ls = "-" if shared else "--"
            axs[0].loglog(h, [r["s_rms"] for r in ok], "o" + ls, label=f"slave p RMS, {lab}")
            axs[0].loglog(h, [r["s_mid"] for r in ok], "s" + ls,
                          label=f"slave p max, central half, {lab}")
            axs[0].loglog(h, [abs(r["total"]) for r in ok], "^" + ls,
                          label=f"total force, {lab}")
            axs[2].loglog(h, [r["g_max"] for r in ok], "o" + ls,
                          label=f"patch: slave on master, {lab}")
        axs[0].set_xlabel("slave spacing h (mm)")
        axs[0].set_ylabel("relative error")
        axs[0].set_title("patch test, nu = 0 (p = rho c v_rel / 2)")
        axs[0].legend(fontsize=7)
    if hertz:
        ok = [r for r in hertz[0] if r is not None]
        h = np.array([r["h"] for r in ok])
        for key, lab in (("a_edge", "a (edge)"), ("a_fit", "a (fit)"), ("p_peak", "p(0)"),
                         ("p_rms", "p RMS")):
            axs[1].loglog(h * 1e6, [max(r[key], 1e-6) for r in ok], "o-", label=lab)
        axs[1].loglog(h * 1e6, ok[0]["a_edge"] * (h / h[0]) ** 2, "k:", label="order 2")
        axs[1].set_xlabel("block spacing h (um)")
        axs[1].set_ylabel("relative error")
        axs[1].set_title("Hertz line contact, final instant")
        axs[1].legend(fontsize=7)
        axs[2].loglog(h * 1e3, [r["g_max"] for r in ok], "d-", label="Hertz: block on circle")
    if patch or hertz:
        hh = np.array([6.25e-6, 4.3e-4])
        axs[2].loglog(hh * 1e3, 8e-5 * hh, "k:", label="8e-5 h (order 1)")
        axs[2].set_xlabel("spacing h (mm)")
        axs[2].set_ylabel("largest gap (m)")
        axs[2].set_title("gap left after the contact correction")
        axs[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "contact_orders.png"))
    plt.close(fig)


def header():
    cpu = ""
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        cpu = [l.split(":", 1)[1].strip() for l in lscpu.splitlines()
               if l.startswith("Model name")][0]
    except (OSError, IndexError):
        pass
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    now = datetime.datetime.now(datetime.timezone.utc)
    emit(f"# Contact patch test and Hertz line contact ({now:%Y-%m-%d %H:%M} UTC)")
    emit(f"\ncommit {commit}, {cpu}, 1 thread, load {os.getloadavg()[0]:.2f}; "
         "command: .venv/bin/python bench/contact_patch.py " + " ".join(sys.argv[1:]))


def main():
    args = sys.argv[1:]
    if "--decks" in args:
        open(os.path.join(ROOT, "input", "patch_test.nml"), "w").write(
            patch_deck(2, out="output/patch_test.h5"))
        open(os.path.join(ROOT, "input", "hertz_cylinder.nml"), "w").write(
            hertz_deck(8, out="output/hertz_cylinder.h5"))
        return
    todo = [a for a in args if a in ("patch", "hertz")] or ["patch", "hertz"]
    work = tempfile.mkdtemp(prefix="mfcd_patch_")
    header()
    patch = patch_study(work) if "patch" in todo else None
    hertz = hertz_study(work) if "hertz" in todo else None
    figures(patch, hertz)
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    path = os.path.join(ROOT, "bench", "results",
                        f"contact_patch_{datetime.date.today():%Y%m%d}.md")
    open(path, "w").write("\n".join(OUT) + "\n")
    print(f"\nwrote {path} and the figures in {FIGS}; runs in {work}")


if __name__ == "__main__":
    main()
