#!/usr/bin/python3
"""Checks a Tumble run directory: snapshots in id order, tumbler-frame positions consistent with the
stored orientation, every particle inside the tumbler, provenance attributes, and the XDMF sidecar
naming every snapshot. Usage: check_snapshot.py RUN_DIR RADIUS"""
import glob
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

run_dir, radius = sys.argv[1], float(sys.argv[2])
snaps = sorted(glob.glob(os.path.join(run_dir, "snap_*.h5")))
assert len(snaps) >= 2, f"expected at least 2 snapshots, found {snaps}"
for path in snaps:
    with h5py.File(path, "r") as f:
        ids = f["id"][:]
        assert np.array_equal(ids, np.arange(len(ids))), f"{path}: ids not 0..N-1 in order"
        x, xt, q = f["x"][:], f["x_tumbler"][:], f["orientation"][:]
        assert np.allclose(q @ q.T, np.eye(3), atol=1e-12), f"{path}: orientation not orthogonal"
        assert np.allclose(xt, x @ q, atol=1e-14), f"{path}: x_tumbler != Q^T x"
        r = np.linalg.norm(x, axis=1) + f["radius"][:]
        assert r.max() < radius * 1.01, f"{path}: particle outside the tumbler ({r.max()} > {radius})"
        for key in ("git_hash", "scene", "seed", "tumble_version", "time", "step"):
            assert key in f.attrs, f"{path}: missing attribute {key}"
        scene = f.attrs["scene"]
        scene = scene.decode() if isinstance(scene, bytes) else scene
        assert "contact.restitution" in scene, f"{path}: scene attribute not resolved"
tree = ET.parse(os.path.join(run_dir, "snapshots.xdmf"))
files = {d.text.split(":")[0] for d in tree.iter("DataItem")}
assert files == {os.path.basename(s) for s in snaps}, f"XDMF lists {files}"
print(f"ok: {len(snaps)} snapshots, {len(ids)} particles")
