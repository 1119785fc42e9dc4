/*
 * Two FMI 2.0 FMUs linked into one program (tests/test_fmu_symbols.py): each
 * FMU's sources compiled with its own FMI2_FUNCTION_PREFIX (A_ and B_), then
 * one link. Each is simulated in co-simulation from 0 to STOP in steps of
 * STEP and the peak of one Real output is printed.
 *
 *   fmi2_two_models GUID_A VR_A GUID_B VR_B STOP STEP
 *
 * Output: "A <peak>" and "B <peak>" (%.17g); exit status 1 on any FMI error.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi2FunctionTypes.h"

#define DECLARE(P)                                                                  \
    extern fmi2InstantiateTYPE P##fmi2Instantiate;                                  \
    extern fmi2SetupExperimentTYPE P##fmi2SetupExperiment;                          \
    extern fmi2EnterInitializationModeTYPE P##fmi2EnterInitializationMode;          \
    extern fmi2ExitInitializationModeTYPE P##fmi2ExitInitializationMode;            \
    extern fmi2DoStepTYPE P##fmi2DoStep;                                            \
    extern fmi2GetRealTYPE P##fmi2GetReal;                                          \
    extern fmi2FreeInstanceTYPE P##fmi2FreeInstance;
DECLARE(A_)
DECLARE(B_)

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

#define RUN(P, GUID, VR, OUT)                                                                       \
    do {                                                                                           \
        fmi2ValueReference vr = (fmi2ValueReference)atoi(VR);                                      \
        fmi2Component c = P##fmi2Instantiate(#P, fmi2CoSimulation, GUID, "", &cb, fmi2False, fmi2False); \
        double t = 0, v;                                                                           \
        long k;                                                                                    \
        if (!c || P##fmi2SetupExperiment(c, fmi2False, 0, 0, fmi2True, stop) != fmi2OK ||          \
            P##fmi2EnterInitializationMode(c) != fmi2OK || P##fmi2ExitInitializationMode(c) != fmi2OK) \
            return 1;                                                                              \
        OUT = -HUGE_VAL;                                                                           \
        for (k = 0; t < stop - 0.5 * step; k++) {                                                  \
            if (P##fmi2DoStep(c, t, step, fmi2True) != fmi2OK) return 1;                            \
            t = (k + 1) * step;                                                                    \
            if (P##fmi2GetReal(c, &vr, 1, &v) != fmi2OK) return 1;                                  \
            if (v > OUT) OUT = v;                                                                  \
        }                                                                                          \
        P##fmi2FreeInstance(c);                                                                    \
    } while (0)

#include <math.h>

int main(int argc, char **argv) {
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    double stop, step, peak_a, peak_b;
    if (argc != 7) {
        fprintf(stderr, "usage: fmi2_two_models GUID_A VR_A GUID_B VR_B STOP STEP\n");
        return 2;
    }
    stop = atof(argv[5]);
    step = atof(argv[6]);
    RUN(A_, argv[1], argv[2], peak_a);
    RUN(B_, argv[3], argv[4], peak_b);
    printf("A %.17g\nB %.17g\n", peak_a, peak_b);
    return 0;
}
