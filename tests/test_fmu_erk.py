"""The explicit Runge-Kutta method inside the FMU's co-simulation
(solver.method 3; 0, auto, the default, takes it where it is the cheapest
over the run): the compiled backend's own C (native/c/shared/pdbfs_erk.c) in the
binary and in sources/, against a tight event-located reference written by
hand (paper_equations.py), the compiled backend's explicit run and the FMU's
CVODE, in FMI 2.0 and 3.0; time events (a valve's switch times), communication
points, tunable parameters changed between steps, reset and FMU state; auto
decided at initialisation as the compiled backend decides for that run."""
import re
import shutil
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

import fmu_support as T  # noqa: E402
from paper_equations import TABLE1, pressure, reference
from pdbfs.fmu import export_fmu
from pdbfs.models import hydraulic_pulse_rig
from pdbfs.native.codegen import ERK_DRIVER
from pdbfs.simulation import Simulator
from pdbfs.simulation.run.stiffness import auto_method, fast_modes

ERK, BDF, ADAMS, AUTO = 3, 1, 2, 0
GRID = np.linspace(0.0, 0.02, 2001)


class Cs:
    """One co-simulation instance of an FMU of either FMI version, its log kept."""

    def __init__(self, path, tmp_path, name="erk"):
        md = fmpy.read_model_description(path)
        self.v3 = md.fmiVersion.startswith("3")
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        d = str(path) if Path(path).is_dir() else \
            fmpy.extract(path, unzipdir=str(tmp_path / f"{name}{int(self.v3) + 2}"))
        if self.v3:
            self.log = []
            self.fmu = FMU3Slave(guid=md.instantiationToken, unzipDirectory=d,
                                 modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
            self.fmu.instantiate(loggingOn=True,
                                 logMessage=lambda env, st, cat, msg: self.log.append(msg.decode()))
        else:
            self.rec = T.Recorder(name)
            self.rec.clear()
            self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=d,
                                 modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
            self.fmu.instantiate(loggingOn=True, callbacks=self.rec.callbacks)

    def messages(self):
        return self.log if self.v3 else [m for *_, m in self.rec.messages]

    def init(self, method=ERK, rtol=1e-8, stop=0.02, **params):
        if self.v3:
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=stop)
            self.fmu.setInt64([self.vr["solver.method"]], [method])
        else:
            self.fmu.setupExperiment(startTime=0.0, stopTime=stop)
            self.fmu.setInteger([self.vr["solver.method"]], [method])
        self.set(**{"solver.rtol": rtol, **params})
        if not self.v3:
            self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def set(self, **values):
        if values:
            (self.fmu.setFloat64 if self.v3 else self.fmu.setReal)([self.vr[k] for k in values],
                                                                   list(values.values()))

    def get(self, name):
        return (self.fmu.getFloat64 if self.v3 else self.fmu.getReal)([self.vr[name]])[0]

    def run(self, t_end, h=1e-5, name="oil.pressure"):
        """Communication steps of h to t_end: the output at each."""
        n = int(round((t_end - self.t) / h))
        t0, out = self.t, []
        for k in range(n):
            self.fmu.doStep(self.t, t0 + (k + 1) * h - self.t)
            self.t = t0 + (k + 1) * h
            out.append(self.get(name))
        return np.array(out)

    def reset(self):
        self.fmu.reset()

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


@pytest.fixture(scope="module")
def tight():
    """The hand-written reference's pressure on GRID (DOP853 at rtol 1e-12,
    restarted at every kink)."""
    return pressure(reference(GRID)[0], TABLE1)


def paper_run(fmi_version, method, rtol, tmp_path):
    a = Cs(T.built_fmu("paper", fmi_version), tmp_path, f"paper{method}")
    a.init(method, rtol)
    p = np.r_[a.get("oil.pressure"), a.run(0.02)]
    a.free()
    return p


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_the_explicit_method_meets_the_tight_reference(fmi_version, tight, tmp_path):
    """Measured (both versions): at rtol 1e-8 the peak on the grid 2.8e-9 off,
    the trace 1.2e-8 of the peak; at 1e-10 1.3e-11 and 6.1e-11: it converges."""
    peak = tight.max()
    for rtol, on_peak, on_trace in ((1e-8, 1e-8, 4e-8), (1e-10, 1e-10, 3e-10)):
        p = paper_run(fmi_version, ERK, rtol, tmp_path)
        assert abs(p.max() - peak) < on_peak * peak, rtol
        assert np.max(np.abs(p - tight)) < on_trace * peak, rtol


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_the_explicit_method_agrees_with_the_compiled_one_and_cvode(fmi_version, tight, tmp_path):
    """At rtol 1e-8 the FMU's and the compiled backend's explicit runs put the
    peak 2.8e-9 and 1.7e-9 off the reference (their atol differ: rtol x
    nominal against 1e-10 m), the FMU's BDF 3.5e-8 (measured): each within
    its solver's reach of the other."""
    peak = tight.max()
    erk = paper_run(fmi_version, ERK, 1e-8, tmp_path)
    bdf = paper_run(fmi_version, BDF, 1e-8, tmp_path)
    _, rig = T.built_model("paper")
    compiled = rig.simulate(t_out=GRID, backend="c", method="erk", rtol=1e-8)["oil.pressure"]
    assert abs(erk.max() - compiled.max()) < 1e-8 * peak
    assert np.max(np.abs(erk - compiled)) < 4e-8 * peak
    assert abs(erk.max() - bdf.max()) < 1e-7 * peak
    assert np.max(np.abs(erk - bdf)) < 4e-7 * peak


#: solver.method auto: the parameters and run lengths (None: no stop time, a
#: run of unknown length) against which the compiled backend picks each
#: method (seal.c 1e9 N s/m: a mode that decays without oscillating, stiff;
#: 0.5 s: 3,500 rad of the breech mode)
AUTO_CASES = {"erk": ({}, 0.02), "bdf": ({"seal.c": 1e9}, 0.02), "erk, a long run": ({}, 0.5),
              "erk, a stiffer mount": ({"mount.k": 2.5e12}, 0.02), "erk, no stop time": ({}, None),
              "bdf, no stop time": ({"seal.c": 1e9}, None)}
NAMES = {"explicit Runge-Kutta 8(5,3)": "erk", "CVODE BDF": "bdf", "CVODE Adams": "adams"}


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("case", list(AUTO_CASES))
def test_auto_decides_at_initialisation_as_the_compiled_backend(fmi_version, case, tmp_path):
    """The importer's parameters and stop time reach the decision (without
    one, the cost of each second of a long run), and the fastest mode the
    FMU's C computes (Hessenberg QR) is numpy's."""
    params, stop = AUTO_CASES[case]
    a = Cs(T.built_fmu("paper", fmi_version), tmp_path, "auto")
    a.init(AUTO, 1e-8, stop, **params)
    said = next(m for m in a.messages() if m.startswith("solver.method auto:"))
    a.free()
    sim = Simulator.of(T.built_model("paper")[1])
    p = sim.param_vector(params)
    x0 = sim.start_vector(p)
    chosen = auto_method(sim.dae, p, x0, np.inf if stop is None else stop, sim.compiled())[0]
    assert chosen == case.split(",")[0]
    assert NAMES[said.split(": ", 1)[1].split(";")[0]] == chosen, said
    fastest = re.search(r"fastest mode \(([-+.e\d]+) rad/s\)", said)
    if chosen != "bdf":
        assert float(fastest.group(1)) == pytest.approx(np.max(np.abs(fast_modes(sim.dae, p, x0))), rel=1e-3)


def test_auto_is_the_default_and_runs_the_explicit_method(tmp_path):
    """No solver.method given: the paper rig runs the explicit method (its
    result is the explicit run's, bit for bit)."""
    a = Cs(T.built_fmu("paper"), tmp_path, "default")
    a.fmu.setupExperiment(startTime=0.0, stopTime=0.02)
    a.fmu.enterInitializationMode()
    a.fmu.exitInitializationMode()
    a.t = 0.0
    assert a.fmu.getInteger([a.vr["solver.method"]])[0] == AUTO
    p = a.run(0.02, h=1e-4)
    a.free()
    b = Cs(T.built_fmu("paper"), tmp_path, "explicit")
    b.init(ERK, 1e-8)
    assert np.array_equal(p, b.run(0.02, h=1e-4))
    b.free()


# -- time events: the valve rig (tests/test_time_events.py) -------------------
T_END = 0.05
PULSE_GRID = np.linspace(0.0, T_END, 501)


def _shifted(T0):
    return {"valve.t_open": T0, "valve.t_close": T0 + 4.5e-3}


@pytest.fixture(scope="module")
def pulse_fmus(tmp_path_factory):
    dae = hydraulic_pulse_rig().compile()
    d = tmp_path_factory.mktemp("pulse")
    return {v: str(export_fmu(dae, d / f"pulse{v}.fmu", fmi_version=v)) for v in (2, 3)}


@pytest.fixture(scope="module")
def pulse_reference():
    """chamber.p of the compiled backend's BDF at rtol 1e-12, per valve shift"""
    rig = hydraulic_pulse_rig()
    return lambda T0: rig.simulate(t_out=PULSE_GRID, params=_shifted(T0), backend="c", method="bdf",
                                   rtol=1e-12, atol=1e-12)["chamber.p"]


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("T0", [0.0137, 0.025])     # 0.025: switches on communication points
def test_the_explicit_method_stops_and_restarts_at_each_switch_time(pulse_fmus, pulse_reference, fmi_version,
                                                                    T0, tmp_path):
    """Measured: 1.0e-7 of the peak at rtol 1e-8, 9.8e-10 at 1e-10 (CVODE's
    BDF: 1.4-2.0e-7 and 2.0-2.5e-9), whatever the valve's shift; one restart
    at each of the four switch times, none elsewhere."""
    ref = pulse_reference(T0)
    peak = ref.max()
    switches = [T0, T0 + 4e-3, T0 + 4.5e-3, T0 + 6.5e-3]   # t_open (+ T_open), t_close (+ T_close)
    for rtol, bound in ((1e-8, 3e-7), (1e-10, 3e-9)):
        a = Cs(pulse_fmus[fmi_version], tmp_path, "pulse")
        a.init(ERK, rtol, T_END, **_shifted(T0))
        p = np.r_[a.get("chamber.p"), a.run(T_END, h=1e-4, name="chamber.p")]
        said = [float(m.split("t=")[1].split(",")[0]) for m in a.messages() if m.startswith("time event")]
        a.free()
        assert np.max(np.abs(p - ref)) < bound * peak, rtol
        assert said == pytest.approx(switches, abs=1e-15)


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_a_shifted_valve_gives_the_same_pulse_shifted(pulse_fmus, fmi_version, tmp_path):
    """Time invariance: the explicit method restarts at each switch time, so
    moving the valve by T moves the whole trajectory by T: measured 5.8e-10
    of the peak apart at most (the steps drift apart only after the pulse,
    where the stop time cuts them differently), against 1e-7 of solver error."""
    runs = {}
    for T0 in (0.0, 0.0137, 0.025):
        a = Cs(pulse_fmus[fmi_version], tmp_path, "shift")
        a.init(ERK, 1e-8, T_END, **_shifted(T0))
        runs[T0] = np.r_[a.get("chamber.p"), a.run(T_END, h=1e-4, name="chamber.p")]
        a.free()
    peak = runs[0.0].max()
    for T0, k in ((0.0137, 137), (0.025, 250)):
        assert np.max(np.abs(runs[T0][k:] - runs[0.0][:len(runs[0.0]) - k])) < 2e-9 * peak, T0


# -- communication points, parameter changes, reset, FMU state ---------------
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_the_trajectory_does_not_depend_on_the_communication_step(fmi_version, tmp_path):
    """The explicit method steps past each communication point and serves it
    from its dense output: its steps, and so the states at common points, are
    those of any other communication step (to roundoff)."""
    out = {}
    for h in (1e-5, 1e-3, 2.5e-4):
        a = Cs(T.built_fmu("paper", fmi_version), tmp_path, "comm")
        a.init(ERK, 1e-8)
        out[h] = a.run(0.02, h=h)
        a.free()
    peak = out[1e-5].max()
    fine = out[1e-5][99::100]
    assert np.max(np.abs(out[1e-3] - fine)) <= 1e-12 * peak
    assert np.max(np.abs(out[2.5e-4][3::4] - fine)) <= 1e-12 * peak


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_a_tunable_change_between_steps_restarts_the_explicit_method(fmi_version, tmp_path):
    """seal.c raised tenfold at 4 ms, mid-pulse: the explicit method and
    CVODE's BDF, both restarted there, agree at rtol 1e-10 (measured 1e-9 of
    the peak) and both differ from the unchanged run by far more."""
    runs = {}
    for method, change in ((ERK, True), (BDF, True), (ERK, False)):
        a = Cs(T.built_fmu("paper", fmi_version), tmp_path, "tune")
        a.init(method, 1e-10)
        first = a.run(0.004, h=1e-4)
        if change:
            a.set(**{"seal.c": 10 * a.get("seal.c")})
        runs[method, change] = np.r_[first, a.run(0.02, h=1e-4)]
        a.free()
    peak = runs[ERK, False].max()
    assert np.max(np.abs(runs[ERK, True] - runs[BDF, True])) < 1e-8 * peak
    assert np.max(np.abs(runs[ERK, True] - runs[ERK, False])) > 1e-3 * peak
    assert np.array_equal(runs[ERK, True][:40], runs[ERK, False][:40])


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_reset_runs_the_same_explicit_run_again(fmi_version, tmp_path):
    a = Cs(T.built_fmu("paper", fmi_version), tmp_path, "reset")
    a.init(ERK, 1e-8)
    first = a.run(0.01, h=1e-4)
    a.reset()
    a.init(ERK, 1e-8)
    assert np.array_equal(a.run(0.01, h=1e-4), first)
    a.free()


def test_a_restored_fmu_state_restarts_the_explicit_method(tmp_path):
    """FMI 2.0 get/set FMU state at 4 ms: the run from the restored state is
    the same each time, and within the tolerance of the uninterrupted one
    (it restarts there)."""
    a = Cs(T.built_fmu("paper"), tmp_path, "state")
    a.init(ERK, 1e-10)
    a.run(0.004, h=1e-4)
    state = a.fmu.getFMUstate()
    straight = a.run(0.02, h=1e-4)
    again = []
    for _ in range(2):
        a.fmu.setFMUstate(state)
        a.t = 0.004
        again.append(a.run(0.02, h=1e-4))
    a.fmu.freeFMUstate(state)
    a.free()
    assert np.array_equal(again[0], again[1])
    assert np.max(np.abs(again[0] - straight)) < 1e-8 * straight.max()


# -- one source of truth: the compiled backend's C in sources/ and the binary -
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_the_fmu_carries_the_compiled_backends_own_explicit_method(fmi_version):
    """sources/ holds native/c/shared/pdbfs_erk.* unchanged but for the private-names
    line on top of the .c, declared for a source build; its functions get the
    FMU's private names."""
    with zipfile.ZipFile(T.built_fmu("paper", fmi_version)) as z:
        names = z.namelist()
        for f in ERK_DRIVER:
            text = z.read(f"sources/{f.name}").decode()
            assert text.endswith(f.read_text()) and len(text) - len(f.read_text()) < 200, f.name
        private = z.read("sources/pdbfs_names.h").decode()
        declared = z.read("modelDescription.xml" if fmi_version == 2
                          else "sources/buildDescription.xml").decode()
    assert "sources/stiffness.c" in names
    for fn in ("pdbfs_erk_advance", "pdbfs_erk_start", "stiffness_choose"):
        assert re.search(rf"#define {fn} PDBFS_NS\({fn}\)", private), fn
    for c in ("pdbfs_erk.c", "stiffness.c"):
        assert f'"{c}"' in declared, c


@pytest.mark.skipif(shutil.which("cmake") is None, reason="the source build needs CMake")
def test_the_source_fmu_built_by_cmake_runs_the_explicit_method(tmp_path):
    """sources/ built by FMPy's CMake project (the system's cc where there is
    one, else zig cc): its explicit and auto runs are the shipped binary's,
    to roundoff (two compilers order a few operations differently)."""
    built = T.source_build(T.built_fmu("paper"), tmp_path / "src")
    shipped = {m: paper_run(2, m, 1e-8, tmp_path / "bin") for m in (ERK, AUTO)}
    peak = shipped[ERK].max()
    for m in (ERK, AUTO):
        a = Cs(str(built), tmp_path, f"src{m}")
        a.init(m, 1e-8)
        p = np.r_[a.get("oil.pressure"), a.run(0.02)]
        a.free()
        assert np.max(np.abs(p - shipped[m])) < 1e-9 * peak, m


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_solver_method_declares_its_four_items(fmi_version):
    md = fmpy.read_model_description(T.built_fmu("paper", fmi_version))
    var = next(v for v in md.modelVariables if v.name == "solver.method")
    items = {i.name: int(i.value) for i in var.declaredType.items}
    assert items == {"auto": AUTO, "BDF": BDF, "Adams": ADAMS, "ERK": ERK}
    assert int(var.start) == AUTO and "explicit Runge-Kutta" in var.description
    assert all(i.description for i in var.declaredType.items)


def test_model_exchange_takes_its_fmu_state_back_under_auto(tmp_path):
    """solver.method auto means nothing to Model Exchange: its FMU state
    after initialisation is given back and taken (regression: the state said
    the method in use was auto, and was refused as invalid)."""
    from fmpy.fmi2 import FMU2Model
    path = T.built_fmu("paper")
    md = fmpy.read_model_description(path)
    rec = T.Recorder("me-auto")
    fmu = FMU2Model(guid=md.guid, unzipDirectory=fmpy.extract(path, unzipdir=str(tmp_path / "me")),
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName="me-auto")
    fmu.instantiate(callbacks=rec.callbacks)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    state = fmu.getFMUstate()
    fmu.setFMUstate(state)
    fmu.freeFMUstate(state)
    assert not rec.errors()
    fmu.terminate()
    fmu.freeInstance()
