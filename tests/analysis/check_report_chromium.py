"""Loads a report in headless Chromium and asserts that every <img> decoded (naturalWidth > 0).

  check_report_chromium.py REPORT.html [--chromium PATH] [--screenshot OUT.png]

The page's own script (postproc/report.py, CHECK_SCRIPT) writes data-images-total / -ok /
-broken on <body> at the load event; --dump-dom prints the DOM after it ran. The image count is
also taken from the HTML text, so a page whose script did not run, or that lost images, fails.
A missing Chromium is a failure: jobs/install_deps.sh installs the Debian package `chromium`.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("report")
ap.add_argument("--chromium", default="")
ap.add_argument("--screenshot")
a = ap.parse_args()

exe = a.chromium or shutil.which("chromium") or shutil.which("chromium-browser")
if not exe:
    print("FAIL: chromium not found (jobs/install_deps.sh installs the Debian package)")
    sys.exit(1)
url = "file://" + os.path.abspath(a.report)
flags = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
         "--hide-scrollbars", "--virtual-time-budget=15000"]
r = subprocess.run(flags + ["--dump-dom", url], capture_output=True, text=True, timeout=180)
m = re.search(r"<body[^>]*>", r.stdout)
if r.returncode != 0 or not m:
    print(r.stderr[-2000:])
    print(f"FAIL: chromium exit code {r.returncode}, no <body> in the dumped DOM")
    sys.exit(1)
body = m.group(0)
attr = dict(re.findall(r'data-images-(\w+)="([^"]*)"', body))
expected = len(re.findall(r"<img\b", open(a.report).read()))
if "total" not in attr:
    print("FAIL: the page's load script did not run (no data-images-total on <body>)")
    sys.exit(1)
total, ok = int(attr["total"]), int(attr["ok"])
print(f"chromium: {ok} of {total} images loaded (the HTML has {expected} <img>)")
if expected == 0 or total != expected or ok != total:
    print(f"FAIL: broken images: {attr.get('broken', '')}")
    sys.exit(1)
if a.screenshot:
    s = subprocess.run(flags + ["--window-size=1200,1900", f"--screenshot={a.screenshot}", url],
                       capture_output=True, text=True, timeout=180)
    if s.returncode != 0 or not os.path.exists(a.screenshot):
        print(s.stderr[-2000:])
        print("FAIL: no screenshot")
        sys.exit(1)
    print(f"screenshot {a.screenshot}")
print("OK")
