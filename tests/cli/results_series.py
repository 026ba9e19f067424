"""The time series of a run's results.h5 and their bit-for-bit comparison, shared by the CLI
tests that stop a run (a kill, a signal) and check that its continuation is the uninterrupted
run (checkpoint_wall_check.py, stop_signal_check.py)."""
import os

import h5py
import numpy as np


def series(run_dir):
    """Every dataset under /series of RUN_DIR/results.h5, by its path below /series."""
    with h5py.File(os.path.join(run_dir, "results.h5"), "r") as f:
        out = {}
        f["series"].visititems(lambda n, o: out.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset) else None)
        return out


def difference(a, b):
    """'' if the two series are equal bit for bit (NaN equal to NaN), else what differs."""
    if sorted(a) != sorted(b):
        return "different series %s vs %s" % (sorted(a), sorted(b))
    for k in a:
        if not np.array_equal(a[k], b[k], equal_nan=True):
            return "series/%s differs" % k
    return ""
