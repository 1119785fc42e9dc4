#!/usr/bin/env python3
"""Memory check of the exported FMU binary: N instantiate/simulate/free
cycles (Co-Simulation and Model Exchange, FMU state, reset, misuse calls)
driven by a small C program that dlopen()s the FMU's .so, under valgrind.

    python scripts/fmu_memcheck.py [--cycles 1000] [--fmu path.fmu] [--no-valgrind]

Exit status 0 when valgrind reports no error and no leak.
"""
from __future__ import annotations

import argparse
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile

DRIVER = r"""
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

static int n_err_msgs = 0;
static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status st, fmi2String cat,
                   fmi2String fmt, ...) {
    char buf[2048];
    va_list ap;
    (void)env; (void)name; (void)cat;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    if (st >= fmi2Error) n_err_msgs++;
}

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(h, #name); if (!name) { \
    fprintf(stderr, "missing %s\n", #name); return 2; }
#define OK(call) do { fmi2Status s_ = (call); if (s_ != fmi2OK) { \
    fprintf(stderr, "cycle %d: %s -> %d\n", cyc, #call, s_); return 3; } } while (0)
#define BAD(call) do { fmi2Status s_ = (call); if (s_ != fmi2Error) { \
    fprintf(stderr, "cycle %d: %s should fail, got %d\n", cyc, #call, s_); return 4; } } while (0)

int main(int argc, char **argv) {
    const char *so = argv[1], *guid = argv[2];
    int cycles = atoi(argv[3]);
    fmi2ValueReference vr_p = (fmi2ValueReference)atoi(argv[4]);   /* oil.pressure */
    fmi2ValueReference vr_v0 = (fmi2ValueReference)atoi(argv[5]);  /* hammer.v0 */
    fmi2ValueReference vr_mass = (fmi2ValueReference)atoi(argv[6]); /* hammer.m */
    int nx = atoi(argv[7]), ne = atoi(argv[8]);
    double tend = atof(argv[9]), dt = atof(argv[10]);
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    double peak_sum = 0.0;
    int cyc;
    void *hdl = dlopen(so, RTLD_NOW | RTLD_LOCAL);
    void *h_ = hdl;
    if (!hdl) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
    {
    void *h = h_;
    LOAD(fmi2Instantiate) LOAD(fmi2FreeInstance) LOAD(fmi2SetupExperiment)
    LOAD(fmi2EnterInitializationMode) LOAD(fmi2ExitInitializationMode) LOAD(fmi2DoStep)
    LOAD(fmi2GetReal) LOAD(fmi2SetReal) LOAD(fmi2Reset) LOAD(fmi2Terminate)
    LOAD(fmi2GetFMUstate) LOAD(fmi2SetFMUstate) LOAD(fmi2FreeFMUstate)
    LOAD(fmi2SerializedFMUstateSize) LOAD(fmi2SerializeFMUstate) LOAD(fmi2DeSerializeFMUstate)
    LOAD(fmi2GetDerivatives) LOAD(fmi2GetEventIndicators) LOAD(fmi2SetContinuousStates)
    LOAD(fmi2GetContinuousStates) LOAD(fmi2SetTime) LOAD(fmi2EnterContinuousTimeMode)
    LOAD(fmi2NewDiscreteStates) LOAD(fmi2EnterEventMode)
    for (cyc = 0; cyc < cycles; cyc++) {
        double v0 = 2.0 + 0.001 * (cyc % 1000), p = 0.0, peak = 0.0, t = 0.0, nan = 0.0 / 0.0;
        fmi2ValueReference bad = 999999;
        int k, nsteps = (int)(tend / dt + 0.5);
        if (cyc % 10 == 9) {
            /* Model Exchange: explicit Euler over a few steps */
            double x[64], dx[64], e[64];
            fmi2EventInfo info;
            fmi2Component c = fmi2Instantiate("me", fmi2ModelExchange, guid, "", &cb, fmi2False, fmi2False);
            if (!c) { fprintf(stderr, "instantiate ME failed\n"); return 3; }
            OK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
            OK(fmi2EnterInitializationMode(c));
            OK(fmi2ExitInitializationMode(c));
            OK(fmi2NewDiscreteStates(c, &info));
            OK(fmi2EnterContinuousTimeMode(c));
            OK(fmi2GetContinuousStates(c, x, nx));
            for (k = 0; k < 200; k++) {
                int i;
                OK(fmi2GetDerivatives(c, dx, nx));
                OK(fmi2GetEventIndicators(c, e, ne));
                for (i = 0; i < nx; i++) x[i] += 1e-6 * dx[i];
                OK(fmi2SetTime(c, (k + 1) * 1e-6));
                OK(fmi2SetContinuousStates(c, x, nx));
            }
            BAD(fmi2DoStep(c, 0.0, 1e-3, fmi2True));
            OK(fmi2EnterEventMode(c));
            OK(fmi2Terminate(c));
            fmi2FreeInstance(c);
            continue;
        }
        {
            fmi2Component c = fmi2Instantiate("cs", fmi2CoSimulation, guid, "", &cb, fmi2False, fmi2False);
            fmi2FMUstate st = NULL, st2 = NULL;
            size_t sz = 0;
            char *bytes;
            if (!c) { fprintf(stderr, "instantiate CS failed\n"); return 3; }
            BAD(fmi2SetReal(c, &vr_mass, 1, &nan));
            BAD(fmi2SetReal(c, &bad, 1, &v0));
            OK(fmi2SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2True, tend));
            OK(fmi2SetReal(c, &vr_v0, 1, &v0));
            OK(fmi2EnterInitializationMode(c));
            OK(fmi2ExitInitializationMode(c));
            BAD(fmi2DoStep(c, 1.0, dt, fmi2True));
            for (k = 0; k < nsteps; k++) {
                OK(fmi2DoStep(c, t, dt, fmi2True));
                t = (k + 1) * dt;
                OK(fmi2GetReal(c, &vr_p, 1, &p));
                if (p > peak) peak = p;
                if (k == nsteps / 4) OK(fmi2GetFMUstate(c, &st));
            }
            OK(fmi2SerializedFMUstateSize(c, st, &sz));
            bytes = (char *)malloc(sz);
            OK(fmi2SerializeFMUstate(c, st, bytes, sz));
            OK(fmi2DeSerializeFMUstate(c, bytes, sz, &st2));
            free(bytes);
            OK(fmi2SetFMUstate(c, st2));
            t = (nsteps / 4 + 1) * dt;
            OK(fmi2DoStep(c, t, dt, fmi2True));
            OK(fmi2FreeFMUstate(c, &st));
            OK(fmi2FreeFMUstate(c, &st2));
            if (cyc % 2) {
                OK(fmi2Reset(c));
                OK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
                OK(fmi2EnterInitializationMode(c));
                OK(fmi2ExitInitializationMode(c));
                OK(fmi2DoStep(c, 0.0, dt, fmi2True));
            }
            OK(fmi2Terminate(c));
            fmi2FreeInstance(c);
            peak_sum += peak;
        }
    }
    }
    dlclose(hdl);
    printf("cycles %d, mean peak pressure %.6g Pa, error messages seen %d\n", cycles,
           peak_sum / (cycles - cycles / 10), n_err_msgs);
    return 0;
}
"""


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cycles", type=int, default=1000)
    ap.add_argument("--fmu", help="FMU to check (default: export the paper rig)")
    ap.add_argument("--t-end", type=float, default=0.02)
    ap.add_argument("--step", type=float, default=1e-3)
    ap.add_argument("--no-valgrind", action="store_true", help="run the driver natively only")
    args = ap.parse_args()

    from pdbfs.fmu.export import _fmi_header_dir
    from pdbfs.models import paper_rig

    with tempfile.TemporaryDirectory(prefix="pdbfs-memcheck-") as tmp:
        tmp = pathlib.Path(tmp)
        fmu = pathlib.Path(args.fmu) if args.fmu else paper_rig().export_fmu(tmp / "rig.fmu")
        with zipfile.ZipFile(fmu) as z:
            z.extractall(tmp / "x")
        root = ET.parse(tmp / "x" / "modelDescription.xml").getroot()
        guid = root.get("guid")
        ident = root.find("CoSimulation").get("modelIdentifier")
        vrs = {sv.get("name"): sv.get("valueReference") for sv in root.iter("ScalarVariable")}
        nx = len(root.find("ModelStructure").find("Derivatives"))
        ne = root.get("numberOfEventIndicators")
        so = tmp / "x" / "binaries" / "linux64" / f"{ident}.so"
        (tmp / "driver.c").write_text(DRIVER)
        from pdbfs.native.toolchain import compiler
        subprocess.run([*compiler(), "-O1", "-g", "-std=gnu99", f"-I{_fmi_header_dir()}", str(tmp / "driver.c"),
                        "-o", str(tmp / "driver"), "-ldl"], check=True)
        cmd = [str(tmp / "driver"), str(so), guid, str(args.cycles), vrs["oil.pressure"], vrs["hammer.v0"],
               vrs["hammer.m"], str(nx), ne, repr(args.t_end), repr(args.step)]
        t0 = time.perf_counter()
        native = subprocess.run(cmd, capture_output=True, text=True)
        print(f"native: {time.perf_counter() - t0:.2f} s, exit {native.returncode}: "
              f"{native.stdout.strip()} {native.stderr.strip()}")
        if native.returncode != 0:
            return 1
        if args.no_valgrind:
            return 0
        if shutil.which("valgrind") is None:
            print("valgrind not found (apt-get install valgrind)")
            return 2
        vg = ["valgrind", "--leak-check=full", "--show-leak-kinds=definite,indirect,possible",
              "--errors-for-leak-kinds=definite,indirect,possible", "--error-exitcode=99",
              "--track-origins=yes"]
        t0 = time.perf_counter()
        r = subprocess.run(vg + cmd, capture_output=True, text=True)
        dt = time.perf_counter() - t0
        log = r.stderr
        summary = re.search(r"ERROR SUMMARY: (\d+) errors", log)
        heap = re.search(r"total heap usage: ([\d,]+) allocs, ([\d,]+) frees, ([\d,]+) bytes allocated", log)
        lost = {k: re.search(rf"{k}: ([\d,]+) bytes", log) for k in
                ("definitely lost", "indirectly lost", "possibly lost")}
        print(f"valgrind: {dt:.1f} s, exit {r.returncode}; driver: {r.stdout.strip()}")
        if heap:
            print(f"  heap: {heap.group(1)} allocs, {heap.group(2)} frees, {heap.group(3)} bytes")
        if "All heap blocks were freed" in log:
            print("  all heap blocks were freed -- no leaks are possible")
        for k, mt in lost.items():
            if mt:
                print(f"  {k}: {mt.group(1)} bytes")
        print(f"  ERROR SUMMARY: {summary.group(1) if summary else '?'} errors")
        ok = r.returncode == 0 and summary and summary.group(1) == "0"
        if not ok:
            print(log[-6000:])
        return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
