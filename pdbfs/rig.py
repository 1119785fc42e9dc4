"""Rig: a component made of connected components, that can be simulated and
exported. The modelling compiler knows only Component; this class joins it to
the back ends (simulation and FMU export), so that ``rig.simulate(...)`` and
``rig.export_fmu(...)`` read as they should."""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.modelling import Component
from pdbfs.simulation import MAX_NUM_STEPS, simulate

if TYPE_CHECKING:
    import os
    from pathlib import Path

    import pandas as pd
    from numpy.typing import ArrayLike

    from pdbfs.modelling import InputInfo, ParamInfo
    from pdbfs.simulation import Linearization, Result


class _OutputChecks:
    """What the rig layer keeps of one compiled rig (in ``DAE.companions``):
    the components' check_output methods, found once; a rig that changes is
    compiled again, and searched again."""

    __slots__ = ("checks",)

    def __init__(self, checks: list):
        self.checks = checks


class Rig(Component):
    """Base class of every rig: a component made of connected components,
    that can be simulated, linearized and exported as an FMU.

    A rig declares its components in ``declare()`` and connects their
    connectors there with ``connect()``. Optional class attributes:
    ``name`` (the DAE's and the FMU's name), ``summary_signals`` (which
    variable plays which role in a summary), ``default_t_end`` and
    ``default_n_out`` (the rig's own experiment).

    Parameters
    ----------
    **values : float
        Values of the rig's own declared parameters by name, SI units (its
        components' parameters are set per run, ``params={"hammer.m": ...}``).
    """

    def simulate(self, t_end: float = 0.02, n_out: int = 2001, *, t_out: ArrayLike | None = None,
                 params: Mapping[str, float] | None = None, start: Mapping[str, float] | None = None,
                 rtol: float | None = None, atol: float | None = None, method: str = "auto",
                 max_step: float | None = None, max_num_steps: int = MAX_NUM_STEPS,
                 backend: str = "auto", initial: str | Sequence[str] | None = None,
                 inputs: Mapping[str, object] | None = None) -> Result:
        """Simulate this rig from t = 0: the same run as ``pdbfs.simulate(rig, ...)``.

        Components with a ``check_output(dt_out, params)`` method (an
        ElasticBar, whose segments may be too coarse for the output rate) are
        asked first.

        Parameters
        ----------
        t_end : float
            End time of the run, s.
        n_out : int
            Number of output points, evenly spaced on [0, t_end].
        t_out : array_like, optional
            Output times, s, increasing from 0 (overrides ``t_end`` and ``n_out``).
        params : mapping of str to float, optional
            Parameter values by dotted name (``{"hammer.v0": 3.0}``), SI units;
            the rest keep their defaults.
        start : mapping of str to float, optional
            Start values by state name, SI units (for a free state: its guess).
        rtol, atol : float, optional
            Relative and absolute tolerances of the integrator (``atol`` in
            each state's unit). None: rtol 1e-8 (5e-8 for ``"erk"``), atol
            1e-10, or 1e-2 * rtol when rtol is below 1e-8.
        method : {"auto", "adams", "bdf", "erk"}
            Integration method; see ``pdbfs.simulate``.
        max_step : float, optional
            Largest internal step, s (None: no limit).
        max_num_steps : int
            Most internal steps between two output points.
        backend : {"auto", "c", "casadi"}
            Compiled C where it builds (ODE rigs), else SUNDIALS through CasADi.
        initial : str or sequence of str, optional
            None: the start as declared (free states solved from the initial
            equations); ``"steady"``: every state at rest; a list of state
            names: those at rest.
        inputs : mapping of str to trace, number or callable, optional
            Values of the rig's inputs by name (``rig.inputs()``): a trace
            ``(t, u)``, a number or a function of time; see ``pdbfs.simulate``.

        Returns
        -------
        Result
            Time and every variable, with peaks, crossings and the summary.

        Raises
        ------
        ParameterError
            A setting, parameter or start value that is refused, before any work.
        SolverError
            The integrator failed; the message says where and why.

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> rig = paper_rig()
        >>> res = rig.simulate(0.02, params={"hammer.v0": 3.0})
        >>> f"{res.summary()['peak_pressure'] / 1e6:.3g} MPa"
        '101 MPa'
        >>> f"{res.peak('contact.fc')[1] / 1e6:.3g} MN"
        '4.14 MN'
        """
        kwargs = {"n_out": n_out, "t_out": t_out, "params": params, "start": start,
                  "rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                  "max_num_steps": max_num_steps, "backend": backend, "initial": initial,
                  "inputs": inputs}
        checks = self._output_checks()
        if checks:
            _check_output(checks, t_end, kwargs)
        return simulate(self, t_end, **kwargs)

    def _output_checks(self) -> list:
        """The components' check_output methods, found once per compiled rig."""
        dae = self.compile()
        return (dae.companions.get(_OutputChecks) or self._find_output_checks(dae)).checks

    def _find_output_checks(self, dae) -> _OutputChecks:
        """The components' check_output methods, found now and kept with ``dae``."""
        checks = [c for c in (getattr(comp, "check_output", None) for comp in self.walk())
                  if c is not None]
        return dae.companions.setdefault(_OutputChecks, _OutputChecks(checks))

    def linearize(self, at: str | float = "start", inputs: str | Sequence[str] | None = None,
                  outputs: str | Sequence[str] | None = None,
                  params: Mapping[str, float] | None = None,
                  start: Mapping[str, float] | None = None,
                  initial: str | Sequence[str] | None = None, rtol: float = 1e-10,
                  atol: float = 1e-12) -> Linearization:
        """State-space matrices A, B, C, D of this rig at an operating point.

        Parameters
        ----------
        at : {"start", "steady"} or float
            The operating point: the start, every state at rest, or the state
            of a run from the start at this time, s.
        inputs : str or sequence of str, optional
            Names of the rig's inputs (held at their start values) and of its
            parameters, each once: the columns of B and D. A one-sided law
            exactly at its kink in one of them (a valve commanded to its
            closed stop) is taken on the side where the input acts and named
            in ``kinks``; where both sides act differently it is refused.
        outputs : str or sequence of str, optional
            Variable names, each once: the rows of C and D (default: the
            rig's outputs).
        params, start, initial
            As in ``simulate``.
        rtol, atol : float
            Tolerances of the run to ``at`` and of the steady state.

        Returns
        -------
        Linearization
            A, B, C, D with the names of their states, inputs and outputs.

        Examples
        --------
        The paper's rig near its peak pressure, hammer and piston in contact:

        >>> from pdbfs.models import paper_rig
        >>> lin = paper_rig().linearize(at=0.0055)
        >>> lin.states
        ['hammer.s', 'hammer.v', 'piston.s', 'piston.v', 'breech.s', 'breech.v']
        >>> [f"{m.frequency:.3g} Hz" for m in lin.modes()]
        ['39.5 Hz', '446 Hz', '1.13e+03 Hz']
        """
        kwargs = dict(inputs=inputs, outputs=outputs, params=params, start=start,
                      initial=initial, rtol=rtol, atol=atol)
        from pdbfs.simulation.analysis.linearize import linearize
        return linearize(self, at, **kwargs)

    def modes(self, at: str | float = "start", params: Mapping[str, float] | None = None,
              start: Mapping[str, float] | None = None,
              initial: str | Sequence[str] | None = None, rtol: float = 1e-10,
              atol: float = 1e-12) -> pd.DataFrame:
        """The rig's modes at an operating point, slowest first.

        Parameters
        ----------
        at, params, start, initial, rtol, atol
            As in ``linearize``.

        Returns
        -------
        pandas.DataFrame
            One row per mode: omega (rad/s), frequency (Hz), damping (ratio;
            NaN for a zero eigenvalue), shape (amplitude by state name) and
            eigenvalue (1/s).
        """
        kwargs = dict(params=params, start=start, initial=initial, rtol=rtol, atol=atol)
        from pdbfs.simulation.analysis.linearize import modes_frame
        return modes_frame(self.linearize(at, **kwargs).modes())

    def export_fmu(self, path: str | os.PathLike = "pdbfs.fmu", model_identifier: str | None = None,
                   *, stop_time: float | None = None, step_size: float | None = None,
                   tolerance: float = 1e-8, keep_build_dir: str | os.PathLike | None = None,
                   cflags: list[str] | None = None, fmi_version: int = 2,
                   platforms: list[str] | str | None = None, author: str | None = None,
                   license: str | None = None, copyright: str | None = None) -> Path:
        """Write an FMU of this rig (Model Exchange and Co-Simulation) and return its path.

        Parameters
        ----------
        path : str or os.PathLike
            The FMU file to write (its folder must exist).
        model_identifier : str, optional
            The C identifier of the FMU's binary (default: the rig's name).
        stop_time, step_size : float, optional
            The DefaultExperiment, s (default: the rig's own experiment,
            ``default_t_end`` and ``default_n_out``, else 0.02 s in 2000
            steps): a finite stop time > 0, a step in (0, stop_time].
        tolerance : float
            The DefaultExperiment's relative tolerance, also the default of
            the FMU's ``solver.rtol``, in [1e-15, 0.1].
        keep_build_dir : str or os.PathLike, optional
            A folder to keep the generated C sources and build files in.
        cflags : list of str, optional
            Extra flags for the C compiler.
        fmi_version : {2, 3}
            FMI 2.0 or FMI 3.0.
        platforms : str or list of str, optional
            Binaries to build: platform tuples (``"x86_64-linux"``,
            ``"x86_64-windows"``, ...), the aliases ``"linux64"`` and
            ``"win64"``, or ``"all"``; default: this machine's.
        author, license, copyright : str, optional
            Written to modelDescription.xml as given (default: no author,
            pdbfs's BSD-3-Clause licence and copyright).

        Returns
        -------
        pathlib.Path
            The FMU written.

        Raises
        ------
        ExportError
            Bad arguments (before any work), a rig with algebraic variables
            or whose equations use an input's rate, or a failed build;
            nothing is left at ``path`` then. The rig's inputs are the FMU's
            inputs.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> from pdbfs.models import paper_rig
        >>> folder = Path(tempfile.mkdtemp())
        >>> fmu = paper_rig().export_fmu(folder / "paper.fmu", fmi_version=3)
        >>> fmu.name, fmu.stat().st_size > 10_000
        ('paper.fmu', True)
        """
        kwargs = dict(model_identifier=model_identifier, tolerance=tolerance,
                      keep_build_dir=keep_build_dir, cflags=cflags, fmi_version=fmi_version,
                      platforms=platforms, author=author, license=license, copyright=copyright,
                      **{k: v for k, v in (("stop_time", stop_time), ("step_size", step_size))
                         if v is not None})
        from pdbfs.fmu import check_experiment, check_fmi_version, check_fmu_name, check_rights, export_fmu
        check_fmi_version(kwargs.get("fmi_version", 2))   # before the rig is compiled
        t_end = getattr(self, "default_t_end", 0.02)      # the rig's own experiment
        kwargs.setdefault("stop_time", t_end)
        if isinstance(kwargs["stop_time"], (int, float)):   # (else refused just below)
            kwargs.setdefault("step_size", kwargs["stop_time"] / (int(getattr(self, "default_n_out", 2001)) - 1))
        check_experiment(kwargs["stop_time"], kwargs.get("step_size"), tolerance)
        check_rights(**{k: kwargs.get(k) for k in ("author", "license", "copyright")})
        check_fmu_name(path)
        return export_fmu(self.compile(), path, **kwargs)

    def parameters(self) -> list[ParamInfo]:
        """The rig's free parameters (ParamInfo: name, value, unit, description), in the DAE's order.

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> p = paper_rig().parameters()[1]
        >>> p.name, p.value, p.unit
        ('hammer.m', 2948.4, 'kg')
        """
        return self.compile().params

    def inputs(self) -> list[InputInfo]:
        """The rig's inputs (InputInfo: name, unit, description, start), one per
        Input component: given to a run by ``simulate(..., inputs={name: ...})``,
        never parameters."""
        return list(self.compile().inputs)

    def _shown(self) -> tuple[str, list[tuple[str, str]]]:
        from pdbfs.errors import PdbfsError
        parts = [f"{n} ({type(c).__name__})" for n, c in self._children.items()]
        rows = []
        try:
            dae = self.compile()          # from the disk cache for pdbfs's own rigs
            rows.append(("size", f"{dae.x.numel()} states, {dae.z.numel()} algebraic, "
                                 f"{len(dae.params)} parameters"))
        except PdbfsError as err:
            rows.append(("size", f"does not compile: {str(err).splitlines()[0]}"))
        rows.append(("components", ", ".join(parts) or "none"))
        return f"{type(self).__name__} '{self.rig_name()}'", rows

    def __repr__(self) -> str:
        title, rows = self._shown()
        return f"<{title}: " + "; ".join(v for _, v in rows) + ">"

    def _repr_html_(self) -> str:
        from pdbfs.simulation.results.reprs import table
        return table(*self._shown())


def _check_output(checks, t_end, kwargs):
    """Ask the components' ``check_output`` methods (an ElasticBar's segments
    against the output step) before a run with these options."""
    t_out = kwargs.get("t_out")
    try:
        dt = float(np.min(np.diff(np.asarray(t_out, float)))) if t_out is not None else \
            float(t_end) / (int(kwargs.get("n_out", 2001)) - 1)
    except (TypeError, ValueError, ZeroDivisionError):
        return                    # bad settings: simulate() says what is wrong
    if not (np.isfinite(dt) and dt > 0):
        return
    for check in checks:
        check(dt, kwargs.get("params"))

