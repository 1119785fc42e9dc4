"""One rig as the page sees it: its parameters as controls, a run as curves
and a summary, uploads and downloads. Everything goes through the public
API (``rig.simulate``, ``pdbfs.calibrate``, ``pdbfs.design``,
``pdbfs.design_map``, ``rig.export_fmu``); nothing here knows the physics.
No Dash in this module: the page (page.py, interact.py, jobs.py) is drawn over it."""
from __future__ import annotations

import math
import re
import tempfile
import threading
import warnings
from pathlib import Path

import numpy as np

from pdbfs.components.laws import impact_velocity
from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.models import RIGS, rig_from
from pdbfs.simulation import SUMMARY_UNITS, Simulator

from . import traces
from .controls import (LOG_UNITS, Control, control_of, drop_height, linear_range, page_groups,
                       parse_number)
from .numbers import short_description

__all__ = ["Workbench", "workbench", "offer", "rig_names", "Control", "LOG_UNITS", "METHODS",
           "drop_height", "parse_number", "control_of"]

#: the integrator's methods the page offers (rig.simulate's ``method``)
METHODS = ("auto", "adams", "bdf")
#: longest run the page offers, in multiples of the rig's default run length
MAX_T_END = 50
#: runs whose curves and summary are kept, per rig (pins and undo are not run again)
KEEP_OUTCOMES = 12
#: the user's rigs (FILE.py:NAME, MODULE:NAME) the server was started with: a page
#: offers these besides RIGS and loads no other (no name from a browser imports a file)
_OFFERED: list = []


def offer(spec: str) -> None:
    """Let the page load the user's rig ``spec`` (``FILE.py:NAME``), as ``pdbfs app --rig`` does."""
    if spec not in RIGS and spec not in _OFFERED:
        _OFFERED.append(spec)


def rig_names() -> list[str]:
    """The rigs a page offers: pdbfs's, then the user's it was started with."""
    return list(RIGS) + _OFFERED


class Workbench:
    """The page's handle on one rig, shared by every session: it holds no
    session state, only the compiled rig and its settings' defaults."""

    def __init__(self, rig_name: str):
        if rig_name not in rig_names():
            raise ParameterError(f"unknown rig {rig_name!r}; choose one of {', '.join(rig_names())}")
        self.name = rig_name
        self.rig = rig_from(rig_name, "--rig")
        self.dae = self.rig.compile()
        self.sim = Simulator.of(self.dae)
        self.t_end = float(getattr(self.rig, "default_t_end", 0.02))
        self.n_out = int(getattr(self.rig, "default_n_out", 2001))
        self.signals = dict(getattr(self.dae, "signals", {}) or {})
        self.controls = [control_of(p) for p in self.dae.params]
        self.units = {p.name: p.unit for p in self.dae.params}
        self.height = self._height_control()
        if self.height:
            self.controls.append(self.height)
            self.units[self.height.name] = "m"
        # the page's order: the rig's key parameters, the rest by component, starts last
        self.groups = page_groups(self.controls, self.key_parameters())
        self.controls = [c for _, cs in self.groups for c in cs]
        self.descriptions = {v.name: v.description for v in
                             (*self.dae.x_info, *self.dae.z_info, *self.dae.y_info)}
        self.parts = self._parts()
        self._lock = threading.Lock()     # one run of this rig at a time (CasADi's buffers)
        self._outcomes: dict = {}
        self.backend, self.backend_note = self._pick_backend()

    def _height_control(self) -> Control | None:
        """``X.h`` beside the striker's impact speed ``X.v0`` (the rig's own drop
        height, if it has one, is already a parameter)."""
        striker = self.signals.get("striker_velocity", "")
        v0 = striker[:-2] + ".v0" if striker.endswith(".v") else ""
        names = set(self.dae.p_names)
        if v0 not in names or "h" in names or v0[:-3] + ".h" in names:
            return None
        info = self.dae.params[self.dae.p_names.index(v0)]
        if info.value <= 0:
            return None
        h0 = drop_height(info.value)
        lo, hi, step = linear_range(h0, 0.0)
        return Control(v0[:-3] + ".h", "m", f"Drop height; sets {v0} = sqrt(2 g h)",
                       h0, lo, hi, False, step, derived=v0)

    def _pick_backend(self):
        """The compiled backend where this rig and a C compiler allow it."""
        if not self.dae.is_ode:
            return "casadi", "CasADi (the rig has algebraic variables)"
        try:
            self.run({}, backend="c")
        except PdbfsError as err:
            return "casadi", f"CasADi (no compiled backend: {err})"
        return "c", "compiled C (explicit Runge-Kutta or CVODE, as method auto picks)"

    def key_parameters(self) -> list:
        """The parameters the rig declares matter most (``key_parameters``),
        else those its page defaults design and calibrate."""
        decl = getattr(self.rig, "key_parameters", None)
        if decl is None:
            pages = dict(getattr(self.rig, "page_defaults", None) or {})
            decl = (*pages.get("design", ()), *pages.get("calibrate", ()))
        return list(decl)

    def shown_groups(self, parts: bool = False) -> list:
        """The page's groups (page_groups) of the controls it draws."""
        hidden = set() if parts else set(self.parts)
        out = [(g, [c for c in cs if c.name not in hidden]) for g, cs in self.groups]
        return [(g, cs) for g, cs in out if cs]

    @property
    def file_name(self) -> str:
        """The rig's name in names of files: its --rig name, or for a rig of
        the user's (``FILE.py:NAME``) the rig's own."""
        return self.name if self.name in RIGS else self.dae.name

    def label(self, name: str) -> str:
        """A parameter as the page names it: ``oil.k: oil column stiffness``."""
        return f"{name}: {short_description(self.control(name).description)}"

    def curve_label(self, name: str) -> str:
        """A variable by its description: ``contact.fc`` -> ``contact compressive
        force``, ``oil.pressure`` -> ``oil pressure`` (its component named
        unless the description does)."""
        text = short_description(self.descriptions.get(name, "")) if name in self.descriptions \
            else name
        owner = name.rsplit(".", 1)[0] if "." in name else ""
        return text if not owner or owner.lower() in text.lower() else f"{owner} {text}"

    def shown(self, parts: bool = False) -> list:
        """The controls the page draws: without the parameters of repeated
        parts (a bar's 30 segments, a seal's parts) unless ``parts``: each
        control costs the browser time on every edit (200 of them, 4-10 s)."""
        return self.controls if parts else [c for c in self.controls if c.name not in self.parts]

    def _parts(self) -> dict:
        """{name: pattern} of the parameters of parts repeated 3 times or more
        (``piston.seg12.s0`` -> ``piston.seg#.s0``)."""
        pattern = {c.name: re.sub(r"(?<=[A-Za-z_])\d+(?=\.)", "#", c.name) for c in self.controls}
        count: dict = {}
        for p in pattern.values():
            count[p] = count.get(p, 0) + 1
        return {n: p for n, p in pattern.items() if "#" in p and count[p] >= 3}

    def parts_note(self) -> str:
        """What the "repeated parts" switch shows ("" for a rig without them)."""
        groups = sorted(set(self.parts.values()))
        return (f"show the {len(self.parts)} parameters of repeated parts ("
                + ", ".join(groups[:3]) + (", ..." if len(groups) > 3 else "")
                + "; editing is slower with them)") if groups else ""

    def index(self, name: str) -> int:
        """The position of the control ``name``."""
        return [c.name for c in self.controls].index(name)

    def control(self, name: str) -> Control:
        """The control ``name``."""
        return self.controls[self.index(name)]

    def study_defaults(self) -> dict:
        """What the study panels offer first: the rig's own ``page_defaults``
        (parameters to calibrate and design, the design map's axes), each
        name checked against the page's controls; a rig that declares none
        gets its first stiffness to calibrate and its drop height to design."""
        names = [c.name for c in self.controls]
        decl = dict(getattr(self.rig, "page_defaults", None) or {})
        stiff = [c.name for c in self.controls if c.log] or names
        first = self.height.name if self.height else ("h" if "h" in names else names[0])
        cal = [n for n in decl.get("calibrate", ()) if n in names] or stiff[:1]
        des = [n for n in decl.get("design", ()) if n in names] or [first]

        def axis(key, name):
            got = decl.get(key)
            if got and got[0] in names:
                return tuple(got)
            c = self.control(name)
            return (name, c.lo, c.hi)
        mx = axis("map_x", des[0])
        my = axis("map_y", cal[0] if cal[0] != mx[0] else stiff[-1])
        return {"cal-free": cal, "des-free": des, "map-x": mx[0], "map-x-lo": mx[1],
                "map-x-hi": mx[2], "map-y": my[0], "map-y-lo": my[1], "map-y-hi": my[2]}

    # -- settings ----------------------------------------------------------------
    def defaults(self) -> dict:
        """Every control's default value by name."""
        return {c.name: c.default for c in self.controls}

    def check(self, name: str, text) -> dict:
        """The settings one field's text changes ({name: value}, and the impact
        speed a drop height stands for), or the command line's ParameterError."""
        value = parse_number(name, text)
        c = self.control(name)
        if c.derived:
            if not value >= 0 or not math.isfinite(value):
                raise ParameterError(f"{name} = {text} m: must be a finite number >= 0 "
                                     f"({c.description})")
            v0 = impact_velocity(value)
            if not math.isfinite(v0):        # 2 g h beyond floating point
                raise ParameterError(f"{name} = {text} m: too large (its impact speed "
                                     f"{c.derived} = sqrt(2 g h) is beyond floating point)")
            self.sim.param_vector({c.derived: v0})
            return {name: value, c.derived: v0}
        self.sim.param_vector({name: value})
        out = {name: value}
        if self.height and name == self.height.derived and value >= 0:
            h = drop_height(value)
            if not math.isfinite(h):      # v0**2 beyond floating point: no drop height
                raise ParameterError(f"{name} = {text} {c.unit}: too large (its drop height "
                                     f"{self.height.name} = v0^2/(2 g) is beyond floating point)")
            out[self.height.name] = h
        return out

    def params(self, settings: dict) -> dict:
        """The rig's parameters of the page's settings (a drop height left out:
        its impact speed is there)."""
        names = set(self.dae.p_names)
        return {k: float(v) for k, v in settings.items() if k in names}

    # -- runs --------------------------------------------------------------------
    def run(self, settings: dict, backend=None, t_end=None, method="auto"):
        """A run of the settings; ``t_end`` (s) the page's run length (the
        rig's default if None), ``method`` the integrator's (auto|adams|bdf)."""
        t_end = self.t_end if t_end is None else t_end
        # the rig's output rate kept for other lengths, within 201 .. 30001 points
        n_out = int(min(max(round((self.n_out - 1) * t_end / self.t_end) + 1, 201), 30001))
        with self._lock:
            return self.rig.simulate(t_end, n_out=n_out, params=self.params(settings),
                                     backend=backend or self.backend, method=method)

    def outcome(self, settings: dict, t_end=None, method="auto") -> dict:
        """What the page draws of a run: its curves, summary rows and warnings,
        kept for the last few settings (a pin, reset, a run length and back
        are not simulated again: the drop rig's summary alone takes 0.3 s)."""
        key = (tuple(sorted(self.params(settings).items())), t_end, method)
        with self._lock:
            hit = self._outcomes.pop(key, None)
        if hit is None:
            res = self.run(settings, t_end=t_end, method=method)
            rows, notes = self.summary(res)
            hit = {"curves": self.curves(res), "rows": rows, "notes": notes,
                   "n": len(res.t), "t_last": float(res.t[-1])}
        with self._lock:
            self._outcomes[key] = hit              # most recent last
            while len(self._outcomes) > KEEP_OUTCOMES:
                self._outcomes.pop(next(iter(self._outcomes)))
        return hit

    def check_run(self, t_end_ms, method) -> tuple:
        """The page's run length (a field in ms) and method, or a ParameterError."""
        t_end = parse_number("t_end", t_end_ms) * 1e-3
        if not (math.isfinite(t_end) and t_end > 0):
            raise ParameterError(f"t_end = {t_end_ms} ms: must be a positive number")
        if t_end > MAX_T_END * self.t_end:
            raise ParameterError(f"t_end = {t_end_ms} ms: at most {MAX_T_END} times the rig's "
                                 f"{self.t_end * 1e3:g} ms on this page (use pdbfs simulate "
                                 "--t-end for longer runs)")
        if method not in METHODS:
            raise ParameterError(f"method {method!r}: choose one of {', '.join(METHODS)}")
        return t_end, method

    def curves(self, res) -> dict:
        """The signals the page plots: pressure, contact force, displacements."""
        names = [n for n in (self.signals.get("pressure"), self.signals.get("contact_force")) if n]
        names += [n for n in res.names if n.endswith(".s") and n.count(".") == 1
                  and res.units.get(n) == "m" and n in self.dae.x_names]
        return {"t": res.t, **{n: (res[n], res.units[n]) for n in names}}

    @staticmethod
    def summary(res) -> tuple:
        """(key, value, unit) rows of the run's summary (``complete`` when the
        API gives it), and the warnings it gave (the t_end that would hold a
        pulse cut off), for the page rather than the server's log."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            rows = [(k, v, SUMMARY_UNITS.get(k, "")) for k, v in res.summary().items()]
        return rows, [str(w.message) for w in caught]

    # -- traces ------------------------------------------------------------------
    def read_upload(self, filename: str, contents: str):
        """A trace uploaded by the browser, read as ``pdbfs calibrate --trace``
        reads a file (see traces.read_upload)."""
        return traces.read_upload(filename, contents, self.signals.get("pressure"))

    # -- downloads ---------------------------------------------------------------
    def results_csv(self, settings: dict, **run) -> bytes:
        """The run at ``settings`` as CSV bytes."""
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp:
            path = Path(tmp) / "results.csv"
            self.run(settings, **run).to_csv(path)
            return path.read_bytes()

    def results_png(self, settings: dict, **run) -> bytes:
        """The run's plot at ``settings`` as PNG bytes."""
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp, _PLOT_LOCK:
            path = Path(tmp) / "results.png"
            self.run(settings, **run).plot(path=path)
            return path.read_bytes()

    def settings_json(self, settings: dict, t_end=None, method="auto") -> dict:
        """The settings as JSON-ready data: rig, t_end, method, parameters and units."""
        return {"rig": self.name, "t_end": self.t_end if t_end is None else t_end,
                "method": method, "params": self.params(settings),
                "units": {k: self.units[k] for k in self.params(settings)},
                **({"drop_height": settings.get(self.height.name)} if self.height else {})}

    def fmu(self, settings: dict, path) -> Path:
        """The rig's FMU with the settings as its parameters' start values."""
        rig = rig_from(self.name, "--rig")
        defaults = {p.name: p.value for p in self.dae.params}
        for name, value in self.params(settings).items():
            if value != defaults[name]:
                *path_, pname = name.split(".")
                comp = rig
                for part in path_:
                    comp = getattr(comp, part)
                comp.bind(pname, value)
        return rig.export_fmu(path)

    # -- studies -----------------------------------------------------------------
    def _fixed_and_start(self, settings, free):
        params = self.params(settings)
        start = {}
        for f in free:
            c = self.control(f)
            start[f] = float(settings[f])
            params.pop(c.derived or f, None)
        return params, start

    def calibrate(self, settings: dict, trace, free: list, progress=None) -> dict:
        """pdbfs.calibrate at ``settings``, as JSON-ready data for the page."""
        import pdbfs
        params, start = self._fixed_and_start(settings, free)
        cal = pdbfs.calibrate(self.rig, trace, free, params=params, start=start,
                              progress=progress)
        return {"params": cal.params, "std": cal.std, "units": cal.units,
                "rms_residual": cal.rms_residual, "unit": cal.unit,
                "undetermined": cal.undetermined, "t": _list(cal.t), "fit": _list(cal.fit)}

    def design(self, settings: dict, target, free: list, progress=None) -> dict:
        """pdbfs.design at ``settings``, as JSON-ready data for the page."""
        import pdbfs
        params, start = self._fixed_and_start(settings, free)
        des = pdbfs.design(self.rig, target, free=free, params=params, start=start,
                           progress=progress)
        return {"params": {**des.params, **des.implied}, "reachable": des.reachable,
                "limit": des.limit, "features": des.features, "targets": des.targets,
                "rms_error": des.rms_error, "unit": des.unit, "units": des.units,
                "t": _list(des.t), "fit": _list(des.fit)}

    def design_map(self, settings: dict, x: tuple, y: tuple, n: int, progress=None) -> dict:
        """pdbfs.design_map over the axes ``x`` and ``y`` (name, from, to), as JSON-ready data."""
        import pdbfs
        params = self.params(settings)
        for name, *_ in (x, y):
            params.pop(self.control(name).derived or name, None)
        m = pdbfs.design_map(self.rig, x, y, n=n, params=params, backend=self.backend,
                             progress=progress if progress is not None else False)
        return {"x_name": m.x_name, "y_name": m.y_name, "x": _list(m.x), "y": _list(m.y),
                "x_unit": m.x_unit, "y_unit": m.y_unit, "failed": m.failed,
                "values": {k: [_list(r) for r in v] for k, v in m.values.items()}}


_PLOT_LOCK = threading.Lock()   # pyplot is not thread-safe


def _list(a):
    """A JSON-ready list (NaN as None)."""
    if a is None:
        return None
    return [None if not np.isfinite(v) else float(v) for v in np.asarray(a, float).ravel()]


_BENCHES: dict = {}
_BENCHES_LOCK = threading.Lock()


def workbench(rig_name: str) -> Workbench:
    """The shared Workbench of a rig, built once per server."""
    with _BENCHES_LOCK:
        if rig_name not in _BENCHES:
            _BENCHES[rig_name] = Workbench(rig_name)
        return _BENCHES[rig_name]
