"""FMI 2.0 export: a rig's DAE -> C code -> one FMU with Model Exchange and
Co-Simulation (CVODE inside), validated by fmpy, simulated by any importer.

    from pdbfs.fmu import export_fmu
    export_fmu(rig.compile(), "rig.fmu")        # or rig.export_fmu("rig.fmu")

    variables.py    the FMU's variables, value references and model structure
    description.py  modelDescription.xml (with <SourceFiles>)
    units.py        unit strings -> FMI base units
    platforms.py    linux64, win64 (MinGW-w64): which can be built, and the build
    sources.py      SUNDIALS' CVODE sources for a source FMU
    documentation.py documentation/index.html
    export.py       pdbfs_model.h, compile, zip
    c/              the generic C: FMI plumbing, Model Exchange, Co-Simulation

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, CVODE). Never the simulation or the studies.
"""
from .export import export_fmu

__all__ = ["export_fmu"]
