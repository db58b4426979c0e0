#!/usr/bin/env python3
"""post/mfcd_h5.py's deck reader types values by the deck's description (issue 21, item 4).

Every deck in input/ is parsed; each value of a variable the description (src/setup/deck_vars.tsv)
knows must have the description's type (real: float, integer: int, logical: bool, string:
str), an array variable must be a list and a scalar one a single value; every default the
description gives is of its type too. Needs numpy and h5py (mfcd_h5 imports them).

Usage: test_deck_reader.py [input directory]
"""
import glob
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "post"))
from mfcd_h5 import deck_vars, parse_deck  # noqa: E402

PYTYPE = {"real": float, "integer": int, "logical": bool, "string": str}


def of_type(v, typ):
    return isinstance(v, PYTYPE[typ]) and not (typ != "logical" and isinstance(v, bool))


def main(argv):
    inp = argv[1] if len(argv) > 1 else os.path.join(ROOT, "input")
    desc = deck_vars()
    problems = []
    if len(desc) < 90:
        problems.append(f"the description has {len(desc)} variables: not read?")
    for (group, name), d in desc.items():
        dflt = d["default"]
        if dflt is None:
            continue
        vals = dflt if isinstance(dflt, list) else [dflt]
        if not all(of_type(v, d["type"]) for v in vals):
            problems.append(f"&{group} {name}: default {dflt!r} is not {d['type']}")
    ndecks = nvals = 0
    for path in sorted(glob.glob(os.path.join(inp, "*.nml"))):
        ndecks += 1
        with open(path, encoding="utf-8") as f:
            groups = parse_deck(f.read())
        for group, vals in groups:
            for key, v in vals.items():
                d = desc.get((group, key.split("(")[0]))
                if d is None:
                    problems.append(f"{path}: &{group} {key}: not in the description")
                    continue
                nvals += 1
                if d["size"] > 1 and "(" not in key:
                    if not isinstance(v, list) or not all(of_type(x, d["type"]) for x in v):
                        problems.append(f"{path}: &{group} {key} = {v!r}: not a list of "
                                        f"{d['type']}")
                elif not of_type(v, d["type"]):
                    problems.append(f"{path}: &{group} {key} = {v!r}: not {d['type']}")
    for p in problems:
        print("[ FAIL ] " + p)
    print(f"{ndecks} decks, {nvals} values typed by {len(desc)} variables: "
          f"{len(problems)} problem(s)")
    return 1 if problems or ndecks == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
