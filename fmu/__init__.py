"""FMI export: a rig's DAE -> C code -> one FMU (FMI 2.0, or 3.0 with
``fmi_version=3``) with Model Exchange and Co-Simulation (an explicit
Runge-Kutta method or CVODE inside, ``solver.method``),
validated by fmpy, simulated by any importer.

    from pdbfs.fmu import export_fmu
    export_fmu(rig.compile(), "rig.fmu")        # or rig.export_fmu("rig.fmu")
    export_ssp("loop.ssp", {"plant": "plant.fmu", "controller": "controller.fmu"},
               [("plant.sensor.y", "controller.measured"), ("controller.pid.y", "plant.opening")])

    variables       the FMU's variables, value references and model structure
    description     modelDescription.xml (FMI 2.0, with <SourceFiles>)
    description3    modelDescription.xml and buildDescription.xml (FMI 3.0)
    units           unit strings -> FMI base units
    platforms       the five platform tuples (x86_64/aarch64 Linux, x86_64 Windows,
                    x86_64/aarch64 macOS) and their aliases; each built by zig cc;
                    prepare_offline(): the sources and every CVODE built ahead
    sources         SUNDIALS' CVODE sources for a source FMU
    derivatives     CasADi's forward and reverse AD for the directional and adjoint derivatives
    symbols         private names for everything but the FMI functions (pdbfs_names.h)
    documentation   documentation/index.html
    rights          version, author, license and copyright (default: pdbfs's BSD-3-Clause;
                    the user's kept before pdbfs's and CVODES's), documentation/licenses/
    header          pdbfs_model.h: sizes, value references, the parameter table
    export          the export: checks, C sources, compile, zip
    ssp             a system of FMUs connected output to input as an SSP 1.0 file (export_ssp)
    master          a co-simulation master on FMPy that runs such a system (cosimulate):
                    inputs held over a step, or interpolated (FMI 2.0)
The FMU's C is pdbfs.native's: native/c/fmu/ holds the generic C of every
FMU (the life cycle, lifecycle.c, calling down into one wrapper per FMI
version, fmi2_* and fmi3_*, over the same model code, co-simulation loop and
derivatives, derivatives.c; stiffness.c: solver.method auto at
initialisation), native/c/shared/ the solvers it shares with the compiled
backend (pdbfs_cvode.c, pdbfs_erk.c).

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, CVODE). Never the simulation or the studies.
"""
from .export import check_experiment, check_fmi_version, check_fmu_name, export_fmu
from .master import CoSimulation, cosimulate
from .rights import check_rights
from .ssp import export_ssp, read_interface, read_ssp

__all__ = ["check_experiment", "check_fmi_version", "check_fmu_name", "check_rights", "export_fmu", "export_ssp",
           "cosimulate", "CoSimulation", "read_interface", "read_ssp"]
