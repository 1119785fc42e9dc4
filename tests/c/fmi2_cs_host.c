/*
 * A minimal FMI 2.0 co-simulation host for the tests (compiled for win64 with
 * MinGW-w64 and run under Wine): loads an FMU's win64 DLL, simulates from 0 to
 * STOP in steps of STEP and prints the peak of one Real output and its time.
 *
 *   fmi2_cs_host DLL GUID VR STOP STEP
 *
 * Output: "peak <value> at <time>" (%.17g); exit status 1 on any FMI error.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <windows.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    va_list ap;
    (void)env;
    va_start(ap, message);
    fprintf(stderr, "[%s %d %s] ", name, (int)status, category);
    vfprintf(stderr, message, ap);
    fputc('\n', stderr);
    va_end(ap);
}

#define LOAD(T, f)                                                      \
    T f = (T)(void (*)(void))GetProcAddress(dll, #f);                   \
    if (!f) {                                                           \
        fprintf(stderr, "missing %s\n", #f);                            \
        return 1;                                                       \
    }
#define CHECK(call)                                                     \
    if ((call) != fmi2OK) {                                             \
        fprintf(stderr, "failed: %s\n", #call);                         \
        return 1;                                                       \
    }

int main(int argc, char **argv) {
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2ValueReference vr;
    double stop, h, t = 0, v, peak = -HUGE_VAL, t_peak = 0;
    long k, n;
    HMODULE dll;
    fmi2Component c;
    if (argc != 6) {
        fprintf(stderr, "usage: fmi2_cs_host DLL GUID VR STOP STEP\n");
        return 2;
    }
    vr = (fmi2ValueReference)strtoul(argv[3], NULL, 10);
    stop = strtod(argv[4], NULL);
    h = strtod(argv[5], NULL);
    dll = LoadLibraryA(argv[1]);
    if (!dll) {
        fprintf(stderr, "cannot load %s (error %lu)\n", argv[1], GetLastError());
        return 1;
    }
    {
        LOAD(fmi2InstantiateTYPE *, fmi2Instantiate)
        LOAD(fmi2SetupExperimentTYPE *, fmi2SetupExperiment)
        LOAD(fmi2EnterInitializationModeTYPE *, fmi2EnterInitializationMode)
        LOAD(fmi2ExitInitializationModeTYPE *, fmi2ExitInitializationMode)
        LOAD(fmi2DoStepTYPE *, fmi2DoStep)
        LOAD(fmi2GetRealTYPE *, fmi2GetReal)
        LOAD(fmi2TerminateTYPE *, fmi2Terminate)
        LOAD(fmi2FreeInstanceTYPE *, fmi2FreeInstance)
        c = fmi2Instantiate("host", fmi2CoSimulation, argv[2], "", &cb, fmi2False, fmi2False);
        if (!c) {
            fprintf(stderr, "fmi2Instantiate failed\n");
            return 1;
        }
        CHECK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, stop))
        CHECK(fmi2EnterInitializationMode(c))
        CHECK(fmi2ExitInitializationMode(c))
        n = (long)(stop / h + 0.5);
        for (k = 0; k <= n; k++) {
            if (k > 0) {
                CHECK(fmi2DoStep(c, t, h, fmi2True))
                t = k * h;   /* as fmpy counts: no accumulated round-off */
            }
            CHECK(fmi2GetReal(c, &vr, 1, &v))
            if (v > peak) {
                peak = v;
                t_peak = t;
            }
        }
        CHECK(fmi2Terminate(c))
        fmi2FreeInstance(c);
    }
    printf("peak %.17g at %.17g\n", peak, t_peak);
    return 0;
}
