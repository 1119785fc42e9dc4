"""Support for the FMU-input and SSP tests (tests/test_fmu_inputs*.py,
tests/test_ssp*.py): the FMUs of the closed-loop pulse rig's plant and
controller and of the mass pushed through an input, each exported once per
test process, the SSP files joining plant and controller, and the
monolithic rig's reference. Not part of the package."""
from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

import numpy as np

from pdbfs.fmu import export_fmu, export_ssp
from pdbfs.models import LOOP, hydraulic_pulse_pid_rig, pulse_controller_rig, pulse_plant_rig

_DIR: list[Path] = []
_CACHE: dict = {}
T_END = 0.02


def folder() -> Path:
    """A temporary folder for this process, removed at exit."""
    if not _DIR:
        d = Path(tempfile.mkdtemp(prefix="pdbfs-test-ssp-"))
        atexit.register(shutil.rmtree, d, True)
        _DIR.append(d)
    return _DIR[0]


def fmu_of(kind: str, fmi_version: int = 2) -> str:
    """The FMU of ``kind`` ("plant", "controller" or "pushed"), exported once."""
    key = (kind, fmi_version)
    if key not in _CACHE:
        if kind == "pushed":
            from input_rigs import Pushed
            rig = Pushed()
        else:
            rig = {"plant": pulse_plant_rig, "controller": pulse_controller_rig}[kind]()
        _CACHE[key] = str(export_fmu(rig.compile(), folder() / f"{kind}{fmi_version}.fmu",
                                     fmi_version=fmi_version, stop_time=T_END))
    return _CACHE[key]


def loop_ssp(fmi_version: int = 2) -> str:
    """The SSP file of plant and controller (of one FMI version), connected as LOOP."""
    key = ("ssp", fmi_version)
    if key not in _CACHE:
        _CACHE[key] = str(export_ssp(folder() / f"loop{fmi_version}.ssp",
                                     {"plant": fmu_of("plant", fmi_version),
                                      "controller": fmu_of("controller", fmi_version)},
                                     LOOP, name="pulse_pid"))
    return _CACHE[key]


def reference():
    """The monolithic closed-loop rig, tight: a function t -> chamber pressure (Pa)."""
    if "ref" not in _CACHE:
        t = np.linspace(0.0, T_END, 6401)
        res = hydraulic_pulse_pid_rig().simulate(T_END, t_out=t, rtol=1e-11, atol=1e-9)
        p = np.asarray(res["chamber.p"])
        _CACHE["ref"] = (t, p)
    t, p = _CACHE["ref"]
    return lambda s: np.interp(s, t, p)


def max_error(t, p) -> float:
    """The largest difference of a co-simulated pressure from the monolithic rig's (Pa)."""
    return float(np.max(np.abs(np.asarray(p) - reference()(np.asarray(t)))))


def order(steps, errors) -> float:
    """The slope of log(error) over log(step), least squares."""
    return float(np.polyfit(np.log(steps), np.log(errors), 1)[0])


def ecos_run(ssp: str, h: float, t_end: float = T_END):
    """(t, the plant's pressure) of the SSP system run by Ecos (ecospy) at the step h."""
    import importlib.util
    import os
    spec = importlib.util.find_spec("ecospy")
    bins = os.path.join(os.path.dirname(spec.origin), "binaries")
    for exe in ("ecos", "proxyfmu"):             # the wheel ships them without the run bit
        f = os.path.join(bins, exe)
        if os.path.isfile(f) and not os.access(f, os.X_OK):
            os.chmod(f, os.stat(f).st_mode | 0o111)
    from ecospy import EcosLib, EcosSimulation
    EcosLib.set_log_level("warn")
    sim = EcosSimulation(ssp_path=ssp, step_size=h)
    sim.init()
    t, p = [sim.get_time()], [sim.get_real("plant::sensor.y")]
    for _ in range(int(round(t_end / h))):
        sim.step()
        t.append(sim.get_time())
        p.append(sim.get_real("plant::sensor.y"))
    sim.terminate()
    sim.free()
    return np.array(t), np.array(p)


def libcosim_run(ssp: str, h: float, t_end: float = T_END):
    """(t, the plant's pressure) of the SSP system run by libcosim (libcosimpy) at the step h."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    log_output_level(CosimLogLevel.ERROR)
    ns = int(round(h * 1e9))
    ex = CosimExecution.from_ssp_file(ssp, step_size=ns)
    idx = {s.name.decode(): s.index for s in ex.slave_infos()}["plant"]
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}["sensor.y"]
    n = int(round(t_end / h))
    obs = CosimObserver.create_time_series(buffer_size=n + 10)
    ex.add_observer(obs)
    assert obs.start_time_series(idx, vr, CosimVariableType.REAL)
    assert ex.simulate_until(n * ns)
    tp, _, vals = obs.time_series_real_samples(idx, vr, from_step=0, sample_count=n + 10)
    return np.array(tp) * 1e-9, np.array(vals)


def _member_functions(kind: str, output: str):
    """The rig of ``kind`` ("plant", "controller") as plain functions for
    scipy: (x0, right-hand side f(t, x, u), output(t, x, u)), its one input
    ``u`` held."""
    import casadi as ca
    rig = {"plant": pulse_plant_rig, "controller": pulse_controller_rig}[kind]()
    dae = rig.compile()
    row = dae.input_rows()[0]
    p = dae.p_default()
    u = ca.SX.sym("u")
    pu = ca.vertcat(dae.p[:row], u, dae.p[row + 1:])
    sub = lambda e: ca.substitute(e, dae.p, pu)  # noqa: E731
    rest = [v for i, v in enumerate(p) if i != row]
    others = ca.vertcat(*[dae.p[i] for i in range(dae.p.numel()) if i != row])
    f = ca.Function("f", [dae.t, dae.x, u, others], [sub(dae.ode)])
    y = ca.Function("y", [dae.t, dae.x, u, others], [sub(dae.y[dae.y_names.index(output)])])
    x0 = np.array(dae.function("start")(p), float).ravel()
    return (x0, lambda t, x, v: np.array(f(t, x, v, rest), float).ravel(),
            lambda t, x, v: float(y(t, x, v, rest)))


def held_reference(h: float, scheme: str = "jacobi", t_end: float = T_END):
    """The closed loop co-simulated as a master does it, each FMU's step
    integrated by scipy (DOP853, rtol 1e-12): inputs held over each
    communication step of h, set at each communication point from the
    outputs there; ``scheme`` "jacobi" (Ecos, libcosim: every output read
    before any input is set, so the controller's command is computed from
    the measurement of the step before) or "passes" (pdbfs's master: the
    measurement set first, the controller's command read after it). The
    plant's pressure at the communication points (Pa), independent of
    pdbfs's solvers."""
    from scipy.integrate import solve_ivp
    key = ("held", h, scheme, t_end)
    if key in _CACHE:
        return _CACHE[key]
    from pdbfs.components.hydraulic import ATMOSPHERE
    xp, fp, yp = _member_functions("plant", "sensor.y")
    xc, fc, yc = _member_functions("controller", "pid.y")
    opening, measured = 0.0, ATMOSPHERE          # the inputs' starts
    n = int(round(t_end / h))
    out = np.empty(n + 1)
    for k in range(n + 1):
        t = k * h
        pressure = yp(t, xp, opening)
        command = yc(t, xc, measured if scheme == "jacobi" else pressure)
        out[k] = pressure
        if k == n:
            break
        measured, opening = pressure, command
        for x, f, v, put in ((xp, fp, opening, 0), (xc, fc, measured, 1)):
            s = solve_ivp(lambda tt, xx, f=f, v=v: f(tt, xx, v), (t, t + h), x, method="DOP853", rtol=1e-12,
                          atol=1e-12 * np.maximum(np.abs(x), 1e-3))
            if put == 0:
                xp = s.y[:, -1]
            else:
                xc = s.y[:, -1]
    _CACHE[key] = out
    return out
