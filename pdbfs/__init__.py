"""pdbfs: acausal component models of impact test rigs.

components declare -> a rig connects -> flatten -> structural simplification
-> one CasADi DAE -> SUNDIALS (pdbfs.simulate) or an FMI 2.0 FMU (pdbfs.fmu).
"""
from .component import Component
from .connectors import Flange, SignalInput, SignalOutput
from .dae import DAE, ParamInfo, VarInfo
from .errors import ConnectError, ModelError, ParameterError, PdbfsError, SolverError
from .symbols import Parameter, State, Variable, der, eq, time

Rig = Component   # a rig is a component made of connected components

__all__ = ["Component", "Rig", "Flange", "SignalInput", "SignalOutput", "DAE", "ParamInfo",
           "VarInfo", "PdbfsError", "ParameterError", "ConnectError", "ModelError",
           "SolverError", "Parameter", "State", "Variable", "der", "eq", "time", "simulate",
           "Result", "sweep"]


def __getattr__(name):   # keep `import pdbfs` light: the solver loads on first use
    if name == "simulate":
        from .simulate import simulate
        return simulate
    if name == "Result":
        from .result import Result
        return Result
    if name == "sweep":
        from .sweep import sweep
        return sweep
    raise AttributeError(name)
