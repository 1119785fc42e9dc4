"""The commands that study a rig over many runs: ``sweep``, ``sensitivity``,
``reproduce``, ``calibrate``, ``design`` and ``design-map``, ``fatigue`` and
``campaign``.

May import what the command line may (pdbfs.cli's docstring) and the
command line's shared helpers; nothing here imports pdbfs.cli.rig.
"""
