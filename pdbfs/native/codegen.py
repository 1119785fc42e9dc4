"""C code generation and compilation shared by the FMU exporter
(``pdbfs.fmu``) and the compiled simulation backend
(``pdbfs.simulation.compiled``).

Conventions (the same for every generated binary):

* the model functions are CasADi Functions of ``(t, x, z, p)`` (``start``
  and ``calc`` of ``(p)``) named ``pdbfs_<what>`` with dense outputs (the
  Jacobians ``jac`` and ``jac_q`` sparse: their nonzeros, the pattern in
  ``pdbfs_<what>_sparsity_out``), and are generated into one C file ``pdbfs_model_funcs.c`` (+ ``.h``) without
  export attributes; the generic C driver calls them with work arrays of
  the sizes returned by :func:`generate` (``PDBFS_SZ_ARG`` ... in the
  generated header);
* the shared library is compiled with ``zig cc -O2 -fPIC -fvisibility=hidden``
  (``toolchain.py``; ``$CC`` for the host if set) and linked with the
  target's static CVODE (``sundials.py``), whose symbols stay private to the
  library (hidden, ``--exclude-libs,ALL`` on ELF) so that they never clash
  with the SUNDIALS that CasADi loads into the same process.
"""
from __future__ import annotations

import os
import subprocess
from pathlib import Path

import casadi as ca

from pdbfs.errors import ExportError

from pdbfs.modelling.initialization import needs_solving

from . import toolchain
from .initial import solved_start_function
from .sundials import Sundials, find_sundials

#: the C shared by every generated binary: CVODE through the events
NATIVE_C = Path(__file__).with_name("c")
CVODE_DRIVER = (NATIVE_C / "pdbfs_cvode.c", NATIVE_C / "pdbfs_cvode.h")

#: name (without extension) of the generated C file of the model functions
FUNCS = "pdbfs_model_funcs"

#: the model functions a driver can ask for
FUNCTION_NAMES = ("ode", "jac", "out", "events", "start", "calc", "conditions")


def model_functions(dae, which=FUNCTION_NAMES, calc_expr=None, roles=(), quad=()) -> list[ca.Function]:
    """CasADi Functions ``pdbfs_<name>`` of the DAE for code generation, in
    the order of ``which``: ``ode`` (der x), ``jac`` (d ode / d x, sparse:
    its nonzeros in CasADi's column-compressed order), ``out`` (y),
    ``events`` (event indicators), ``start``
    (x0 of p), ``calc`` (``calc_expr`` of p: the calculated parameters),
    ``conditions`` (of p: the components' consistency conditions, each >= 0),
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
        # a solved start (initial equations, free states): Newton in the C (initial.py)
        "start": lambda: solved_start_function(dae) if needs_solving(dae) else
        ca.Function("pdbfs_start", [dae.p], [ca.densify(dae.x0)], ["p"], ["x0"]),
        "calc": lambda: ca.Function("pdbfs_calc", [dae.p],
                                    [ca.densify(calc_expr if calc_expr is not None else ca.SX(0, 1))],
                                    ["p"], ["c"]),
        # the components' physical consistency (Component.conditions): each >= 0
        "conditions": lambda: ca.Function("pdbfs_conditions", [dae.p], [ca.densify(
            ca.vertcat(*[e for e, _ in getattr(dae, "conditions", None) or []])
            if getattr(dae, "conditions", None) else ca.SX(0, 1))], ["p"], ["c"]),
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
    """Write ``<name>.c`` and ``<name>.h`` of ``funcs`` into ``directory``
    (large functions split into parts, see :func:`split`); return the work
    sizes (arg, res, iw, w) a caller must provide."""
    cg = ca.CodeGenerator(f"{name}.c", {"with_header": True, "with_export": False, "verbose": False})
    funcs = [split(f) for f in funcs]
    for f in funcs:
        cg.add(f)
    cg.generate(str(directory) + os.sep)
    return work_sizes(funcs)


#: instructions per generated C function at most (about 35 kB of C): GCC's
#: optimisation grows faster than linearly with the size of one function
#: (measured on the split piston, N = 200: one function per output, 17 s
#: and 520 MB at -O2; in parts of 2,000 instructions, 5.7 s and 295 MB;
#: N = 1,000: 30 s and 760 MB)
PART_INSTRUCTIONS = 2000
#: and output rows at most: each written output is a branch in the C, and
#: many branches in one function cost GCC as much as many instructions
PART_ROWS = 256


def split(f: ca.Function, size: int = PART_INSTRUCTIONS) -> ca.Function:
    """``f`` (an SX Function with one output) as a Function of the same
    name, inputs and output sparsity that calls parts computing blocks of
    the output's rows; ``f`` itself when it is small."""
    if not f.is_a("SXFunction") or f.n_out() != 1 or (f.n_instructions() <= size
                                                        and f.size1_out(0) <= PART_ROWS):
        return f
    ins = f.sx_in()
    out = f.call(ins, True, False)[0]
    blocks, todo = [], [(0, out.size1())]
    while todo:             # halve row blocks until each is small (rows differ in cost)
        r0, r1 = todo.pop()
        if r1 - r0 > PART_ROWS or (r1 - r0 > 1 and ca.Function(
                "part", ins, [out[r0:r1, :]]).n_instructions() > size):
            todo += [((r0 + r1) // 2, r1), (r0, (r0 + r1) // 2)]
        else:
            blocks.append((r0, r1))
    parts = [ca.Function(f"{f.name()}_part{k}", ins, [out[r0:r1, :]])
             for k, (r0, r1) in enumerate(blocks)]
    mx = [ca.MX.sym(f.name_in(i), f.sparsity_in(i)) for i in range(f.n_in())]
    return ca.Function(f.name(), mx, [ca.vertcat(*[g(*mx) for g in parts])], f.name_in(),
                       f.name_out())


def work_sizes(funcs: list[ca.Function]) -> tuple[int, int, int, int]:
    return (max(f.sz_arg() for f in funcs), max(f.sz_res() for f in funcs),
            max(f.sz_iw() for f in funcs), max(f.sz_w() for f in funcs))


def sizes_header_lines(work: tuple[int, int, int, int]) -> list[str]:
    """``#define PDBFS_SZ_ARG ...``: the work sizes for a generated header."""
    return [f"#define PDBFS_SZ_ARG {work[0]}", f"#define PDBFS_SZ_RES {work[1]}",
            f"#define PDBFS_SZ_IW {work[2]}", f"#define PDBFS_SZ_W {work[3]}"]


def compile_command(sources: list[Path], out: Path, include_dirs: list[Path],
                    cflags: list[str] | None = None, sd: Sundials | None = None,
                    target: str | None = None) -> list[str]:
    """The command line that builds a shared library of ``sources`` for
    ``target`` (default: the host's) linked with that target's static CVODE."""
    target = target or toolchain.host_target()
    sd = sd or find_sundials(target=target)
    cc = toolchain.compiler(target)
    before, after = toolchain.shared_flags(target, cc)
    return [*cc, *toolchain.cflags(target), *before, *(cflags or []),
            *[f"-I{d}" for d in include_dirs], f"-I{sd.include_dir}",
            *map(str, sources), "-o", str(out), *sd.link_args(), *after]


#: peak memory of the compiler: a base and so much per byte of generated C
#: (measured at -O2 on split C: 295 MB for 1.1 MB, 760 MB for 5.9 MB)
COMPILER_BASE_BYTES = 300_000_000
COMPILER_BYTES_PER_BYTE = 150


def check_compiler_memory(generated_c: Path, what: str, available: int | None = None) -> None:
    """Refuse, before the compiler is started, C that the machine's free
    memory cannot compile (the kernel would kill the compiler midway)."""
    size = generated_c.stat().st_size
    need = COMPILER_BASE_BYTES + size * COMPILER_BYTES_PER_BYTE
    free = available if available is not None else _available_memory()
    if free is not None and need > free:
        raise ExportError(
            f"{what}: the generated C is {size / 1e6:.1f} MB, and compiling it needs about "
            f"{need / 1e9:.1f} GB of memory but {free / 1e9:.1f} GB are free; use a rig with "
            "fewer masses (e.g. fewer bar segments) or a machine with more memory")


def _available_memory() -> int | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def run_compiler(cmd: list[str], what: str) -> None:
    try:
        r = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as err:
        raise ExportError(f"compiling {what}: could not start the compiler: {err}") from err
    if r.returncode < 0:
        raise ExportError(f"compiling {what}: the compiler was killed by signal {-r.returncode}"
                          " (out of memory? a rig this large needs fewer masses or more memory)")
    if r.returncode != 0:
        # one line (the first error); the whole output is the compiler's to give when run by hand
        raise ExportError(f"compiling {what} with {Path(cmd[0]).name} failed: {toolchain.first_error(r.stderr)}")
