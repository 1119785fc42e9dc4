"""The modelling compiler: declarations, connections, flattening, structural
analysis, and the one CasADi DAE every back end consumes.

    symbols.py     Parameter, Variable, State, der(), eq(), time
    rig_inputs.py  RigInput: an input of the rig, u + du (t - t_ref) in p
    connectors.py  Flange (position across, force through), HydraulicPort (pressure
                   across, volume flow through), HeatPort (temperature across, heat
                   flow through), signal connectors
    component.py   Component: declare(), equations(), connect(), compile()
    flatten.py     a component tree -> one flat list of symbols and equations
    structure.py   flat equations -> DAE: parameter bindings, then its passes (passes/):
      aliases.py     alias elimination (derivatives included)
      blt.py         matching, BLT sorting, symbolic solution of linear blocks
      index.py       index reduction to any index (Pantelides, dummy derivatives)
      reduced_start.py  declared starts of states index reduction made algebraic
      smoothness.py  signals it differentiates must not jump where they switch
    dae.py         the DAE (x, z, p, ode, alg, outputs, events) and its infos
    dae_cache.py   compiled DAEs kept on disk, keyed by the rig's declaration and sources
    pressure_bound.py  the pressures an oil circuit's sources bound (a run's check)

May import: pdbfs.errors only. Nothing here knows about solvers, C code,
FMUs or studies.
"""
from .component import Component, switch_times
from .connectors import Flange, HeatPort, HydraulicPort, SignalInput, SignalOutput
from .dae import DAE, InputInfo, ParamInfo, VarInfo
from .rig_inputs import RigInput
from .symbols import (Parameter, State, Variable, check_value, der, eq, quantity, time,
                      within_limits)

__all__ = ["Component", "Flange", "HeatPort", "HydraulicPort", "SignalInput", "SignalOutput", "DAE", "InputInfo",
           "ParamInfo", "RigInput", "VarInfo",
           "Parameter", "State", "Variable", "check_value", "der", "eq", "quantity", "switch_times", "time",
           "within_limits"]
