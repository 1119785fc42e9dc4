"""FMI 3.0 description of a pdbfs FMU: modelDescription.xml (Model Exchange
and Co-Simulation, the same variables, units, causalities, variability and
bounds as FMI 2.0, plus the independent variable ``time`` and the event
indicators as variables, which FMI 3.0 asks for) and
sources/buildDescription.xml."""
from __future__ import annotations

from xml.sax.saxutils import quoteattr

import casadi as ca

from pdbfs.errors import ExportError

from .derivatives import OUTPUT_DERIVATIVE_ORDER
from .description import LOG_CATEGORIES, _x, model_text, type_attrs, unit_lines
from .variables import SOLVER_METHODS, FmuModel, _deps

#: FMI 2.0 type -> FMI 3.0 element
_TYPES = {"Real": "Float64", "Integer": "Int32", "Enumeration": "Enumeration"}
#: words of the 2.0 descriptions that name 2.0 calls
_CALLS = {"fmi2SetupExperiment": "fmi3EnterInitializationMode", "fmi2DoStep": "fmi3DoStep"}


def event_variable_names(model: FmuModel) -> list[str]:
    """The names of the event-indicator variables, in the order of the DAE's events."""
    return [f"event.{n}" for n in model.dae.event_names]


def vr_time(model: FmuModel) -> int:
    """Value reference of ``time``; the event indicators follow it."""
    return model.vr_maxnumsteps + 1


def header_lines(model: FmuModel) -> list[str]:
    """What pdbfs_model.h adds for FMI 3.0 (the C serves these value references)."""
    return [f"#define PDBFS_VR_TIME {vr_time(model)}", f"#define PDBFS_VR_E {vr_time(model) + 1}"]


def _check_names(model: FmuModel) -> None:
    taken = {v.name for v in model.vars}
    for n in ["time"] + event_variable_names(model):
        if n in taken:
            raise ExportError(f"rig {model.dae.name}: the variable name '{n}' is taken; FMI 3.0 needs it for "
                              "time or an event indicator")


def _variable(v, vr_of_index) -> str:
    tag = _TYPES[v.type]
    desc = v.description
    for old, new in _CALLS.items():
        desc = desc.replace(old, new)
    a = [f"name={quoteattr(v.name)}", f'valueReference="{v.vr}"', f"description={quoteattr(desc)}",
         f'causality="{v.causality}"', f'variability="{v.variability}"']
    if v.initial:
        a.append(f'initial="{v.initial}"')
    if v.causality == "output":   # read in the importer's intermediate updates inside fmi3DoStep
        a.append('intermediateUpdate="true"')
    a += type_attrs(v)
    if v.derivative is not None:
        a.append(f'derivative="{vr_of_index(v.derivative)}"')
    return f'    <{tag} {" ".join(a)}/>'


def model_description3(model: FmuModel, token: str) -> str:
    """modelDescription.xml (FMI 3.0) of ``model`` with instantiation token ``token``."""
    _check_names(model)
    d = model.dae
    vr_of_index = lambda i: model.vars[i - 1].vr  # noqa: E731  (2.0 indices are 1-based)
    caps = ('canGetAndSetFMUState="true" canSerializeFMUState="true" canBeInstantiatedOnlyOncePerProcess="false" '
            'providesDirectionalDerivatives="true" providesAdjointDerivatives="true"')
    L = ['<?xml version="1.0" encoding="UTF-8"?>',
         '<fmiModelDescription',
         '  fmiVersion="3.0"',
         f'  modelName={quoteattr(d.name)}',
         f'  instantiationToken="{token}"',
         f'  description={quoteattr(model_text(model))}',
         *model.rights,
         '  generationTool="pdbfs.fmu (CasADi code generation, CVODE co-simulation)"',
         '  variableNamingConvention="structured">',
         f'  <ModelExchange modelIdentifier="{model.ident}" {caps} needsCompletedIntegratorStep="false"/>',
         f'  <CoSimulation modelIdentifier="{model.ident}" {caps} canHandleVariableCommunicationStepSize="true" '
         f'maxOutputDerivativeOrder="{OUTPUT_DERIVATIVE_ORDER}" hasEventMode="false" '
         'providesIntermediateUpdate="true" mightReturnEarlyFromDoStep="false" '
         'canReturnEarlyAfterIntermediateUpdate="true"/>',
         '  <UnitDefinitions>', *unit_lines(model), '  </UnitDefinitions>',
         '  <TypeDefinitions>',
         '    <EnumerationType name="pdbfs.SolverMethod" description="Co-Simulation integration method">',
         *[f'      <Item name="{n}" value="{v}" description={quoteattr(d)}/>' for n, v, d in SOLVER_METHODS],
         '    </EnumerationType>',
         '  </TypeDefinitions>',
         *LOG_CATEGORIES,
         f'  <DefaultExperiment startTime="0" stopTime="{_x(model.stop_time)}" '
         f'stepSize="{_x(model.step_size)}" tolerance="{_x(model.tolerance)}"/>',
         '  <ModelVariables>']
    L += [_variable(v, vr_of_index) for v in model.vars]
    t = vr_time(model)
    L.append(f'    <Float64 name="time" valueReference="{t}" causality="independent" variability="continuous" '
             'description="simulation time" unit="s"/>')
    for k, n in enumerate(event_variable_names(model)):
        L.append(f'    <Float64 name={quoteattr(n)} valueReference="{t + 1 + k}" causality="local" '
                 f'variability="continuous" description={quoteattr(_event_text(d, d.event_names[k]))}/>')
    L.append('  </ModelVariables>')
    outputs, derivs, init = model.structure()
    # an event indicator depends on states and inputs (a commanded valve's stops on its command)
    knowns = ca.vertcat(d.x, d.p[model.u_rows[0]:model.u_rows[0] + model.nu])
    vrs = [model.vr_x + k for k in range(model.nx)] + [model.vr_u + k for k in range(model.nu)]
    events = _deps(ca.jacobian_sparsity(d.events, knowns), vrs) if model.ne else []

    def unk(tag, vr, deps):
        return f'    <{tag} valueReference="{vr}" dependencies="{" ".join(map(str, deps))}"/>'
    L.append('  <ModelStructure>')
    L += [unk("Output", vr_of_index(i), [vr_of_index(j) for j in dp]) for i, dp in outputs]
    L += [unk("ContinuousStateDerivative", vr_of_index(i), [vr_of_index(j) for j in dp]) for i, dp in derivs]
    L += [unk("InitialUnknown", vr_of_index(i), [vr_of_index(j) for j in dp]) for i, dp in init]
    L += [unk("EventIndicator", t + 1 + k, dp) for k, dp in enumerate(events)]
    L.append('  </ModelStructure>')
    L.append('</fmiModelDescription>')
    return "\n".join(L) + "\n"


def _event_text(dae, name: str) -> str:
    """What the indicator's sign change marks, as its component says."""
    what = getattr(dae, "event_text", {}).get(name)
    return f"event indicator {name}: changes sign where " + (
        what if what else "the right-hand side switches (a non-smooth point)")


#: platforms whose C runtime keeps the math functions in a library of their own (libm: -lm)
LIBM_PLATFORMS = ("x86_64-linux", "aarch64-linux")


def build_description(model: FmuModel, sources: list[str], sundials_version: str | None) -> str:
    """sources/buildDescription.xml: the C files of the FMU (relative to
    sources/, which is the include folder). With ``sundials_version`` the
    build must provide SUNDIALS' CVODE (an external library); None when the
    sources carry CVODE's own C among ``sources``. One configuration per
    platform that must link the C math library (Linux: libm, which a plain
    ``cc -shared`` does not link), then one for every other platform."""
    L = ['<?xml version="1.0" encoding="UTF-8"?>', '<fmiBuildDescription fmiVersion="3.0">']
    for platform in (*LIBM_PLATFORMS, None):
        where = f' platform="{platform}"' if platform else ""
        L += [f'  <BuildConfiguration modelIdentifier="{model.ident}"{where} '
              'description="the generic FMI 3.0 wrapper, the co-simulation loop and the generated model">',
              '    <SourceFileSet language="C99">']
        L += [f'      <SourceFile name={quoteattr(s)}/>' for s in sources]
        L += ['      <IncludeDirectory name="."/>', '    </SourceFileSet>']
        if sundials_version is not None:
            L.append(f'    <Library name="sundials_cvode" version={quoteattr(sundials_version)} external="true" '
                     'description="SUNDIALS CVODE, built as a static, position-independent library: '
                     'see README.txt"/>')
        if platform:
            L.append('    <Library name="m" external="true" description="the C math library (link with -lm): '
                     'the model and CVODE call the functions of math.h"/>')
        L.append('  </BuildConfiguration>')
    L.append('</fmiBuildDescription>')
    return "\n".join(L) + "\n"
