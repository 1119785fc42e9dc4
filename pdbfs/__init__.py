"""pdbfs: acausal component models of impact test rigs.

components declare -> a rig connects -> flatten -> structural simplification
-> one CasADi DAE -> SUNDIALS (pdbfs.simulate) or an FMI 2.0 FMU (pdbfs.fmu)
-> studies on the same DAE (pdbfs.sweep, pdbfs.calibrate, pdbfs.design).

The stages, each a package whose docstring says what it may import:

    pdbfs.modelling    the modelling compiler: components -> one CasADi DAE
    pdbfs.native       C code generation and CVODE, shared by the two below
    pdbfs.simulation   SUNDIALS (through CasADi, or compiled) -> Result
    pdbfs.fmu          rig -> C code -> FMU
    pdbfs.studies      sweeps (local or Dask), sensitivity, calibration, design, the paper
    pdbfs.fatigue      a breech's fatigue from pressure histories (rainflow, S-N, Paris' law)
    pdbfs.cli          the command line, a thin layer over this API
    pdbfs.app          the workbench page in the browser (Dash), another thin layer

and the libraries on top of the compiler: pdbfs.components (the component
library: translational mechanics, and hydraulics in pdbfs.components.hydraulic)
and pdbfs.models (rigs built from it).
"""
from typing import TYPE_CHECKING

from .errors import (ConnectError, DataError, ExportError, ModelError, ParameterError,
                     PdbfsError, SolverError)
from .errors import PdbfsWarning, PulseIncompleteWarning, SampleTooSmallWarning

#: the API's names by the module that holds them, each imported on first use:
#: ``import pdbfs`` costs next to nothing (numpy and CasADi come with the
#: first rig), and the command line answers ``--help`` or a bad option
#: without them; the studies pull in scipy.stats, SALib, dask
_LAZY = {
    **dict.fromkeys(("DAE", "Component", "Flange", "HeatPort", "HydraulicPort", "Parameter",
                     "ParamInfo", "SignalInput", "SignalOutput", "State", "Variable", "VarInfo",
                     "der", "eq", "time"), "modelling"),
    "example_data": "files", "Rig": "rig",
    **dict.fromkeys(("Result", "simulate", "trajectory_function"), "simulation"),
    **dict.fromkeys(("calibrate", "design", "design_map", "sensitivity", "sweep"), "studies"),
}

if TYPE_CHECKING:     # the same names for static readers (type checkers, the reference's pages)
    from .files import example_data
    from .modelling import (DAE, Component, Flange, HeatPort, HydraulicPort, Parameter, ParamInfo,
                            SignalInput, SignalOutput, State, Variable, VarInfo, der, eq, time)
    from .rig import Rig
    from .simulation import Result, simulate, trajectory_function
    from .studies import calibrate, design, design_map, sensitivity, sweep


def __getattr__(name):
    where = _LAZY.get(name)
    if where is not None:
        import importlib
        value = getattr(importlib.import_module(f".{where}", __name__), name)
        globals()[name] = value        # found once: later reads are plain attribute reads
        return value
    if name == "__version__":          # the installed distribution's, read on first use
        from importlib.metadata import PackageNotFoundError, version
        try:
            return version("pdbfs")
        except PackageNotFoundError:   # run from a source tree that was never installed
            return "unknown"
    raise AttributeError(f"module 'pdbfs' has no attribute {name!r}")


def __dir__():
    return sorted({*globals(), *_LAZY})

__all__ = ["PdbfsError", "ParameterError", "ConnectError", "ModelError", "ExportError", "DataError",
           "SolverError", "PdbfsWarning", "PulseIncompleteWarning", "SampleTooSmallWarning", *_LAZY]
