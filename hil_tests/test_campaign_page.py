"""The campaign's page in a real browser (Debian's headless chromium, through
hil_tests/browser.py, as the HIL report): at a desktop's and a phone's width no
table is wider than the window and every image, a file beside the page, loads
(docs/campaigns.md, "The report")."""

import pytest
from browser import measured

from host.campaign.report import write_report
from host.tests.test_campaign import POOL, planted_grid, planted_pool

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_report")]


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
    m = measured(page, tmp_path, width)
    assert m["width"] == width, f"chromium's window is {m['width']} px, expected {width}"
    assert not m["problems"], f"{page} at {width} px: {m['problems']}"
    images = m["images"]
    assert len(images) >= 5 and all(src.startswith(("plots/", "maps/")) for src in images), images
    assert sum(src.startswith("maps/") for src in images) == 2, f"expected the two worst runs' floor maps: {images}"
