"""Input: a signal that comes from outside the rig (a command, a measured
trace, another model's output), named by the component that holds it."""
from __future__ import annotations

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, SignalOutput, eq

from .interfaces import SO


class Input(SO):
    """An input of the rig, with the output signal ``y``: ``self.command =
    Input("1")`` in a rig's ``declare()`` makes the rig's input ``command``
    (the component's dotted path, ``sub.command`` inside a sub-rig). ``unit``
    is the input's unit, ``start`` its value at the start, ``description``
    what it is.

    For now the input holds its ``start`` value for the whole run: it is
    the parameter ``start`` (``params={"command.start": 2.0}`` sets it), so
    a rig using inputs simulates, sweeps and exports as any other. The one
    place where the value comes from is ``value()``: when the rig's inputs
    are given from outside (a trace, a callable, an FMU's input variable),
    ``value()`` is what returns the input's symbol instead of the parameter,
    and ``start`` remains the input's start value (the value where none is
    given).
    """

    #: marks the components that are inputs of the rig (found by walking the tree)
    rig_input = True

    def __init__(self, unit: str = "1", start=0.0, description: str = "", **params):
        if not isinstance(description, str):
            raise ParameterError(f"Input: description = {description!r} must be text")
        self._description = description.strip()
        super().__init__(unit=unit, start=start, **params)

    def declare(self):
        what = self._description or "Input of the rig"
        self.y = SignalOutput(self._unit, what)
        self.start = Parameter(0.0, self._unit, f"{what}: its value at the start (held while "
                               "no other is given)")

    def input_name(self) -> str:
        """The name of the rig's input: the component's dotted path."""
        return self.path()

    def value(self):
        """The input's value in the equations: today its ``start``
        parameter; the single place where the rig's input vector plugs in."""
        return self.start

    def equations(self):
        return [eq(self.y.value, self.value())]

