"""One pinned file fetched the way pip finds packages (used by sundials.py).

Where pip looks: ``--index-url`` (default https://pypi.org/simple),
``--extra-index-url``, ``--find-links`` and ``--no-index``, with ``cert`` and
``proxy``, read from pip's configuration files (site-wide, the user's, the
environment's, ``$PIP_CONFIG_FILE``; sections ``[global]``, then
``[download]`` and ``[install]``) and its ``PIP_*`` environment variables, in
pip's order of precedence. An index is read through the simple repository
API: PEP 691's JSON where the server offers it, else PEP 503's HTML; a
find-links entry is a folder or a page of links. Credentials in an index's
address (``https://user:token@host/simple``) or in ``~/.netrc`` are sent as
HTTP basic authentication; ``https_proxy`` and ``no_proxy`` are honoured.

The file is accepted only with its pinned SHA-256. Everything (every index,
the download) happens within :data:`DEADLINE` seconds, in a worker thread
the caller stops waiting for, so that neither a proxy that never answers nor
a name lookup that hangs holds a simulation for minutes.
"""
from __future__ import annotations

import configparser
import hashlib
import json
import os
import sys
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from dataclasses import dataclass, field
from html.parser import HTMLParser
from pathlib import Path

#: seconds the whole search and download may take
DEADLINE = 20.0
DEFAULT_INDEX = "https://pypi.org/simple"
ACCEPT = ("application/vnd.pypi.simple.v1+json, application/vnd.pypi.simple.v1+html;q=0.2, "
          "text/html;q=0.1")


class FetchError(RuntimeError):
    """The file could not be had from any place pip is configured with; the
    message (one line) names the places and why. ``unreachable``: some place
    could not be asked (else each answered without the file, or with another hash)."""

    def __init__(self, message: str, unreachable: bool = True):
        super().__init__(message)
        self.unreachable = unreachable


@dataclass
class PipSettings:
    """Where pip looks for packages, as its configuration says."""
    index_url: str = DEFAULT_INDEX
    extra_index_urls: list[str] = field(default_factory=list)
    find_links: list[str] = field(default_factory=list)
    no_index: bool = False
    cert: str | None = None
    proxy: str | None = None

    @property
    def indexes(self) -> list[str]:
        """The index URLs to ask, in order (none with ``--no-index``)."""
        return [] if self.no_index else [self.index_url, *self.extra_index_urls]

    def key(self, environ=None) -> str:
        """A digest of everything that decides where a fetch goes: these
        settings and the proxy variables urllib reads (``https_proxy``,
        ``no_proxy``, ...); equal keys, the same places asked the same way."""
        environ = os.environ if environ is None else environ
        proxies = sorted((k.lower(), v) for k, v in environ.items()
                         if k.lower() in ("http_proxy", "https_proxy", "all_proxy", "no_proxy"))
        text = json.dumps([self.index_url, self.extra_index_urls, self.find_links, self.no_index,
                           self.cert, self.proxy, proxies])
        return hashlib.sha256(text.encode()).hexdigest()


def config_files() -> list[Path]:
    """pip's configuration files, lowest precedence first (pip's order: site-wide,
    the user's, the environment's, then $PIP_CONFIG_FILE)."""
    env_file = os.environ.get("PIP_CONFIG_FILE")
    if env_file == os.devnull:           # pip: load no file at all
        return []
    home = Path.home()
    ini = "pip.ini" if sys.platform == "win32" else "pip.conf"
    if sys.platform == "win32":
        site_wide = [Path(os.environ.get("PROGRAMDATA", r"C:\ProgramData")) / "pip" / ini]
        user = [home / "pip" / ini,
                Path(os.environ.get("APPDATA", home / "AppData" / "Roaming")) / "pip" / ini]
    elif sys.platform == "darwin":
        site_wide = [Path("/Library/Application Support/pip") / ini]
        user = [home / ".pip" / ini, home / "Library" / "Application Support" / "pip" / ini,
                home / ".config" / "pip" / ini]
    else:
        dirs = os.environ.get("XDG_CONFIG_DIRS") or "/etc/xdg"
        site_wide = [Path(d) / "pip" / ini for d in reversed(dirs.split(os.pathsep)) if d]
        site_wide.append(Path("/etc") / ini)
        config_home = os.environ.get("XDG_CONFIG_HOME") or str(home / ".config")
        user = [home / ".pip" / ini, Path(config_home) / "pip" / ini]
    files = [*site_wide, *user, Path(sys.prefix) / ini]
    if env_file:
        files.append(Path(env_file))
    return files


def _truth(text: str) -> bool:
    return text.strip().lower() in ("1", "yes", "true", "on")


def pip_settings(environ=None) -> PipSettings:
    """The index, extra indexes, find-links, cert and proxy pip would use."""
    environ = os.environ if environ is None else environ
    values: dict[str, str] = {}
    for path in config_files():
        parser = configparser.RawConfigParser()
        try:
            parser.read(path, encoding="utf-8")
        except (OSError, configparser.Error, UnicodeDecodeError):
            continue                     # pip would stop on a broken file; we only look
        for section in ("global", "download", "install"):
            if parser.has_section(section):
                values.update({k.lower().replace("_", "-"): v
                               for k, v in parser.items(section)})
    for key in ("index-url", "extra-index-url", "find-links", "no-index", "cert", "proxy"):
        env = environ.get("PIP_" + key.upper().replace("-", "_"))
        if env is not None:
            values[key] = env
    return PipSettings(index_url=values.get("index-url", "").strip() or DEFAULT_INDEX,
                       extra_index_urls=values.get("extra-index-url", "").split(),
                       find_links=values.get("find-links", "").split(),
                       no_index=_truth(values.get("no-index", "")),
                       cert=values.get("cert", "").strip() or None,
                       proxy=values.get("proxy", "").strip() or None)


# -- reading an index -----------------------------------------------------------------------
class _Links(HTMLParser):
    """The anchors of a PEP 503 page: (href, text)."""

    def __init__(self):
        super().__init__()
        self.links: list[tuple[str, str]] = []
        self._href: str | None = None
        self._text: list[str] = []

    def handle_starttag(self, tag, attrs):
        if tag == "a":
            self._href, self._text = dict(attrs).get("href"), []

    def handle_data(self, data):
        if self._href is not None:
            self._text.append(data)

    def handle_endtag(self, tag):
        if tag == "a" and self._href is not None:
            self.links.append((self._href, "".join(self._text).strip()))
            self._href = None


def files_of_page(body: bytes, content_type: str, base: str) -> dict[str, tuple[str, str | None]]:
    """{file name: (absolute URL, sha256 or None)} of a simple-API project page
    (PEP 691 JSON or PEP 503 HTML) or a find-links page."""
    out: dict[str, tuple[str, str | None]] = {}
    if "json" in content_type:
        doc = json.loads(body.decode("utf-8"))
        for f in doc.get("files", []):
            url = urllib.parse.urljoin(base, f["url"])
            out[f["filename"]] = (url, (f.get("hashes") or {}).get("sha256"))
        return out
    parser = _Links()
    parser.feed(body.decode("utf-8", errors="replace"))
    for href, text in parser.links:
        url, _, fragment = urllib.parse.urljoin(base, href).partition("#")
        name = urllib.parse.unquote(urllib.parse.urlsplit(url).path.rsplit("/", 1)[-1]) or text
        digest = fragment[len("sha256="):] if fragment.startswith("sha256=") else None
        out.setdefault(name, (url, digest))
    return out


class _Client:
    """GET with pip's cert, proxy and credentials, never past the deadline."""

    def __init__(self, settings: PipSettings, deadline: float):
        import ssl
        self.deadline = deadline
        handlers: list = []
        if settings.proxy:
            handlers.append(urllib.request.ProxyHandler({"http": settings.proxy,
                                                         "https": settings.proxy}))
        context = ssl.create_default_context(cafile=settings.cert) if settings.cert else None
        handlers.append(urllib.request.HTTPSHandler(context=context))
        self.opener = urllib.request.build_opener(*handlers)

    def left(self) -> float:
        return self.deadline - time.monotonic()

    def get(self, url: str, accept: str | None = None) -> tuple[bytes, str, str]:
        """(body, content type, final URL); file:// folders read their index.html."""
        if url.startswith("file:"):
            path = Path(urllib.request.url2pathname(urllib.parse.urlsplit(url).path))
            if path.is_dir():
                path = path / "index.html"
            return path.read_bytes(), "text/html", path.resolve().as_uri()
        parts = urllib.parse.urlsplit(url)
        headers = {"User-Agent": "pdbfs (urllib)"}
        if accept:
            headers["Accept"] = accept
        user, password = _credentials(parts)
        if parts.username is not None:           # no credentials in the address sent
            netloc = parts.hostname + (f":{parts.port}" if parts.port else "")
            url = urllib.parse.urlunsplit(parts._replace(netloc=netloc))
        if user is not None:
            import base64
            token = base64.b64encode(f"{user}:{password or ''}".encode()).decode()
            headers["Authorization"] = f"Basic {token}"
        if self.left() <= 0:
            raise TimeoutError("out of time")
        with self.opener.open(urllib.request.Request(url, headers=headers),
                              timeout=max(0.1, self.left())) as r:
            chunks = []
            while True:                      # a server that trickles is cut off too
                if self.left() <= 0:
                    raise TimeoutError("out of time")
                chunk = r.read(1 << 16)
                if not chunk:
                    break
                chunks.append(chunk)
            return b"".join(chunks), r.headers.get("Content-Type", ""), r.geturl()


def _credentials(parts) -> tuple[str | None, str | None]:
    if parts.username is not None:
        return urllib.parse.unquote(parts.username), urllib.parse.unquote(parts.password or "")
    try:
        import netrc
        found = netrc.netrc().authenticators(parts.hostname or "")
    except (OSError, netrc.NetrcParseError):
        return None, None
    return (found[0], found[2]) if found else (None, None)


def _shown(url: str) -> str:
    """An address as a message shows it: without credentials."""
    parts = urllib.parse.urlsplit(url)
    if parts.username is None:
        return url
    return urllib.parse.urlunsplit(parts._replace(netloc="***@" + parts.netloc.rsplit("@", 1)[1]))


def _reason(err: BaseException) -> str:
    if isinstance(err, urllib.error.HTTPError):
        return f"HTTP {err.code}"
    if isinstance(err, FileNotFoundError):
        return "not found"
    reason = getattr(err, "reason", None) or err
    text = str(reason).strip().splitlines()[0] if str(reason).strip() else type(err).__name__
    return text


# -- the search ------------------------------------------------------------------------------
def _search(project: str, filename: str, sha256: str, settings: PipSettings, deadline: float,
            tried: list[str], where: list[str]) -> tuple[bytes, str]:
    client = _Client(settings, deadline)
    unreached = [False]              # some place could not be asked (it may have the file)
    places = [(link, False) for link in settings.find_links] + \
        [(index.rstrip("/") + f"/{project}/", True) for index in settings.indexes]
    for place, is_index in places:
        where[0] = _shown(place)
        try:
            local = Path(place) if "://" not in place else \
                Path(urllib.request.url2pathname(urllib.parse.urlsplit(place).path)) \
                if place.startswith("file:") and not is_index else None
            if local is not None and local.is_dir():
                if (local / filename).is_file():
                    data = (local / filename).read_bytes()
                    if hashlib.sha256(data).hexdigest() == sha256:
                        return data, str(local / filename)
                    tried.append(f"{place}: {filename} has another SHA-256")
                continue
            body, ctype, final = client.get(place, ACCEPT if is_index else None)
            files = files_of_page(body, ctype, final)
            if filename not in files:
                tried.append(f"{_shown(place)}: no {filename}")
                continue
            url, listed = files[filename]
            if listed and listed.lower() != sha256:
                tried.append(f"{_shown(place)}: lists {filename} with another SHA-256")
                continue
            where[0] = _shown(url)
            data = client.get(url)[0]
            if hashlib.sha256(data).hexdigest() != sha256:
                tried.append(f"{_shown(url)}: another SHA-256 than the pinned one")
                continue
            return data, _shown(url)
        except (OSError, ValueError, TimeoutError) as err:
            tried.append(f"{_shown(place)}: {_reason(err)}")
            unreached[0] = True
    raise FetchError("; ".join(tried) or "pip is configured with no index (--no-index) "
                     "and no find-links", unreachable=unreached[0])


def fetch(project: str, filename: str, sha256: str, deadline: float | None = None,
          settings: PipSettings | None = None) -> tuple[bytes, str]:
    """The bytes of ``filename`` of ``project`` and where they came from, from
    the first place pip's configuration names that has it with SHA-256
    ``sha256``; FetchError (one line) when none has it within ``deadline`` s
    (default :data:`DEADLINE`)."""
    settings = settings or pip_settings()
    limit = DEADLINE if deadline is None else deadline
    end = time.monotonic() + limit
    box: dict = {}
    tried: list[str] = []
    where = [""]

    def work():
        try:
            box["ok"] = _search(project, filename, sha256, settings, end, tried, where)
        except BaseException as err:      # handed to the caller's thread
            box["err"] = err
    worker = threading.Thread(target=work, name="pdbfs-fetch", daemon=True)
    worker.start()
    worker.join(max(0.0, end - time.monotonic()) + 0.5)
    if "ok" in box:
        return box["ok"]
    if "err" in box:
        err = box["err"]
        text = str(err) if isinstance(err, FetchError) else f"{where[0]}: {_reason(err)}"
        if time.monotonic() >= end - 0.5:          # ended by the deadline: say so
            text = f"gave up after {limit:g} s: {text}"
        raise FetchError(text, getattr(err, "unreachable", True)) from None
    done = "; ".join(tried)
    raise FetchError(f"no answer within {limit:g} s from {where[0] or 'the index'}"
                     + (f" (before: {done})" if done else ""))
