"""The passes of structural analysis that structure.py runs on a rig's flat
equations: alias elimination, matching and BLT sorting, index reduction,
the starts of states index reduction made algebraic, and the smoothness of
differentiated signals.

May import what pdbfs.modelling may (pdbfs.errors) and the modelling
compiler's own helpers (symbols, rig inputs, CasADi helpers).
"""
