"""What a run gives: the Result, its summary, and what is read off the solution.

    result.py      Result: arrays by dotted name, values off the grid, peaks
                   and crossings located on the solution, CSV, pandas, plot
    source.py      RunSource: what a Result asks of the run that made it
    summary.py     what a test engineer reads off a pulse (peak pressure,
                   duration, restitution, complete or not, each blow)
    summary_run.py the summary's own solution: a fixed grid, until the pulse is over
    c_summary.py   a compiled run's summary from the run itself (no second run),
                   and the summary driver's keys in its order
    impulse.py     impulses and Guo & Batzer's restitution of sampled forces
    contact_impulse.py  a contact force's impulse integrated by the solver (a
                   quadrature on the solution: the summary's restitution)
    hermite.py     peaks, crossings and integrals located on the solution's cubics
    on_grid.py     outputs, rates and event indicators on a whole grid (mixed into
                   the Simulator)
    plotting.py    matplotlib plots of a Result
    exports.py     a Result as a dict, CSV (written a block at a time), pandas,
                   a plot, and its readable line and HTML table
    reprs.py       one readable line and an HTML table for Result, Rig and the studies

A Result integrates again (values off the grid, the summary's own solution)
through the run it was made by (a RunSource), never by importing it.

May import: pdbfs.errors, pdbfs.files, pdbfs.modelling, pdbfs.native,
pdbfs.simulation.state and pdbfs.simulation.setup; never run or analysis
(run makes Results), not even for annotations.
"""
