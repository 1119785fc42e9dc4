"""Partial bases of the blocks (after Modelica.Blocks.Interfaces): a block
with one output ``y`` (SO), one input ``u`` and one output ``y`` (SISO),
several inputs ``u1 .. un`` and one output ``y`` (MISO).

A block's ``unit`` (a constructor argument, "1" by default) is the unit of
its signals and of the parameters that carry a signal's value (a step's
height, a limiter's bounds, a start value). A block with a gain (Gain,
Integrator, FirstOrder, SecondOrder, PID) may take its input in another
unit, ``input_unit``: its gain converts. ``connect()`` joins signals of one
unit only ("1" the same as none); pdbfs converts no unit along a connection.
"""
from __future__ import annotations

from pdbfs.errors import ParameterError
from pdbfs.modelling import Component, Parameter, SignalInput, SignalOutput


class Block(Component):
    """Base of every block: a component of signals only, whose signals carry
    the unit ``unit`` (SI text such as "N", "Pa", "m/s"; "1" for a plain
    number).

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    pressure_bound = {}      # signals carry no energy (modelling.pressure_bound)

    def __init__(self, unit: str = "1", **params):
        if not isinstance(unit, str) or not unit.strip():
            raise ParameterError(f"{type(self).__name__}: unit = {unit!r} must be a unit's "
                                 "text, such as 'N', 'Pa' or '1'")
        self._unit = unit.strip()
        super().__init__(**params)

    def signal_parameter(self, default, description: str, **limits) -> Parameter:
        """A parameter in the unit of the block's signals, to declare in
        ``declare()``: ``self.offset = self.signal_parameter(0.0, "...")``.

        Parameters
        ----------
        default : float
            Its default value, in the block's unit.
        description : str
            What it means.
        **limits
            ``min``, ``max``, ``positive``, ``tunable``, as Parameter takes them.

        Returns
        -------
        Parameter
            The declaration.
        """
        return Parameter(default, self._unit, description, **limits)


class SO(Block):
    """A block with one output signal ``y``.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    output_description = "Output signal"

    def declare(self):
        self.y = SignalOutput(self._unit, self.output_description)


class SISO(SO):
    """A block with one input signal ``u`` and one output signal ``y``.
    ``input_unit`` (where the class ``converts``: a block with a gain) is
    the unit of ``u``, the output's by default.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    input_unit : None
        Not taken: its input is in the unit of its output (only a block with a
        gain converts; given, it is refused).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or an input_unit where the class does not convert.
    """

    input_description = "Input signal"
    #: whether ``u`` may be in another unit than ``y`` (the gain converts)
    converts = False

    def __init__(self, unit: str = "1", input_unit: str | None = None, **params):
        if input_unit is not None and not self.converts:
            raise ParameterError(f"{type(self).__name__}: takes its input in the unit of its "
                                 f"output (unit = {unit!r}); input_unit is for a block with a "
                                 "gain")
        if input_unit is not None and (not isinstance(input_unit, str) or not input_unit.strip()):
            raise ParameterError(f"{type(self).__name__}: input_unit = {input_unit!r} must be a "
                                 "unit's text, such as 'N', 'Pa' or '1'")
        self._input_unit = None if input_unit is None else input_unit.strip()
        super().__init__(unit=unit, **params)

    def declare(self):
        self.u = SignalInput(self._input_unit or self._unit, self.input_description)
        super().declare()


class MISO(SO):
    """A block with ``n`` input signals ``u1 .. un`` (``n`` >= 1, a
    constructor argument, 2 by default) and one output ``y``.

    Connectors: the signal inputs ``u1``, ``u2`` .. ``un`` and the output ``y``.

    Parameters
    ----------
    n : int
        The number of inputs ``u1 .. un`` (>= 1).
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or n that is not a whole number >= 1.
    """

    def __init__(self, n: int = 2, unit: str = "1", **params):
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise ParameterError(f"{type(self).__name__}: n = {n!r} must be a whole number of "
                                 "inputs >= 1")
        self._n = n
        super().__init__(unit=unit, **params)

    def declare(self):
        for i in range(1, self._n + 1):
            setattr(self, f"u{i}", SignalInput(self._unit, f"Input signal {i}"))
        super().declare()

    def input_values(self) -> list:
        """The input signals' values, u1 first."""
        return [getattr(self, f"u{i}").value for i in range(1, self._n + 1)]
