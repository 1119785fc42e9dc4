"""A parameter the model cannot run at, though within its declared range
(oil.A at FMI's smallest positive Real, 2.2e-308 m2: an infinite pressure),
never passes as OK (issue 22): the step, or the read of the output, that
meets a non-finite state, derivative or output returns an error status with
one log line naming it, in Co-Simulation and Model Exchange, FMI 2.0 and 3.0."""
import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import fmu_support as T
from fmu_support import fmu_log_text

TINY = 2.2250738585072014e-308


def _declared_min(fmu, name):
    md = fmpy.read_model_description(fmu)
    return float(next(v for v in md.modelVariables if v.name == name).min)


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_infinite_pressure_is_an_error(fmi_version, fmi_type, capsys):
    fmu = T.built_fmu("paper", fmi_version)
    assert _declared_min(fmu, "oil.A") == TINY       # allowed by the declared range
    # FMPy's own logger prints (a logger of our own would stay behind in FMPy's
    # process-wide logger proxy after the run and be called by later FMUs)
    with pytest.raises(FMICallException):
        fmpy.simulate_fmu(fmu, fmi_type=fmi_type, stop_time=0.02, output_interval=1e-5,
                          start_values={"oil.A": TINY}, output=["oil.pressure"])
    out = fmu_log_text(capsys.readouterr().out)
    assert "output oil.pressure = inf at t=" in out and "check the parameters" in out, out


def test_the_same_step_with_a_real_area_is_ok():
    fmu = T.built_fmu("paper")
    r = fmpy.simulate_fmu(fmu, fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          start_values={"oil.A": 1e-3}, output=["oil.pressure"])
    assert np.all(np.isfinite(r["oil.pressure"])) and r["oil.pressure"].max() > 0
