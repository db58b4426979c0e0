#!/usr/bin/env python3
"""doc/deck.md against the deck's description, src/setup/deck_vars.tsv (issue 21, item 4).

The description is the one place a deck variable is defined: mfcd's namelists, defaults and
value checks are generated from it, and this test holds the tables of doc/deck.md to it.
For every table row of a group's section (| `name` | type | unit | default | valid | ...):

- the variable is one of the group's in the description, and each of the group's variables
  has a row;
- type is the description's, written as `real`, `integer`, `logical`, `string (L)`, with the
  extents of an array: `real (3)`, `real (2, 64)`, `string (64) x 16`;
- unit begins with the description's unit (bold and a note in parentheses may follow);
- default: where the description gives a literal (not unset, not derived), the cell's
  first `code` span is it;
- valid: every choice of a `one of` variable is listed, quoted; an interval or bound appears
  as the description writes it.

Standard library only. Usage: test_deck_doc.py [doc/deck.md [src/setup/deck_vars.tsv]]
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def read_description(path):
    """{(group, name): {column: value}} from the TSV, in file order."""
    cols = ["group", "name", "type", "dims", "length", "unit", "default", "valid", "hint"]
    out = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line or line.startswith("#"):
                continue
            parts = line.split("\t")
            if len(parts) != len(cols):
                raise ValueError(f"{path}: {len(parts)} columns in {line!r}")
            row = dict(zip(cols, parts))
            out[(row["group"], row["name"])] = row
    return out


def render_type(row):
    dims = [] if row["dims"] == "-" else row["dims"].split()
    if row["type"] == "string":
        text = f"string ({row['length']})"
        return text + (f" x {' x '.join(dims)}" if dims else "")
    return row["type"] + (f" ({', '.join(dims)})" if dims else "")


def render_default(row):
    """The default as the doc writes it in a code span, None where it is derived (unset)."""
    d = row["default"]
    if d in ("unset", "huge", "-huge") or d.startswith("derived "):
        return None
    return d


def doc_rows(path):
    """[(group, line number, [cells])] of the variable tables under each '## `&group`'."""
    rows = []
    group = None
    with open(path, encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            m = re.match(r"^## `&(\w+)`", line)
            if m:
                group = m.group(1)
                continue
            if line.startswith("## "):
                group = None
                continue
            if group and line.startswith("| `"):
                cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
                if len(cells) >= 5 and re.fullmatch(r"`\w+`", cells[0]):
                    rows.append((group, lineno, cells))
    return rows


def check(doc, tsv):
    desc = read_description(tsv)
    problems = []
    seen = set()
    for group, lineno, cells in doc_rows(doc):
        name = cells[0].strip("`")
        where = f"{os.path.relpath(doc, ROOT)}:{lineno} &{group} {name}"
        row = desc.get((group, name))
        if row is None:
            problems.append(f"{where}: not a variable of &{group} in src/setup/deck_vars.tsv")
            continue
        seen.add((group, name))
        typ, unit, default, valid = cells[1], cells[2], cells[3], cells[4]
        if typ != render_type(row):
            problems.append(f"{where}: type '{typ}', the description says "
                            f"'{render_type(row)}'")
        if not unit.replace("*", "").startswith(row["unit"]):
            problems.append(f"{where}: unit '{unit}', the description says '{row['unit']}'")
        want = render_default(row)
        if want is not None:
            spans = re.findall(r"`([^`]*)`", default)
            if not spans or spans[0] != want:
                problems.append(f"{where}: default '{default}', the description says "
                                f"`{want}`")
        v = row["valid"]
        if v.startswith("one of "):
            for choice in re.findall(r"'[^']*'", v):
                if f"`{choice}`" not in valid:
                    problems.append(f"{where}: valid '{valid}' lacks `{choice}`")
        elif v != "any" and v not in valid:
            problems.append(f"{where}: valid '{valid}' lacks the description's '{v}'")
    for key in desc:
        if key not in seen:
            problems.append(f"doc/deck.md: no row for &{key[0]} {key[1]} (src/setup/deck_vars.tsv)")
    return problems


def main(argv):
    doc = argv[1] if len(argv) > 1 else os.path.join(ROOT, "doc", "deck.md")
    tsv = argv[2] if len(argv) > 2 else os.path.join(ROOT, "src", "setup", "deck_vars.tsv")
    problems = check(doc, tsv)
    for p in problems:
        print("[ FAIL ] " + p)
    n = len(doc_rows(doc))
    print(f"{n} table rows checked against {len(read_description(tsv))} variables: "
          f"{len(problems)} problem(s)")
    # the check must be able to fail: a description with a changed type is caught
    if not problems:
        desc = read_description(tsv)
        row = next(iter(desc.values()))
        bad = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"deck_vars_{os.getpid()}.tsv")
        try:
            with open(tsv, encoding="utf-8") as f, open(bad, "w", encoding="utf-8") as g:
                for line in f:
                    parts = line.split("\t")
                    if len(parts) == 9 and (parts[0], parts[1]) == (row["group"], row["name"]):
                        parts[2] = "logical" if parts[2] != "logical" else "real"
                        line = "\t".join(parts)
                    g.write(line)
            if not check(doc, bad):
                print("[ FAIL ] a changed type in the description went unnoticed")
                return 1
        finally:
            if os.path.exists(bad):
                os.remove(bad)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
