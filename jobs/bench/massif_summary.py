#!/usr/bin/python3
"""The heap of a `tumble run` under valgrind's massif, by phase and by owner.

usage: massif_summary.py MASSIF_OUT PARTICLES

Massif (run with --detailed-freq=1) records the live heap as a tree of allocation stacks. A
snapshot belongs to the *stepping* phase when memory allocated inside Simulation::step is live
and no checkpoint is being written or read (the restart before the first step and the final
checkpoint after the last have peaks of their own, reported apart). In each snapshot the bytes
are split by who allocated them: the engine (stacks through tumble's code below Simulation or the
neighbour list), the libraries' own allocations at start-up (Open MPI, HDF5, PETSc: stacks with
no tumble frame below main or through their init calls), and the rest of tumble (scene, run
state, observers). Prints the stepping phase's peak and its split, per particle.
"""
import re
import sys


def snapshots(path):
    """Yields (index, time, heap bytes incl. allocator overhead, tree lines) per snapshot."""
    with open(path) as f:
        lines = f.read().split("\n")
    k = 0
    while k < len(lines):
        if not lines[k].startswith("snapshot="):
            k += 1
            continue
        index = int(lines[k].split("=")[1])
        fields, tree = {}, []
        k += 1
        while k < len(lines) and not lines[k].startswith("snapshot="):
            line = lines[k]
            if "=" in line and not line.startswith(" ") and not line.startswith("n"):
                key, _, value = line.partition("=")
                fields[key] = value
            elif re.match(r"^ *n\d+:", line):
                tree.append(line)
            k += 1
        heap = int(fields["mem_heap_B"]) + int(fields["mem_heap_extra_B"])
        yield index, int(fields["time"]), heap, int(fields["mem_heap_B"]), tree


def leaves(tree):
    """(bytes, stack from the allocation upwards) of every leaf of a detailed tree."""
    out, stack = [], []
    for line in tree:
        m = re.match(r"^( *)n(\d+): (\d+) (.*)$", line)
        depth, children, size, label = len(m.group(1)), int(m.group(2)), int(m.group(3)), m.group(4)
        del stack[depth:]
        stack.append(label)
        if children == 0:
            out.append((size, list(stack)))
    return out


ENGINE = re.compile(r"tumble::(Simulation|neighbor::|parallel::Domain|Particles|apply_permutation)")
LIBRARY = re.compile(r"(libmpi|libopen-|libpmix|libhwloc|libevent|libhdf5|libpetsc|ompi_|opal_|"
                     r"orte_|H5[A-Z]|PetscInit|MPI_Init|_dl_|dlopen|libucx|libucs|libfabric)")


def owner(stack):
    text = " ".join(stack)
    if ENGINE.search(text):
        return "engine"
    if LIBRARY.search(text) or "tumble::" not in text:
        return "libraries"
    return "other"


def main():
    path, particles = sys.argv[1], int(sys.argv[2])
    stepping, overall = [], (0, -1)
    for index, time, heap, useful, tree in snapshots(path):
        overall = max(overall, (useful, index))
        if not tree:
            continue
        text = "\n".join(tree)
        if "Simulation::step" not in text or "write_checkpoint" in text:
            continue
        split = {"engine": 0, "libraries": 0, "other": 0}
        for size, stack in leaves(tree):
            if "(heap allocation functions)" in stack[-1] and len(stack) == 1:
                continue
            split[owner(stack)] += size
        stepping.append((useful, index, heap, split))
    if not stepping:
        sys.exit("no snapshot of the stepping phase (run massif with --detailed-freq=1)")
    useful, index, heap, split = max(stepping)
    per = 1.0 / particles
    print(f"stepping phase: {len(stepping)} snapshots; peak at snapshot {index}: "
          f"heap {useful / 2**20:.2f} MiB ({useful * per:.0f} B per particle; "
          f"{heap / 2**20:.2f} MiB with the allocator's overhead)")
    for key in ("engine", "libraries", "other"):
        print(f"  {key:10s} {split[key] / 2**20:6.2f} MiB  {split[key] * per:5.0f} B per particle")
    print(f"whole run: peak heap {overall[0] / 2**20:.2f} MiB at snapshot {overall[1]} "
          f"({overall[0] * per:.0f} B per particle; the restart or the final checkpoint when it "
          f"is above the stepping phase's)")


if __name__ == "__main__":
    main()
