"""The thresholds of ``method="auto"``, one rule for every path: the compiled
and CasADi backends (pdbfs.simulation.stiffness, which computes the modes)
and the FMU's co-simulation (its C decides at initialisation with these
numbers, written into pdbfs_model.h)."""

#: Adams steps over the run beyond which a fast decaying mode makes BDF the
#: cheaper method (BDF's own accuracy-limited step count on impact pulses at
#: rtol 1e-8 is of this order: 5,000-50,000 on the rigs here)
STIFF_STEPS = 5e4

#: above this many states, only the eigenvalues of largest modulus
DENSE_UP_TO = 400

#: the explicit Runge-Kutta method is taken for runs up to this many radians
#: of the fastest mode: beyond, its steps are limited by stability rather
#: than accuracy, where it wanders (measured on the drop rig over 0.27 s,
#: 1,900 rad of the breech mode: the piston at rest drifted 1e-9 m/s at rtol
#: 1e-9 and 2e-8 at 1e-10, Adams 9e-11); the paper rig's 20 ms are 140 rad
ERK_RADIANS = 1000.0
