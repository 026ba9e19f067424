"""Runs a command and signals it once its own output says so (the signal tests of tests/cli), so
that the tests do not depend on the machine's speed."""
import subprocess
import sys
import threading
import time


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def signalled(name, command, sig, when, settle=0.0, wait=120):
    """Starts `command`, sends `sig` once a line for which `when` holds is out (and `settle` more
    seconds have passed), and returns (exit code, output). The test fails if no such line comes
    within `wait` seconds, if the command ended before the signal, or if it still runs `wait`
    seconds after it."""
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines, seen = [], threading.Event()

    def read():
        for line in proc.stdout:
            lines.append(line)
            if when(line):
                seen.set()

    reader = threading.Thread(target=read)
    reader.start()
    if not seen.wait(wait):
        proc.kill()
        reader.join()
        fail("%s: no line to signal it at within %d s\n%s" % (name, wait, "".join(lines)))
    time.sleep(settle)
    if proc.poll() is not None:
        reader.join()
        fail("%s: the run ended before it could be signalled: make it longer\n%s" % (name, "".join(lines)))
    proc.send_signal(sig)
    try:
        rc = proc.wait(timeout=wait)
    except subprocess.TimeoutExpired:
        proc.kill()
        fail("%s: still running %d s after %s" % (name, wait, sig.name))
    reader.join()
    return rc, "".join(lines)
