"""The commands about one rig: ``simulate``, ``params`` and ``export-fmu``
(simulate.py), ``export-ssp``, ``modes``, ``linearize`` and ``rigs``.

May import what the command line may (pdbfs.cli's docstring) and the
command line's shared helpers; nothing here imports pdbfs.cli.studies.
"""
