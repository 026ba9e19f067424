"""campaign.status_without_mpi: `campaign --status` and `--list` run in one process without MPI.

The job-array scripts ask for a slice's status outside the MPI launcher (jobs/run_slice.sh), and a
singleton MPI start fails on some clusters (an MPICH without mpiexec on PATH, Open MPI built
without PMI-1 inside a Slurm allocation, Flux): the status failed with it, and so did every slice.
Here Open MPI is made unable to start (OMPI_MCA_pml names no component): a campaign run fails with
it (the control), `--status` and `--list` of the single run's directory (fixture
campaign.mpi2_complete) do not, and still read the statistics in full: a field of ensemble.h5
changed behind its checksum makes the status say so (exit 10), as it does with MPI. Under mpiexec
(the launcher in the environment) they start MPI and rank 0 prints once."""
import os
import shutil
import subprocess

import h5py

import campaign_checks as cc

ap = cc.campaign_arguments(__doc__)
ap.add_argument("--full", required=True, help="output of the single run (fixture)")
a = ap.parse_args()

broken = dict(os.environ, OMPI_MCA_pml="no_such_component")
for name in ("OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"):
    broken.pop(name, None)


def campaign(out, *args, env=broken, launch=()):
    return subprocess.run(list(launch) + [a.tumble, "campaign", a.campaign, "--output", out]
                          + list(args), env=env, capture_output=True, text=True, timeout=120)


# The control: with this environment MPI cannot start, so a run fails.
r = campaign("ci_no_mpi_control")
if r.returncode == 0 or "MPI" not in r.stdout + r.stderr:
    cc.fail("the control: a campaign run with OMPI_MCA_pml=no_such_component exited %d (want a "
            "failed MPI start)\n%s%s" % (r.returncode, r.stdout, r.stderr))
shutil.rmtree("ci_no_mpi_control", ignore_errors=True)
print("control: a run cannot start MPI here (exit %d)" % r.returncode)

r = campaign(a.full, "--status")
if r.returncode != 0 or "8 cases: 6 done, 2 failed, 0 to run" not in r.stdout:
    cc.fail("--status without MPI: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
r = campaign(a.full, "--list")
rows = [x for x in r.stdout.splitlines() if x and not x.startswith("#")]
if r.returncode != 0 or len(rows) != 8:
    cc.fail("--list without MPI: exit %d, %d case rows (want 8)\n%s%s"
            % (r.returncode, len(rows), r.stdout, r.stderr))
r = campaign(a.full, "--slice", "2/3", "--status")
if r.returncode != 10 or "slice 2/3" not in r.stdout:  # (no partials in a 1/1 run: work left)
    cc.fail("--slice 2/3 --status without MPI: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
print("--status (0), --list (8 cases) and a slice's --status (10) without MPI")

# The statistics are still read in full: one value of a field changed behind its checksum.
damaged = "ci_no_mpi_damaged"
shutil.rmtree(damaged, ignore_errors=True)
shutil.copytree(a.full, damaged)
with h5py.File(os.path.join(damaged, "ensemble.h5"), "r+") as f:
    f["fields/concentration/c_L/mean"][0, 0] += 0.25
r = campaign(damaged, "--status")
if r.returncode != 10 or "does not read" not in r.stdout or "checksum" not in r.stdout:
    cc.fail("--status of a damaged ensemble.h5 without MPI: exit %d (want 10, its checksum named)"
            "\n%s%s" % (r.returncode, r.stdout, r.stderr))
shutil.rmtree(damaged, ignore_errors=True)
print("a field changed behind its checksum: --status 10 without MPI")

# Under the launcher MPI starts (the usual environment): one status from 2 ranks.
launch = cc.mpiexec_command(a.mpiexec, a.np_flag, 2)
r = campaign(a.full, "--status", env=os.environ, launch=launch)
if r.returncode != 0 or r.stdout.count("done, 2 failed") != 1:
    cc.fail("--status under mpiexec -n 2: exit %d\n%s%s" % (r.returncode, r.stdout, r.stderr))
print("OK: under mpiexec -n 2 the status is said once")
