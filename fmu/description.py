"""modelDescription.xml of a pdbfs FMU (FMI 2.0, Model Exchange and
Co-Simulation): every parameter with its unit, bounds and description."""
from __future__ import annotations

from xml.sax.saxutils import quoteattr

from . import units as _units
from .derivatives import OUTPUT_DERIVATIVE_ORDER
from .variables import SOLVER_METHODS, FmuModel


def _x(v: float) -> str:
    """A float for the XML."""
    return repr(float(v))


#: the log categories of every pdbfs FMU (the C checks the same names)
LOG_CATEGORIES = ['  <LogCategories>',
                  '    <Category name="logEvents" description="events and solver restarts"/>',
                  '    <Category name="logStatusWarning" description="warnings"/>',
                  '    <Category name="logStatusError" description="errors"/>',
                  '    <Category name="logAll" description="everything"/>',
                  '  </LogCategories>']


def model_text(model: FmuModel) -> str:
    """modelDescription's description: what the rig is (its class docstring), its size."""
    d = model.dae
    what = getattr(d, "description", "") or "A rig built with pdbfs."
    ins = f", {model.nu} input{'s' if model.nu != 1 else ''}" if model.nu else ""
    return f"{what} pdbfs rig '{d.name}': {model.nx} states, {model.npar} parameters{ins}."


def _interface(tag: str, attrs: str, source_files) -> list[str]:
    """<ModelExchange .../> or <CoSimulation .../>, with <SourceFiles> when
    the FMU ships sources that build its binary."""
    if not source_files:
        return [f"  <{tag} {attrs}/>"]
    return ([f"  <{tag} {attrs}>", "    <SourceFiles>"]
            + [f"      <File name={quoteattr(f)}/>" for f in source_files]
            + ["    </SourceFiles>", f"  </{tag}>"])


def unit_lines(model: FmuModel) -> list[str]:
    """The <Unit> elements of the units ``model`` uses (FMI 2.0 and 3.0 alike)."""
    units_used = []
    for v in model.vars:
        if v.unit and v.unit not in units_used:
            units_used.append(v.unit)
    L = []
    for u in units_used:
        try:
            attrs = _units.base_unit_attrs(u)
        except _units.UnitError:
            attrs = None  # unknown symbol: the unit is declared without SI exponents
        if attrs is None:
            L.append(f'    <Unit name={quoteattr(u)}/>')
        else:
            a = " ".join(f'{k}="{v}"' for k, v in attrs.items())
            L.append(f'    <Unit name={quoteattr(u)}><BaseUnit{" " + a if a else ""}/></Unit>')
    return L


def type_attrs(v) -> list[str]:
    """The attributes of a variable's type (FMI 2.0 and 3.0 alike): declared
    type, start, unit, bounds, nominal."""
    a = []
    if v.declared_type:
        a.append(f'declaredType="{v.declared_type}"')
    if v.start is not None:
        a.append(f'start="{v.start if v.type != "Real" else _x(v.start)}"')
    if v.unit:
        a.append(f"unit={quoteattr(v.unit)}")
    if v.min is not None:
        a.append(f'min="{_x(v.min) if v.type == "Real" else v.min}"')
    if v.max is not None:
        a.append(f'max="{_x(v.max)}"')
    if v.nominal is not None:
        a.append(f'nominal="{_x(v.nominal)}"')
    return a


def model_description(model: FmuModel, guid: str, source_files: list[str] | tuple = ()) -> str:
    """modelDescription.xml of ``model`` with ``guid``; ``source_files``
    (relative to sources/) are declared under both interfaces."""
    d = model.dae
    L = ['<?xml version="1.0" encoding="UTF-8"?>',
         '<fmiModelDescription',
         '  fmiVersion="2.0"',
         f'  modelName={quoteattr(d.name)}',
         f'  guid="{guid}"',
         f'  description={quoteattr(model_text(model))}',
         *model.rights,
         '  generationTool="pdbfs.fmu (CasADi code generation, CVODE co-simulation)"',
         '  variableNamingConvention="structured"',
         f'  numberOfEventIndicators="{model.ne}">',
         *_interface("ModelExchange", f'modelIdentifier="{model.ident}" canGetAndSetFMUstate="true" '
                     'canSerializeFMUstate="true" completedIntegratorStepNotNeeded="true" '
                     'canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="false" '
                     'providesDirectionalDerivative="true"', source_files),
         *_interface("CoSimulation", f'modelIdentifier="{model.ident}" '
                     'canHandleVariableCommunicationStepSize="true" '
                     f'canInterpolateInputs="{str(model.nu > 0).lower()}" '
                     f'maxOutputDerivativeOrder="{OUTPUT_DERIVATIVE_ORDER}" '
                     'canRunAsynchronuously="false" '
                     'canGetAndSetFMUstate="true" canSerializeFMUstate="true" '
                     'canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="false" '
                     'providesDirectionalDerivative="true"', source_files),
         '  <UnitDefinitions>']
    L += unit_lines(model)
    L += ['  </UnitDefinitions>',
          '  <TypeDefinitions>',
          '    <SimpleType name="pdbfs.SolverMethod" description="Co-Simulation integration method">',
          '      <Enumeration>',
          *[f'        <Item name="{n}" value="{v}" description={quoteattr(d)}/>' for n, v, d in SOLVER_METHODS],
          '      </Enumeration>',
          '    </SimpleType>',
          '  </TypeDefinitions>',
          *LOG_CATEGORIES,
          f'  <DefaultExperiment startTime="0" stopTime="{_x(model.stop_time)}" '
          f'stepSize="{_x(model.step_size)}" tolerance="{_x(model.tolerance)}"/>',
          '  <ModelVariables>']
    for i, v in enumerate(model.vars, start=1):
        head = (f'    <ScalarVariable name={quoteattr(v.name)} valueReference="{v.vr}" '
                f'description={quoteattr(v.description)} causality="{v.causality}" '
                f'variability="{v.variability}"' + (f' initial="{v.initial}"' if v.initial else "") + ">")
        a = type_attrs(v)
        if v.derivative is not None:
            a.append(f'derivative="{v.derivative}"')
        L.append(head + f'<{v.type} {" ".join(a)}/></ScalarVariable>')
    L.append('  </ModelVariables>')
    outputs, derivs, init = model.structure()

    def unk(i, deps):
        return f'      <Unknown index="{i}" dependencies="{" ".join(map(str, deps))}"/>'
    L.append('  <ModelStructure>')
    L.append('    <Outputs>')
    L += [unk(i, dp) for i, dp in outputs]
    L.append('    </Outputs>')
    L.append('    <Derivatives>')
    L += [unk(i, dp) for i, dp in derivs]
    L.append('    </Derivatives>')
    L.append('    <InitialUnknowns>')
    L += [unk(i, dp) for i, dp in init]
    L.append('    </InitialUnknowns>')
    L.append('  </ModelStructure>')
    L.append('</fmiModelDescription>')
    return "\n".join(L) + "\n"

# -- pdbfs_model.h -----------------------------------------------------------
