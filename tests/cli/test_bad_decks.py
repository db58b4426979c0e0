#!/usr/bin/env python3
"""The corpus of bad decks (issue 8, item 9): every deck in tests/cli/bad_decks/ must be refused.

For each deck, in a fresh temporary directory holding a copy of the deck and of the files it
needs, both `mfcd DECK` and `mfcd --check DECK` must exit with code 2, print one error that
names the deck file and every expected word, and leave the directory exactly as it was (no
file created, removed or changed: names, sizes, modification times and contents).

A deck's header says what is wrong and what to expect:

    ! <first line: what is wrong with the deck>
    ! expect: <a word the message must contain, usually the variable>   (one or more lines)
    ! needs: <file> [<file> ...]     (particle files and gmsh scripts beside the deck, copied along)
    ! requires: meminfo              (skipped where /proc/meminfo has no MemAvailable)
    ! requires: gmsh                 (skipped where mfcd is built without gmsh: `mfcd --version`)
    ! requires: no-gmsh              (skipped where mfcd is built with gmsh)

Standard library only. Usage: test_bad_decks.py /path/to/mfcd [deck-name-substring ...]
"""
import os
import shutil
import subprocess
import sys
import tempfile

from dir_state import snapshot

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "bad_decks")


def header(path):
    """The deck's description and its expect/needs/requires lines."""
    meta = {"what": "", "expect": [], "needs": [], "requires": []}
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if not lines or not lines[0].startswith("!"):
        raise ValueError(f"{path}: the first line must be a comment saying what is wrong")
    meta["what"] = lines[0].lstrip("! ").strip()
    for line in lines[1:]:
        if not line.startswith("!"):
            break
        body = line.lstrip("! ")
        for key in ("expect", "needs", "requires"):
            if body.startswith(key + ":"):
                value = body[len(key) + 1:].strip()
                if key == "expect":
                    meta[key].append(value)
                else:
                    meta[key].extend(value.split())
    if not meta["expect"]:
        raise ValueError(f"{path}: no '! expect: <word>' line")
    return meta


def has_meminfo():
    try:
        with open("/proc/meminfo") as f:
            return any(line.startswith("MemAvailable:") for line in f)
    except OSError:
        return False


def has_gmsh(mfcd):
    """Whether this mfcd meshes .geo scripts: its --version names gmsh's version."""
    p = subprocess.run([mfcd, "--version"], capture_output=True, text=True)
    return any(line.startswith("gmsh 4") for line in p.stdout.splitlines())


def main():
    mfcd = os.path.abspath(sys.argv[1])
    gmsh = has_gmsh(mfcd)
    only = sys.argv[2:]
    decks = sorted(d for d in os.listdir(CORPUS) if d.endswith(".nml"))
    if only:
        decks = [d for d in decks if any(o in d for o in only)]
    failures = []
    nrun = 0
    for deck in decks:
        meta = header(os.path.join(CORPUS, deck))
        if "meminfo" in meta["requires"] and not has_meminfo():
            print(f"[ SKIP ] {deck}: /proc/meminfo has no MemAvailable")
            continue
        if "gmsh" in meta["requires"] and not gmsh:
            print(f"[ SKIP ] {deck}: this mfcd is built without gmsh")
            continue
        if "no-gmsh" in meta["requires"] and gmsh:
            print(f"[ SKIP ] {deck}: this mfcd is built with gmsh")
            continue
        nrun += 1
        problems = []
        with tempfile.TemporaryDirectory(prefix="mfcd_bad_") as tmp:
            for name in [deck] + meta["needs"]:
                shutil.copy2(os.path.join(CORPUS, name), os.path.join(tmp, name))
            before = snapshot(tmp)
            for args in ([deck], ["--check", deck]):
                label = " ".join(["mfcd"] + args)
                try:
                    p = subprocess.run([mfcd] + args, cwd=tmp, capture_output=True,
                                       timeout=300, env=dict(os.environ, OMP_NUM_THREADS="1"))
                except subprocess.TimeoutExpired:
                    problems.append(f"{label}: no answer in 300 s")
                    continue
                err = p.stderr.decode("utf-8", errors="replace")
                if p.returncode != 2:
                    problems.append(f"{label}: exit code {p.returncode}, expected 2; "
                                    f"stderr: {err.strip()[-600:]!r}")
                    continue
                if err.count("mfcd: error:") != 1:
                    problems.append(f"{label}: expected one 'mfcd: error:' line: {err!r}")
                missing = [w for w in [deck] + meta["expect"] if w not in err]
                if missing:
                    problems.append(f"{label}: message lacks {missing}: {err.strip()!r}")
                after = snapshot(tmp)
                if after != before:
                    changed = sorted(k for k in set(before) | set(after)
                                     if before.get(k) != after.get(k))
                    problems.append(f"{label}: the directory changed: {changed}")
        if problems:
            failures.append(deck)
            print(f"[ FAIL ] {deck} ({meta['what']})")
            for text in problems:
                print("         " + text)
        else:
            print(f"[  OK  ] {deck}: {meta['what']}")
    print(f"{nrun - len(failures)} of {nrun} bad decks refused as expected")
    sys.exit(1 if failures or nrun == 0 else 0)


if __name__ == "__main__":
    main()
