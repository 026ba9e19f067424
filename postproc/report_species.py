"""The names the report gives the two species. The engine's fields follow species 0 and 1 (c_L is
species 1's share, dpsi_large species 1's Δψ, dpsi_small species 0's); what the species are is
the scene's: "small" and "large" in a size-bidisperse bed, "light" and "heavy" in a
density-bidisperse bed of equal sizes (src/scene/mixture.cpp), written as the attributes
species_0 and species_1 of every case's fields.h5 and of analysis.h5. A label that says "large"
for the heavy particles of Yu 2022 Fig. 13's beds misleads, so every label that names a species
goes through `named`."""
import re

SIZE_NAMES = ("small", "large")


def species_names(pts):
    """(name of species 0, name of species 1) that every point's files agree on; ("small",
    "large") where no file says (written before the names) and ("species 0", "species 1")
    where the points' beds differ in kind (a size and a density bed in one report)."""
    seen = set()
    for q in pts:
        attrs = [q["an"]["attrs"]] if q.get("an") else []
        attrs += list(q.get("members", []))
        for a in attrs:
            if a.get("species_0") is not None and a.get("species_1") is not None:
                seen.add((str(a["species_0"]), str(a["species_1"])))
    if not seen:
        return SIZE_NAMES
    return seen.pop() if len(seen) == 1 else ("species 0", "species 1")


def named(label, names):
    """A label written for a size-bidisperse bed ("Δψ large [deg]", "large share of the shell")
    with the species' own names: "large" is species 1, "small" species 0."""
    if tuple(names) == SIZE_NAMES:
        return label
    return re.sub(r"\b(large|small)\b", lambda m: names[1] if m.group(1) == "large" else names[0],
                  label)
