"""FMI export: a rig's DAE -> C code -> one FMU (FMI 2.0, or 3.0 with
``fmi_version=3``) with Model Exchange and Co-Simulation (CVODE inside),
validated by fmpy, simulated by any importer.

    from pdbfs.fmu import export_fmu
    export_fmu(rig.compile(), "rig.fmu")        # or rig.export_fmu("rig.fmu")

    variables.py    the FMU's variables, value references and model structure
    description.py  modelDescription.xml (FMI 2.0, with <SourceFiles>)
    description3.py modelDescription.xml and buildDescription.xml (FMI 3.0)
    units.py        unit strings -> FMI base units
    platforms.py    linux64, win64 (MinGW-w64): which can be built, and the build
    sources.py      SUNDIALS' CVODE sources for a source FMU
    derivatives.py  CasADi's forward and reverse AD for the directional and adjoint derivatives
    symbols.py      private names for everything but the FMI functions (pdbfs_names.h)
    documentation.py documentation/index.html
    export.py       pdbfs_model.h, compile, zip
    c/              the generic C: one wrapper per FMI version (fmi2_*, fmi3_*)
                    over the same model code and co-simulation loop

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, CVODE). Never the simulation or the studies.
"""
from .export import check_fmi_version, export_fmu

__all__ = ["check_fmi_version", "export_fmu"]
