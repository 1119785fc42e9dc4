"""A co-simulation master on FMPy's FMU2Slave and FMU3Slave: the FMUs of a
system (an SSP file, ``ssp.py``) stepped together at a fixed communication
step, each output fed to the inputs it is connected to at every
communication point.

At a communication point the master reads the outputs and sets the
connected inputs, in passes until nothing changes (an output that depends
directly on an input, as a controller's on its measurement, is read after
that input is set: no algebraic loop is assumed); then every FMU steps.
Inputs are held over the step (first order in the step), or, with
``interpolate=True`` and FMI 2.0 FMUs that can interpolate inputs, run on a
line (``fmi2SetRealInputDerivatives``; second order) whose slope is the
connected output's time derivative at the communication point where its
FMU gives it (``maxOutputDerivativeOrder`` >= 1: pdbfs's FMUs, from the
model's own derivatives), else the output's slope over the step before.
FMI 3.0 has no call for an input's derivative: its inputs are held.
"""
from __future__ import annotations

import os
import shutil
import tempfile
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pdbfs.errors import ExportError, SolverError

from .ssp import read_ssp


@dataclass
class CoSimulation:
    """A co-simulated system's results (``cosimulate`` makes it):
    ``co["plant.sensor.y"]`` is a recorded variable at the communication
    points.

    Attributes
    ----------
    t : numpy.ndarray
        The communication points, s.
    values : dict
        ``"element.variable"`` -> its values at ``t``.
    step : float
        The communication step, s.
    interpolated : bool
        Whether FMI 2.0 inputs ran on a line over each step (else held).
    seconds : float
        The wall time of the FMUs' calls, s.
    """

    t: np.ndarray
    values: dict[str, np.ndarray] = field(default_factory=dict)
    step: float = 0.0
    interpolated: bool = False
    seconds: float = 0.0

    def __getitem__(self, name: str) -> np.ndarray:
        if name not in self.values:
            raise KeyError(f"{name!r} was not recorded; recorded: {', '.join(self.values)}")
        return self.values[name]


class _Member:
    """One FMU of the system, instantiated from its extracted folder."""

    def __init__(self, name: str, folder: str, tolerance: float | None, t0: float, t1: float):
        from fmpy import read_model_description
        md = read_model_description(folder)
        if md.coSimulation is None:
            raise ExportError(f"component {name}: its FMU offers no Co-Simulation")
        self.name, self.fmi3 = name, md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.interpolates = bool(getattr(md.coSimulation, "canInterpolateInputs", False)) and not self.fmi3
        self.derivatives = int(getattr(md.coSimulation, "maxOutputDerivativeOrder", 0) or 0) >= 1
        kw = dict(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=name)
        if self.fmi3:
            from fmpy.fmi3 import FMU3Slave
            self.fmu = FMU3Slave(**kw)
            self.fmu.instantiate()
            self.fmu.enterInitializationMode(tolerance=tolerance, startTime=t0, stopTime=t1)
        else:
            from fmpy.fmi2 import FMU2Slave
            self.fmu = FMU2Slave(**kw)
            self.fmu.instantiate()
            self.fmu.setupExperiment(tolerance=tolerance, startTime=t0, stopTime=t1)
            self.fmu.enterInitializationMode()

    def get(self, names: list[str]) -> list[float]:
        vrs = [self.vr[n] for n in names]
        return list(self.fmu.getFloat64(vrs) if self.fmi3 else self.fmu.getReal(vrs))

    def set(self, names: list[str], values: list[float]) -> None:
        vrs = [self.vr[n] for n in names]
        if self.fmi3:
            self.fmu.setFloat64(vrs, values)
        else:
            self.fmu.setReal(vrs, values)

    def rates(self, names: list[str]) -> list[float]:
        """The outputs' first time derivatives now (the FMU's own)."""
        vrs = [self.vr[n] for n in names]
        get = self.fmu.getOutputDerivatives if self.fmi3 else self.fmu.getRealOutputDerivatives
        return list(get(vrs, [1] * len(vrs)))

    def step(self, t: float, h: float) -> None:
        self.fmu.doStep(t, h)

    def close(self) -> None:
        try:
            self.fmu.terminate()
        finally:
            self.fmu.freeInstance()


def cosimulate(ssp: str | os.PathLike, step: float, t_end: float | None = None, *,
               outputs: list[str] | None = None, interpolate: bool = False,
               tolerance: float | None = None) -> CoSimulation:
    """Co-simulate the system of the SSP file ``ssp`` at a fixed communication step.

    Parameters
    ----------
    ssp : str or os.PathLike
        The SSP file (``export_ssp``).
    step : float
        The communication step, s (> 0, dividing the run into whole steps).
    t_end : float, optional
        The end, s (default: the SSP file's default stop time); the run
        starts at its default start.
    outputs : list of str, optional
        The variables recorded at every communication point
        (``"element.variable"``; default: every connected output).
    interpolate : bool
        Inputs of FMI 2.0 FMUs that can interpolate run on a line instead
        of being held, its slope the feeding output's derivative at the
        communication point where its FMU gives it, else that output's
        slope over the step before.
    tolerance : float, optional
        The FMUs' relative tolerance (default: their own).

    Returns
    -------
    CoSimulation
        The communication points and the recorded variables there.

    Raises
    ------
    ExportError
        A bad system or argument.
    SolverError
        Where an FMU refuses a call (its log says why).
    """
    comps, conns, exp = read_ssp(ssp)
    t0 = float(exp.get("startTime", 0.0))
    t1 = float(t_end if t_end is not None else exp.get("stopTime", "nan"))
    if not (isinstance(step, (int, float)) and not isinstance(step, bool) and 0 < step < float("inf")):
        raise ExportError(f"step = {step!r}: give a communication step in s > 0")
    if not np.isfinite(t1) or t1 <= t0:
        raise ExportError(f"t_end = {t_end!r}: give an end time after the start {t0} s (the SSP file "
                          "states no stop time)" if not np.isfinite(t1) else f"t_end {t1} s is not after "
                          f"the start {t0} s")
    n = int(round((t1 - t0) / step))
    if n < 1 or abs(n * step - (t1 - t0)) > 1e-9 * max(1.0, abs(t1)):
        raise ExportError(f"step {step} s does not divide the run {t0}..{t1} s into whole steps")
    outputs = list(outputs) if outputs is not None else list(dict.fromkeys(f"{a}.{av}" for a, av, _, _ in conns))
    with tempfile.TemporaryDirectory(prefix="pdbfs-cosim-") as tmp:
        with zipfile.ZipFile(ssp) as z:
            z.extractall(tmp)
        folders = {}
        for name, source in comps.items():
            folders[name] = str(Path(tmp) / name)
            with zipfile.ZipFile(Path(tmp) / source) as z:
                z.extractall(folders[name])
        members: dict[str, _Member] = {}
        try:
            for name in comps:
                members[name] = _Member(name, folders[name], tolerance, t0, t1)
            for o in outputs:
                e, _, v = o.partition(".")
                if e not in members or v not in members[e].vr:
                    raise ExportError(f"output {o!r}: no such variable in the system")
            return _run(members, conns, outputs, t0, step, n, interpolate)
        except ExportError:
            raise
        except Exception as err:       # an FMU's refusal (fmpy raises it): one line
            raise SolverError(f"co-simulation of {Path(ssp).name} failed: {err}") from None
        finally:
            for m in members.values():
                try:
                    m.close()
                except Exception:      # an instance in error: freed as far as it goes
                    pass
            shutil.rmtree(tmp, ignore_errors=True)


def _propagate(members, conns) -> dict:
    """Every connected input set to its output's value, in passes until
    nothing changes (at most one pass per connection); the values set."""
    last: dict = {}
    for _ in range(max(1, len(conns))):
        changed = False
        for a, av, b, bv in conns:
            v = members[a].get([av])[0]
            if last.get((b, bv)) != v:
                members[b].set([bv], [v])
                last[(b, bv)] = v
                changed = True
        if not changed:
            break
    return last


def _slopes(members, conns, now: dict, prev: dict | None, h: float) -> None:
    """Each input that can interpolate given its line's slope: the connected
    output's derivative where its FMU gives it (in passes, as the values: a
    derivative that depends on an input's slope is read after it is set),
    else the output's change over the step before divided by h."""
    last: dict = {}
    for _ in range(max(1, len(conns))):
        changed = False
        for a, av, b, bv in conns:
            if not members[b].interpolates:
                continue
            if members[a].derivatives:
                slope = members[a].rates([av])[0]
            else:
                slope = 0.0 if prev is None else (now[(b, bv)] - prev[(b, bv)]) / h
            if last.get((b, bv)) != slope:
                members[b].fmu.setRealInputDerivatives([members[b].vr[bv]], [1], [slope])
                last[(b, bv)] = slope
                changed = True
        if not changed:
            break


def _run(members, conns, outputs, t0, h, n, interpolate) -> CoSimulation:
    import time as _time
    start = _time.perf_counter()
    _propagate(members, conns)
    for m in members.values():
        m.fmu.exitInitializationMode()
    rec = {o: np.empty(n + 1) for o in outputs}
    split = [(o, *o.split(".", 1)) for o in outputs]

    def record(i):
        for o, e, v in split:
            rec[o][i] = members[e].get([v])[0]
    prev = None
    for i in range(n + 1):         # each communication point: inputs set, outputs read, then the step
        now = _propagate(members, conns)
        record(i)
        if i == n:
            break
        if interpolate:
            _slopes(members, conns, now, prev, h)
        prev = now
        for m in members.values():
            m.step(t0 + i * h, h)
    return CoSimulation(t0 + h * np.arange(n + 1), rec, h, bool(interpolate), _time.perf_counter() - start)
