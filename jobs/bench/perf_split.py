#!/usr/bin/python3
"""Where the time under one function goes: the samples of a `perf record --call-graph dwarf`
recording whose call chain passes through FUNCTION, split by the function it called (the
child on the chain), with the share of all samples. `perf report --children` gives each
function's inclusive share but not which of its callees carry it when the same callee is also
reached by other paths; this counts each sample once, by the chain it was taken on.

usage: perf_split.py PERF_DATA FUNCTION [FUNCTION ...] [--top N] [--within F]
  perf record -e cpu-clock -F 1000 --call-graph dwarf,16384 -o PERF_DATA <command>
  (a binary built with -g names the inlined helpers too; cmake -DCMAKE_CXX_FLAGS=-g)
Each FUNCTION is matched as a substring of the symbol (e.g. Simulation::step,
rebuild_distributed); a sample counts under the outermost frame that matches. --within F
counts only the samples whose chain also passes through F (e.g. Simulation::step, to leave out
the restart's first neighbour build).
"""
import argparse
import collections
import re
import subprocess
import sys


def chains(perf_data):
    """The call chains of the recording, leaf first, as symbol names without offsets."""
    out = subprocess.run(["perf", "script", "-i", perf_data, "-F", "ip,sym"],
                         capture_output=True, text=True, errors="replace", check=True).stdout
    chain = []
    for line in out.splitlines():
        if not line.strip():
            if chain:
                yield chain
            chain = []
            continue
        m = re.match(r"\s*[0-9a-f]+\s+(.*)$", line)
        if m:
            chain.append(re.sub(r"\+0x[0-9a-f]+$", "", m.group(1)).strip())
    if chain:
        yield chain


def short(symbol, width=90):
    """The name without its parameter list (templates and namespaces kept)."""
    depth, cut = 0, len(symbol)
    for k, ch in enumerate(symbol):
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == "(" and depth == 0 and k > 0:
            cut = k
            break
    return symbol[:cut][:width]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("perf_data")
    ap.add_argument("functions", nargs="+")
    ap.add_argument("--top", type=int, default=20)
    ap.add_argument("--within", default="", help="count only chains through this function too")
    a = ap.parse_args()
    all_chains = list(chains(a.perf_data))
    total = len(all_chains)
    if total == 0:
        sys.exit(f"perf_split.py: no samples with call chains in {a.perf_data}")
    print(f"{total} samples in {a.perf_data}")
    for function in a.functions:
        under, split = 0, collections.Counter()
        for chain in all_chains:
            at = [k for k, s in enumerate(chain) if function in s]
            if not at or (a.within and not any(a.within in s for s in chain)):
                continue
            under += 1
            k = at[-1]  # the outermost frame that matches
            split[short(chain[k - 1]) if k > 0 else "(itself)"] += 1
        within = f" within {a.within}" if a.within else ""
        print(f"\n{function}{within}: {under} samples, {100 * under / total:.1f}% of all")
        for name, n in split.most_common(a.top):
            print(f"  {n:7d} {100 * n / total:5.1f}%  {name}")
        rest = under - sum(n for _, n in split.most_common(a.top))
        if rest:
            print(f"  {rest:7d} {100 * rest / total:5.1f}%  (the other callees)")


if __name__ == "__main__":
    main()
