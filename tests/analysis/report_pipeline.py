"""The analyses and the report on a real campaign directory, checked independently.

  report_pipeline.py --tumble BIN --mpiexec MPIEXEC --np-flag=-n --campaign FILE --out DIR
                     --report-dir OUT [--expect-failed N]
  report_pipeline.py --tumble BIN --existing DIR --out COPY --report-dir OUT --expect-failed N
  (both: [--islands-cache DIR] to share the computed CM islands with other tests)

Runs the campaign (2 ranks) unless --existing names a finished one, then `tumble analyze
campaign` and postproc/report.py, and asserts, with h5py/numpy only:
  * analysis.h5: a point with CM islands (57°,57°: the six period-3 islands at least) and
    enrichment per case equal to a recomputation from the case's volume map and the coverage the
    file records; a (68°,68°) point with no islands and NaN enrichment;
  * Fig. 8 counts (when snapshots were kept): the four classes sum to the large particles of
    the snapshots;
  * a Fig. 8 window end past the snapshots warned about for each case;
  * `--dpsi-lags`: each (57°,57°) case's Δψ inside / outside the islands from its snapshots
    equal to a numpy recomputation (starts, cells, angles, weighting); the contrast of each
    case's collected Δψ maps (analysis.h5 dpsi_fields, the report's table 3c) likewise;
  * every point's enrichment against the (57°,57°) islands equal to a recomputation from each
    case's map; the Fig. 5 section of every point (cut by the (57°,57°) plane) equal to a numpy
    binning of the snapshots of each case's last half;
  * the report: report.html, every figure it names present as a PNG, every <img> a data URI,
    every CSV named; failed cases joined to their parameters in failed_cases.csv.
"""
import argparse
import csv
import glob
import os
import re
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.dirname(os.path.dirname(HERE))


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def run(cmd, **kw):
    print("+ " + " ".join(cmd), flush=True)
    t = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    print(r.stdout[-3000:] + r.stderr[-3000:])
    if r.returncode != 0:
        fail(f"exit code {r.returncode}: {' '.join(cmd)}")
    return time.time() - t


def text(a):
    return a.decode() if isinstance(a, bytes) else str(a)


def check_map_enrichment(d, ids, values, cover, what):
    """Each case's value = (share of its mapped species' volume on the mask) / (the mask's
    share), from its fields.h5 volume map and the coverage per cell (1e-12 relative). The mapped
    species is the large one, or the light one of a density-bidisperse case (species 0 when
    R_rho > 1): the fields file says which, and that is checked against its parameters."""
    for cid, e in zip(ids, values):
        with h5py.File(os.path.join(d, "cases", cid, "fields.h5"), "r") as cf:
            mapped = int(cf.attrs["mapped_species"])
            params = dict(kv.split("=", 1) for kv in text(cf.attrs["params"]).split(";"))
            density = float(params.get("size_ratio", 2)) == 1 and float(params.get("R_rho", 1)) != 1
            want = (0 if float(params["R_rho"]) > 1 else 1) if density else 1
            if mapped != want or text(cf.attrs["species_%d" % mapped]) != ("light" if density else "large"):
                fail(f"case {cid} ({params}): mapped species {mapped} "
                     f"({text(cf.attrs['species_%d' % mapped])}), expected {want}")
            vl = cf["concentration/volume_large" if mapped == 1 else "concentration/volume_small"][:].ravel()
        ok = np.isfinite(vl)
        mine = (np.sum(cover[ok] * vl[ok]) / np.sum(vl[ok])) / (cover[ok].sum() / len(vl))
        if not abs(mine - e) <= 1e-12 * abs(mine):
            fail(f"case {cid}: {what} {e} vs recomputed {mine}")


def repeated(iterations):
    """snapshot_data.hpp's rule, written again: a snapshot closer to the one before than 1% of
    the median spacing repeats it (a run's end a few steps after its last periodic snapshot)."""
    it = np.asarray(iterations, float)
    if len(it) < 2:
        return np.zeros(len(it), bool)
    gaps = np.diff(it)
    tiny = 0.01 * np.sort(gaps)[len(gaps) // 2]
    return np.r_[False, gaps < tiny]


def check_dpsi_snapshots(d, g):
    """`--dpsi-lags`: each case's Δψ inside / outside the islands recomputed with numpy from its
    snapshots (lab directions, 0.8 <= r/R <= 1 at the start, the report's Lambert cells and the
    file's coverage), starts chosen by the rule of dpsi_snapshots.hpp, to 1e-9 degrees."""
    sys.path.insert(0, os.path.join(SRC, "postproc"))
    from report_mixing import cell_of_direction
    lag_groups = [l for l in g["dpsi_snapshots"].values() if abs(l.attrs["lag"] - DPSI_LAG) < 1e-12]
    if len(lag_groups) != 1:
        fail(f"analysis.h5: no dpsi_snapshots group of lag {DPSI_LAG}")
    lg, cover, n = lag_groups[0], g["coverage"][:].ravel(), int(g.attrs["grid_n"])
    slack = 1e-3
    for j, cid in enumerate(text(g.attrs["cases"]).split("\n")):
        frm, to = g["fates/from_iteration"][j], g["fates/to_iteration"][j]
        snaps = []
        for path in sorted(glob.glob(os.path.join(d, "cases", cid, "snap_*.h5"))):
            with h5py.File(path, "r") as s:
                scene = text(s.attrs["scene"])
                R = float(re.search(r"^tumbler.radius = (.*)$", scene, re.M).group(1))
                snaps.append((float(s.attrs["iteration"]), s["x"][:], s["species"][:], R))
        sums = np.zeros((2, n * n))
        counts = np.zeros((2, n * n))
        starts = 0
        rep = repeated([e[0] for e in snaps])
        snaps = [e for e, r in zip(snaps, rep) if not r]
        for k, (it, x, sp, R) in enumerate(snaps):
            if it < frm - slack or it + DPSI_LAG > to + slack:
                continue
            ends = [e for e in snaps[k + 1:] if e[0] >= it + DPSI_LAG - slack]
            if not ends or abs(ends[0][0] - (it + DPSI_LAG)) > slack:
                continue
            r = np.linalg.norm(x, axis=1)
            u0, u1 = x / r[:, None], ends[0][1] / np.linalg.norm(ends[0][1], axis=1)[:, None]
            cell = np.where((r >= 0.8 * R) & (r <= R), cell_of_direction(u0, n), -1)
            ang = np.arctan2(np.linalg.norm(np.cross(u0, u1), axis=1), np.sum(u0 * u1, axis=1))
            for s_ in (0, 1):
                k_ = (cell >= 0) & (sp == s_)
                sums[s_] += np.bincount(cell[k_], weights=ang[k_], minlength=n * n)
                counts[s_] += np.bincount(cell[k_], minlength=n * n)
            starts += 1
        if starts != lg["starts"][j]:
            fail(f"case {cid}: Δψ from snapshots over {starts} starts here, {lg['starts'][j]} in analysis.h5")
        compared = []
        for s_, name in ((1, "large"), (0, "small")):
            ok = counts[s_] > 0
            w_in, w_out = (cover * counts[s_])[ok], ((1 - cover) * counts[s_])[ok]
            if starts == 0 or w_in.sum() <= 0 or w_out.sum() <= 0:
                continue
            inside = np.sum((cover * sums[s_])[ok]) / w_in.sum() * 180 / np.pi
            outside = np.sum(((1 - cover) * sums[s_])[ok]) / w_out.sum() * 180 / np.pi
            got = (lg["inside_" + name][j], lg["outside_" + name][j])
            if abs(got[0] - inside) > 1e-9 or abs(got[1] - outside) > 1e-9:
                fail(f"case {cid}: Δψ {name} inside/outside {got} in analysis.h5, {inside}, {outside} "
                     "recomputed from the snapshots")
            compared.append(f"{name} {inside:.4f} / {outside:.4f} deg")
        if not compared:
            fail(f"case {cid}: no Δψ from the snapshots to compare (no start, or no side with particles)")
        print(f"case {cid}: Δψ over {DPSI_LAG} iterations from {starts} snapshot starts, inside / "
              f"outside = numpy's: " + ", ".join(compared))


def check_cross_enrichment(d, pts, ref):
    """Every point's maps against the (57, 57) islands: a recomputation from each case's volume
    map and the reference point's coverage; the reference against itself is its own enrichment."""
    ref_id = ref.name.split("/")[-1]
    cover = ref["coverage"][:].ravel()
    for pid, g in pts.items():
        if f"enrichment_vs/{ref_id}" not in g:
            fail(f"point {pid}: no enrichment against the islands of {ref_id}")
        vals = g[f"enrichment_vs/{ref_id}/values"][:]
        check_map_enrichment(d, text(g.attrs["cases"]).split("\n"), vals, cover,
                             f"enrichment against {ref_id}")
        if pid == ref_id and not np.array_equal(vals, g["enrichment_map"][:]):
            fail("the (57, 57) point against its own islands differs from its enrichment")
        print(f"point {pid} against the islands of {ref_id}: {np.round(vals, 4)}")


def check_sections(d, pts, ref):
    """Fig. 5: every point cut by the (57, 57) plane; its mean c_L per bin equals the mean over
    its cases of a numpy binning of the snapshots of each case's last half."""
    import tomllib
    ref_id = ref.name.split("/")[-1]
    for pid, g in pts.items():
        if "section/mean" not in g:
            fail(f"point {pid}: no Fig. 5 section")
        sg = g["section"]
        if text(sg.attrs["plane_of"]) != ref_id:
            fail(f"point {pid}: section plane of {text(sg.attrs['plane_of'])}, not {ref_id}")
        e1, e2 = sg["e1"][:], sg["e2"][:]
        if abs(e1 @ e2) > 1e-12 or abs(e1 @ e1 - 1) > 1e-12 or abs(e2 @ e2 - 1) > 1e-12:
            fail(f"point {pid}: section axes not orthonormal")
        if len(sg["tube_crossings"][:]) == 0:
            fail(f"point {pid}: no KAM-tube boundaries on the plane")
        nrm, hw, mean = np.cross(e1, e2), sg.attrs["half_width_m"], sg["mean"][:]
        n = mean.shape[0]
        per_case = []
        for cid in text(g.attrs["cases"]).split("\n"):
            snaps = sorted(glob.glob(os.path.join(d, "cases", cid, "snap_*.h5")))
            files = [h5py.File(p, "r") for p in snaps]
            last = max(f.attrs["iteration"] for f in files)
            vol = np.zeros((2, n * n))
            rep = repeated([f.attrs["iteration"] for f in files])
            for f, r in zip(files, rep):
                if r or f.attrs["iteration"] < 0.5 * last:  # a repeat counts once
                    continue
                R = tomllib.loads(text(f.attrs["scene"]))["tumbler"]["radius"]
                x, r, sp = f["x"][:], f["radius"][:], f["species"][:]
                a = np.floor((x @ e1 / R + 1) * 0.5 * n).astype(int)
                b = np.floor((x @ e2 / R + 1) * 0.5 * n).astype(int)
                keep = (np.abs(x @ nrm) <= hw) & (a >= 0) & (a < n) & (b >= 0) & (b < n)
                np.add.at(vol, ((sp[keep] == 1).astype(int), a[keep] * n + b[keep]),
                          4 / 3 * np.pi * r[keep] ** 3)
            for f in files:
                f.close()
            tot = vol.sum(axis=0)
            per_case.append(np.where(tot > 0, vol[1] / np.where(tot > 0, tot, 1), np.nan))
        per_case = np.array(per_case)
        cnt = np.sum(np.isfinite(per_case), axis=0)
        mine = np.where(cnt > 0, np.nansum(per_case, axis=0) / np.maximum(cnt, 1), np.nan)
        both = np.isfinite(mine) & np.isfinite(mean.ravel())
        if not np.array_equal(np.isfinite(mine), np.isfinite(mean.ravel())) or \
                np.max(np.abs(mine[both] - mean.ravel()[both])) > 1e-12:
            fail(f"point {pid}: section mean differs from the numpy binning")
        print(f"point {pid}: Fig. 5 section, {both.sum()} bins filled, mean c_L "
              f"{np.nanmean(mine):.3f}")


ap = argparse.ArgumentParser()
ap.add_argument("--tumble", required=True)
ap.add_argument("--mpiexec")
ap.add_argument("--np-flag", default="-n")
ap.add_argument("--campaign")
ap.add_argument("--out")
ap.add_argument("--existing")
ap.add_argument("--report-dir", required=True)
ap.add_argument("--expect-failed", type=int, default=0)
ap.add_argument("--islands-cache", help="shared cache of computed CM islands")
a = ap.parse_args()

if a.existing:
    # A copy: the analysis writes into the campaign directory, which belongs to other tests.
    d = a.out
    shutil.rmtree(d, ignore_errors=True)
    shutil.copytree(a.existing, d)
else:
    d = a.out
    shutil.rmtree(d, ignore_errors=True)
    cmd = [a.mpiexec, a.np_flag, "2"]
    if "Open MPI" in subprocess.run([a.mpiexec, "--version"], capture_output=True,
                                    text=True).stdout:
        cmd.append("--oversubscribe")
    run(cmd + [a.tumble, "campaign", a.campaign, "--output", d, "--quiet"])

DPSI_LAG = 0.002  # iterations: the snapshots' spacing in this campaign (t = 0, 0.025 s, end)
t_an = run([a.tumble, "analyze", "campaign", d, "--dpsi-lags", str(DPSI_LAG)]
           + (["--islands-cache", a.islands_cache] if a.islands_cache else []))
# A window end past every case's last snapshot: each case with fates is compared at its last
# snapshot instead, and the analysis says so per case (to a file of its own, not analysis.h5).
r = subprocess.run([a.tumble, "analyze", "campaign", d, "--to", "1", "-o", os.path.join(d, "late.h5")]
                   + (["--islands-cache", a.islands_cache] if a.islands_cache else []),
                   capture_output=True, text=True)
late = re.findall(r"warning: point \S+ case (\S+): no snapshot at the window's end \(1\)", r.stdout)
kept_snapshots = bool(glob.glob(os.path.join(d, "cases", "*", "snap_*.h5")))
if r.returncode != 0 or (kept_snapshots and not late):
    fail(f"--to 1 past the snapshots: exit {r.returncode}, no per-case warning\n{r.stdout[-2000:]}")
print(f"--to 1 past the snapshots: {len(late)} cases warned"
      + ("" if kept_snapshots else " (no snapshots kept: no Fig. 8 window to warn about)"))
with h5py.File(os.path.join(d, "analysis.h5"), "r") as f:
    pts = {pid: g for pid, g in f["points"].items()}
    with_islands = [g for g in pts.values() if g.attrs["theta_z"] == 57 and g.attrs["theta_x"] == 57]
    if not with_islands:
        fail("no (57, 57) point in analysis.h5")
    for g in with_islands:
        if g.attrs["n_islands"] < 6:
            fail(f"(57, 57) has {g.attrs['n_islands']} islands, expected the six period-3 ones")
        cover = g["coverage"][:].ravel()
        share = cover.mean()
        if not 0.05 < share < 0.3 or abs(share - g.attrs["island_area_fraction"]) > 0.02:
            fail(f"coverage mean {share} vs island_area_fraction {g.attrs['island_area_fraction']}")
        ids = text(g.attrs["cases"]).split("\n")
        check_map_enrichment(d, ids, g["enrichment_map"][:], cover, "enrichment")
        classes = ("persistent", "switched", "captured", "dispersed", "other")
        fates = {k: g["fates/" + k][:] for k in classes}
        chance = {k: g["fates/chance/" + k][:] for k in classes}
        for j, cid in enumerate(ids):
            if fates["persistent"][j] < 0:
                continue
            # The chance counts redistribute the same particles with the same island occupancy
            # at the start (persistent + switched + dispersed) and at the end.
            for name, obs, exp in (
                    ("total", sum(fates[k][j] for k in classes), sum(chance[k][j] for k in classes)),
                    ("inside at the start", fates["persistent"][j] + fates["switched"][j]
                     + fates["dispersed"][j], chance["persistent"][j] + chance["switched"][j]
                     + chance["dispersed"][j]),
                    ("inside at the end", fates["persistent"][j] + fates["switched"][j]
                     + fates["captured"][j], chance["persistent"][j] + chance["switched"][j]
                     + chance["captured"][j])):
                if abs(obs - exp) > 1e-9 * max(1, obs):
                    fail(f"case {cid}: Fig. 8 by chance, {name}: {exp} against {obs} observed")
            snaps = sorted(glob.glob(os.path.join(d, "cases", cid, "snap_*.h5")))
            with h5py.File(snaps[0], "r") as s:
                n_large = int(np.sum(s["species"][:] == 1))
            total = sum(int(fates[k][j]) for k in fates)
            if total != n_large:
                fail(f"case {cid}: Fig. 8 classes sum to {total}, snapshot has {n_large} large")
            print(f"case {cid}: Fig. 8 counts " +
                  ", ".join(f"{k} {int(fates[k][j])}" for k in fates) + f" of {n_large}")
    for g in pts.values():
        if g.attrs["theta_z"] == 68 and g.attrs["theta_x"] == 68:
            if g.attrs["n_islands"] != 0 or np.isfinite(g["enrichment_map"][:]).any():
                fail("(68, 68) should have no islands and undefined enrichment")
    check_cross_enrichment(d, pts, with_islands[0])
    if kept_snapshots:
        for g in with_islands:
            check_dpsi_snapshots(d, g)
    if glob.glob(os.path.join(d, "cases", "*", "snap_*.h5")):
        check_sections(d, pts, with_islands[0])
    elif any("section" in g for g in pts.values()):
        fail("a Fig. 5 section without snapshots")

rep = a.report_dir
shutil.rmtree(rep, ignore_errors=True)
t_rep = run(["/usr/bin/python3", os.path.join(SRC, "postproc", "report.py"), d, "-o", rep])
page = open(os.path.join(rep, "report.html")).read()
imgs = re.findall(r"<img [^>]*>", page)
if len(imgs) < 5:
    fail(f"report has {len(imgs)} images")
for tag in imgs:
    if 'src="data:image/png;base64,' not in tag:
        fail("an image is not embedded: " + tag[:80])
for name in re.findall(r'<a href="([^"]+)">', page):
    if not os.path.exists(os.path.join(rep, name)):
        fail(f"report links {name}, which was not written")
for name in ("maps.csv", "series.csv", "case_scalars.csv", "scalar_summary.csv", "cases.csv",
             "convergence.csv", "provenance.csv", "points.csv", "findings.csv",
             "difference_tests.csv", "mixing_random.csv", "scalar_differences.csv"):
    if not os.path.exists(os.path.join(rep, name)):
        fail(f"{name} missing")
# Δψ over every lag the campaign collected (its collect text: ";k=0.0015,0.003;"): each lag has
# its group and maps, and the inside/outside contrast table holds each lag's mean, recomputed
# here from the fields files and the island coverage.
lags = []
for f in sorted(glob.glob(os.path.join(d, "cases", "*", "fields.h5")))[:1]:
    with h5py.File(f, "r") as h:
        ks = re.search(r"(?:^|;)k=([^;]+)", text(h.attrs["collect"])).group(1).split(",")
        lags = [("displacement" if i == 0 else f"displacement_k{k}", k) for i, k in enumerate(ks)]
        for grp, k in lags:
            if grp not in h or abs(h[grp].attrs["periods"] - float(k)) > 1e-15:
                fail(f"{f}: no Δψ group {grp} over {k} periods")
print("Δψ lags collected: " + ", ".join(k for _, k in lags))
for grp, _ in lags[1:]:
    if not os.path.exists(os.path.join(rep, f"map_{grp}_dpsi_large.png")):
        fail(f"map_{grp}_dpsi_large.png missing (lag collected)")
if lags and not os.path.exists(os.path.join(rep, "dpsi_contrast.csv")):
    fail("dpsi_contrast.csv missing")
with h5py.File(os.path.join(d, "analysis.h5"), "r") as h:
    for pid, g in h["points"].items():
        if g.attrs["n_islands"] == 0:
            continue
        cover = g["coverage"][:].ravel()
        for grp, lag in lags:
            vals = []
            stored = g[f"dpsi_fields/lag_{lag}/contrast_large"][:]
            for j, cid in enumerate(text(g.attrs["cases"]).split("\n")):
                with h5py.File(os.path.join(d, "cases", cid, "fields.h5"), "r") as c:
                    m = c[grp + "/dpsi_large"][:].ravel() * 180 / np.pi
                    w = c[grp + "/count_large"][:].ravel()
                ok = np.isfinite(m) & (w > 0)
                wi, wo = (w * cover)[ok], (w * (1 - cover))[ok]
                if wi.sum() > 0 and wo.sum() > 0:
                    vals.append(np.sum(wo * m[ok]) / wo.sum() - np.sum(wi * m[ok]) / wi.sum())
                    # analysis.h5 dpsi_fields (C++, the one definition) against numpy, per case.
                    if not abs(stored[j] - vals[-1]) <= 1e-9:
                        fail(f"analysis.h5 dpsi_fields lag {lag}, case {cid}: {stored[j]} deg, "
                             f"recomputed {vals[-1]}")
            rows = [r for r in csv.DictReader(open(os.path.join(rep, "dpsi_contrast.csv")))
                    if r["point"].startswith("A") and r["lag [iterations]"] == lag
                    and r["species"] in ("large", "heavy")]  # species 1, named per point
            if vals:
                got = [float(r["contrast outside − inside [deg]"].split()[0]) for r in rows]
                if not any(abs(x - np.mean(vals)) <= 0.0051 for x in got):
                    fail(f"Δψ contrast of {pid}, lag {lag}: report {got}, recomputed "
                         f"{np.mean(vals):.3f}")
                print(f"Δψ contrast of {pid} over {lag} periods (large): {np.mean(vals):.2f} deg")
# The random-bed reference of the mixing index bins the last snapshot in Python
# (postproc/report_mixing.py); its index of the unshuffled snapshot must be the C++ series'
# value where the last series sample is taken at the last snapshot (1e-9).
mixing = list(csv.DictReader(open(os.path.join(rep, "mixing_random.csv"))))
if snaps_kept := glob.glob(os.path.join(d, "cases", "*", "snap_*.h5")):
    if not mixing:
        fail("mixing_random.csv is empty although cases kept snapshots")
    same = [r for r in mixing if abs(float(r["index_last_snapshot"])
                                     - float(r["index_series_last_sample"])) <= 1e-9]
    print(f"mixing index: {len(same)} of {len(mixing)} cases' last snapshots give the series' "
          "last value to 1e-9")
    if not same:
        fail("no case's mixing index recomputed from its last snapshot equals the series' last "
             f"value: {mixing}")
    for r in mixing:
        if not 0 < float(r["random_bed_mean"]) < 1:
            fail(f"random-bed mixing index {r['random_bed_mean']} outside (0, 1)")
failed = []
if os.path.exists(os.path.join(rep, "failed_cases.csv")):
    failed = list(csv.DictReader(open(os.path.join(rep, "failed_cases.csv"))))
if len(failed) != a.expect_failed:
    fail(f"failed_cases.csv lists {len(failed)} cases, expected {a.expect_failed}")
for r in failed:
    if "theta_z=" not in r["parameters"] or not r["failure"]:
        fail(f"failed case {r['case']} not joined to its parameters: {r}")
# Time-lapse renders of one case's snapshots: one PNG per snapshot and a GIF with as many frames.
snaps = sorted(glob.glob(os.path.join(d, "cases", "*", "snap_*.h5")))
if snaps:
    case = os.path.dirname(snaps[0])
    snaps = [s for s in snaps if os.path.dirname(s) == case]
    gif = os.path.join(rep, "timelapse.gif")
    run(["/usr/bin/python3", os.path.join(SRC, "postproc", "render_bottom.py")] + snaps
        + ["--gif", gif, "--frames", os.path.join(rep, "frames"), "--size", "300"])
    from PIL import Image
    frames = sorted(glob.glob(os.path.join(rep, "frames", "frame_*.png")))
    n_gif = Image.open(gif).n_frames
    if len(frames) != len(snaps) or n_gif != len(snaps) or len(snaps) < 2:
        fail(f"time-lapse: {len(snaps)} snapshots, {len(frames)} PNGs, {n_gif} GIF frames")
    for fr in frames:
        w, h = Image.open(fr).size
        px = np.asarray(Image.open(fr).convert("RGB"), float)
        # Both species drawn: blue-dominant (large) and red-dominant (small) pixels present.
        blue = np.sum((px[..., 2] > px[..., 0] + 40))
        red = np.sum((px[..., 0] > px[..., 2] + 40))
        if (w, h) != (300, 300) or blue < 50 or red < 500:
            fail(f"{fr}: {w}x{h}, {blue} blue and {red} red pixels")
    print(f"time-lapse: {len(frames)} frames and a {n_gif}-frame GIF")
print(f"OK: analyze {t_an:.1f} s, report {t_rep:.1f} s, {len(imgs)} images, "
      f"{len(failed)} failed cases joined to their parameters")
