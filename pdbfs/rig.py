"""Rig: a component made of connected components, that can be simulated and
exported. The modelling compiler knows only Component; this class joins it to
the back ends (simulation and FMU export), so that ``rig.simulate(...)`` and
``rig.export_fmu(...)`` read as they should."""
from __future__ import annotations

import numpy as np

from pdbfs.modelling import Component
from pdbfs.simulation import Simulator, replay, simulate


class Rig(Component):
    """Base class of every rig. Optional class attributes: ``name`` (the
    DAE's and the FMU's name), ``summary_signals`` (which variable plays which
    role in a summary), ``default_t_end`` and ``default_n_out`` (the rig's own
    experiment)."""

    def simulate(self, t_end: float = 0.02, **kwargs):
        """Simulate this rig; see ``pdbfs.simulate`` for the arguments.
        Components with a ``check_output(dt_out, params)`` method (e.g. an
        ElasticBar, whose segments may be too coarse for the output rate)
        are asked first."""
        if not kwargs:
            # the rig's own run again: its plan replayed, nothing asked again (replay.py)
            dae = self._compiled
            plans = dae.__dict__.get("_own_plans") if dae is not None else None
            if plans and type(t_end) is float:
                own = plans.get(t_end)
                if own is not None and own[1].params is dae.params:
                    return replay.run(*own)
            if not self._output_checks():
                return replay.own(Simulator.of(self), t_end)
        self._check_output(t_end, kwargs)
        return simulate(self, t_end, **kwargs)

    def _check_output(self, t_end, kwargs):
        checks = self._output_checks()
        if not checks:
            return
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

    def _output_checks(self) -> list:
        """The components' check_output methods, found once per compiled rig
        (a rig changed since is compiled again, and searched again)."""
        dae = self.compile()
        checks = dae.__dict__.get("_output_checks")
        if checks is None:
            checks = [c for c in (getattr(comp, "check_output", None) for comp in self.walk())
                      if c is not None]
            dae.__dict__["_output_checks"] = checks
        return checks

    def linearize(self, at="start", **kwargs):
        """State-space matrices A, B, C, D at ``at`` ("start", "steady" or a
        time of a run, s); see pdbfs.simulation.linearize."""
        from pdbfs.simulation.linearize import linearize
        return linearize(self, at, **kwargs)

    def modes(self, at="start", **kwargs):
        """The rig's modes at ``at`` as a pandas DataFrame: omega (rad/s),
        frequency (Hz), damping (ratio; NaN for a zero eigenvalue), shape
        (amplitude by state name), eigenvalue; slowest first."""
        from pdbfs.simulation.linearize import modes_frame
        return modes_frame(self.linearize(at, **kwargs).modes())

    def export_fmu(self, path="pdbfs.fmu", **kwargs):
        """Write an FMI 2.0 FMU (co-simulation and model exchange) of this rig;
        ``fmi_version=3`` writes FMI 3.0."""
        from pathlib import Path

        from pdbfs.errors import ExportError
        from pdbfs.fmu import check_fmi_version, check_fmu_name, check_rights, export_fmu
        check_fmi_version(kwargs.get("fmi_version", 2))   # before the rig is compiled
        check_rights(**{k: kwargs.get(k) for k in ("author", "license", "copyright")})
        if Path(path).is_dir():
            raise ExportError(f"{path}: is a folder; name the FMU file to write")
        check_fmu_name(path)
        dae = self.compile()
        t_end = float(getattr(self, "default_t_end", 0.02))   # the rig's own experiment
        kwargs.setdefault("stop_time", t_end)
        kwargs.setdefault("step_size", t_end / (int(getattr(self, "default_n_out", 2001)) - 1))
        return export_fmu(dae, path, **kwargs)

    def parameters(self):
        """The rig's free parameters (ParamInfo), in the DAE's order."""
        return self.compile().params

    def inputs(self):
        """The rig's inputs (InputInfo: name, unit, description, start), one per
        Input component: given to a run by ``simulate(..., inputs={name: ...})``,
        never parameters."""
        return list(self.compile().inputs)
