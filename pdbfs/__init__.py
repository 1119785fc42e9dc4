"""pdbfs: acausal component models of impact test rigs.

components declare -> a rig connects -> flatten -> structural simplification
-> one CasADi DAE -> SUNDIALS (pdbfs.simulate) or an FMI 2.0 FMU (pdbfs.fmu).
"""
from .component import Component
from .connectors import Flange, SignalInput, SignalOutput
from .dae import DAE, ParamInfo, VarInfo
from .errors import (ConnectError, ExportError, ModelError, ParameterError, PdbfsError,
                     SolverError)
from .result import Result
from .simulation import simulate
from .sweeps import sweep
from .symbols import Parameter, State, Variable, der, eq, time
from .trajectory import trajectory_function

Rig = Component   # a rig is a component made of connected components

__all__ = ["Component", "Rig", "Flange", "SignalInput", "SignalOutput", "DAE", "ParamInfo",
           "VarInfo", "PdbfsError", "ParameterError", "ConnectError", "ModelError", "ExportError",
           "SolverError", "Parameter", "State", "Variable", "der", "eq", "time", "simulate",
           "Result", "sweep", "trajectory_function"]
