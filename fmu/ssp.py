"""A system of FMUs as an SSP file (System Structure and Parameterization
1.0): a zip holding ``SystemStructure.ssd``, which names the components (the
FMUs, stored under ``resources/``), each one's connectors (its FMU's inputs
and outputs) and the connections from outputs to inputs, with the units the
connectors use and a default experiment.

    export_ssp("loop.ssp", {"plant": "plant.fmu", "controller": "controller.fmu"},
               [("plant.sensor.y", "controller.measured"),
                ("controller.pid.y", "plant.opening")], stop_time=0.02)

Any FMI 2.0 or 3.0 FMU with Co-Simulation can be a component; a connection
joins an output to an input of the same type and unit. ``read_interface``
reads what an FMU offers; ``read_ssp`` reads a system back (the FMU
co-simulation master of ``master.py`` runs it).
"""
from __future__ import annotations

import os
import re
import zipfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from xml.etree import ElementTree as ET
from xml.sax.saxutils import quoteattr

from pdbfs.errors import ExportError
from pdbfs.files import whole

#: the SSP 1.0 namespaces of SystemStructure.ssd
NS = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
      "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon"}
#: the date of every entry of the zip (as an FMU's): the same system gives the same bytes
ZIP_DATE = (1980, 1, 1, 0, 0, 0)
_REAL = {"Real", "Float64", "Float32"}


@dataclass
class Variable:
    """An input or output of an FMU: its type (FMI element name) and unit."""

    name: str
    type: str
    unit: str | None = None


@dataclass
class FmuInterface:
    """What a system needs to know of an FMU: its FMI version, whether it
    offers Co-Simulation, its inputs and outputs, its units' definitions
    (name -> BaseUnit attributes, None where it gives none) and its default
    stop time."""

    path: Path
    fmi_version: str
    model_name: str
    cosimulation: bool
    inputs: dict[str, Variable] = field(default_factory=dict)
    outputs: dict[str, Variable] = field(default_factory=dict)
    units: dict[str, dict | None] = field(default_factory=dict)
    stop_time: float | None = None


def read_interface(fmu: str | os.PathLike) -> FmuInterface:
    """What a system needs to know of an FMU, read from its
    modelDescription.xml: its FMI version, whether it offers Co-Simulation,
    its inputs and outputs with their units, and its default stop time.

    Parameters
    ----------
    fmu : str or os.PathLike
        The FMU file (FMI 2.0 or 3.0).

    Returns
    -------
    FmuInterface
        ``path``, ``fmi_version``, ``model_name``, ``cosimulation``,
        ``inputs`` and ``outputs`` (name -> Variable: name, type, unit),
        ``units`` (name -> its BaseUnit's attributes) and ``stop_time``.

    Raises
    ------
    pdbfs.ExportError
        In one line, for a missing file or one that is not an FMI 2.0 or
        3.0 FMU.
    """
    if not str(os.fspath(fmu)).strip():
        raise ExportError("an FMU's file name is empty: name the FMU file")
    path = Path(fmu)
    if path.is_dir():
        raise ExportError(f"{path} is a folder, not an FMU file: name the .fmu file")
    if not path.is_file():
        raise ExportError(f"{path}: no such FMU file")
    try:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
    except KeyError:
        raise ExportError(f"{path}: not an FMU: the zip holds no modelDescription.xml") from None
    except (zipfile.BadZipFile, ET.ParseError, OSError) as err:
        raise ExportError(f"{path}: not an FMU (a zip with modelDescription.xml): {err}") from None
    version = root.get("fmiVersion", "")
    if not version.startswith(("2.", "3.")):
        raise ExportError(f"{path}: FMI version {version or '(none)'}; a system takes FMI 2.0 or 3.0 FMUs")
    out = FmuInterface(path, version, root.get("modelName", path.stem), root.find("CoSimulation") is not None)
    for u in root.iter("Unit"):
        base = u.find("BaseUnit")
        out.units[u.get("name")] = dict(base.attrib) if base is not None else None
    exp = root.find("DefaultExperiment")
    if exp is not None and exp.get("stopTime") is not None:
        out.stop_time = float(exp.get("stopTime"))
    for v in _variables(root, version):
        where = {"input": out.inputs, "output": out.outputs}.get(v[1])
        if where is not None:
            where[v[0]] = Variable(v[0], v[2], v[3])
    return out


def _variables(root, version: str):
    """(name, causality, type, unit) of every variable of a modelDescription."""
    if version.startswith("2."):
        for sv in root.iter("ScalarVariable"):
            typ = next(iter(sv), None)
            if typ is not None:
                yield sv.get("name"), sv.get("causality", "local"), typ.tag, typ.get("unit")
        return
    mv = root.find("ModelVariables")
    for v in (mv if mv is not None else []):
        yield v.get("name"), v.get("causality", "local"), v.tag, v.get("unit")


def _split(end: str, what: str, fmus: Mapping) -> tuple[str, str]:
    element, dot, variable = str(end).partition(".")
    if not dot or not variable:
        raise ExportError(f"connection {what} {end!r}: give ELEMENT.VARIABLE (e.g. plant.sensor.y)")
    if element not in fmus:
        raise ExportError(f"connection {what} {end!r}: no component {element!r}; the components are "
                          + ", ".join(fmus))
    return element, variable


def check_connections(interfaces: Mapping[str, FmuInterface],
                      connections: Iterable) -> list[tuple[str, str, str, str]]:
    """The connections as (start element, output, end element, input), each
    checked: an output to an input of the same type and unit, each input
    fed once. An ExportError in one line names the first that is not."""
    out, fed = [], {}
    for c in connections:
        if isinstance(c, str) or len(c) != 2:
            raise ExportError(f"connection {c!r}: give a pair (output, input), e.g. "
                              "('plant.sensor.y', 'controller.measured')")
        (a, av), (b, bv) = _split(c[0], "from", interfaces), _split(c[1], "to", interfaces)
        src, dst = interfaces[a], interfaces[b]
        if av not in src.outputs:
            raise ExportError(f"connection from {c[0]}: {av!r} is not an output of {a} ({src.path.name}); "
                              f"its outputs: {', '.join(src.outputs) or 'none'}")
        if bv not in dst.inputs:
            raise ExportError(f"connection to {c[1]}: {bv!r} is not an input of {b} ({dst.path.name}); "
                              f"its inputs: {', '.join(dst.inputs) or 'none'}")
        o, i = src.outputs[av], dst.inputs[bv]
        if (o.type in _REAL) != (i.type in _REAL) or (o.type not in _REAL and o.type != i.type):
            raise ExportError(f"connection {c[0]} -> {c[1]}: an output of type {o.type} cannot feed an "
                              f"input of type {i.type}")
        if (o.unit or "1") != (i.unit or "1"):
            raise ExportError(f"connection {c[0]} -> {c[1]}: the output is in {o.unit or '1'}, the input in "
                              f"{i.unit or '1'}; connect signals of one unit (a Gain block converts)")
        if (b, bv) in fed:
            raise ExportError(f"input {c[1]} is fed twice (from {fed[(b, bv)]} and {c[0]}); an input takes "
                              "one output")
        fed[(b, bv)] = c[0]
        out.append((a, av, b, bv))
    return out


def check_ssp_target(path: str | os.PathLike) -> None:
    """Refuse, before any work, an SSP path that does not end in ``.ssp``,
    is a folder, or lies in a folder that does not exist."""
    path = Path(path)
    if path.suffix.lower() != ".ssp":
        raise ExportError(f"{path}: an SSP file's name ends in .ssp; name it e.g. "
                          f"{path.with_suffix('.ssp').name}")
    if path.is_dir():
        raise ExportError(f"{path} is a folder: give the SSP file's name (e.g. {path / 'system.ssp'})")
    if not path.parent.is_dir():
        raise ExportError(f"{path}: the folder {path.parent} does not exist")


def export_ssp(path: str | os.PathLike, fmus: Mapping[str, str | os.PathLike], connections: Iterable,
               *, name: str = "system", start_time: float = 0.0, stop_time: float | None = None) -> Path:
    """Write a system of FMUs joined output to input as an SSP 1.0 file
    (System Structure and Parameterization), which SSP engines (Ecos,
    libcosim) and ``cosimulate`` run.

    The FMUs are stored under ``resources/`` in the file; each component
    lists its FMU's inputs and outputs as connectors (with their units,
    defined in the file when the FMU defines them).

    Parameters
    ----------
    path : str or os.PathLike
        The SSP file to write (``.ssp``).
    fmus : mapping of str to str or os.PathLike
        Component name (letters, digits and _) -> FMU file, each with
        Co-Simulation.
    connections : iterable of pairs of str
        ``("element.output", "element.input")``: an output to an input of
        the same unit, each input fed once (``pdbfs.models.LOOP`` joins the
        pulse plant and its controller).
    name : str
        The system's name.
    start_time : float
        The default experiment's start, s.
    stop_time : float, optional
        Its stop, s (default: the shortest default experiment of the FMUs).

    Returns
    -------
    pathlib.Path
        The SSP file written.

    Raises
    ------
    pdbfs.ExportError
        In one line, before anything is written, for a name that is not a
        component's, an FMU that is not one or offers no Co-Simulation, a
        connection that does not join an output to an input of the same
        unit, an input fed twice, or bad times.

    Examples
    --------
    The pulse plant and its PID controller as two FMUs, joined in a loop
    and run by pdbfs's own co-simulation master:

    >>> import tempfile
    >>> from pathlib import Path
    >>> from pdbfs.fmu import cosimulate, export_ssp
    >>> from pdbfs.models import LOOP, pulse_controller_rig, pulse_plant_rig
    >>> folder = Path(tempfile.mkdtemp())
    >>> plant = pulse_plant_rig().export_fmu(folder / "plant.fmu")
    >>> controller = pulse_controller_rig().export_fmu(folder / "controller.fmu")
    >>> LOOP
    (('plant.sensor.y', 'controller.measured'), ('controller.pid.y', 'plant.opening'))
    >>> ssp = export_ssp(folder / "loop.ssp", {"plant": plant, "controller": controller}, LOOP)
    >>> co = cosimulate(ssp, 1e-4, outputs=["plant.sensor.y"])
    >>> len(co.t), f"{co['plant.sensor.y'].max() / 1e6:.2g} MPa"
    (201, '93 MPa')
    """
    path = Path(path)
    check_ssp_target(path)
    if not isinstance(fmus, Mapping) or not fmus:
        raise ExportError("export_ssp: give the components as a mapping of names to FMU files, e.g. "
                          "{'plant': 'plant.fmu'}")
    for element in fmus:
        if not isinstance(element, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", element):
            raise ExportError(f"component name {element!r}: use letters, digits and _ (no dots: "
                              "a connection names ELEMENT.VARIABLE)")
    if not isinstance(name, str) or not name.strip():
        raise ExportError(f"system name {name!r}: give a name")
    interfaces = {e: read_interface(f) for e, f in fmus.items()}
    for e, i in interfaces.items():
        if not i.cosimulation:
            raise ExportError(f"component {e} ({i.path.name}) offers no Co-Simulation; a system's engine "
                              "steps its FMUs")
    joined = check_connections(interfaces, connections)
    stops = [i.stop_time for i in interfaces.values() if i.stop_time is not None]
    stop = stop_time if stop_time is not None else (min(stops) if stops else None)
    for what, t in (("start_time", start_time), ("stop_time", stop)):
        if t is not None and not (isinstance(t, (int, float)) and not isinstance(t, bool)
                                  and float(t) == float(t) and abs(float(t)) != float("inf")):
            raise ExportError(f"{what} = {t!r}: give a finite time in s")
    if stop is not None and not float(stop) > float(start_time):
        raise ExportError(f"stop_time {stop} s must be after start_time {start_time} s")
    ssd = system_description(name, interfaces, joined, float(start_time), None if stop is None else float(stop))
    with whole(path) as part, zipfile.ZipFile(part, "w", zipfile.ZIP_DEFLATED) as z:
        def put(arc: str, data: bytes) -> None:
            info = zipfile.ZipInfo(arc, ZIP_DATE)
            info.compress_type, info.external_attr, info.create_system = zipfile.ZIP_DEFLATED, 0o644 << 16, 3
            z.writestr(info, data)
        put("SystemStructure.ssd", ssd.encode())
        for e, i in interfaces.items():
            put(f"resources/{e}.fmu", i.path.read_bytes())
    return path


def system_description(name: str, interfaces: Mapping[str, FmuInterface], joined, start: float,
                       stop: float | None) -> str:
    """SystemStructure.ssd of the components ``interfaces`` and the checked connections ``joined``."""
    q = quoteattr
    units: dict[str, dict] = {}

    def real(v: Variable, i: FmuInterface) -> str:
        base = i.units.get(v.unit) if v.unit else None
        if base is None:          # a unit without base units: the FMU's own declaration stands
            return "<ssc:Real/>"
        units.setdefault(v.unit, base)
        return f"<ssc:Real unit={q(v.unit)}/>"
    L = ['<?xml version="1.0" encoding="UTF-8"?>',
         f'<ssd:SystemStructureDescription xmlns:ssc="{NS["ssc"]}" xmlns:ssd="{NS["ssd"]}" version="1.0" '
         f'name={q(name)} generationTool="pdbfs">',
         f'  <ssd:System name={q(name)}>', '    <ssd:Elements>']
    for e, i in interfaces.items():
        L.append(f'      <ssd:Component name={q(e)} type="application/x-fmu-sharedlibrary" '
                 f'source="resources/{e}.fmu" implementation="CoSimulation">')
        conns = [(v, "input") for v in i.inputs.values()] + [(v, "output") for v in i.outputs.values()]
        conns = [(v, k) for v, k in conns if v.type in _REAL]
        if conns:
            L.append("        <ssd:Connectors>")
            L += [f'          <ssd:Connector name={q(v.name)} kind="{k}">{real(v, i)}</ssd:Connector>'
                  for v, k in conns]
            L.append("        </ssd:Connectors>")
        L.append("      </ssd:Component>")
    L.append("    </ssd:Elements>")
    if joined:
        L.append("    <ssd:Connections>")
        L += [f'      <ssd:Connection startElement={q(a)} startConnector={q(av)} endElement={q(b)} '
              f'endConnector={q(bv)}/>' for a, av, b, bv in joined]
        L.append("    </ssd:Connections>")
    L.append("  </ssd:System>")
    if units:
        L.append("  <ssd:Units>")
        for u, base in units.items():
            attrs = " ".join(f"{k}={q(str(v))}" for k, v in base.items())
            L.append(f'    <ssc:Unit name={q(u)}><ssc:BaseUnit{" " + attrs if attrs else ""}/></ssc:Unit>')
        L.append("  </ssd:Units>")
    L.append(f'  <ssd:DefaultExperiment startTime="{start!r}"' + (f' stopTime="{stop!r}"' if stop is not None
                                                                     else "") + "/>")
    L.append("</ssd:SystemStructureDescription>")
    return "\n".join(L) + "\n"


def read_ssp(path: str | os.PathLike) -> tuple[dict[str, str], list[tuple[str, str, str, str]], dict]:
    """The components and connections of an SSP file.

    Parameters
    ----------
    path : str or os.PathLike
        The SSP file.

    Returns
    -------
    tuple
        (component name -> its FMU's entry in the zip, the connections as
        (start element, output, end element, input), the
        DefaultExperiment's attributes).

    Raises
    ------
    pdbfs.ExportError
        For a file that is not an SSP file.
    """
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("SystemStructure.ssd"))
    except KeyError:
        raise ExportError(f"{path}: not an SSP file: the zip holds no SystemStructure.ssd") from None
    except (zipfile.BadZipFile, ET.ParseError, OSError) as err:
        raise ExportError(f"{path}: not an SSP file (a zip with SystemStructure.ssd): {err}") from None
    system = root.find("ssd:System", NS)
    if system is None:
        raise ExportError(f"{path}: SystemStructure.ssd has no System")
    comps = {c.get("name"): c.get("source") for c in system.iterfind("ssd:Elements/ssd:Component", NS)}
    conns = [(c.get("startElement"), c.get("startConnector"), c.get("endElement"), c.get("endConnector"))
             for c in system.iterfind("ssd:Connections/ssd:Connection", NS)]
    exp = root.find("ssd:DefaultExperiment", NS)
    return comps, conns, dict(exp.attrib) if exp is not None else {}
