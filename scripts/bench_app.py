"""Benchmark: from moving the drop-height slider of `pdbfs app` to the new
curve, for the paper rig, against a bare compiled simulation in the same
process (the baseline). Target: 100 ms.

    python scripts/bench_app.py [--repeat N] [--no-browser]

1. server side: the one request a slider step makes (the settings edited, the
   rig run, the figure and summary returned), through Dash's own request
   handling (Flask's test client), JSON in and out;
2. browser round trip (headless Chromium, if installed): a key press on the
   slider until the page shows the new peak, Plotly's redraw included.
Prints medians and ratios against `rig.simulate(backend="c")`.
"""
import argparse
import json
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import timeit

import orjson

from pdbfs.app import create_app
from pdbfs.app.workbench import workbench
from pdbfs.models import paper_rig


def median_ms(fn, repeat):
    fn()                                   # warm up, untimed
    return 1e3 * statistics.median(timeit.repeat(fn, number=1, repeat=repeat))


def output_key(app, fragment):
    return next(k for k in app.callback_map if fragment in k)


def server_side(repeat):
    """Both requests of a slider move, handled by the Dash app in this process."""
    app = create_app("paper")
    client = app.server.test_client()
    client.get("/")
    wb = workbench("paper")
    names = [c.name for c in wb.controls]
    k = names.index("hammer.h")
    settings = {"rig": "paper", "values": wb.defaults(), "t_end": wb.t_end, "method": "auto",
                "parts": False}
    edit_key = output_key(app, '"type":"slider"}.value')
    outputs = edit_key.strip(".").split("...")[7:]     # figure, summary, status

    def wild(kind, prop, values=None):
        return [{"id": {"name": n, "type": kind}, "property": prop,
                 **({"value": values[i]} if values is not None else {})} for i, n in enumerate(names)]

    state = {"s": settings, "h": 0.40}

    def move():
        # a new height each time: the page keeps its last runs, a repeated one is not timed
        h = state["h"] = round(state["h"] + 0.01, 6) if state["h"] < 0.99 else 0.101
        sliders = [c.to_slider(state["s"]["values"][c.name]) for c in wb.controls]
        sliders[k] = h
        body = {"output": edit_key,
                "outputs": [wild("slider", p) for p in ("value", "min", "max", "marks")]
                + [wild("field", "value"), wild("msg", "children"),
                   {"id": "settings", "property": "data"}]
                + [{"id": o.rpartition(".")[0], "property": o.rpartition(".")[2]} for o in outputs],
                "inputs": [wild("slider", "value", sliders),
                           wild("field", "value", [str(v) for v in state["s"]["values"].values()]),
                           {"id": "reset", "property": "n_clicks", "value": 0},
                           {"id": "cal-apply", "property": "n_clicks", "value": 0},
                           {"id": "des-apply", "property": "n_clicks", "value": 0}],
                "changedPropIds": [json.dumps({"name": "hammer.h", "type": "slider"},
                                              separators=(",", ":")) + ".value"],
                "state": [{"id": "settings", "property": "data", "value": state["s"]},
                          {"id": "cal", "property": "data", "value": None},
                          {"id": "des", "property": "data", "value": None},
                          wild("msg", "children", [None] * len(names)),
                          {"id": "pins", "property": "data", "value": []},
                          {"id": "trace", "property": "data", "value": None}]}
        r = client.post("/_dash-update-component", json=body)
        assert r.status_code == 200, r.data[:300]
        resp = orjson.loads(r.data)["response"]     # the client's decoding, not the server's work
        assert "pulse" in resp and "summary" in resp, list(resp)
        state["s"] = resp["settings"]["data"]
    return median_ms(move, repeat)


def browser_round_trip(repeat):
    """Key press on the drop-height slider -> the new peak on the page."""
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
        from selenium.webdriver.common.by import By
    except ImportError:
        return None
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--port", str(port)],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    proc.stdout.readline()
    opts = webdriver.ChromeOptions()
    opts.binary_location = "/usr/bin/chromium"
    for a in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
              "--disable-background-networking", "--disable-component-update", "--disable-sync",
              f"--user-data-dir={tempfile.mkdtemp(prefix='pdbfs-bench-')}"):
        opts.add_argument(a)
    d = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)
    try:
        time.sleep(1.0)
        d.get(f"http://127.0.0.1:{port}/")
        t0 = time.time()
        while time.time() - t0 < 30 and not (d.find_elements(By.ID, "sum-peak_pressure") and
                                             d.find_elements(By.CSS_SELECTOR, "#pulse .main-svg")):
            time.sleep(0.05)
        time.sleep(1.0)
        # timed in the page: a key press on the slider until the summary shows a new peak
        script = """
            const done = arguments[arguments.length - 1];
            const key = arguments[0];
            const thumb = document.querySelector(
                "[id='{\\"name\\":\\"hammer.h\\",\\"type\\":\\"slider\\"}'] [role=slider]");
            const old = document.getElementById("sum-peak_pressure").textContent;
            const plot = document.querySelector("#pulse .js-plotly-plot");
            const t0 = performance.now();
            let shown = null, drawn = null;
            const finish = () => { if (shown !== null && drawn !== null) done([shown, drawn]); };
            const obs = new MutationObserver(() => {
                const e = document.getElementById("sum-peak_pressure");
                if (e && e.textContent !== old && shown === null) {
                    obs.disconnect(); shown = performance.now() - t0; finish(); }
            });
            const drew = () => { plot.removeListener("plotly_afterplot", drew);
                                 drawn = performance.now() - t0; finish(); };
            plot.on("plotly_afterplot", drew);
            obs.observe(document.getElementById("summary"),
                        {childList: true, subtree: true, characterData: true});
            thumb.focus();
            thumb.dispatchEvent(new KeyboardEvent("keydown", {key: key, bubbles: true}));
        """
        d.set_script_timeout(30)
        # always to the right: a new height each step (a height seen before is not run again)
        times = [d.execute_async_script(script, "ArrowRight") for i in range(min(repeat, 50) + 1)]
        return tuple(statistics.median(t[j] for t in times[1:]) for j in (0, 1))
    finally:
        d.quit()
        proc.terminate()
        proc.wait(10)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=30)
    ap.add_argument("--no-browser", action="store_true")
    args = ap.parse_args()
    rig = paper_rig()
    base = median_ms(lambda: rig.simulate(0.02, params={"hammer.v0": 3.0}, backend="c"), args.repeat)
    print(f"baseline: rig.simulate(backend='c'), paper rig, 2001 points: {base:.2f} ms")
    both = server_side(args.repeat)
    print(f"server side, one slider step (request in, figure and summary out): {both:7.2f} ms"
          f"  ({both / base:5.1f} x baseline)  target 100 ms: {'met' if both < 100 else 'MISSED'}")
    if not args.no_browser:
        rt = browser_round_trip(args.repeat)
        if rt is None:
            print("browser round trip: selenium not installed")
        else:
            for label, v in zip(("the new peak shown", "the new curve drawn"), rt):
                print(f"browser round trip, key press to {label}: {v:7.2f} ms"
                      f"  ({v / base:5.1f} x baseline)  target 100 ms: {'met' if v < 100 else 'MISSED'}")


if __name__ == "__main__":
    main()
