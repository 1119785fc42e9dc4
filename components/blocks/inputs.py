"""Input: a signal that comes from outside the rig (a command, a measured
trace, another model's output), named by the component that holds it."""
from __future__ import annotations

from pdbfs.errors import ParameterError
from pdbfs.modelling import RigInput, SignalOutput, eq

from .interfaces import SO


class Input(SO):
    """An input of the rig, with the output signal ``y = u(t)``, the value a
    run gives it: ``self.command = Input("1")`` in a rig's ``declare()`` makes the rig's input ``command``
    (the component's dotted path, ``sub.command`` inside a sub-rig). ``unit``
    is the input's unit, ``start`` its value at the start and wherever no
    other value is given, ``description`` what it is.

    A run gives it with ``rig.simulate(t_end, inputs={"command": (t, u)})``
    (a trace, interpolated linearly; a number; or a function of time); an
    FMU of the rig has it as an input variable. It is not a parameter of
    the rig: ``rig.compile().inputs`` lists the rig's inputs.

    Connector: the signal output ``y``.

    Parameters
    ----------
    unit : str
        The input's unit (SI text; "1" for a plain number).
    start : float
        Its value at the start, and wherever a run gives none, in ``unit``.
    description : str
        What the input is (the FMU's input variable carries it).
    **params : float or casadi.SX
        Values of declared parameters (an Input declares none).

    Raises
    ------
    pdbfs.ParameterError
        For a description that is not text, a start that is not a finite
        number, or a unit that is not a unit's text.
    """

    #: marks the components that are inputs of the rig (found by walking the tree)
    rig_input = True

    def __init__(self, unit: str = "1", start=0.0, description: str = "", **params):
        if not isinstance(description, str):
            raise ParameterError(f"Input: description = {description!r} must be text")
        self._description = description.strip()
        try:
            self._start = RigInput(unit, self._description, start).start
        except ParameterError as err:
            raise ParameterError(f"Input: {err}") from None
        super().__init__(unit=unit, **params)

    def declare(self):
        what = self._description or "Input of the rig"
        self.y = SignalOutput(self._unit, what)
        # the input's value in the equations: u + du (t - t_ref), held at start by default
        self.signal = RigInput(self._unit, what, self._start)

    def input_name(self) -> str:
        """The name of the rig's input: the component's dotted path."""
        return self.path()

    def value(self):
        """The input's value in the equations: its value and slope over the
        run's current segment, ``u + du*(t - t_ref)``."""
        return self.signal

    def equations(self):
        return [eq(self.y.value, self.value())]
