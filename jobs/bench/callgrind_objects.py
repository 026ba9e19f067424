#!/usr/bin/env python3
"""Instructions (callgrind's Ir) per object file, summed over callgrind output files.

  /usr/bin/python3 jobs/bench/callgrind_objects.py FILE... [--object tumble]

Prints each object's exclusive instructions over all the files (one per rank of an MPI run) and
their total, or with --object only the instructions of the objects whose path ends with that name
(e.g. the engine's own binary, leaving out Open MPI's polling, whose count depends on how long a
rank waited, and the C library). Exclusive: a cost line that follows a `calls=` line is the
inclusive cost of that call and is skipped, so each instruction is counted once, in the object
that executed it. The sum over all objects is checked against each file's `totals:` line.

callgrind_annotate prints per function, not per object, hence this reader of the format
(valgrind's docs, "Callgrind Format Specification": `ob=(id) name` defines a compressed name,
`ob=(id)` reuses it; cost lines are positions then events)."""
import argparse
import os
import re
import sys
from collections import defaultdict


def compressed_name(line, table):
    """The name of an `ob=`, `cob=`, `fn=` or `cfn=` line: "(id) name" defines id in `table`,
    "(id)" reuses it. ob= and cob= share one table (a name may be defined in a cob= line, a call
    into that object, and then be used as ob=(id)); fn= and cfn= share another."""
    value = line.split("=", 1)[1]
    m = re.match(r"\((\d+)\)(?: (.*))?$", value)
    if not m:
        return value
    if m.group(2) is not None:
        table[m.group(1)] = m.group(2)
    return table.get(m.group(1), m.group(1))


def object_costs(path, by_function=False):
    """{object name: exclusive Ir} of one callgrind.out file (by_function: {(object, function):
    exclusive Ir}), and the file's totals."""
    names = {}
    fn_names = {}
    costs = defaultdict(int)
    ob = fn = "?"
    skip_next = False
    n_pos = 1
    ir_col = 0
    totals = None
    with open(path, errors="replace") as f:
        for line in f:
            line = line.rstrip("\n")
            if not line:
                continue
            c = line[0]
            if c.isdigit() or c in "+-*":
                if skip_next:  # the inclusive cost of a call
                    skip_next = False
                    continue
                parts = line.split()
                ev = parts[n_pos:]
                if len(ev) > ir_col:
                    costs[(ob, fn) if by_function else ob] += int(ev[ir_col])
                continue
            if line.startswith(("ob=", "cob=")):
                name = compressed_name(line, names)
                if line.startswith("ob="):
                    ob = name
            elif line.startswith(("fn=", "cfn=")):
                name = compressed_name(line, fn_names)
                if line.startswith("fn="):
                    fn = name
            elif line.startswith("calls="):
                skip_next = True
            elif line.startswith("positions:"):
                n_pos = len(line.split()[1:])
            elif line.startswith("events:"):
                events = line.split()[1:]
                ir_col = events.index("Ir") if "Ir" in events else 0
            elif line.startswith("totals:") or line.startswith("summary:"):
                totals = int(line.split()[1 + ir_col])
    return costs, totals


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--object", help="count only objects whose file name is this (e.g. tumble)")
    ap.add_argument("--functions", type=int, default=0, metavar="K",
                    help="with --object: that object's K costliest functions, then its total")
    ap.add_argument("--minus", nargs="+", default=[], metavar="FILE",
                    help="with --functions: subtract these files' costs (a shorter run's)")
    a = ap.parse_args()
    if a.functions and a.object:
        per_fn = defaultdict(int)
        for sign, paths in ((1, a.files), (-1, a.minus)):
            for path in paths:
                costs, _ = object_costs(path, by_function=True)
                for (ob, fn), v in costs.items():
                    if os.path.basename(ob) == a.object:
                        per_fn[fn] += sign * v
        for fn, v in sorted(per_fn.items(), key=lambda kv: -abs(kv[1]))[:a.functions]:
            print(f"{v:>16,d}  {fn}")
        print(f"{sum(per_fn.values()):>16,d}  all of {a.object}")
        return
    per_object = defaultdict(int)
    for path in a.files:
        costs, totals = object_costs(path)
        s = sum(costs.values())
        if totals is not None and s != totals:
            sys.exit(f"{path}: objects sum to {s}, the file's totals say {totals}")
        for k, v in costs.items():
            per_object[k] += v
    if a.object:
        print(sum(v for k, v in per_object.items() if os.path.basename(k) == a.object))
        return
    for k, v in sorted(per_object.items(), key=lambda kv: -kv[1]):
        print(f"{v:>16,d}  {k}")
    print(f"{sum(per_object.values()):>16,d}  all")


if __name__ == "__main__":
    main()
