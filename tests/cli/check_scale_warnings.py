#!/usr/bin/env python3
"""Scale sanity (issue 22, item 3): `mfcd --check` (and the run, whose log has the same
set-up lines) warns, without failing, when a material's dilatational wave speed lies
outside 100-20,000 m/s, a body is smaller than 1 um or larger than 100 m across, or the run
ends in fewer than 10 steps, and each warning names the likely unit mistake.

From input/bar_impact_elastic.nml (a steel bar, 6 x 60 mm, on a rigid wall): the deck as it
is warns of nothing; E in GPa, density in g/cm^3, lengths in mm (t_end in s as before: the
run would end in 2 steps), lengths in km (a bar of 6 nm) or in um (6 km), and t_end in us
each give their warning and exit 0.

Usage: check_scale_warnings.py MFCD DECK
"""
import os
import re
import subprocess
import sys
import tempfile

MFCD, DECK = (os.path.abspath(a) for a in sys.argv[1:3])
results = []


def check(name, cond, detail=""):
    results.append(bool(cond))
    print(f"[{'  OK  ' if cond else 'FAILED'}] {name}" + ("" if cond else f": {detail}"))


def scale_lengths(text, f):
    """Every lo/hi/edge_point value of the deck times f (the lengths, as a unit slip)."""
    def mul(m):
        vals = [float(v) * f for v in m.group(2).split(",")]
        return m.group(1) + ", ".join(repr(v) for v in vals)
    return re.sub(r"(?m)^(\s*(?:lo|hi|edge_point)\s*=\s*)([-0-9.eE+, ]+)$", mul, text)


def main():
    base = open(DECK).read()
    base = re.sub(r"file = '[^']*'", "file = 'out/scale.h5'", base)
    cases = [
        ("as written", base, []),
        ("E in GPa", base.replace("youngs_modulus = 211.0e9", "youngs_modulus = 211.0"),
         ["below 100 m/s", "in GPa"]),
        ("density in g/cm^3", base.replace("density = 7800.0", "density = 7.8"),
         ["above 20,000 m/s", "g/cm^3"]),
        ("lengths in mm", scale_lengths(base, 1000.0), ["fewer than 10", "lengths in mm"]),
        ("lengths in km", scale_lengths(base, 1.0e-6), ["outside 1 um - 100 m", "in km"]),
        ("lengths in um", scale_lengths(base, 1.0e6), ["outside 1 um - 100 m", "in um"]),
        ("t_end in us", base.replace("t_end = 40.0e-6", "t_end = 40.0e-9").replace(
            "snapshot_times = 0.0, 10.0e-6, 20.0e-6, 30.0e-6, 40.0e-6", "snapshot_times = 0.0"),
         ["fewer than 10", "1 us = 1e-6"]),
    ]
    with tempfile.TemporaryDirectory() as work:
        for name, text, words in cases:
            path = os.path.join(work, "deck.nml")
            open(path, "w").write(text)
            p = subprocess.run([MFCD, "--check", path], cwd=work, capture_output=True,
                               text=True, timeout=300)
            warns = [ln for ln in p.stdout.splitlines() if ln.startswith("warning:")]
            check(f"{name}: --check exits 0 (a warning, not an error)", p.returncode == 0,
                  p.stdout[-600:] + p.stderr[-600:])
            if not words:
                check(f"{name}: no warning", not warns, warns)
                continue
            found = [w for w in warns if all(x in w for x in words)]
            check(f"{name}: a warning naming {words}", found, warns)
    print(f"{sum(results)} passed, {len(results) - sum(results)} failed")
    sys.exit(0 if all(results) else 1)


if __name__ == "__main__":
    main()
