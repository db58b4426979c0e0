#!/usr/bin/env python3
"""This build's results against a reference commit's, to the bit (issue 21: a refactor that
must change no result).

Builds the reference commit (default 762ac98) in a git worktree under build-ref/ (Release,
gmsh from .venv as this build has it; with --mpi also an MPI build of each), then runs every
deck with both programs and compares the two HDF5 files:

- every dataset under /snapshots and /history, and every /summary attribute that does not
  time the run (wall time, rates, threads), bit for bit (NaN equal to NaN);
- for a detect deck (example_2_2), every dataset under /detection.

Each dynamic deck is also run with a checkpoint half way and continued with --restart by
both programs, and the continued files compared likewise. Serial runs with 1 and 2 OpenMP
threads (--threads); with --mpi, mfcd_mpi on 1-4 ranks of each build (decks the MPI
driver refuses, such as a subcycled one, are skipped when both builds refuse them).

Not a test: it takes minutes (the paper's Taylor bars are half a minute a run); its result
goes in the closing note of a refactor. Exit 0 when everything compared is equal.

The reference's files are kept under build-ref/cache-<ref>/ and reused by later runs (its
program never changes), so a second comparison costs the new build's runs only; --ref-only
fills that cache and compares nothing (run it while the new tree is still being edited).
--new COMMIT compares a commit (checked out in a worktree under build-ref/) instead of this
working tree, so the tree may change while the comparison runs.

Usage: python bench/compare_builds.py [--ref COMMIT] [--new COMMIT] [--ref-only]
                                      [--threads 1,2] [--mpi] [--ranks 1,2,3,4] [DECK ...]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
DECKS = ["taylor_bar_rkpm", "taylor_bar_fem_cfl", "taylor_bar_rkpm_coarse",
         "bars_collision_elastic", "c_shape_fold", "torus_crush", "hertz_cylinder_rkpm",
         "example_2_2"]
TIMING = ("wall_time", "particle_steps_per_second", "point_steps_per_second", "threads",
          "time_loop", "ranks")


def sh(args, cwd=ROOT, env=None, check=True):
    p = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True)
    if check and p.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: exit {p.returncode}\n{p.stderr[-2000:]}")
    return p


def build(src, bdir, mpi):
    """Configure and build mfcd (and mfcd_mpi) in bdir from the tree src."""
    gmsh = os.path.join(ROOT, ".venv")
    args = ["cmake", "-S", src, "-B", bdir, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release",
            "-DMFCD_BUILD_TESTS=OFF", f"-DMFCD_GMSH_ROOT={gmsh}"]
    if mpi:
        args += ["-DMFCD_MPI=ON", "-DMFCD_GMSH=OFF"]
    sh(args)
    sh(["ninja", "-C", bdir] + (["mfcd", "mfcd_mpi"] if mpi else ["mfcd"]))


def equal(a, b):
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.dtype != b.dtype:
        return False
    if a.dtype.kind == "f":
        return bool(np.array_equal(a, b, equal_nan=True))
    return bool(np.array_equal(a, b))


def compare(f_ref, f_new):
    """'' when equal, else the first difference."""
    with h5py.File(f_ref, "r") as r, h5py.File(f_new, "r") as n:
        for group in ("snapshots", "history", "detection"):
            if group not in r and group not in n:
                continue
            if (group in r) != (group in n):
                return f"/{group} in one file only"
            names_r, names_n = [], []
            r[group].visit(lambda k: names_r.append(k))
            n[group].visit(lambda k: names_n.append(k))
            if sorted(names_r) != sorted(names_n):
                return f"/{group}: {sorted(set(names_r) ^ set(names_n))[:5]} in one only"
            for k in names_r:
                if isinstance(r[group][k], h5py.Dataset):
                    if not equal(r[group][k][()], n[group][k][()]):
                        return f"/{group}/{k} differs"
        if "summary" in r:
            sr, sn = dict(r["summary"].attrs), dict(n["summary"].attrs)
            for k in sorted(set(sr) | set(sn)):
                if k in TIMING:
                    continue
                if k not in sr or k not in sn or not equal(sr[k], sn[k]):
                    return f"/summary@{k} differs ({sr.get(k)!r} against {sn.get(k)!r})"
    return ""


def deck_copy(deck, work, tag, extra=""):
    """The deck with its output in work (name tag.h5) and extra &output variables."""
    text = open(os.path.join(ROOT, "input", deck + ".nml")).read()
    out = os.path.join(work, tag + ".h5")
    text, n = re.subn(r"(?m)^(\s*file\s*=\s*)'output/[^']*'", rf"\1'{out}'", text)
    if n != 1:
        raise RuntimeError(f"{deck}: no single output/ file to redirect")
    if extra:
        text = re.sub(r"(?m)^(\s*file\s*=\s*'" + re.escape(out) + "')", rf"\1\n{extra}",
                      text)
    path = os.path.join(work, tag + ".nml")
    with open(path, "w") as f:
        f.write(text)
    return path, out


def worktree(commit):
    """A checkout of commit under build-ref/ (made once)."""
    src = os.path.join(ROOT, "build-ref", "src-" + commit)
    if not os.path.isdir(src):
        os.makedirs(os.path.dirname(src), exist_ok=True)
        sh(["git", "worktree", "add", "--detach", src, commit])
    return src


def cached(cache, key, out, produce):
    """The reference's file for key: from the cache, or produced (produce() returns the
    exit status; 2 on ranks is a refusal, kept as such) and copied there. Returns
    (exit status, path)."""
    keep = os.path.join(cache, key + ".h5")
    refused = os.path.join(cache, key + ".refused")
    if os.path.exists(keep):
        return 0, keep
    if os.path.exists(refused):
        return 2, ""
    rc = produce()
    if rc == 0:
        shutil.copyfile(out, keep + ".part")
        os.replace(keep + ".part", keep)
        return 0, keep
    if rc == 2:
        open(refused, "w").close()
    return rc, ""


def steps_of(h5):
    with h5py.File(h5, "r") as f:
        return int(f["summary"].attrs["steps"])


def restarted(deck, work, prog, env, tag, every):
    """The deck run with a checkpoint at step every and continued from it by --restart."""
    path, out = deck_copy(deck, work, f"{deck}_{tag}_ck", f"  checkpoint_every = {every}")
    rc, err = run([prog, path], env)
    if rc != 0:
        raise RuntimeError(f"{deck} {tag} checkpoint: {err[-1500:]}")
    ck = out[:-3] + ".checkpoint.h5"
    os.remove(out)
    rc, err = run([prog, "--restart", ck, path], env)
    if rc != 0:
        raise RuntimeError(f"{deck} {tag} restart: {err[-1500:]}")
    return out


def restart_ref(deck, work, progs, env, cache, key, full):
    """The reference's restarted file (cached like its plain runs)."""
    every = max(1, steps_of(full)//2)

    def produce():
        restarted(deck, work, progs["ref"], env, "ref", every)
        return 0
    rc, out = cached(cache, key + "_restart", os.path.join(work, f"{deck}_ref_ck.h5"),
                     produce)
    return out


def run(cmd, env):
    p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    return p.returncode, p.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ref", default="762ac98")
    ap.add_argument("--new", default="")
    ap.add_argument("--ref-only", action="store_true")
    ap.add_argument("--threads", default="1,2")
    ap.add_argument("--mpi", action="store_true")
    ap.add_argument("--ranks", default="1,2,3,4")
    ap.add_argument("decks", nargs="*")
    a = ap.parse_args()
    decks = a.decks or DECKS
    ref_src = worktree(a.ref)
    new_src = worktree(a.new) if a.new else ROOT
    cache = os.path.join(ROOT, "build-ref", "cache-" + a.ref)
    os.makedirs(cache, exist_ok=True)
    progs = {}
    builds = (("ref", ref_src),) if a.ref_only else (("ref", ref_src), ("new", new_src))
    for tag, src in builds:
        name = f"new-{a.new}" if tag == "new" and a.new else tag
        bdir = os.path.join(ROOT, "build-ref", f"{name}-serial")
        build(src, bdir, False)
        progs[tag] = os.path.join(bdir, "bin", "mfcd")
        if a.mpi:
            bdir = os.path.join(ROOT, "build-ref", f"{name}-mpi")
            build(src, bdir, True)
            progs[tag + "_mpi"] = os.path.join(bdir, "bin", "mfcd_mpi")
    failures = 0
    total = 0
    with tempfile.TemporaryDirectory(prefix="mfcd_compare_") as work:
        for deck in decks:
            text = open(os.path.join(ROOT, "input", deck + ".nml")).read()
            dynamic = re.search(r"(?im)^\s*mode\s*=\s*'dynamic'", text) is not None
            runs = [(f"{t} thread(s)", dict(os.environ, OMP_NUM_THREADS=t), None)
                    for t in a.threads.split(",")]
            if a.mpi:
                runs += [(f"{n} rank(s)", dict(os.environ, OMP_NUM_THREADS="1",
                                                OMPI_ALLOW_RUN_AS_ROOT="1",
                                                OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1"), int(n))
                         for n in a.ranks.split(",")]
            for label, env, ranks in runs:
                files = {}
                refused = 0
                key = f"{deck}_" + label.replace(" ", "_").replace("(", "").replace(")", "")
                for tag in ("ref",) if a.ref_only else ("ref", "new"):
                    prog = progs[tag] if ranks is None else progs[tag + "_mpi"]
                    cmd = ([prog] if ranks is None else
                           ["mpirun", "--oversubscribe", "-np", str(ranks), prog])
                    path, out = deck_copy(deck, work, f"{deck}_{tag}")
                    err = ""

                    def produce():
                        nonlocal err
                        rc, err = run(cmd + [path], env)
                        return rc
                    if tag == "ref":
                        rc, out = cached(cache, key, out, produce)
                    else:
                        rc = produce()
                    if rc == 2 and ranks is not None:
                        refused += 1
                        continue
                    if rc != 0:
                        raise RuntimeError(f"{deck} {tag} {label}: exit {rc}\n{err[-1500:]}")
                    files[tag] = out
                if a.ref_only:
                    if files and dynamic and ranks is None:
                        restart_ref(deck, work, progs, env, cache, key, files["ref"])
                    print(f"[ REF  ] {deck}, {label}", flush=True)
                    continue
                if refused == 2:
                    print(f"[ SKIP ] {deck}, {label}: refused by both builds' mfcd_mpi")
                    continue
                if refused == 1:
                    print(f"[ FAIL ] {deck}, {label}: refused by one build only")
                    failures += 1
                    total += 1
                    continue
                diff = compare(files["ref"], files["new"])
                total += 1
                failures += bool(diff)
                print(("[  OK  ] " if not diff else "[ FAIL ] ") + f"{deck}, {label}"
                      + (": " + diff if diff else ""), flush=True)
                if not dynamic or ranks is not None:
                    continue
                # a checkpoint half way, continued by --restart, by both programs
                every = max(1, steps_of(files["ref"])//2)
                cont = {"ref": restart_ref(deck, work, progs, env, cache, key, files["ref"]),
                        "new": restarted(deck, work, progs["new"], env, "new", every)}
                diff = compare(cont["ref"], cont["new"])
                total += 1
                failures += bool(diff)
                print(("[  OK  ] " if not diff else "[ FAIL ] ") + f"{deck}, {label}, "
                      f"restarted at step {every}" + (": " + diff if diff else ""),
                      flush=True)
    if a.ref_only:
        print(f"reference files of {a.ref} in {cache}")
        return 0
    print(f"{total - failures} of {total} comparisons equal to the bit ({a.ref} against "
          f"{a.new or 'this tree'})")
    return 0 if failures == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
