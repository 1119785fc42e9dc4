"""One rig as the page sees it: its parameters as controls, a run as curves
and a summary, uploads and downloads. Everything goes through the public
API (``rig.simulate``, ``pdbfs.calibrate``, ``pdbfs.design``,
``pdbfs.design_map``, ``rig.export_fmu``); nothing here knows the physics.
No Dash in this module: the page (page.py, actions.py) is drawn over it."""
from __future__ import annotations

import base64
import inspect
import math
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdbfs.components.laws import STANDARD_GRAVITY, impact_velocity
from pdbfs.errors import DataError, ParameterError, PdbfsError
from pdbfs.models import RIGS
from pdbfs.simulation import SUMMARY_UNITS, Simulator

#: units whose values span decades: stiffness and damping get a logarithmic slider
LOG_UNITS = ("N/m", "N.s/m")


@dataclass(frozen=True)
class Control:
    """A parameter as the page offers it: a number field and a slider."""

    name: str
    unit: str
    description: str
    default: float
    lo: float              # slider range, in the parameter's value (not its log)
    hi: float
    log: bool
    step: float            # slider step, in slider units (log10 of the value when log)
    derived: str = ""      # "hammer.v0" for a drop height that stands for it

    def to_slider(self, value: float) -> float:
        if self.log:
            return math.log10(value) if value > 0 else math.log10(self.lo)
        return value

    def from_slider(self, s: float) -> float:
        return 10.0 ** s if self.log else s

    def slider_range(self, value: float | None = None) -> tuple[float, float]:
        """The slider's (min, max), widened to hold ``value``."""
        lo, hi = self.to_slider(self.lo), self.to_slider(self.hi)
        if value is not None and (value > 0 or not self.log):
            s = self.to_slider(value)
            lo, hi = min(lo, _floor(s, self.step)), max(hi, _ceil(s, self.step))
        return lo, hi


def _floor(x, step):
    return round(math.floor(x / step) * step, 12)


def _ceil(x, step):
    return round(math.ceil(x / step) * step, 12)


def _linear_range(default: float, pmin):
    """A round range about a default: 0 .. about 2.5 x default (or both signs)."""
    if default == 0:
        return (0.0, 1.0, 0.01) if pmin is not None and pmin >= 0 else (-1.0, 1.0, 0.01)
    mag = 10.0 ** math.floor(math.log10(abs(default) * 2.5))
    top = math.ceil(abs(default) * 2.5 / mag) * mag
    step = 10.0 ** (math.floor(math.log10(top)) - 2)
    lo = 0.0 if default > 0 else -top
    hi = top if default > 0 else 0.0
    if pmin is not None and pmin > lo:
        lo = _floor(pmin, step)
    return lo, hi, step


def control_of(info) -> Control:
    log = info.unit.startswith(LOG_UNITS) and info.value > 0
    if log:
        c = math.log10(info.value)
        lo, hi = 10.0 ** _floor(c - 1, 0.01), 10.0 ** _ceil(c + 1, 0.01)
        return Control(info.name, info.unit, info.description, info.value, lo, hi, True, 0.01)
    lo, hi, step = _linear_range(info.value, info.min)
    if info.max is not None:
        hi = min(hi, info.max)
    return Control(info.name, info.unit, info.description, info.value, lo, hi, False, step)


def drop_height(v0: float) -> float:
    """The drop height whose free fall gives ``v0`` (impact_velocity inverted)."""
    return v0 * v0 / (2.0 * STANDARD_GRAVITY)


def parse_number(name: str, text) -> float:
    """A field's text as a number, or the one-line error the command line gives."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    try:
        return float(str(text).strip())
    except ValueError:
        raise ParameterError(f"{name}: {str(text).strip()!r} is not a number") from None


class Workbench:
    """The page's handle on one rig, shared by every session: it holds no
    session state, only the compiled rig and its settings' defaults."""

    def __init__(self, rig_name: str):
        if rig_name not in RIGS:
            raise ParameterError(f"unknown rig {rig_name!r}; choose one of {', '.join(RIGS)}")
        self.name = rig_name
        self.rig = RIGS[rig_name]()
        self.dae = self.rig.compile()
        self.sim = Simulator.of(self.dae)
        self.t_end = float(getattr(self.rig, "default_t_end", 0.02))
        self.n_out = int(getattr(self.rig, "default_n_out", 2001))
        self.signals = dict(getattr(self.dae, "signals", {}) or {})
        self.controls = [control_of(p) for p in self.dae.params]
        self.units = {p.name: p.unit for p in self.dae.params}
        self.height = self._height_control()
        if self.height:
            self.controls.insert(self.index(self.height.derived) + 1, self.height)
            self.units[self.height.name] = "m"
        self._lock = threading.Lock()     # one run of this rig at a time (CasADi's buffers)
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
        lo, hi, step = _linear_range(h0, 0.0)
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

    def index(self, name: str) -> int:
        return [c.name for c in self.controls].index(name)

    def control(self, name: str) -> Control:
        return self.controls[self.index(name)]

    # -- settings ----------------------------------------------------------------
    def defaults(self) -> dict:
        return {c.name: c.default for c in self.controls}

    def check(self, name: str, text) -> dict:
        """The settings one field's text changes ({name: value}, and the impact
        speed a drop height stands for), or the command line's ParameterError."""
        value = parse_number(name, text)
        c = self.control(name)
        if c.derived:
            if not value >= 0 or not math.isfinite(value):
                raise ParameterError(f"{name} = {text} m: must be >= 0 ({c.description})")
            v0 = impact_velocity(value)
            self.sim.param_vector({c.derived: v0})
            return {name: value, c.derived: v0}
        self.sim.param_vector({name: value})
        out = {name: value}
        if self.height and name == self.height.derived and value >= 0:
            out[self.height.name] = drop_height(value)
        return out

    def params(self, settings: dict) -> dict:
        """The rig's parameters of the page's settings (a drop height left out:
        its impact speed is there)."""
        names = set(self.dae.p_names)
        return {k: float(v) for k, v in settings.items() if k in names}

    # -- runs --------------------------------------------------------------------
    def run(self, settings: dict, backend=None):
        with self._lock:
            return self.rig.simulate(self.t_end, n_out=self.n_out, params=self.params(settings),
                                     backend=backend or self.backend)

    def curves(self, res) -> dict:
        """The signals the page plots: pressure, contact force, displacements."""
        names = [n for n in (self.signals.get("pressure"), self.signals.get("contact_force")) if n]
        names += [n for n in res.names if n.endswith(".s") and n.count(".") == 1
                  and res.units.get(n) == "m" and n in self.dae.x_names]
        return {"t": res.t, **{n: (res[n], res.units[n]) for n in names}}

    @staticmethod
    def summary(res) -> list:
        """(key, value, unit) rows of the run's summary (``complete`` when the
        API gives it)."""
        return [(k, v, SUMMARY_UNITS.get(k, "")) for k, v in res.summary().items()]

    # -- traces ------------------------------------------------------------------
    def read_upload(self, filename: str, contents: str):
        """A trace uploaded by the browser (a data URL) read as ``pdbfs
        calibrate --trace`` reads a file; errors name the file as uploaded."""
        from pdbfs.studies import read_trace
        name = Path(filename or "trace.csv").name
        try:
            data = base64.b64decode(contents.partition(",")[2], validate=False)
        except (ValueError, TypeError):
            raise DataError(f"trace file {name!r}: the upload could not be decoded") from None
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp:
            path = Path(tmp) / name
            path.write_bytes(data)
            kwargs = {}
            if "signal" in inspect.signature(read_trace).parameters and self.signals.get("pressure"):
                kwargs["signal"] = self.signals["pressure"]
            try:
                return read_trace(path, **kwargs)
            except PdbfsError as err:
                raise type(err)(str(err).replace(str(path), name)) from None

    # -- downloads ---------------------------------------------------------------
    def results_csv(self, settings: dict) -> bytes:
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp:
            path = Path(tmp) / "results.csv"
            self.run(settings).to_csv(path)
            return path.read_bytes()

    def results_png(self, settings: dict) -> bytes:
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp, _PLOT_LOCK:
            path = Path(tmp) / "results.png"
            self.run(settings).plot(path=path)
            return path.read_bytes()

    def settings_json(self, settings: dict) -> dict:
        return {"rig": self.name, "params": self.params(settings),
                "units": {k: self.units[k] for k in self.params(settings)},
                **({"drop_height": settings.get(self.height.name)} if self.height else {})}

    def fmu(self, settings: dict, path) -> Path:
        """The rig's FMU with the settings as its parameters' start values."""
        rig = RIGS[self.name]()
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
        import pdbfs
        params, start = self._fixed_and_start(settings, free)
        cal = pdbfs.calibrate(self.rig, trace, free, params=params, start=start,
                              progress=progress)
        return {"params": cal.params, "std": cal.std, "units": cal.units,
                "rms_residual": cal.rms_residual, "unit": cal.unit,
                "undetermined": cal.undetermined, "t": _list(cal.t), "fit": _list(cal.fit)}

    def design(self, settings: dict, target, free: list, progress=None) -> dict:
        import pdbfs
        params, start = self._fixed_and_start(settings, free)
        des = pdbfs.design(self.rig, target, free=free, params=params, start=start,
                           progress=progress)
        return {"params": {**des.params, **des.implied}, "reachable": des.reachable,
                "limit": des.limit, "features": des.features, "targets": des.targets,
                "rms_error": des.rms_error, "unit": des.unit, "units": des.units,
                "t": _list(des.t), "fit": _list(des.fit)}

    def design_map(self, settings: dict, x: tuple, y: tuple, n: int, progress=None) -> dict:
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
