"""The report page: captions for every figure, a movie per class, the phase table in a box of its own.
Rendered in headless Chromium where it is installed (skipped with a message otherwise): at a phone's
width and a desktop's the page has no horizontal overflow, the wide phase table scrolls inside its box,
and every figure keeps its aspect."""

import html
import json
import re
import shutil
import subprocess

import pytest
from edmd_analysis import report as report_module
from PIL import Image

BROWSERS = ("chromium", "chromium-headless-shell", "chromium-browser", "google-chrome")

# Measures the page once everything has loaded and leaves the numbers on <body>.
PROBE = """<script>
window.addEventListener('load', () => {
  const box = document.querySelector('.table-box');
  const imgs = [...document.querySelectorAll('img')].map(i => ({src: i.getAttribute('src'),
      w: i.clientWidth, h: i.clientHeight, nw: i.naturalWidth, nh: i.naturalHeight}));
  document.body.setAttribute('data-probe', JSON.stringify({
      page: document.documentElement.scrollWidth, view: window.innerWidth,
      box: box.clientWidth, table: box.scrollWidth, imgs: imgs}));
});
</script>"""


@pytest.fixture(scope="module")
def page(classified_sweep, tmp_path_factory):
    return report_module.report(classified_sweep, tmp_path_factory.mktemp("page") / "rep")


def test_every_figure_has_a_caption_and_each_class_a_movie(page, classified_sweep):
    text = page.read_text()
    images = re.findall(r'<img src="([^"]+)"', text)
    assert images and len(set(images)) == len(images)
    for name in images:
        assert (page.parent / name).exists(), name
        assert report_module.legend(name), f"no caption for {name}"
    assert text.count("<figcaption>") == len(images)
    movies = [n for n in images if n.startswith("movie-")]
    index_classes = sorted({c for c in report_module.io.read_index(classified_sweep)["class"]
                            if c in report_module.MOVIE_CLASSES})
    assert sorted(n.split("-")[1] for n in movies) == index_classes
    for name in movies:
        with Image.open(page.parent / name) as im:
            assert im.n_frames == 3  # snapshots at tau 0, 5 and the final state
    assert '<div class="table-box">' in text and 'name="viewport"' in text


def browser():
    for name in BROWSERS:
        path = shutil.which(name)
        if path:
            return path
    pytest.skip(f"no headless Chromium ({', '.join(BROWSERS)}) on the PATH: page not rendered "
                "(apt-get install chromium-headless-shell)")


@pytest.mark.parametrize("width", [390, 1280])
def test_page_has_no_horizontal_overflow(page, width):
    exe = browser()
    probe = page.with_name("probe.html")
    probe.write_text(page.read_text().replace("</body>", PROBE + "</body>"))
    dom = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                          f"--window-size={width},900", "--virtual-time-budget=10000", "--dump-dom",
                          probe.as_uri()], capture_output=True, text=True, timeout=120).stdout
    found = re.search(r'data-probe="([^"]+)"', dom)
    assert found, f"the page did not load in {exe}: {dom[:500]}"
    m = json.loads(html.unescape(found.group(1)))
    assert m["view"] == width
    assert m["page"] <= m["view"], f"page {m['page']} px wide in a {width} px window"
    if width == 390:
        assert m["table"] > m["box"], "the phase table should scroll inside its box"
    assert m["imgs"]
    for img in m["imgs"]:
        assert img["nw"] > 0, f"{img['src']} did not load"
        assert img["w"] <= m["view"]
        aspect, drawn = img["nw"] / img["nh"], img["w"] / img["h"]
        assert drawn == pytest.approx(aspect, rel=0.02, abs=2 / img["h"]), img
