"""Inputs of a rig: values given from outside during a run (a command, a
measured trace, another model's output).

A component declares one with ``self.signal = RigInput(unit, description,
start)`` in ``declare()`` (pdbfs.components.blocks.Input does); the input is
named by that component's dotted path. In the equations the attribute is
the expression

    u(t) = u + du * (t - t_ref)

of three symbols that flattening renames and structural analysis appends
to the DAE's parameter vector ``p``, after the free parameters: the value
``u`` at ``t_ref`` (named like the input, ``command``), its slope ``du``
(``der(command)``) and one ``t_ref`` shared by every input. A run holds
them constant over a segment between the inputs' breakpoints and sets
them anew at each (piecewise-linear inputs); a slope of 0 holds an input.
Every back end and the generated C take them as parameters, unchanged.

Index reduction may differentiate an input once (its derivative within a
segment is ``du``); a second derivative (an input prescribing a position
whose acceleration the rig needs) would miss the impulses at the
breakpoints, so it is refused, naming the input.
"""
from __future__ import annotations

import math

import casadi as ca

from pdbfs.errors import ModelError, ParameterError

from .symbols import time

#: where the inputs' current segment starts (one for every input of a rig)
T_REF = ca.SX.sym("t_ref(inputs)")


class RigInput:
    """The declaration of an input of the rig: its unit, what it is, and its
    ``start`` value (held while no other value is given)."""

    def __init__(self, unit: str, description: str, start: float = 0.0):
        try:
            value = float(start)
        except (TypeError, ValueError):
            raise ParameterError(f"input start = {start!r}: must be a number") from None
        if not math.isfinite(value):
            raise ParameterError(f"input start = {start!r}: must be finite")
        self.unit, self.description, self.start = unit, description, value


class InputSlot:
    """A RigInput of one component instance: its local symbols (renamed by
    flattening) and the expression the component's equations use."""

    def __init__(self, decl: RigInput, name: str):
        self.decl, self.name = decl, name
        self.value = ca.SX.sym(f"{name}.u")
        self.slope = ca.SX.sym(f"{name}.du")
        self.expr = self.value + self.slope * (time - T_REF)


def input_name(comp, attribute: str) -> str:
    """The name of the input a component declares: its dotted path (the
    attribute's name at the top of the rig)."""
    return comp.path() or attribute


def refuse_second_derivative(expr, slopes: dict, t) -> None:
    """Before ``expr`` is differentiated in time: where it holds an input's
    slope other than in the input's own u + du (t - t_ref) (a derivative of
    the input already), its derivative needs the input's second derivative:
    refused, naming the input. ``slopes``: slope symbol name -> input name.
    Otherwise the slopes are constants of the segment (their own derivative 0)."""
    found = [s for s in ca.symvar(expr) if s.name() in slopes] if slopes else []
    if not found:
        return
    at_ref = ca.substitute(expr, t, T_REF)        # u = its value there: no du left in it
    for s in found:
        if ca.depends_on(at_ref, s):
            raise second_derivative(slopes[s.name()])


def second_derivative(name: str) -> ModelError:
    """The refusal of an input that index reduction would differentiate twice."""
    return ModelError(
        f"input {name}: the rig needs its second derivative (index reduction differentiates "
        "it twice, e.g. a prescribed position whose acceleration a mass needs); an input is "
        "piecewise linear, its second derivative impulses at the breakpoints: drive a force, "
        "or filter the input (a SecondOrder block) before it prescribes a position")
