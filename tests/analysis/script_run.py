"""Run a project script as the check scripts here do: its stdout, and on a failure its stdout and
stderr printed (the check that reads the output then fails and the reason is in the test log)."""
import subprocess
import sys


def script_stdout(script, *args):
    r = subprocess.run([sys.executable, script, *args], capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
    return r.stdout
