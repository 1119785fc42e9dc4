"""Rig: a component made of connected components, that can be simulated and
exported. The modelling compiler knows only Component; this class joins it to
the back ends (simulation and FMU export), so that ``rig.simulate(...)`` and
``rig.export_fmu(...)`` read as they should."""
from __future__ import annotations

from pdbfs.modelling import Component


class Rig(Component):
    """Base class of every rig. Optional class attributes: ``name`` (the
    DAE's and the FMU's name), ``summary_signals`` (which variable plays which
    role in a summary), ``default_t_end`` and ``default_n_out`` (the rig's own
    experiment)."""

    def simulate(self, t_end: float = 0.02, **kwargs):
        """Simulate this rig; see ``pdbfs.simulate`` for the arguments."""
        from pdbfs.simulation import simulate
        return simulate(self, t_end, **kwargs)

    def export_fmu(self, path="pdbfs.fmu", **kwargs):
        """Write an FMI 2.0 FMU (co-simulation and model exchange) of this rig."""
        from pdbfs.fmu import export_fmu
        t_end = float(getattr(self, "default_t_end", 0.02))   # the rig's own experiment
        kwargs.setdefault("stop_time", t_end)
        kwargs.setdefault("step_size", t_end / (int(getattr(self, "default_n_out", 2001)) - 1))
        return export_fmu(self.compile(), path, **kwargs)

    def parameters(self):
        """The rig's free parameters (ParamInfo), in the DAE's order."""
        return self.compile().params
