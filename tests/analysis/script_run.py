"""Run a project script as the check scripts here do: its stdout, and on a failure its stdout and
stderr printed (the check that reads the output then fails and the reason is in the test log)."""
import subprocess
import sys


def script_stdout(script, *args):
    r = subprocess.run([sys.executable, script, *args], capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
    return r.stdout


class Checks:
    """A check script's `ok`/`FAIL` lines and its count of failures (its exit status)."""

    def __init__(self):
        self.failures = 0

    def __call__(self, name, ok, detail=""):
        print(f"{'ok  ' if ok else 'FAIL'} {name}{': ' + detail if detail else ''}")
        self.failures += not ok
