"""C code generation and compilation shared by the FMU exporter
(``pdbfs.fmu``) and the compiled simulation backend
(``pdbfs.simulation.compiled``).

Conventions (the same for every generated binary):

* the model functions are CasADi Functions of ``(t, x, z, p)`` (``start``
  and ``calc`` of ``(p)``) named ``pdbfs_<what>`` with dense outputs, and
  are generated into one C file ``pdbfs_model_funcs.c`` (+ ``.h``) without
  export attributes; the generic C driver calls them with work arrays of
  the sizes returned by :func:`generate` (``PDBFS_SZ_ARG`` ... in the
  generated header);
* the shared library is compiled with ``$CC -O2 -fPIC -fvisibility=hidden``
  and linked with SUNDIALS' static CVODE (``sundials.py``), whose symbols are
  kept private to the library (``--exclude-libs,ALL``) so that they never
  clash with the SUNDIALS that CasADi loads into the same process.
"""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import casadi as ca

from pdbfs.errors import ExportError

from .sundials import Sundials, find_sundials

#: the C shared by every generated binary: CVODE through the events
NATIVE_C = Path(__file__).with_name("c")
CVODE_DRIVER = (NATIVE_C / "pdbfs_cvode.c", NATIVE_C / "pdbfs_cvode.h")

#: name (without extension) of the generated C file of the model functions
FUNCS = "pdbfs_model_funcs"

#: flags of every shared library built here (the FMU binary, the batch driver)
CFLAGS = ["-std=gnu99", "-O2", "-fPIC", "-shared", "-fvisibility=hidden", "-fno-math-errno"]
LDFLAGS = ["-lm", "-Wl,--exclude-libs,ALL", "-Wl,-z,defs", "-static-libgcc"]

#: the model functions a driver can ask for
FUNCTION_NAMES = ("ode", "jac", "out", "events", "start", "calc")


def model_functions(dae, which=FUNCTION_NAMES, calc_expr=None, roles=(), quad=()) -> list[ca.Function]:
    """CasADi Functions ``pdbfs_<name>`` of the DAE for code generation, in
    the order of ``which``: ``ode`` (der x), ``jac`` (d ode / d x, sparse:
    its nonzeros in CasADi's column-compressed order), ``out`` (y), ``events`` (event indicators), ``start``
    (x0 of p), ``calc`` (``calc_expr`` of p: the calculated parameters),
    ``roles`` (the outputs named in ``roles``) and ``roles_rate`` (their time
    derivatives for a state derivative v: (d/dx) v + d/dt, a function of
    (t, x, v, p)), ``roles_dot`` (their derivatives along the solution),
    ``ode_q`` and ``jac_q`` (the ODE with the outputs named in ``quad``
    integrated as extra states, and its Jacobian)."""
    args, names = [dae.t, dae.x, dae.z, dae.p], ["t", "x", "z", "p"]
    r = ca.vertcat(*[dae.y[dae.y_names.index(n)] for n in roles]) if roles else ca.SX(0, 1)
    v = ca.SX.sym("v", dae.x.numel())
    r_rate = ca.jtimes(r, dae.x, v) + ca.jacobian(r, dae.t) if roles else ca.SX(0, 1)
    r_dot = ca.jtimes(r, dae.x, dae.ode) + ca.jacobian(r, dae.t) if roles else ca.SX(0, 1)
    q = ca.SX.sym("q", len(quad))
    xq = ca.vertcat(dae.x, q)
    ode_q = ca.vertcat(dae.ode, *[dae.y[dae.y_names.index(n)] for n in quad])
    args_q = [dae.t, xq, dae.z, dae.p]
    make = {
        "ode": lambda: ca.Function("pdbfs_ode", args, [ca.densify(dae.ode)], names, ["xdot"]),
        # sparse: the C reads the pattern from pdbfs_jac_sparsity_out (a chain's
        # Jacobian is banded; dense code would grow as nx^2)
        "jac": lambda: ca.Function("pdbfs_jac", args, [ca.jacobian(dae.ode, dae.x)], names, ["jac"]),
        "out": lambda: ca.Function("pdbfs_out", args, [ca.densify(dae.y)], names, ["y"]),
        "events": lambda: ca.Function("pdbfs_events", args, [ca.densify(dae.events)], names, ["e"]),
        "start": lambda: ca.Function("pdbfs_start", [dae.p], [ca.densify(dae.x0)], ["p"], ["x0"]),
        "calc": lambda: ca.Function("pdbfs_calc", [dae.p],
                                    [ca.densify(calc_expr if calc_expr is not None else ca.SX(0, 1))],
                                    ["p"], ["c"]),
        "roles": lambda: ca.Function("pdbfs_roles", args, [ca.densify(r)], names, ["r"]),
        "roles_rate": lambda: ca.Function("pdbfs_roles_rate", [dae.t, dae.x, v, dae.p],
                                          [ca.densify(r_rate)], ["t", "x", "v", "p"], ["r_dot"]),
        "roles_dot": lambda: ca.Function("pdbfs_roles_dot", args, [ca.densify(r_dot)], names,
                                         ["r_dot"]),
        "ode_q": lambda: ca.Function("pdbfs_ode_q", args_q, [ca.densify(ode_q)], names, ["xdot"]),
        "jac_q": lambda: ca.Function("pdbfs_jac_q", args_q, [ca.jacobian(ode_q, xq)], names,
                                     ["jac"]),
    }
    unknown = [w for w in which if w not in make]
    if unknown:
        raise ExportError(f"unknown model function(s) {unknown}; known: {', '.join(FUNCTION_NAMES)}")
    return [make[w]() for w in which]


def generate(funcs: list[ca.Function], directory: str | os.PathLike,
             name: str = FUNCS) -> tuple[int, int, int, int]:
    """Write ``<name>.c`` and ``<name>.h`` of ``funcs`` into ``directory``;
    return the work sizes (arg, res, iw, w) a caller must provide."""
    cg = ca.CodeGenerator(f"{name}.c", {"with_header": True, "with_export": False, "verbose": False})
    for f in funcs:
        cg.add(f)
    cg.generate(str(directory) + os.sep)
    return work_sizes(funcs)


def work_sizes(funcs: list[ca.Function]) -> tuple[int, int, int, int]:
    return (max(f.sz_arg() for f in funcs), max(f.sz_res() for f in funcs),
            max(f.sz_iw() for f in funcs), max(f.sz_w() for f in funcs))


def sizes_header_lines(work: tuple[int, int, int, int]) -> list[str]:
    """``#define PDBFS_SZ_ARG ...``: the work sizes for a generated header."""
    return [f"#define PDBFS_SZ_ARG {work[0]}", f"#define PDBFS_SZ_RES {work[1]}",
            f"#define PDBFS_SZ_IW {work[2]}", f"#define PDBFS_SZ_W {work[3]}"]


def compiler() -> str:
    cc = os.environ.get("CC", "gcc")
    if shutil.which(cc) is None:
        raise ExportError(f"C compiler '{cc}' not found (set CC)")
    return cc


def compile_command(sources: list[Path], out: Path, include_dirs: list[Path],
                    cflags: list[str] | None = None, sd: Sundials | None = None,
                    cc: str | None = None) -> list[str]:
    """The command line that builds a shared library of ``sources`` linked
    with SUNDIALS' static CVODE."""
    sd = sd or find_sundials()
    cc = cc or compiler()
    return [cc, *CFLAGS, *(cflags or []), *[f"-I{d}" for d in include_dirs], f"-I{sd.include_dir}",
            *map(str, sources), "-o", str(out), *sd.link_args(), *LDFLAGS]


def run_compiler(cmd: list[str], what: str) -> None:
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise ExportError(f"compiling {what} failed:\n{' '.join(cmd)}\n{r.stderr[-4000:]}")
