"""FMI 2.0 export of pdbfs rigs (Model Exchange + Co-Simulation with CVODE).

    from pdbfs.fmu import export_fmu
    export_fmu(rig.compile(), "rig.fmu")
"""
from .export import export_fmu

__all__ = ["export_fmu"]
