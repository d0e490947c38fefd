"""The campaign's page in a real browser (Debian's headless chromium, as
hil_tests/test_report.py renders the HIL report): at a desktop's and a phone's width no
table is wider than the window and every image, a file beside the page, loads
(docs/campaigns.md, "The report")."""

import json
import re

import pytest
from test_report import run_chromium

from host.campaign.report import write_report
from host.tests.test_campaign import POOL, planted_grid, planted_pool

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_report")]

FRAME = """<!DOCTYPE html><html><body style="margin:0">
<iframe id="page" src="campaign.html" style="width:{width}px;height:4000px;border:0"></iframe>
<script>
addEventListener("load", () => {{
  const doc = document.getElementById("page").contentDocument;
  const vw = doc.documentElement.clientWidth;
  const wide = [...doc.querySelectorAll("table")]
    .filter(t => t.getBoundingClientRect().right > vw + 1 || t.scrollWidth > t.clientWidth + 1)
    .map(t => t.className + " " + Math.round(t.getBoundingClientRect().width) + " px");
  const images = [...doc.images].map(i => ({{src: i.getAttribute("src"), loaded: i.complete && i.naturalWidth > 0,
    inside: i.getBoundingClientRect().right <= vw + 1}}));
  const probe = document.createElement("pre");
  probe.id = "probe";
  probe.textContent = JSON.stringify({{vw, page_w: doc.documentElement.scrollWidth, wide, images}});
  document.body.appendChild(probe);
}});
</script></body></html>"""
"""The page in a frame of the width wanted (chromium's window is 500 px wide at least: a
phone's 390 px is a frame's), measured from the frame's document once all has loaded."""


@pytest.fixture(scope="module")
def page(tmp_path_factory):
    """A pool campaign's page: 50 planted runs, two worst runs with their floor's grid."""
    out = tmp_path_factory.mktemp("campaign")
    planted_grid(out, "sonar-faults/default/4", missed_rows=7)
    planted_grid(out, "sonar-faults/default/19", missed_rows=3)
    showcase = {**POOL, "expected": {"sonar-faults": 0.22}, "explained": "docs/campaigns.md"}
    return write_report(out, showcase, planted_pool())["html"]


@pytest.mark.parametrize("width", [1920, 390])
def test_chromium_shows_the_campaign_page_with_no_table_wider_than_the_window_and_every_image(page, width, tmp_path):
    probe = page.with_name(f"frame-{width}.html")
    probe.write_text(FRAME.format(width=width))
    window = f"--window-size={max(width, 500) + 20},1200"
    done = run_chromium(tmp_path, "--allow-file-access-from-files", window, "--dump-dom", probe.as_uri())
    found = re.search(r'<pre id="probe">(.*?)</pre>', done.stdout, re.S)
    assert done.returncode == 0 and found, f"chromium did not render {probe}: {done.stderr[-2000:]}"
    seen = json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    assert abs(seen["vw"] - width) < 40, f"expected a {width} px window, the page saw {seen['vw']} px"
    assert not seen["wide"] and seen["page_w"] <= seen["vw"], f"at {width} px, tables wider than the window: {seen}"
    images = seen["images"]
    assert len(images) >= 5 and all(i["src"].startswith(("plots/", "maps/")) for i in images), images
    assert all(i["loaded"] and i["inside"] for i in images), f"at {width} px, images not loaded or cut: {images}"
    assert sum(i["src"].startswith("maps/") for i in images) == 2, "expected the two worst runs' floor maps"
