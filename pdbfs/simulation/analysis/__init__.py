"""What is computed of a rig beyond a run: linearization, modes, and the
simulation as a differentiable function.

    linearize.py   A, B, C, D at an operating point (algebraic variables
                   eliminated), modes: omega, frequency, damping, shape
    kinks.py       one-sided laws exactly at their kink at that point: the side linearized
    trajectory.py  the simulation as a differentiable CasADi Function of
                   chosen parameters (CVODES sensitivities)
    driven_trajectory.py  a run with inputs as CasADi expressions of parameters
                   (calibration and design with a measured command)

May import: pdbfs.errors, pdbfs.files, pdbfs.modelling, pdbfs.native and every
other part of pdbfs.simulation (state, setup, results, run).
"""
