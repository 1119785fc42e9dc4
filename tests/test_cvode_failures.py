"""pdbfs_cvode.c under failure: a start that fails half way (every allocation
made to fail in turn, bad settings) frees what it built, and the next start
integrates as a clean one does; under valgrind, without leaks or invalid
accesses. The C harness is tests/c/cvode_failures.c, on the paper rig's
generated model functions."""
import re
import shutil
import subprocess

import numpy as np
import pytest

from pdbfs.models import paper_rig
from pdbfs.native.codegen import CVODE_DRIVER, generate, model_functions, sizes_header_lines
from pdbfs.native import toolchain
from pdbfs.native.sundials import find_sundials
from pdbfs.simulation import Simulator

from pathlib import Path

HARNESS = Path(__file__).with_name("c") / "cvode_failures.c"
#: the SUNDIALS calls of a start the harness makes fail (tests/c/cvode_failures.c)
FAILED = ("SUNContext_Create", "N_VNew_Serial", "CVodeCreate", "CVodeInit",
           "SUNNonlinSol_FixedPoint", "CVodeSetNonlinearSolver", "SUNDenseMatrix", "SUNBandMatrix",
           "SUNLinSol_Dense", "SUNLinSol_Band", "CVodeSetLinearSolver", "CVodeRootInit")


def _array(v):
    return "{" + ", ".join(repr(float(x)) for x in v) + "}"


@pytest.fixture(scope="module")
def harness(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("cvode-failures")
    rig = paper_rig()
    dae, sim = rig.compile(), Simulator.of(rig)
    work = generate(model_functions(dae, ("ode", "jac", "events")), tmp)
    p = sim.param_vector()
    (tmp / "harness.h").write_text("\n".join([
        f"#define NX {dae.x.numel()}", f"#define NE {dae.events.numel()}",
        f"#define NP {dae.p.numel()}", f"#define P_VALUES {_array(p)}",
        f"#define X0_VALUES {_array(sim.start_vector(p))}",
        "#define T_OUT 0.002", "#define T_STOP 0.003",     # past the first separation (1.2 ms)
        *[line.replace("PDBFS_", "") for line in sizes_header_lines(work)], ""]))
    sd = find_sundials()
    exe = tmp / "cvode_failures"
    inc = [f"-I{tmp}", f"-I{CVODE_DRIVER[0].parent}", f"-I{sd.include_dir}"]
    renamed = [f"-D{f}=test_{f}" for f in ("malloc", *FAILED)]   # pdbfs_cvode.c's calls only
    cc = toolchain.compiler()   # zig cc, or $CC
    for cmd in ([*cc, "-std=gnu99", "-O1", "-g", "-c", *inc, *renamed, str(CVODE_DRIVER[0]),
                 "-o", str(tmp / "pdbfs_cvode.o")],
                [*cc, "-std=gnu99", "-O1", "-g", *inc, str(HARNESS), str(tmp / "pdbfs_cvode.o"),
                 str(CVODE_DRIVER[0].with_name("pdbfs_eval.c")),
                 str(CVODE_DRIVER[0].with_name("pdbfs_cvode_ls.c")),
                 str(tmp / "pdbfs_model_funcs.c"), "-o", str(exe), *sd.link_args(), "-lm"]):
        r = subprocess.run(cmd, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr[-3000:]
    return exe


@pytest.mark.parametrize("method", [0, 1])      # Adams (fixed point), BDF (Newton, dense LU)
def test_every_failed_start_is_recovered(harness, method):
    r = subprocess.run([str(harness), str(method)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    alloc = re.search(r"allocation failures (\d+), (\d+) not recovered", r.stdout)
    total = re.search(r"^failures (\d+), (\d+) not recovered", r.stdout, re.M)
    # every allocating call of a start: SUNDIALS' context, 3 vectors, CVodeCreate, CVodeInit,
    # the root functions, and fixed point (solver, attach) or Newton (Jacobian nonzeros,
    # matrix, linear solver, attach); and 4 starts with bad tolerances
    assert alloc.groups() == (str(9 if method == 0 else 11), "0")
    assert total.groups() == (str(int(alloc.group(1)) + 4), "0")


@pytest.mark.skipif(shutil.which("valgrind") is None, reason="valgrind not installed")
def test_no_leaks_or_invalid_accesses_under_valgrind(harness):
    r = subprocess.run(["valgrind", "--error-exitcode=3", "--leak-check=full",
                        "--errors-for-leak-kinds=definite,indirect", "-q", str(harness), "1"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr[-4000:]
    assert np.isfinite(len(r.stdout))
