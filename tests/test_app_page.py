"""`pdbfs app` in headless Chromium, at the edges a user reaches (issue 21):
huge values, a failed run, the run length, a large upload, a server that
stops, rigs switched, jobs cancelled, and the page's own layout."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from pdbfs.app.workbench import workbench
from pdbfs.models import paper_rig

from app_support import (HAVE, By, Keys, api_peak, browser, free_port, load, pid,  # noqa: F401
                         server, shown_peak, start_server, tab, trace_names, type_into, wait)

pytestmark = pytest.mark.skipif(not HAVE, reason="needs chromium, chromium-driver, selenium, dash")


def status(d):
    return d.find_element(By.ID, "status").text


def test_a_huge_value_is_refused_beside_its_field_or_simulated(server, browser):
    load(browser, server)
    type_into(browser, "hammer.v0", "1e300")
    msg = wait(browser, pid("msg", "hammer.v0"), lambda e: e.text).text
    with pytest.raises(Exception) as err:
        workbench("paper").check("hammer.v0", "1e300")
    assert msg == str(err.value)
    type_into(browser, "hammer.v0", "2.73")
    wait(browser, pid("msg", "hammer.v0"), lambda e: e.text == "")
    type_into(browser, "piston.v0", "1e308")            # accepted: the solver says no
    wait(browser, "#run-failed")
    assert "solver failed" in status(browser)
    assert browser.find_element(By.CSS_SELECTOR, pid("field", "piston.v0")).get_attribute(
        "value") == "1e308"
    type_into(browser, "piston.v0", "0")                # and the server lives on
    peak, _ = shown_peak(browser)
    assert peak == pytest.approx(api_peak(), rel=1e-9)


def test_a_failed_run_leaves_no_old_result_and_the_method_can_be_chosen(server, browser):
    load(browser, server)
    # CVODE's Adams takes about 2 s of steps before it fails (the default explicit
    # method fails within 0.3 s, before the busy note is due)
    browser.find_element(By.ID, "method").click()
    wait(browser, "[role=option]", lambda e: e.text == "adams").click()
    wait(browser, "#status", lambda e: "method adams" in e.text)
    type_into(browser, "oil.k", "1e30")
    assert wait(browser, "#busy", lambda e: e.is_displayed(), timeout=10)   # said while it runs
    wait(browser, "#run-failed")
    assert not browser.find_elements(By.ID, "sum-peak_pressure")
    assert trace_names(browser) == []                   # the old curves are gone
    text = status(browser)
    assert "method bdf (beside t_end)" in text and "method='bdf'" not in text
    browser.find_element(By.ID, "method").click()
    wait(browser, "[role=option]", lambda e: e.text == "bdf").click()
    wait(browser, "#status", lambda e: "the error test failed" in e.text)
    type_into(browser, "oil.k", "3e8")
    peak, _ = shown_peak(browser)
    assert peak == pytest.approx(paper_rig().simulate(0.02, params={"oil.k": 3e8}, backend="c",
                                                      method="bdf").summary()["peak_pressure"],
                                 rel=1e-9)
    assert "method bdf" in status(browser)


def test_t_end_on_the_page_and_the_hint_that_names_it(server, browser):
    load(browser, server)
    f = browser.find_element(By.ID, "t-end")
    f.send_keys(Keys.CONTROL, "a")
    f.send_keys("5" + Keys.ENTER)
    wait(browser, "#sum-complete", lambda e: e.text.startswith("no"))
    note = wait(browser, "#status .note", lambda e: "set t_end to" in e.text).text
    need = note.split("set t_end to ")[1].split(" ms")[0]
    f.send_keys(Keys.CONTROL, "a")
    f.send_keys(need + Keys.ENTER)
    wait(browser, "#sum-complete", lambda e: e.text == "yes")
    api = paper_rig().simulate(float(need) * 1e-3, backend="c").summary()
    shown = float(browser.find_element(By.ID, "sum-pulse_duration").get_attribute("data-value"))
    assert shown == api["pulse_duration"]
    f.send_keys(Keys.CONTROL, "a")
    f.send_keys("-3" + Keys.ENTER)
    wait(browser, "#run-msg", lambda e: e.text == "t_end = -3 ms: must be a positive number")


def test_a_large_upload_is_refused_with_its_size(server, browser, tmp_path):
    load(browser, server)
    tab(browser, "trace")
    big = tmp_path / "huge.csv"
    line = b"0.000123456789,123456789.123456789\n"
    big.write_bytes(b"time [s],p [Pa]\n" + line * (21_000_000 // len(line)))
    browser.find_element(By.CSS_SELECTOR, "#upload input[type=file]").send_keys(str(big))
    msg = wait(browser, "#upload-msg", lambda e: e.text, timeout=60).text
    assert msg.startswith("trace file 'huge.csv': 21.0 MB, more than the page takes (20 MB)")


def test_rigs_bring_their_own_study_defaults_and_say_they_are_building(server, browser):
    load(browser, server)
    _, text = shown_peak(browser)
    # every text the note takes, kept by the page itself: the note lasts only as long
    # as the server takes to answer, which a poll from here can miss on a fast machine
    browser.execute_script("""
        window.pdbfsNotes = [];
        new MutationObserver(() => {
            const e = document.getElementById('rig-note');
            if (e) window.pdbfsNotes.push(e.textContent);
        }).observe(document.body, {childList: true, characterData: true, subtree: true});""")
    browser.find_element(By.ID, "rig").click()
    wait(browser, "[role=option]", lambda e: e.text == "hydraulic-pulse").click()
    t0 = time.time()
    while not any(n.startswith("building rig hydraulic-pulse")
                  for n in browser.execute_script("return window.pdbfsNotes")):
        assert time.time() - t0 < 30, "the page never said it was building the rig"
        time.sleep(0.05)
    shown_peak(browser, text)
    wait(browser, "#rig-note", lambda e: e.text == "")
    tab(browser, "trace")
    assert "chamber.K" in browser.find_element(By.ID, "cal-free").text
    assert "mount.s_rel0" not in browser.find_element(By.ID, "cal-free").text
    tab(browser, "map")
    d = workbench("hydraulic-pulse").study_defaults()
    assert float(browser.find_element(By.ID, "map-y-lo").get_attribute("value")) == d["map-y-lo"]
    assert browser.find_element(By.ID, "t-end").get_attribute("value") == "20"


def test_cancel_says_so(server, browser):
    load(browser, server)
    tab(browser, "map")
    e = browser.find_element(By.ID, "map-n")
    e.send_keys(Keys.CONTROL, "a")
    e.send_keys("40")
    browser.find_element(By.ID, "map-cancel").click()       # nothing running: nothing said
    time.sleep(0.5)
    assert browser.find_element(By.ID, "map-progress").text == ""
    browser.find_element(By.ID, "map-run").click()
    wait(browser, "#map-progress", lambda e: "mapping" in e.text)
    browser.find_element(By.ID, "map-cancel").click()
    wait(browser, "#map-progress", lambda e: e.text.startswith("cancelled at"))


def test_pins_never_share_a_label(server, browser):
    load(browser, server)
    for k in range(7):
        type_into(browser, "seal.c", str(20000 + 1000 * k))
        wait(browser, "#status", lambda e: "points" in e.text)
        time.sleep(0.3)
        browser.find_element(By.ID, "pin").click()
        wait(browser, "#pulse", lambda e: f"pin {k + 1} " in " ".join(trace_names(browser)))
    labels = {n.split(":")[0] for n in trace_names(browser) if n.startswith("pin")}
    assert len(labels) == 5 and "pin 7 (seal.c=26000)" in labels


def test_the_layout_a_newcomer_sees(server, browser):
    """An introduction; the study tabs above the fold; slider labels inside
    their panel; design results with units."""
    load(browser, server)
    intro = browser.find_element(By.ID, "intro")
    intro.click()
    assert "drop-hammer" in intro.text
    top = browser.execute_script("return document.getElementById('study-tab')"
                                 ".getBoundingClientRect().bottom <= window.innerHeight")
    assert top, "the study tabs are below the fold"
    rects = browser.execute_script("""
        const col = document.getElementById('controls').parentElement;   // it clips
        const r = col.getBoundingClientRect();
        const box = {left: r.left, right: r.left + col.clientWidth};     // no scroll bar
        return [...document.querySelectorAll('#controls .slider-box')].flatMap(s =>
            [...s.querySelectorAll('*')].filter(e => e.children.length === 0 && e.textContent.trim())
              .map(e => e.getBoundingClientRect())
              .map(r => [r.left, r.right, box.left, box.right]));""")
    assert len(rects) >= 12                             # two end labels per slider
    assert all(b_lo - 0.5 <= lo and hi <= b_hi + 0.5 for lo, hi, b_lo, b_hi in rects), rects
    tab(browser, "design")
    browser.find_element(By.ID, "des-run").click()
    out = wait(browser, "#des-out", lambda e: "reached" in e.text, timeout=60).text
    assert "MPa" in out and "hammer.h" in out


def test_a_stopped_server_is_noticed_and_leaves_no_cache(browser, tmp_path):
    proc, url = start_server(tmp_path, env={**os.environ, "TMPDIR": str(tmp_path)})
    try:
        load(browser, url)
        assert list(tmp_path.glob("pdbfs-app-cache-*"))
        assert not browser.find_element(By.ID, "conn-lost").is_displayed()
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(20)
    assert wait(browser, "#conn-lost", lambda e: e.is_displayed(), timeout=10)
    assert "connection to the pdbfs server is lost" in browser.find_element(By.ID, "conn-lost").text
    assert not list(tmp_path.glob("pdbfs-app-cache-*"))


def test_listening_beyond_this_machine_is_warned_about(tmp_path):
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--host", "0.0.0.0",
                             "--port", str(port)], cwd=tmp_path, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "TMPDIR": str(tmp_path)})
    try:
        line = proc.stderr.readline()
    finally:
        proc.terminate()
        proc.wait(20)
    assert line.startswith("pdbfs: warning: --host 0.0.0.0: the page is open to every machine")


def test_bar_piston_draws_its_parts_when_asked(server, browser):
    load(browser, server)
    _, text = shown_peak(browser)
    browser.find_element(By.ID, "rig").click()
    wait(browser, "[role=option]", lambda e: e.text == "bar-piston").click()
    _, text = shown_peak(browser, text)
    fields = browser.find_elements(By.CSS_SELECTOR, "#controls .field")
    assert 15 < len(fields) < 30
    wait(browser, "#parts input", lambda e: e.click() is None)    # again if re-drawn meanwhile
    wait(browser, "#controls", lambda e: len(e.find_elements(By.CSS_SELECTOR, ".field")) > 200)
    time.sleep(0.5)
    wait(browser, pid("field", "piston.E"),
         lambda e: e.send_keys(Keys.CONTROL, "a") or e.send_keys("1.5e11" + Keys.ENTER) or True)
    peak, _ = shown_peak(browser, text)
    from pdbfs.models import RIGS
    api = RIGS["bar-piston"]().simulate(0.02, params={"piston.E": 1.5e11}, backend="c")
    assert peak == pytest.approx(api.summary()["peak_pressure"], rel=1e-9)


LAYOUT = """
const box = e => { const r = e.getBoundingClientRect();
                   return {left: r.left, right: r.right, top: r.top, bottom: r.bottom}; };
const side = document.getElementById('controls').parentElement;
const s = box(side);
const clip = {left: s.left, right: s.left + side.clientWidth};    // it clips at its scroll bar
const leaves = root => [...root.querySelectorAll('*')].filter(
    e => e.children.length === 0 && e.textContent.trim() && e.getClientRects().length);
const controls = [...document.querySelectorAll('#controls .control')].map(c => ({
    name: JSON.parse(c.querySelector('input').id).name,
    field: box(c.querySelector('.field')), label: box(c.querySelector('b')),
    texts: leaves(c).map(box)}));
const run = ['pin', 'unpin', 't-end', 'method', 'reset'].map(id => [id, box(document.getElementById(id))]);
const legend = [...document.querySelectorAll('#pulse .legend')].map(box);
const panels = [...document.querySelectorAll('#pulse .nsewdrag')].map(box);
return {inner: window.innerWidth, height: window.innerHeight,
        scroll: document.documentElement.scrollWidth, client: document.documentElement.clientWidth,
        side: s, clip: clip, plot: box(document.getElementById('pulse')), panels: panels,
        summary: box(document.getElementById('summary')), tabs: box(document.getElementById('study-tab')),
        controls: controls, run: run, legend: legend,
        legendTexts: [...document.querySelectorAll('#pulse .legendtext')].map(e => e.textContent)};
"""


@pytest.mark.parametrize("width", [1280, 1920])
def test_the_page_at_common_screen_widths(server, browser, width, tmp_path):
    """At 1280 and 1920 px: no horizontal scroll bar; the parameters and the
    plot side by side, both in view; nothing cut off (the sidebar's texts,
    fields, the run's controls, the summary); the rig's key settings first;
    the legend in descriptions and units, clear of the panels."""
    browser.set_window_size(width, 1000)
    try:
        load(browser, server)
        wait(browser, "#pulse .legendtext")
        time.sleep(0.5)                       # the legend laid out
        g = browser.execute_script(LAYOUT)
        shots = os.environ.get("PDBFS_APP_LAYOUT_SHOTS")      # e.g. /tmp/app- (+ width.png)
        browser.save_screenshot(f"{shots}{width}.png" if shots else str(tmp_path / "page.png"))
    finally:
        browser.set_window_size(1400, 1000)
    assert g["inner"] == width
    assert g["scroll"] <= g["client"], "a horizontal scroll bar"
    side, plot = g["side"], g["plot"]
    assert side["right"] <= plot["left"] and side["top"] < g["height"] and plot["top"] < g["height"]
    assert side["right"] - side["left"] >= 300 and plot["right"] <= g["client"]
    assert min(p["right"] - p["left"] for p in g["panels"]) >= (420 if width == 1280 else 900)
    assert g["summary"]["right"] <= g["client"] and g["summary"]["left"] >= plot["right"] - 1
    assert g["tabs"]["bottom"] <= g["height"], "the study tabs are below the fold"
    for c in g["controls"]:
        assert c["label"]["right"] <= c["field"]["left"], c["name"]
        for r in [c["field"], *c["texts"]]:
            assert g["clip"]["left"] - 0.5 <= r["left"] and r["right"] <= g["clip"]["right"] + 0.5, c
    run = dict(g["run"])
    for key, r in run.items():
        assert 0 <= r["left"] and r["right"] <= g["client"], key
    assert run["reset"]["right"] <= side["right"]         # with the parameters, not the run
    # the key settings first, in view; the start positions last
    names = [c["name"] for c in g["controls"]]
    assert names[:4] == ["hammer.v0", "hammer.h", "oil.k", "seal.c"]
    assert all(c["field"]["bottom"] <= g["height"] for c in g["controls"][:4])
    assert set(names[-5:]) <= {"frame.s0", "hammer.s0", "piston.s0", "piston.v0", "breech.s0",
                               "breech.v0", "mount.s_rel0"}
    # the legend: descriptions and units, above the first panel
    assert g["legendTexts"] == ["oil pressure [MPa]", "contact compressive force [kN]",
                                "hammer position [mm]", "piston position [mm]",
                                "breech position [mm]"]
    top = min(p["top"] for p in g["panels"])
    assert all(r["bottom"] <= top + 1 for r in g["legend"]), (g["legend"], top)


def test_reset_sets_the_parameters_back_and_keeps_the_run_settings(server, browser):
    """Reset parameters: every parameter back to the rig's default; the run
    length and the method are the run's and stay (the button sits with the
    parameters, and says which it resets)."""
    load(browser, server)
    button = browser.find_element(By.ID, "reset")
    assert button.text == "Reset parameters" and "t_end" in button.get_attribute("title")
    f = browser.find_element(By.ID, "t-end")
    f.send_keys(Keys.CONTROL, "a")
    f.send_keys("15" + Keys.ENTER)
    wait(browser, "#status", lambda e: "to 15 ms" in e.text)
    browser.find_element(By.ID, "method").click()
    wait(browser, "[role=option]", lambda e: e.text == "bdf").click()
    wait(browser, "#status", lambda e: "method bdf" in e.text)
    _, text = shown_peak(browser)
    type_into(browser, "oil.k", "5e8")
    _, text = shown_peak(browser, text)
    type_into(browser, "hammer.h", "0.6")
    _, text = shown_peak(browser, text)
    browser.find_element(By.ID, "reset").click()
    back, _ = shown_peak(browser, text)
    field = lambda name: browser.find_element(By.CSS_SELECTOR, pid("field", name)).get_attribute(
        "value")
    assert (field("oil.k"), field("hammer.v0"), field("hammer.h")) == ("2.228e8", "2.73", "0.38")
    assert browser.find_element(By.ID, "t-end").get_attribute("value") == "15"
    assert "method bdf" in status(browser) and "to 15 ms" in status(browser)
    api = paper_rig().simulate(0.015, backend="c", method="bdf").summary()
    assert back == pytest.approx(api["peak_pressure"], rel=1e-9)
