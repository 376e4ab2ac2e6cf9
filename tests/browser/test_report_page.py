#!/usr/bin/env python3
"""report.html in a real browser: headless Chromium at 1400 px opens OUTDIR/report.html from disk
through tests/browser/report_probe.html, which drives the viewer and reports what it saw.

    test_report_page.py OUTDIR MAX_HEIGHT_PX

Fails when the page is taller than MAX_HEIGHT_PX or wider than 1400 px, when the browser logs any
console message (a script error among them), when an image does not load, when anything but a
file:// resource is requested, or when a viewer check fails. Exits 77 (ctest: skipped) when no
chromium is installed. Standard library only.
"""
import html
import json
import os
import re
import shutil
import subprocess
import sys
import time

SKIP = 77
WIDTH = 1400


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    out, budget = os.path.abspath(argv[1]), int(argv[2])
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        print("SKIP: chromium not found on PATH (Debian package chromium; tools/install-deps.sh installs it)")
        return SKIP
    page = os.path.join(out, "report.html")
    if not os.path.isfile(page):
        print(f"FAIL: {page} missing", file=sys.stderr)
        return 1
    text = open(page, encoding="utf-8").read()
    failures = [f"report.html links the network: {m}" for m in re.findall(r'(?:src|href)="(https?://[^"]*)"', text)]

    probe = os.path.join(out, "report_probe.html")
    shutil.copyfile(os.path.join(os.path.dirname(os.path.abspath(__file__)), "report_probe.html"), probe)
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--no-default-browser-check",
           "--allow-file-access-from-files", "--no-proxy-server", f"--window-size={WIDTH},1000",
           "--virtual-time-budget=20000", "--enable-logging=stderr", "--v=0", f"--user-data-dir={out}/chromium-profile",
           "--dump-dom", "file://" + probe]
    start = time.monotonic()
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=90)
    seconds = time.monotonic() - start
    # Every console message counts, bar the browser's advice to the probe about its own readbacks.
    console = [line for line in run.stderr.splitlines()
               if ":CONSOLE" in line and not ('"Canvas2D:' in line and "report_probe.html" in line)]
    failures += [f"console: {line}" for line in console]
    m = re.search(r'<pre id="result">(.*?)</pre>', run.stdout, re.S)
    if m is None or m.group(1) == "pending":
        print(run.stderr[-3000:], file=sys.stderr)
        print(f"FAIL: the probe did not finish (chromium exit {run.returncode})", file=sys.stderr)
        return 1
    result = json.loads(html.unescape(m.group(1)))
    failures += result["failures"]
    failures += [f"image did not load: {src}" for src in result.get("broken_images", [])]
    failures += [f"non-file resource: {url}" for url in result.get("non_file_resources", [])]
    if "height" in result and result["height"] > budget:
        failures.append(f"page is {result['height']} px tall at {WIDTH} px wide, over the budget of {budget} px")
    if "width" in result and result["width"] > WIDTH:
        failures.append(f"page is {result['width']} px wide: it scrolls sideways at {WIDTH} px")
    print(f"report page at {WIDTH} px: {result.get('height')} px tall (budget {budget}), {result.get('width')} px wide, "
          f"{result.get('renders')} renders, {len(result['checks'])} viewer checks, chromium {seconds:.1f} s")
    for f in failures:
        print(f"FAIL: {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
