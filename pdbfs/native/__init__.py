"""Native code shared by the compiled simulation backend and the FMU: CasADi
C code generation of a DAE's functions, the compiler command, the CVODE
driver both link (``c/pdbfs_cvode.c``: CVODE through the rig's non-smooth
points with dense output), and the static SUNDIALS it needs (located, or
built once with SUNDIALS' own CMake by ``build_sundials.sh``).

    codegen.py          model functions -> C; compile and link commands
    initial.py          a solved start (initial equations) as a C-generatable
                        damped Newton of the parameters
    sundials.py         find_sundials(): an install prefix of CVODE
    tolerances.py       the one rule for relative tolerances (every path, the FMU's too)
    build_sundials.sh   SUNDIALS' CMake build, cached under ~/.cache/pdbfs
    c/pdbfs_cvode.[ch]  the CVODE driver

May import: pdbfs.errors and pdbfs.modelling. Nothing here knows about
FMI, results or studies.
"""
