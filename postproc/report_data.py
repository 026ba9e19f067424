"""Everything the report reads from a campaign directory (layout: docs/campaign.md), with h5py and
the standard library: the manifest (latest record per case), the campaign file, ensemble.h5 (per
parameter point: mean / ci95 / count of every field), the per-case fields files (for the scalar
metrics and the convergence with replicas) and, when `tumble analyze campaign` has run,
analysis.h5 (CM islands, island enrichment, also against the other points' islands, Fig. 8
counts, lighter-particle maps, Fig. 5 sections)."""
import glob
import json
import os
import sys

import h5py
import numpy as np


def text(a):
    return a.decode() if isinstance(a, bytes) else str(a)


def manifest(d):
    """Latest record of every case, by its time stamp (docs/campaign.md, Manifest)."""
    lines = []
    for f in sorted(glob.glob(os.path.join(d, "manifest", "*.jsonl"))):
        with open(f) as fh:
            for line in fh:
                line = line.strip()
                if not line:
                    continue
                try:
                    lines.append(json.loads(line))
                except json.JSONDecodeError:
                    pass  # a torn last line after a machine crash: ignored, as the C++ reader does
    lines.sort(key=lambda r: r.get("t", 0))
    latest = {}
    for r in lines:
        latest[r["case"]] = r
    return latest


def cases_tsv(d):
    """Every case the campaign expands to (also those never started), by case id, in the
    campaign file's order (the expansion's; column index)."""
    out = {}
    path = os.path.join(d, "cases.tsv")
    if not os.path.exists(path):
        return out
    with open(path) as fh:
        cols = None
        for line in fh:
            parts = line.rstrip("\n").split("\t")
            if line.startswith("#"):
                cols = [c.strip("# ") for c in parts]
                continue
            if cols:
                out[parts[1]] = dict(zip(cols, parts))
    return out


def parse_params(s):
    out = {}
    for kv in s.split(";"):
        if "=" in kv:
            k, v = kv.split("=", 1)
            out[k] = v
    return out


def _fnv1a64(data):
    """FNV-1a 64 of a bytes object, as src/base/hash.hpp computes it."""
    h = 1469598103934665603
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def verify_ensemble(e, path):
    """The digests Tumble stores with an ensemble or partial (root attribute "checksums",
    docs/guarantees.md): every table listed there must read back with its digest (FNV-1a 64 of
    the values as row-major doubles), else the file is refused with exit code 3, as `tumble merge`
    refuses it. Files written before the checksums have none and are read as they are."""
    if "checksums" not in e.attrs:
        return
    for line in text(e.attrs["checksums"]).splitlines():
        obj, _, digest = line.partition(" ")
        name = obj.lstrip("/")
        if not name or name not in e or not isinstance(e[name], h5py.Dataset):
            continue  # point-attribute and field-list digests: checked by tumble merge
        values = np.ascontiguousarray(e[name][()], dtype="<f8").tobytes()
        if "%016x" % _fnv1a64(values) != digest:
            print(f"report: corrupt input: ensemble '{path}': '{obj}' fails its checksum; the file "
                  "is damaged or was not written by Tumble", file=sys.stderr)
            sys.exit(3)


def load_ensemble(path):
    """Per point: attributes and, per field, the mean / ci95 / count rows."""
    points = {}
    with h5py.File(path, "r") as e:
        verify_ensemble(e, path)
        root = {k: (text(v) if isinstance(v, (bytes, str)) else v) for k, v in e.attrs.items()}
        stats = {}
        for field in _fields(e):
            stats[field] = {s: e[f"fields/{field}/{s}"][:]
                            for s in ("mean", "ci95", "count", "variance")
                            if f"fields/{field}/{s}" in e}
        times = e["series/time"][:] if "series/time" in e else None
        iters = e["series/iteration"][:] if "series/iteration" in e else None
        for pid, g in e["points"].items():
            a = {k: (text(v) if isinstance(v, (bytes, str, np.bytes_)) else v)
                 for k, v in g.attrs.items()}
            row = int(np.asarray(a["row"]).ravel()[0])
            p = dict(id=pid, attrs=a, row=row, params=a.get("params", ""),
                     grid_n=int(np.asarray(a.get("grid_n", 0)).ravel()[0]), fields={})
            for field, st in stats.items():
                p["fields"][field] = {s: st[s][row] for s in st}
            if times is not None:
                n = int(np.asarray(a.get("series_length", times.shape[1])).ravel()[0])
                p["series_time"] = times[row][:n]
                p["series_iteration"] = iters[row][:n]
            points[pid] = p
    return root, points


def _fields(e):
    out = []

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and name.endswith("/mean") and name.startswith("fields/"):
            out.append(name[len("fields/"):-len("/mean")])
    e.visititems(visit)
    return sorted(out)


def load_case_fields(d):
    """Per case (finished, with fields.h5): its attributes, maps and series."""
    out = {}
    for path in sorted(glob.glob(os.path.join(d, "cases", "*", "fields.h5"))):
        with h5py.File(path, "r") as f:
            c = {k: text(v) if isinstance(v, (bytes, str)) else v for k, v in f.attrs.items()}
            c["dir"] = os.path.dirname(path)
            c["snapshots"] = sorted(glob.glob(os.path.join(c["dir"], "snap_*.h5")))
            c["data"] = {}
            f.visititems(lambda n, o: c["data"].__setitem__(n, o[()])
                         if isinstance(o, h5py.Dataset) else None)
            out[c["case_id"]] = c
    return out


def read_fates(g):
    """The Fig. 8 counts per case. Files written before "persistent" meant the same island
    (analysis.h5 with a same_island column, persistent = in an island at both times) are read
    into today's classes: persistent = same_island, switched = the rest of the old persistent."""
    f = g["fates"]
    if "switched" in f:
        return {k: f[k][:] for k in ("persistent", "captured", "dispersed", "other", "switched")}
    old, same = f["persistent"][:], f["same_island"][:]
    out = {k: f[k][:] for k in ("captured", "dispersed", "other")}
    out["persistent"] = same
    out["switched"] = np.where(old >= 0, old - same, -1)
    return out


def load_analysis(d):
    """analysis.h5 of `tumble analyze campaign`, per point; None if it has not been run."""
    path = os.path.join(d, "analysis.h5")
    if not os.path.exists(path):
        return None
    out = {}
    with h5py.File(path, "r") as f:
        for pid, g in f["points"].items():
            a = {k: text(v) if isinstance(v, (bytes, str)) else v for k, v in g.attrs.items()}
            v, off = g["islands/vertices"][:], g["islands/offsets"][:]
            p = dict(attrs=a, islands=[v[off[k]:off[k + 1]] for k in range(len(off) - 1)],
                     replica=g["replica"][:], enrichment_map=g["enrichment_map"][:],
                     enrichment_snap=g["enrichment_snap"][:],
                     enrichment_window=g["enrichment_window"][:] if "enrichment_window" in g
                     else None,
                     cases=text(a.get("cases", "")).split("\n"),
                     fates=read_fates(g),
                     fates_by_chance={k: g["fates/chance/" + k][:] for k in g["fates/chance"]}
                     if "fates/chance" in g else None,
                     island_period=int(g["fates"].attrs.get("island_period", 0)),
                     coverage=g["coverage"][:] if "coverage" in g else None,
                     fates_from=g["fates/from_iteration"][:], fates_to=g["fates/to_iteration"][:])
            if "fates/example" in g:
                ex = g["fates/example"]
                p["fate_example"] = dict(fate=ex["fate"][:], x_start=ex["x_start"][:],
                                         x_end=ex["x_end"][:], case=text(ex.attrs["case"]),
                                         frm=float(ex.attrs["from_iteration"]),
                                         to=float(ex.attrs["to_iteration"]))
            for name in ("shell_share_mapped", "shell_share_other"):  # absent: older files
                if name in g:
                    p[name] = g[name][:]
            if "light/mean" in g:
                p["light_mean"], p["light_ci95"] = g["light/mean"][:], g["light/ci95"][:]
            p["enrichment_vs"] = {q: dict(values=e["values"][:],
                                          mean=float(e.attrs["enrichment_mean"]),
                                          ci95=float(e.attrs["enrichment_ci95"]),
                                          n=int(e.attrs["enrichment_n"]))
                                  for q, e in g.get("enrichment_vs", {}).items()}
            if "section/mean" in g:
                s = g["section"]
                p["section"] = dict(mean=s["mean"][:], ci95=s["ci95"][:],
                                    tubes=s["tube_crossings"][:], snapshots=s["snapshots"][:],
                                    plane_of=text(s.attrs["plane_of"]),
                                    half_width=float(s.attrs["half_width_m"]))
            # Δψ inside / outside the islands per lag: from the snapshots (`tumble analyze
            # campaign --dpsi-lags`) and from the maps the run collected (absent from files
            # written before it).
            for name in ("dpsi_snapshots", "dpsi_fields"):
                if name == "dpsi_fields" and name not in g:
                    continue
                p[name] = [
                    dict(lag=float(l.attrs["lag"]), starts=l["starts"][:],
                         first=l["first_start"][:], last=l["last_start"][:],
                         **{f"{w}_{sp}": l[f"{w}_{sp}"][:]
                            for w in ("inside", "outside", "contrast") for sp in ("large", "small")})
                    for l in sorted(g.get(name, {}).values(), key=lambda l: l.attrs["lag"])]
            out[pid] = p
    return out


def load_campaign(d):
    """One campaign directory, all of the above."""
    d = d.rstrip("/")
    if d.endswith(".h5"):
        d = os.path.dirname(d) or "."
    c = dict(dir=d, name=os.path.basename(os.path.abspath(d)))
    toml = os.path.join(d, "campaign.toml")
    c["toml"] = open(toml).read() if os.path.exists(toml) else ""
    c["manifest"] = manifest(d)
    c["cases_tsv"] = cases_tsv(d)
    ens = os.path.join(d, "ensemble.h5")
    if not os.path.exists(ens):
        raise SystemExit(f"{d}: no ensemble.h5 (run the campaign, or `tumble merge {d}`)")
    c["root"], c["points"] = load_ensemble(ens)
    c["case_fields"] = load_case_fields(d)
    c["analysis"] = load_analysis(d)
    return c
