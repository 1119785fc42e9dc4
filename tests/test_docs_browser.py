"""The built documentation site as a reader sees it in Chromium (Debian's
headless chromium and chromedriver, through selenium), at 1280 px: no code
block is wider than its column, so no command or comment hides behind a
scroll bar, and no page is wider than the window."""
import os

import pytest

import docs_examples as D

CHROMIUM, CHROMEDRIVER = "/usr/bin/chromium", "/usr/bin/chromedriver"
if not all(os.access(p, os.X_OK) for p in (CHROMIUM, CHROMEDRIVER)):
    pytest.skip("needs Debian's chromium and chromium-driver (scripts/setup.sh installs them as root)",
                allow_module_level=True)
webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is a test extra")
pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install 'pdbfs[docs]')")
from selenium.webdriver.chrome.service import Service  # noqa: E402

WIDTH = 1280
#: each code block's width against its column, and the page's against the window
MEASURE = """
const blocks = [];
for (const pre of document.querySelectorAll('.md-content pre')) {
  const code = pre.querySelector('code') || pre;
  blocks.push([code.scrollWidth, code.clientWidth, code.textContent.split('\\n')[0].slice(0, 60)]);
}
return [blocks, document.documentElement.scrollWidth, document.documentElement.clientWidth];
"""


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("site")
    r = D.build_site(out)
    assert r.returncode == 0, r.stderr[-4000:]
    return out


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
              "--disable-background-networking", "--disable-component-update",
              f"--user-data-dir={tmp_path_factory.mktemp('profile')}",
              f"--window-size={WIDTH},900", "--host-resolver-rules=MAP * ~NOTFOUND"):
        opts.add_argument(a)
    d = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    yield d
    d.quit()


def test_code_blocks_fit_their_column_at_1280_px(site, browser):
    """Every page with code: each block's lines wrap within its column
    (getting started's install lines and the tutorials' longer lines were
    cut off behind a scroll bar)."""
    pages = sorted(site.rglob("index.html"))
    assert len(pages) > 20
    checked = 0
    for page in pages:
        browser.get(page.as_uri())
        blocks, page_width, window = browser.execute_script(MEASURE)
        where = page.parent.relative_to(site).as_posix() or "home"
        assert page_width <= window, f"{where}: the page is {page_width} px wide in {window} px"
        for scroll, client, first in blocks:
            assert scroll <= client + 1, f"{where}: a code block needs {scroll} px in {client} px: {first!r}"
        checked += len(blocks)
    assert checked > 100
