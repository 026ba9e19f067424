"""Loads a report in headless Chromium and asserts that every <img> decoded (naturalWidth > 0),
that the page opens with its Findings, and that no printed interval leaves its bounds.

  check_report_chromium.py REPORT.html [--chromium PATH] [--screenshot OUT.png]
                           [--expect-name TEXT ...] [--expect-warning] [--expect-pipeline-check]

On the DOM Chromium dumps after the load event:
  * a section id="findings" comes before every other section heading, contains every
    --expect-name (e.g. both protocols' labels) and at least one number with its interval
    ("m [lower, upper]" in a span.ci);
  * every span.ci on the page (the report prints each interval of a quantity with physical
    bounds in one, with data-lo / data-hi) reads "m [lower, upper]" with
    lo <= lower <= upper <= hi and lo <= m <= hi;
  * --expect-warning: the findings warn about fewer than 3 replicas ("N = 1" or "N = 2");
  * --expect-pipeline-check: the findings call the run a pipeline check (R/d_large < 8).

The page's own script (postproc/report_page.py, CHECK_SCRIPT) writes data-images-total / -ok /
-broken on <body> at the load event; --dump-dom prints the DOM after it ran. The image count is
also taken from the HTML text, so a page whose script did not run, or that lost images, fails.
A missing Chromium is a failure: jobs/install_deps.sh installs the Debian package `chromium`.
"""
import argparse
import html
import os
import re
import shutil
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("report")
ap.add_argument("--chromium", default="")
ap.add_argument("--screenshot")
ap.add_argument("--expect-name", action="append", default=[])
ap.add_argument("--expect-warning", action="store_true")
ap.add_argument("--expect-pipeline-check", action="store_true")
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

dom = r.stdout
problems = []
f = re.search(r'<section id="findings">(.*?)</section>', dom, re.S)
if not f:
    problems.append("no Findings section")
else:
    first_h2 = re.search(r"<h2>(.*?)</h2>", dom)
    if not first_h2 or first_h2.group(1) != "Findings":
        problems.append(f"the first section is {first_h2.group(1) if first_h2 else None!r}, "
                        "not Findings")
    text = html.unescape(re.sub(r"<[^>]+>", "", f.group(1)))
    for name in a.expect_name:
        if name not in text:
            problems.append(f"Findings do not name {name!r}")
    if not re.search(r'<span class="ci"[^>]*>[-+0-9.e]+ \[[-+0-9.e]+, [-+0-9.e]+\]', f.group(1)):
        problems.append("no number with its interval in the Findings")
    if a.expect_warning and not re.search(r"Warning: N = [12] replica", text):
        problems.append("no warning about fewer than 3 replicas")
    if a.expect_pipeline_check and "is a pipeline check" not in text:
        problems.append("the Findings do not call the run a pipeline check")
    print("findings: " + re.sub(r"\s+", " ", text)[:3000])
spans = re.findall(r'<span class="ci" data-lo="([^"]+)" data-hi="([^"]+)">([^<]*)</span>', dom)
checked = 0
for lo, hi, t in spans:
    t = html.unescape(t)
    m = re.match(r"([-+0-9.e]+) \[([-+0-9.e]+), ([-+0-9.e]+)\]", t)
    if not m:
        problems.append(f"interval text {t!r} not 'm [lower, upper]'")
        continue
    mean, lower, upper = (float(x) for x in m.groups())
    lo, hi = float(lo), float(hi)
    checked += 1
    if not (lo <= lower <= upper <= hi and lo <= mean <= hi):
        problems.append(f"interval {t!r} leaves its bounds [{lo:g}, {hi:g}]")
print(f"bounded intervals on the page: {checked}, all within their bounds"
      if checked and not problems else f"bounded intervals on the page: {checked}")
if checked == 0:
    problems.append("no bounded interval (span.ci) on the page")
if problems:
    for p in problems:
        print("FAIL: " + p)
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
