"""FMI export: a rig's DAE -> C code -> one FMU (FMI 2.0, or 3.0 with
``fmi_version=3``) with Model Exchange and Co-Simulation (an explicit
Runge-Kutta method or CVODE inside, ``solver.method``),
validated by fmpy, simulated by any importer.

    from pdbfs.fmu import export_fmu
    export_fmu(rig.compile(), "rig.fmu")        # or rig.export_fmu("rig.fmu")

    variables.py    the FMU's variables, value references and model structure
    description.py  modelDescription.xml (FMI 2.0, with <SourceFiles>)
    description3.py modelDescription.xml and buildDescription.xml (FMI 3.0)
    units.py        unit strings -> FMI base units
    platforms.py    the five platform tuples (x86_64/aarch64 Linux, x86_64 Windows,
                    x86_64/aarch64 macOS) and their aliases; each built by zig cc;
                    prepare_offline(): the sources and every CVODE built ahead
    sources.py      SUNDIALS' CVODE sources for a source FMU
    derivatives.py  CasADi's forward and reverse AD for the directional and adjoint derivatives
    symbols.py      private names for everything but the FMI functions (pdbfs_names.h)
    documentation.py documentation/index.html
    rights.py       version, author, license and copyright (default: pdbfs's BSD-3-Clause;
                    the user's kept before pdbfs's and CVODES's), documentation/licenses/
    export.py       pdbfs_model.h, compile, zip
    c/              the generic C: the life cycle (lifecycle.c) calling down into one
                    wrapper per FMI version (fmi2_*, fmi3_*) over the same model
                    code, co-simulation loop and derivatives (derivatives.c);
                    stiffness.c: solver.method auto at initialisation
    (the co-simulation's solvers are pdbfs.native's C, native/c/pdbfs_cvode.c and
    native/c/pdbfs_erk.c, the compiled backend's own files)

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, CVODE). Never the simulation or the studies.
"""
from .export import check_fmi_version, check_fmu_name, export_fmu
from .rights import check_rights

__all__ = ["check_fmi_version", "check_fmu_name", "check_rights", "export_fmu"]
