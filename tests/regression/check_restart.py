#!/usr/bin/env python3
"""Checkpoint and restart (issue 8, item 7): a run continued from a checkpoint with
`mfcd --restart CHECKPOINT.h5 DECK.nml` reproduces the uninterrupted run bit for bit.

Main deck (argument 2; input/bar_impact_j2_coarse.nml: RKPM, J2 plasticity, contact with
friction, adaptive step, the edge particle tracked), with OMP_NUM_THREADS = 1 and 2:
- the uninterrupted run, checkpoint_every = 500, is the reference; its checkpoint is the
  last one (step 1500) and it is kept after the run;
- a second run of the same deck is killed (SIGKILL) as soon as the log reports its first
  checkpoint: the checkpoint is intact, nothing is under the result's name;
- the restart from that checkpoint completes; its /history (every column, every row from
  t = 0), the snapshots it wrote (those after the checkpoint), its /summary (every
  attribute but the wall-clock timings) and its /deck equal the reference's exactly
  (numpy array_equal, no tolerance), and its own checkpoints replaced the one it was
  restarted from. The 2-thread deck has overwrite = .false.: the checkpoint given to
  --restart is the one existing file the run may replace.
Other decks (arguments 3...: deformable master, CST4 elements, a prescribed velocity,
self-contact with its skipping state), one thread: the run is restarted from the last checkpoint of the uninterrupted run, taken at
about 60% of its steps, and must equal it likewise.
The first other deck also from a checkpoint taken at its last step (no step left): its
/history and /summary as the uninterrupted run's.
Refused with exit 2, nothing created: the checkpoint with a deck that differs in one number
(the message names both files and says 'written by a different deck'); an mfcd output file;
a file that is not HDF5; a checkpoint of another format or mfcd version; --check with the
different deck. Also: --check --restart with the right deck exits 0 and writes nothing;
checkpoint_every < 0 exits 2 naming it; with overwrite = .false. an earlier run's
checkpoint is refused like the other names.
Usage: check_restart.py /path/to/mfcd main.nml [other.nml ...]
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile

import h5py  # checkpoints (not output files), the snapshot walk of compare(), refusals' inputs
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "post"))
from mfcd_h5 import MfcdFile, is_timing  # noqa: E402

MFCD = os.path.abspath(sys.argv[1])
MAIN = os.path.abspath(sys.argv[2])
OTHERS = [os.path.abspath(d) for d in sys.argv[3:]]
EVERY = 500
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(("[  OK  ] " if cond else "[ FAIL ] ") + "restart." + name
          + ("" if cond else ": " + str(detail)[-1500:]), flush=True)


def env(threads):
    e = dict(os.environ)
    e["OMP_NUM_THREADS"] = str(threads)
    # threads sleep at barriers instead of spinning: ctest -j runs tests side by side on
    # few cores (the result does not depend on it)
    e["OMP_WAIT_POLICY"] = "passive"
    return e


def run(args, cwd, threads=1):
    p = subprocess.run([MFCD] + args, cwd=cwd, capture_output=True, text=True, timeout=600,
                       env=env(threads))
    return p.returncode, p.stdout, p.stderr


def make_deck(src, work, every, extra_output="", edge=False, name="deck.nml"):
    """A copy of deck src writing out/run.h5 with checkpoints every `every` steps."""
    text = open(src).read()
    text, n = re.subn(r"file\s*=\s*'[^']*\.h5'", "file = 'out/run.h5'\n  checkpoint_every = "
                      + str(every) + extra_output, text)
    assert n == 1, src
    if edge:
        text = re.sub(r"(\n\s*mu\s*=\s*[0-9.eE+-]+)", r"\1\n  edge_point = 0.005, 0.0", text)
    path = os.path.join(work, name)
    open(path, "w").write(text)
    return path


def step_of(path):
    # a checkpoint is mfcd's input, not an output file: mfcd_h5 does not read it
    with h5py.File(path, "r") as f:
        return int(f.attrs["step"])


def attr_text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def compare(tag, ref, new, restart_step):
    """new (restarted) against ref (uninterrupted), exactly."""
    with MfcdFile(ref) as fa, MfcdFile(new) as fb:
        check(f"{tag}: /deck is the deck", fa.deck == fb.deck)
        ha, hb = fa.history(), fb.history()
        cols = list(ha)
        bad = [c for c in cols if ha[c].shape != hb[c].shape
               or not np.array_equal(ha[c], hb[c])]
        check(f"{tag}: /history equal in all {len(cols)} columns, "
              f"{ha['step'].shape[0]} rows from t = 0", not bad, bad)
        sa, sb = fa.summary_flat(), fb.summary_flat()
        # every value but the wall-clock ones (mfcd_h5.is_timing)
        keys = [k for k in sa if not is_timing(k)]
        diff = [k for k in keys if not np.array_equal(np.asarray(sa[k]), np.asarray(sb.get(k)))]
        check(f"{tag}: /summary equal but the timings ({len(keys)} values: "
              f"steps {sb['steps']}, time {sb['time']:.6e}, energies, counters, bodies)",
              not diff, [(k, sa[k], sb.get(k)) for k in diff])
        check(f"{tag}: status completed", attr_text(sb["status"]) == "completed")
        labels_a, labels_b = sorted(fa.snapshot_labels()), sorted(fb.snapshot_labels())
        labels = [l for l in labels_a if fa.snapshot_time(l) > fb.restart["restart_time"]]
        check(f"{tag}: the snapshots after the restart, {labels}, and only they",
              labels_b == sorted(labels), (labels_b, labels))
        restart = fb.restart
    # bit for bit: walks every dataset of each snapshot group, known to the reader or not
    with h5py.File(ref, "r") as a, h5py.File(new, "r") as b:
        bad = []
        for lab in labels:
            # every dataset at any depth (bodies' fields, det/contact<k>/... grids)
            paths = []
            a["snapshots"][lab].visititems(
                lambda n, o: paths.append(n) if isinstance(o, h5py.Dataset) else None)
            for name in paths:
                p = f"snapshots/{lab}/{name}"
                if p not in b or not np.array_equal(a[p][()], b[p][()]):
                    bad.append(p)
        check(f"{tag}: snapshot fields equal ({labels[-1] if labels else '-'} is the final "
              "state)", labels and not bad, bad)
    check(f"{tag}: root attributes name the restart (step {restart_step})",
          int(restart["restart_step"]) == restart_step
          and int(restart["snapshots_before_restart"]) == len(labels_a) - len(labels))


def main_deck(threads, root):
    """Reference, a killed run, its restart; threads OpenMP threads."""
    tag = f"{os.path.basename(MAIN)}, {threads} thread(s)"
    extra = "\n  overwrite = .false." if threads == 2 else ""
    ref_dir, int_dir = os.path.join(root, f"ref{threads}"), os.path.join(root, f"int{threads}")
    os.makedirs(ref_dir)
    os.makedirs(int_dir)
    deck_ref = make_deck(MAIN, ref_dir, EVERY, extra, edge=True)
    deck_int = make_deck(MAIN, int_dir, EVERY, extra, edge=True)
    rc, out, err = run([deck_ref], ref_dir, threads)
    check(f"{tag}: reference run exits 0", rc == 0, err)
    if rc:
        return None
    ref = os.path.join(ref_dir, "out", "run.h5")
    ck = os.path.join(ref_dir, "out", "run.checkpoint.h5")
    with MfcdFile(ref) as f:
        nsteps = int(f.summary["steps"])
    last = EVERY * (nsteps // EVERY)
    check(f"{tag}: checkpoint kept after completion, the last one (step {last} of {nsteps})",
          os.path.exists(ck) and step_of(ck) == last, os.listdir(os.path.dirname(ck)))
    check(f"{tag}: the log reports every checkpoint",
          len(re.findall(r"dynamic: checkpoint at step", out)) == nsteps // EVERY)
    check(f"{tag}: no temporary file left", not [n for n in os.listdir(os.path.dirname(ck))
                                                  if ".tmp-" in n])

    # a run killed after its first checkpoint
    p = subprocess.Popen([MFCD, deck_int], cwd=int_dir, stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, text=True, env=env(threads))
    for line in p.stdout:
        if line.startswith("dynamic: checkpoint at step"):
            p.send_signal(signal.SIGKILL)
            break
    p.stdout.close()
    p.wait()
    ck_int = os.path.join(int_dir, "out", "run.checkpoint.h5")
    killed = p.returncode == -signal.SIGKILL
    check(f"{tag}: run killed after a checkpoint", killed and os.path.exists(ck_int),
          p.returncode)
    if not os.path.exists(ck_int):
        return None
    s = step_of(ck_int)
    check(f"{tag}: the killed run left its checkpoint (step {s}) and no result",
          0 < s < nsteps and not os.path.exists(os.path.join(int_dir, "out", "run.h5")))

    rc, out, err = run(["--restart", "out/run.checkpoint.h5", deck_int], int_dir, threads)
    check(f"{tag}: restart from step {s} exits 0", rc == 0, err)
    if rc:
        return None
    check(f"{tag}: the log says where it restarted",
          f"restart: from checkpoint 'out/run.checkpoint.h5' at step {s}," in out, out[-3000:])
    compare(tag, ref, os.path.join(int_dir, "out", "run.h5"), s)
    if s < last:
        check(f"{tag}: the restarted run's checkpoints replaced the one it started from "
              f"(now step {step_of(ck_int)})", step_of(ck_int) == last)
    return ref, ck, deck_ref


def reference(src, root, tag, sub, every_of):
    """The uninterrupted run of src in root/sub with checkpoint_every = every_of(its step
    count, from a first run without checkpoints): (work, deck, ref, checkpoint, steps), or
    None when a run fails."""
    work = os.path.join(root, sub)
    os.makedirs(work)
    probe = make_deck(src, work, 0, name="probe.nml")
    rc, _, err = run([probe], work)
    check(f"{tag}: first run exits 0", rc == 0, err)
    if rc:
        return None
    with MfcdFile(os.path.join(work, "out", "run.h5")) as f:
        nsteps = int(f.summary["steps"])
    every = every_of(nsteps)
    deck = make_deck(src, work, every)
    rc, _, err = run([deck], work)
    check(f"{tag}: reference run with checkpoint_every = {every} exits 0", rc == 0, err)
    if rc:
        return None
    ref = os.path.join(work, "ref.h5")
    shutil.move(os.path.join(work, "out", "run.h5"), ref)
    return work, deck, ref, os.path.join(work, "out", "run.checkpoint.h5"), nsteps


def other_deck(src, root):
    """Restart from the last checkpoint of the uninterrupted run, at ~60% of its steps."""
    tag = os.path.basename(src)
    got = reference(src, root, tag, tag.replace(".nml", ""), lambda n: max(1, (6 * n) // 10))
    if got is None:
        return
    work, deck, ref, ck, nsteps = got
    s = step_of(ck)
    rc, _, err = run(["--restart", ck, deck], work)
    check(f"{tag}: restart from step {s} of {nsteps} exits 0", rc == 0, err)
    if rc == 0:
        compare(tag, ref, os.path.join(work, "out", "run.h5"), s)


def final_step(src, root):
    """A checkpoint taken at the run's last step, continued: no step is left, and the
    summary (every value but the timings) and the history must still be the uninterrupted
    run's. The points' stabilization energies, which the internal work takes in, are made
    by each force evaluation: the checkpoint keeps them (until 2026-11-30 it did not, and
    such a continuation reported the internal work without them)."""
    tag = os.path.basename(src) + ", checkpoint at the last step"
    got = reference(src, root, tag, os.path.basename(src).replace(".nml", "") + "_final",
                    lambda n: n)
    if got is None:
        return
    work, deck, ref, ck, nsteps = got
    with h5py.File(ck, "r") as f:
        e_stab = sum(float(np.asarray(g.attrs["energies"])[7]) for g in f["solids"].values())
    check(f"{tag}: checkpoint at step {step_of(ck)} of {nsteps}, stabilization energy "
          f"{e_stab:.3e} (not zero: the test sees it)", step_of(ck) == nsteps and e_stab != 0)
    rc, _, err = run(["--restart", ck, deck], work)
    check(f"{tag}: continued, exits 0", rc == 0, err)
    if rc:
        return
    with MfcdFile(ref) as fa, MfcdFile(os.path.join(work, "out", "run.h5")) as fb:
        ha, hb = fa.history(), fb.history()
        bad = [c for c in ha if c not in hb or not np.array_equal(ha[c], hb[c])]
        check(f"{tag}: /history equal", not bad, bad)
        sa, sb = fa.summary_flat(), fb.summary_flat()
        keys = [k for k in sa if not is_timing(k)]
        diff = [k for k in keys if not np.array_equal(np.asarray(sa[k]), np.asarray(sb.get(k)))]
        check(f"{tag}: /summary equal but the timings (internal work "
              f"{sb.get('internal_work')})", not diff, [(k, sa[k], sb.get(k)) for k in diff])


def refusals(root, ref, ck, deck):
    """Bad restarts exit 2 and create nothing."""
    work = os.path.join(root, "bad")
    os.makedirs(work)
    for f in (ck, deck):
        shutil.copy(f, work)
    shutil.copy(ref, os.path.join(work, "output.h5"))
    text = open(deck).read()
    other = text.replace("yield_stress = 400.0e6", "yield_stress = 401.0e6")
    assert other != text
    open(os.path.join(work, "other.nml"), "w").write(other)
    shutil.copy(ck, os.path.join(work, "fmt.h5"))
    # checkpoints altered to be refused: mfcd's inputs, written with h5py (the format this
    # mfcd writes, which the refusal names, read from its own checkpoint)
    with h5py.File(os.path.join(work, "fmt.h5"), "a") as f:
        fmt = int(f.attrs["format_version"])
        f.attrs["format_version"] = np.int32(99)
    shutil.copy(ck, os.path.join(work, "ver.h5"))
    with h5py.File(os.path.join(work, "ver.h5"), "a") as f:
        f.attrs["code_version"] = np.bytes_(b"0.0.1")
    before = sorted(os.listdir(work))
    cases = [
        ("a different deck", ["--restart", "run.checkpoint.h5", "other.nml"],
         ["written by a different deck", "'run.checkpoint.h5'", "'other.nml'",
          "yield_stress = 401.0e6"]),
        ("a different deck with --check", ["--check", "--restart", "run.checkpoint.h5",
                                           "other.nml"], ["written by a different deck"]),
        ("an mfcd output file", ["--restart", "output.h5", "deck.nml"],
         ["not an mfcd checkpoint"]),
        ("a file that is not HDF5", ["--restart", "deck.nml", "deck.nml"],
         ["is not an HDF5 file"]),
        ("a missing file", ["--restart", "missing.h5", "deck.nml"], ["not found"]),
        ("another checkpoint format", ["--restart", "fmt.h5", "deck.nml"],
         ["checkpoint format 99", f"reads format {fmt}"]),
        ("another mfcd version", ["--restart", "ver.h5", "deck.nml"],
         ["written by mfcd 0.0.1"]),
        ("--restart without a file", ["deck.nml", "--restart"], ["--restart needs"]),
    ]
    for what, args, words in cases:
        rc, out, err = run(args, work)
        missing = [w for w in words if w not in err]
        check(f"refused, exit 2: {what}", rc == 2 and not missing, (rc, missing, err))
    check("nothing created by the refusals", sorted(os.listdir(work)) == before,
          sorted(os.listdir(work)))
    rc, out, err = run(["--check", "--restart", "run.checkpoint.h5", "deck.nml"], work)
    check("--check --restart with the right deck exits 0 and writes nothing",
          rc == 0 and "is valid" in out and sorted(os.listdir(work)) == before, (rc, err))

    # checkpoint_every < 0
    open(os.path.join(work, "neg.nml"), "w").write(
        text.replace("checkpoint_every = 500", "checkpoint_every = -3"))
    rc, out, err = run(["neg.nml"], work)
    check("checkpoint_every = -3 exits 2 naming it", rc == 2 and "&output" in err
          and "checkpoint_every = -3" in err, err)
    # overwrite = .false.: an earlier run's checkpoint is refused (the --restart file is the
    # exception: main_deck with 2 threads)
    os.makedirs(os.path.join(work, "out"))
    shutil.copy(ck, os.path.join(work, "out", "run.checkpoint.h5"))
    open(os.path.join(work, "keep.nml"), "w").write(
        text.replace("checkpoint_every = 500", "checkpoint_every = 500\n  overwrite = .false."))
    rc, out, err = run(["keep.nml"], work)
    check("overwrite = .false.: an existing checkpoint is refused", rc == 2
          and "run.checkpoint.h5' exists and overwrite = .false." in err, err)


def main():
    root = tempfile.mkdtemp(prefix="mfcd_restart_")
    got = None
    for threads in (1, 2):
        r = main_deck(threads, root)
        got = got or r
    for src in OTHERS:
        other_deck(src, root)
    if OTHERS:
        final_step(OTHERS[0], root)
    if got:
        refusals(root, *got)
    else:
        check("reference available for the refusal checks", False)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    if all(results):
        shutil.rmtree(root, ignore_errors=True)
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
