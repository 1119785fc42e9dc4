"""What the browser tests of `pdbfs app` share: Debian's headless Chromium
driven through selenium and the system chromedriver, a server started with
the command line on a free loopback port, and helpers to read the page."""
from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time

import pytest

from pdbfs.models import paper_rig

CHROMIUM, CHROMEDRIVER = "/usr/bin/chromium", "/usr/bin/chromedriver"
HAVE = all(os.access(p, os.X_OK) for p in (CHROMIUM, CHROMEDRIVER))
try:
    import dash  # noqa: F401
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
except ImportError:
    HAVE = False
    By = Keys = None
if not HAVE and os.environ.get("CI"):
    pytest.fail("CI must have chromium, chromium-driver, dash and selenium (scripts/setup.sh)",
                pytrace=False)
WAIT = 30.0


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(cwd, *args, env=None):
    """`pdbfs app` on a free loopback port: (process, its printed address)."""
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--port", str(port), *args],
                            cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=env)
    line = proc.stdout.readline()
    url = f"http://127.0.0.1:{port}/"
    assert url in line, f"pdbfs app printed {line!r}, not its address"
    t0 = time.time()
    while time.time() - t0 < WAIT:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            time.sleep(0.1)
    return proc, url


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """`pdbfs app` on a free loopback port (its temporary files in a folder of
    the test's); its printed address."""
    cwd = tmp_path_factory.mktemp("app")
    proc, url = start_server(cwd, env={**os.environ, "TMPDIR": str(cwd)})
    yield url
    proc.terminate()
    proc.wait(10)


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    profile = tmp_path_factory.mktemp("chromium-profile")
    downloads = tmp_path_factory.mktemp("downloads")
    opts = webdriver.ChromeOptions()
    opts.binary_location = CHROMIUM
    for a in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
              "--disable-background-networking", "--disable-component-update", "--disable-sync",
              f"--user-data-dir={profile}", "--window-size=1400,1000",
              "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1"):
        opts.add_argument(a)
    opts.add_experimental_option("prefs", {"download.default_directory": str(downloads)})
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    d = webdriver.Chrome(service=Service(CHROMEDRIVER), options=opts)
    d.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow",
                                                      "downloadPath": str(downloads)})
    d.downloads = downloads
    yield d
    d.quit()


def wait(d, css, cond=lambda e: True, timeout=WAIT):
    t0 = time.time()
    while time.time() - t0 < timeout:
        for e in d.find_elements(By.CSS_SELECTOR, css):
            try:
                if cond(e):
                    return e
            except Exception:       # noqa: BLE001 - re-rendered while read: look again
                pass
        time.sleep(0.05)
    raise AssertionError(f"{css} did not appear (or change) within {timeout} s")


def pid(kind, name):
    return f"[id='{{\"name\":\"{name}\",\"type\":\"{kind}\"}}']"


def load(d, url):
    d.get(url)
    return wait(d, "#sum-peak_pressure", lambda e: e.text).text


def shown_peak(d, old=None) -> float:
    e = wait(d, "#sum-peak_pressure", lambda e: e.text and e.text != old)
    return float(json.loads(e.get_attribute("data-value"))), e.text


def type_into(d, name, text):
    f = d.find_element(By.CSS_SELECTOR, pid("field", name))
    f.send_keys(Keys.CONTROL, "a")
    f.send_keys(text + Keys.ENTER)


def trace_names(d):
    return d.execute_script("const g = document.querySelector('#pulse .js-plotly-plot');"
                            "return g && g.data ? g.data.map(t => t.name) : [];")


def api_peak(**params) -> float:
    return paper_rig().simulate(0.02, params=params, backend="c").summary()["peak_pressure"]


def cli_error(*args, cwd) -> str:
    p = subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True, text=True,
                       cwd=cwd)
    assert p.returncode == 2, p.stderr
    return p.stderr.strip().removeprefix("pdbfs: error: ")


def tab(d, key):
    """Show one of the study panels (trace, design, map, downloads)."""
    d.find_element(By.CSS_SELECTOR, f"#study-tab input[value='{key}']").click()
    wait(d, f"#panel-{key}", lambda e: e.is_displayed())
