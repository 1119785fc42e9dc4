"""SUNDIALS' sources come the way pip finds packages: through the index pip
is configured with (PIP_INDEX_URL, pip.conf; PEP 503 HTML or PEP 691 JSON),
checked against the pinned SHA-256, in a fresh cache, with the default
address unreachable; a server that never answers is given up within about
20 s in one line; the explicit method and the CasADi backend need no CVODE
at all."""
import hashlib
import http.server
import json
import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

import pdbfs
from pdbfs.native import pipindex
from pdbfs.native import sundials as S
from pdbfs.native.toolchain import zig_env

#: an address nothing listens on: the default index (and any proxy) unreachable
DEAD = "http://127.0.0.1:9"


@pytest.fixture(scope="module")
def sdist() -> bytes:
    """The pinned sdist, from this machine's pdbfs cache (fetched into it once)."""
    kept = S.sdist_path()
    if not kept.is_file():
        try:
            data, _ = pipindex.fetch(S.PROJECT, S.SDIST, S.SDIST_SHA256, deadline=60)
        except pipindex.FetchError as err:
            pytest.skip(f"the sdist is not at hand here ({err})")
        kept.parent.mkdir(parents=True, exist_ok=True)
        kept.write_bytes(data)
    data = kept.read_bytes()
    assert hashlib.sha256(data).hexdigest() == S.SDIST_SHA256
    return data


@pytest.fixture
def offline(tmp_path, monkeypatch):
    """A fresh cache and no pip configuration but what the test sets; the
    default index and any proxy unreachable, 127.0.0.1 reached directly."""
    env = {"XDG_CACHE_HOME": str(tmp_path / "cache"), "PIP_CONFIG_FILE": os.devnull,
           "https_proxy": DEAD, "http_proxy": DEAD, "HTTPS_PROXY": DEAD, "HTTP_PROXY": DEAD,
           "no_proxy": "127.0.0.1,localhost", "NO_PROXY": "127.0.0.1,localhost",
           # zig's own cache (its C libraries per target) kept where it was: only pdbfs's is fresh
           "ZIG_GLOBAL_CACHE_DIR": zig_env()["ZIG_GLOBAL_CACHE_DIR"]}
    for k in ("PIP_INDEX_URL", "PIP_EXTRA_INDEX_URL", "PIP_FIND_LINKS", "PIP_NO_INDEX",
              "PDBFS_SUNDIALS_SDIST"):
        monkeypatch.delenv(k, raising=False)
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    return env


class Index:
    """A package index on 127.0.0.1 serving the sdist: PEP 503 HTML, and PEP
    691 JSON to clients that ask for it (``json``)."""

    def __init__(self, data: bytes, json_api: bool):
        self.requests: list[tuple[str, str]] = []
        outer = self

        class Handler(http.server.BaseHTTPRequestHandler):
            def log_message(self, *args):
                pass

            def do_GET(self):
                accept = self.headers.get("Accept", "")
                outer.requests.append((self.path, accept))
                if self.path == f"/simple/{S.PROJECT}/":
                    if json_api and "application/vnd.pypi.simple.v1+json" in accept:
                        body = json.dumps({"meta": {"api-version": "1.0"}, "name": S.PROJECT,
                                           "files": [{"filename": S.SDIST,
                                                      "url": f"../../files/{S.SDIST}",
                                                      "hashes": {"sha256": S.SDIST_SHA256}}]})
                        self.reply(body.encode(), "application/vnd.pypi.simple.v1+json")
                    else:
                        body = (f'<html><body><a href="../../files/{S.SDIST}#sha256='
                                f'{S.SDIST_SHA256}">{S.SDIST}</a></body></html>')
                        self.reply(body.encode(), "text/html")
                elif self.path == f"/files/{S.SDIST}":
                    self.reply(data, "application/gzip")
                else:
                    self.send_error(404)

            def reply(self, body, ctype):
                self.send_response(200)
                self.send_header("Content-Type", ctype)
                self.send_header("Content-Length", str(len(body)))
                self.end_headers()
                self.wfile.write(body)

        self.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Handler)
        self.url = f"http://127.0.0.1:{self.server.server_port}/simple"
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def close(self):
        self.server.shutdown()
        self.server.server_close()


class Silent:
    """A server on 127.0.0.1 that takes connections and never says a word."""

    def __init__(self):
        self.sock = socket.socket()
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(16)
        self.url = f"http://127.0.0.1:{self.sock.getsockname()[1]}/simple"
        self.held, self.stop = [], threading.Event()
        self.thread = threading.Thread(target=self.hold, daemon=True)
        self.thread.start()

    def hold(self):
        self.sock.settimeout(0.2)
        while not self.stop.is_set():
            try:
                self.held.append(self.sock.accept()[0])
            except OSError:
                pass

    def close(self):
        self.stop.set()
        self.thread.join(2)
        for c in self.held:
            c.close()
        self.sock.close()


@pytest.mark.parametrize("api", ["html", "json"])
def test_sources_from_a_local_index_with_the_default_unreachable(api, sdist, offline,
                                                                 monkeypatch):
    index = Index(sdist, json_api=api == "json")
    try:
        monkeypatch.setenv("PIP_INDEX_URL", index.url)
        assert pipindex.pip_settings().indexes == [index.url]
        src = S.find_sundials_sources()
    finally:
        index.close()
    assert str(src.root).startswith(offline["XDG_CACHE_HOME"])
    assert (src.src / "cvodes" / "cvodes.c").is_file() and src.license.is_file()
    assert S.SDIST_SHA256 in (src.root / "ORIGIN").read_text()
    assert S.sdist_path().read_bytes() == sdist            # kept, to carry offline
    page = [a for p, a in index.requests if p.endswith(f"/{S.PROJECT}/")]
    assert page and "application/vnd.pypi.simple.v1+json" in page[0]
    assert (f"/files/{S.SDIST}", "") in [(p, "") for p, _ in index.requests]


def test_a_file_with_another_hash_is_refused(sdist, offline, monkeypatch):
    index = Index(sdist[:-1] + bytes([sdist[-1] ^ 1]), json_api=False)
    try:
        monkeypatch.setenv("PIP_INDEX_URL", index.url)
        with pytest.raises(S.SundialsNotFound) as err:
            S.find_sundials_sources()
    finally:
        index.close()
    assert "SHA-256" in str(err.value) and "\n" not in str(err.value)
    assert not S.sdist_path().exists()


def test_an_extra_index_and_find_links_are_searched(sdist, offline, monkeypatch, tmp_path):
    folder = tmp_path / "wheels"
    folder.mkdir()
    (folder / S.SDIST).write_bytes(sdist)
    monkeypatch.setenv("PIP_INDEX_URL", DEAD + "/simple")
    monkeypatch.setenv("PIP_FIND_LINKS", str(folder))
    data, origin = pipindex.fetch(S.PROJECT, S.SDIST, S.SDIST_SHA256, deadline=10)
    assert data == sdist and origin == str(folder / S.SDIST)
    monkeypatch.setenv("PIP_FIND_LINKS", folder.as_uri())          # as a file:// address
    assert pipindex.fetch(S.PROJECT, S.SDIST, S.SDIST_SHA256, deadline=10)[0] == sdist
    monkeypatch.delenv("PIP_FIND_LINKS")
    index = Index(sdist, json_api=True)
    try:
        monkeypatch.setenv("PIP_EXTRA_INDEX_URL", index.url)
        data, origin = pipindex.fetch(S.PROJECT, S.SDIST, S.SDIST_SHA256, deadline=10)
    finally:
        index.close()
    assert data == sdist and origin.startswith(index.url.rsplit("/", 1)[0])


def test_pip_configuration_files_and_variables_in_pips_order(tmp_path, monkeypatch):
    site = tmp_path / "site.conf"
    site.write_text("[global]\nindex-url = https://a.example/simple\n"
                    "extra-index-url = https://b.example/simple\n  https://c.example/simple\n"
                    "cert = /etc/ca.pem\n")
    user = tmp_path / "user.conf"
    user.write_text("[install]\nindex-url = https://d.example/simple\n")
    monkeypatch.setattr(pipindex, "config_files", lambda: [site, user])
    s = pipindex.pip_settings(environ={})
    assert s.index_url == "https://d.example/simple"          # [install] over [global], later file
    assert s.extra_index_urls == ["https://b.example/simple", "https://c.example/simple"]
    assert s.cert == "/etc/ca.pem"
    s = pipindex.pip_settings(environ={"PIP_INDEX_URL": "https://e.example/simple",
                                       "PIP_NO_INDEX": "1"})
    assert s.index_url == "https://e.example/simple" and s.indexes == []
    # the files pip reads: PIP_CONFIG_FILE last (it wins), os.devnull: none at all
    monkeypatch.undo()
    monkeypatch.setenv("PIP_CONFIG_FILE", str(user))
    files = pipindex.config_files()
    assert files[-1] == user and Path(sys.prefix) / "pip.conf" in files
    monkeypatch.setenv("PIP_CONFIG_FILE", os.devnull)
    assert pipindex.config_files() == []


def test_a_silent_server_is_given_up_in_time(offline, monkeypatch):
    silent = Silent()
    try:
        monkeypatch.setenv("PIP_INDEX_URL", silent.url)
        t0 = time.monotonic()
        with pytest.raises(pipindex.FetchError) as err:
            pipindex.fetch(S.PROJECT, S.SDIST, S.SDIST_SHA256, deadline=3.0)
        took = time.monotonic() - t0
    finally:
        silent.close()
    assert 2.5 < took < 5.0, took
    assert "\n" not in str(err.value) and "127.0.0.1" in str(err.value)


def cli(args, env, cwd, timeout=300):
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                       text=True, cwd=cwd, env={**os.environ, **env}, timeout=timeout)
    return r, time.monotonic() - t0


def test_simulate_gives_up_on_a_silent_index_within_20_s_in_one_line(offline, tmp_path):
    """CVODE's methods need the sources: a proxy or index that never answers
    held `pdbfs simulate` for 124 s."""
    silent = Silent()
    try:
        env = {**offline, "PIP_INDEX_URL": silent.url}
        r, took = cli(["simulate", "--method", "bdf", "--backend", "c", "--t-end", "0.005"],
                      env, tmp_path)
    finally:
        silent.close()
    assert r.returncode == 2, r.stderr
    errors = [line for line in r.stderr.splitlines() if line.startswith("pdbfs: error")]
    assert len(errors) == 1 and "Traceback" not in r.stderr, r.stderr
    assert "20 s" in errors[0] and "prepare-offline" in errors[0], errors[0]
    assert took < pipindex.DEADLINE + 15, took


def test_a_silent_index_is_waited_for_once_then_auto_falls_back_at_once(offline, tmp_path,
                                                                         monkeypatch):
    """Behind a black-hole index the first CVODE command waits the deadline
    out; the next one with backend "auto" falls back to CasADi at once,
    without asking the index, in one short line saying why and what fixes
    it; an explicit backend "c" and prepare-offline ask the index again."""
    silent = Silent()
    try:
        env = {**offline, "PIP_INDEX_URL": silent.url}
        monkeypatch.setenv("PIP_INDEX_URL", silent.url)
        args = ["simulate", "--method", "bdf", "--json"]
        first, took1 = cli(args, env, tmp_path)
        time.sleep(0.5)                           # the last connection accepted, if any
        asked = len(silent.held)
        second, took2 = cli(args, env, tmp_path)
        time.sleep(0.5)
        assert len(silent.held) == asked >= 1, "the index was asked again"
        # no fallback where the user asked for the compiled backend: it tries again
        monkeypatch.setattr(pipindex, "DEADLINE", 1.0)
        from pdbfs.models import paper_rig
        with pytest.raises(pdbfs.PdbfsError, match="CVODE"):
            paper_rig().simulate(0.005, method="bdf", backend="c")
        time.sleep(0.5)
        assert len(silent.held) > asked
        asked = len(silent.held)
        from pdbfs.cli import main
        assert main(["prepare-offline", "--platforms", "x86_64-linux", "--out", "carry"]) == 2
        time.sleep(0.5)
        assert len(silent.held) > asked
    finally:
        silent.close()
    for r in (first, second):
        assert r.returncode == 0, r.stderr
        assert json.loads(r.stdout)["stats"]["backend"] == "casadi"
        warned = [line for line in r.stderr.splitlines() if line.startswith("pdbfs: warning")]
        assert len(warned) == 1 and len(warned[0]) < 160, warned
        assert "CasADi" in warned[0] and "pdbfs prepare-offline" in warned[0], warned[0]
    assert "unreachable" in first.stderr and " ago" in second.stderr, second.stderr
    assert "fetching" in first.stderr and "fetching" not in second.stderr
    assert took1 >= pipindex.DEADLINE and took2 < took1 / 2, (took1, took2)


def test_a_remembered_failure_lasts_ten_minutes_for_the_same_index_settings(offline,
                                                                             monkeypatch,
                                                                             capsys):
    monkeypatch.setenv("PIP_INDEX_URL", DEAD + "/simple")

    def attempt() -> tuple[str, bool]:
        """(the error, whether the index was asked) of a fetch with a fallback at hand"""
        with S.remembered_failures(), pytest.raises(S.SundialsNotFound) as err:
            S.find_sundials_sources()
        return str(err.value), "fetching" in capsys.readouterr().err
    assert attempt()[1]
    message, asked = attempt()
    assert not asked and " ago" in message and "prepare-offline" in message, message
    monkeypatch.setenv("https_proxy", DEAD + "1")            # other settings: asked again
    assert attempt()[1]
    assert not attempt()[1]
    memo = S._memo_path()
    kept = json.loads(memo.read_text())
    memo.write_text(json.dumps({**kept, "at": kept["at"] - S.REMEMBER - 1}))
    assert attempt()[1]                                      # ten minutes on: asked again
    assert S.REMEMBER == 600


def test_a_fetch_that_succeeds_forgets_the_failure(sdist, offline, monkeypatch):
    monkeypatch.setenv("PIP_INDEX_URL", DEAD + "/simple")
    with S.remembered_failures(), pytest.raises(S.SundialsNotFound):
        S.find_sundials_sources()
    assert S._memo_path().is_file()
    index = Index(sdist, json_api=False)
    try:
        monkeypatch.setenv("PIP_INDEX_URL", index.url)
        S.find_sundials_sources()                 # outside the block: asks, finds, forgets
    finally:
        index.close()
    assert not S._memo_path().exists()


def test_the_explicit_method_and_casadi_need_no_cvode(offline, tmp_path):
    """A fresh cache, no index reachable: the default run (the explicit method
    on the compiled backend) builds its library without SUNDIALS and gives the
    summary of the library with CVODE; the CasADi backend runs too; neither
    fetches anything."""
    env = {**offline, "PIP_INDEX_URL": DEAD + "/simple"}
    ref, _ = cli(["simulate", "--method", "erk", "--json"], {}, tmp_path)  # this machine's cache
    assert ref.returncode == 0, ref.stderr
    r, _ = cli(["simulate", "--method", "erk", "--backend", "c", "--json"], env, tmp_path)
    assert r.returncode == 0, r.stderr
    assert "fetching" not in r.stderr and "warning" not in r.stderr, r.stderr
    got, want = json.loads(r.stdout), json.loads(ref.stdout)
    assert got["stats"]["backend"] == "c" and got["stats"]["method"].startswith("erk")
    for key in ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force"):
        assert got[key] == pytest.approx(want[key], rel=1e-12, abs=0), key
    r, _ = cli(["simulate", "--backend", "casadi", "--json"], env, tmp_path)
    assert r.returncode == 0 and "fetching" not in r.stderr, r.stderr
    assert json.loads(r.stdout)["peak_pressure"] == pytest.approx(want["peak_pressure"], rel=1e-5)
    cache = Path(offline["XDG_CACHE_HOME"]) / "pdbfs"
    assert not (cache / f"sundials-{S.VERSION}").exists()
    assert not (cache / f"cvode-{S.VERSION}").exists()
    assert list(tmp_path.glob("*")) == [Path(offline["XDG_CACHE_HOME"])]  # --out not given


def test_prepare_offline_then_carry_the_cache_to_a_machine_without_network(sdist, offline,
                                                                          tmp_path):
    """`pdbfs prepare-offline` fetches the sources through pip's index and
    compiles CVODE, saying each step with its share; the cache it names,
    copied to a machine whose index is unreachable, runs CVODE's methods."""
    import shutil
    index = Index(sdist, json_api=False)
    try:
        env = {**offline, "PIP_INDEX_URL": index.url}
        r, _ = cli(["prepare-offline", "--platforms", "x86_64-linux", "--out", "carry"], env,
                   tmp_path, timeout=600)
    finally:
        index.close()
    assert r.returncode == 0, r.stderr
    steps = [line for line in r.stderr.splitlines() if line.startswith("pdbfs: [")]
    assert steps[0].startswith("pdbfs: [1/2]") and any("[2/2] CVODE for x86_64-linux" in s
                                                      for s in steps), r.stderr
    n = len(S.SUNDIALS_C)
    assert any(f"[{n}/{n}] compiled" in s and "x86_64-linux" in s for s in steps), r.stderr
    cache = Path(offline["XDG_CACHE_HOME"]) / "pdbfs"
    assert str(cache) in r.stdout and "PDBFS_SUNDIALS_SDIST" in r.stdout
    assert (tmp_path / "carry" / S.SDIST).read_bytes() == sdist
    # the air-gapped machine: the cache copied there, no index reachable
    there = tmp_path / "there"
    shutil.copytree(cache, there / "pdbfs")
    env = {**offline, "XDG_CACHE_HOME": str(there), "PIP_INDEX_URL": DEAD + "/simple"}
    r, _ = cli(["simulate", "--method", "bdf", "--backend", "c", "--t-end", "0.012", "--json"],
               env, tmp_path)
    assert r.returncode == 0 and "fetching" not in r.stderr, r.stderr
    assert json.loads(r.stdout)["stats"]["method"].startswith("bdf")


def test_auto_falls_back_to_casadi_for_cvode_methods_without_the_sources(offline, tmp_path):
    """backend "auto" means the compiled backend where it can be had, else
    CasADi: a CVODE method whose sources are out of reach runs on CasADi,
    with one warning line; backend "c" asked for says so and stops."""
    env = {**offline, "PIP_INDEX_URL": DEAD + "/simple"}
    r, took = cli(["simulate", "--method", "bdf", "--json"], env, tmp_path)
    assert r.returncode == 0, r.stderr
    warned = [line for line in r.stderr.splitlines() if line.startswith("pdbfs: warning")]
    assert len(warned) == 1 and "simulating with CasADi" in warned[0], r.stderr
    assert len(warned[0]) < 160 and "pdbfs prepare-offline" in warned[0], warned[0]
    got = json.loads(r.stdout)
    assert got["stats"]["backend"] == "casadi" and got["stats"]["method"].startswith("bdf")
    ref, _ = cli(["simulate", "--method", "bdf", "--backend", "casadi", "--json"], {}, tmp_path)
    assert got["peak_pressure"] == json.loads(ref.stdout)["peak_pressure"]
