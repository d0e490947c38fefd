"""A real browser for the tests of our pages (the HIL report, the campaign page): Debian's
headless chromium with no network, its processes gone when a call returns, and a layout
probe that says, at a given viewport width, which tables overflow their container and which
images did not load or stick out of the page."""

import json
import os
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

BROWSER_TIMEOUT_S = 90


def chromium_path() -> str:
    path = shutil.which("chromium") or "/usr/bin/chromium"
    if not os.access(path, os.X_OK):
        pytest.fail(
            "expected Debian's chromium at /usr/bin/chromium to render the report, found none: `make setup` "
            "installs it when run as root; otherwise run `sudo apt-get install -y chromium`"
        )
    return path


def run_chromium(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    """Headless chromium with no network at all; its processes are gone when this returns."""
    cmd = [
        chromium_path(),
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--host-resolver-rules=MAP * ~NOTFOUND",
        f"--user-data-dir={tmp_path / 'profile'}",
        *args,
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=BROWSER_TIMEOUT_S)
    finally:
        _end_group(proc)
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def _end_group(proc) -> None:
    """Give chromium's helper processes a moment to exit, then end what is left (exited
    helpers may stay zombies until init reaps them: they hold nothing)."""
    deadline = time.monotonic() + 5
    while _live_members(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.05)
    for pid in _live_members(proc.pid):
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    if proc.poll() is None:
        proc.kill()
        proc.wait(timeout=5)


def _live_members(pgid: int) -> list[int]:
    """Processes of a process group that are not zombies, from /proc."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            found.append(int(entry.name))
    return found


MEASURE = """
<script>
document.querySelectorAll("details").forEach((d) => { d.open = true; });
window.addEventListener("load", () => {
  const problems = [];
  const edge = (e) => e.getBoundingClientRect().right;
  document.querySelectorAll("table").forEach((t, i) => {
    const box = t.parentElement;
    if (t.scrollWidth > box.clientWidth + 1 || edge(t) > edge(box) + 1) {
      problems.push(`table ${i} (${t.className}) is ${t.scrollWidth} px wide in a ${box.clientWidth} px container`);
    }
  });
  const images = [...document.images];
  images.forEach((img) => {
    if (!img.complete || img.naturalWidth === 0) problems.push(`image not loaded: ${img.getAttribute("src")}`);
    else if (edge(img) > window.innerWidth + 1) problems.push(`image out of the page: ${img.getAttribute("src")}`);
  });
  const page = document.documentElement.scrollWidth;
  if (page > window.innerWidth + 1) problems.push(`the page is ${page} px wide in a ${window.innerWidth} px window`);
  parent.postMessage(JSON.stringify({width: window.innerWidth, tables: document.querySelectorAll("table").length,
                                     images: images.map((i) => i.getAttribute("src")), problems}), "*");
});
</script>
"""
FRAME = """<!DOCTYPE html><html><body style="margin:0">
<iframe src="{page}" style="border:0; width:{width}px; height:900px"></iframe>
<pre id="measured"></pre>
<script>
window.addEventListener("message", (e) => {{ document.getElementById("measured").textContent = e.data; }});
</script>
</body></html>
"""


def measured(report: Path, tmp_path: Path, width: int) -> dict:
    """The report as chromium lays it out in a viewport ``width`` px wide (an iframe: a
    headless window is at least 500 px wide): the tables that overflow their container,
    the images that did not load, which a copy of the page beside it (its images' paths
    unchanged) measures and hands to the frame's page, read back with --dump-dom."""
    page = report.with_name(f"measured_{width}.html")
    frame = report.with_name(f"frame_{width}.html")
    page.write_text(report.read_text().replace("</body>", MEASURE + "</body>"))
    frame.write_text(FRAME.format(page=page.name, width=width))
    try:
        dom = run_chromium(
            tmp_path,
            f"--window-size={width + 40},1000",
            "--allow-file-access-from-files",
            "--virtual-time-budget=20000",
            "--dump-dom",
            frame.as_uri(),
        )
    finally:
        page.unlink()
        frame.unlink()
    found = re.search(r'<pre id="measured">(.+?)</pre>', dom.stdout, re.S)
    assert found, f"chromium wrote no measurements of {report} at {width} px: {dom.stdout[-1000:]}{dom.stderr[-2000:]}"
    return json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
