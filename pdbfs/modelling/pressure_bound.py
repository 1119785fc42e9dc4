"""Which pressures of a rig its sources bound: a circuit of oil fed by
pressure sources through volumes, orifices and valves (and driven by signals,
which carry no energy) cannot hold a pressure above the highest of its
sources' and its start pressures. A run that shows one is not accurate
enough; the result's summary warns (simulation.results.summary.implausible).

A component says how it bounds the pressures by its class attribute
``pressure_bound``: None (the default) where it may raise a pressure above
every source's (a mass, a force, a flow source, heat, a component pdbfs
knows nothing of); else a dict of its variables' names, ``"sources"``
(pressures whose values over the run bound the circuit's), ``"stores"``
(pressures whose start values bound them, checked over the run), an empty
dict for a component that only passes on or dissipates energy.
"""
from __future__ import annotations


def pressure_bound(root) -> dict | None:
    """The bound of the pressures of the rig ``root``, or None.

    Parameters
    ----------
    root : Component
        The rig.

    Returns
    -------
    dict or None
        ``{"sources": [...], "stores": [...]}`` (the rig's variable names,
        dotted) where every component of the rig declares its bound and at
        least one gives a source or a store; None where any may raise a
        pressure by other means (no bound is known).
    """
    sources, stores = [], []
    for comp in root.walk():
        # (the base's equations() by name: component.py imports this module)
        own = comp._vars or type(comp).equations.__qualname__ != "Component.equations"
        if not own and comp._children:          # a container: its parts say
            continue
        bound = type(comp).pressure_bound
        if bound is None:
            return None
        prefix = f"{comp.path()}." if comp.path() else ""
        sources += [prefix + n for n in bound.get("sources", ())]
        stores += [prefix + n for n in bound.get("stores", ())]
    return {"sources": sources, "stores": stores} if sources or stores else None
