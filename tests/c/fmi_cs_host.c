/*
 * A minimal FMI co-simulation host for the tests (compiled by zig cc for
 * win64 and run under Wine, or for Linux on arm64 and run under qemu-aarch64):
 * loads an FMU's DLL or shared object, simulates from 0 to
 * STOP in steps of STEP and prints the peak of one Real output and its time.
 * FMI 2.0 by default; compiled with -DFMI3 it drives an FMI 3.0 FMU.
 *
 *   fmi_cs_host DLL TOKEN VR STOP STEP      (TOKEN: guid / instantiationToken)
 *
 * Output: "peak <value> at <time>" (%.17g); exit status 1 on any FMI error
 * or when the library does not load (with the loader's reason). It calls no
 * function of libm, so built without -lm it has no libm of its own
 * (tests/test_fmu_libm.py).
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#ifdef _WIN32
#include <windows.h>
#define SYMBOL(lib, name) GetProcAddress(lib, name)
static char load_error[32];
#define LOAD_ERROR() (sprintf(load_error, "error %lu", (unsigned long)GetLastError()), load_error)
#else
#include <dlfcn.h>
typedef void *HMODULE;
#define LoadLibraryA(path) dlopen(path, RTLD_NOW | RTLD_LOCAL)
#define LOAD_ERROR() dlerror()
#define SYMBOL(lib, name) dlsym(lib, name)
#endif

#ifdef FMI3
#include "fmi3Functions.h"
#define OK fmi3OK
typedef fmi3ValueReference VR;
typedef fmi3Instance Instance;

static void logger(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message) {
    (void)env;
    fprintf(stderr, "[%d %s] %s\n", (int)status, category, message);
}
#else
#include "fmi2Functions.h"
#define OK fmi2OK
typedef fmi2ValueReference VR;
typedef fmi2Component Instance;

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
#endif

#define LOAD(f)                                                         \
    f##TYPE *f = (f##TYPE *)(void (*)(void))SYMBOL(dll, #f);       \
    if (!f) {                                                           \
        fprintf(stderr, "missing %s\n", #f);                            \
        return 1;                                                       \
    }
#define CHECK(call)                                                     \
    if ((call) != OK) {                                                 \
        fprintf(stderr, "failed: %s\n", #call);                         \
        return 1;                                                       \
    }

int main(int argc, char **argv) {
    VR vr;
    double stop, h, t = 0, v, peak = -HUGE_VAL, t_peak = 0;
    long k, n;
    HMODULE dll;
    Instance c;
    if (argc != 6) {
        fprintf(stderr, "usage: fmi_cs_host DLL TOKEN VR STOP STEP\n");
        return 2;
    }
    vr = (VR)strtoul(argv[3], NULL, 10);
    stop = strtod(argv[4], NULL);
    h = strtod(argv[5], NULL);
    dll = LoadLibraryA(argv[1]);
    if (!dll) {
        fprintf(stderr, "cannot load %s: %s\n", argv[1], LOAD_ERROR());
        return 1;
    }
    {
#ifdef FMI3
        fmi3Boolean event, terminate, early;
        fmi3Float64 last;
        LOAD(fmi3InstantiateCoSimulation)
        LOAD(fmi3EnterInitializationMode)
        LOAD(fmi3ExitInitializationMode)
        LOAD(fmi3DoStep)
        LOAD(fmi3GetFloat64)
        LOAD(fmi3Terminate)
        LOAD(fmi3FreeInstance)
        c = fmi3InstantiateCoSimulation("host", argv[2], "", fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0,
                                        NULL, logger, NULL);
#define ENTER_INIT() fmi3EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3True, stop)
#define EXIT_INIT() fmi3ExitInitializationMode(c)
#define DO_STEP() fmi3DoStep(c, t, h, fmi3True, &event, &terminate, &early, &last)
#define GET() fmi3GetFloat64(c, &vr, 1, &v, 1)
#define TERMINATE() fmi3Terminate(c)
#define FREE() fmi3FreeInstance(c)
#else
        fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
        LOAD(fmi2Instantiate)
        LOAD(fmi2SetupExperiment)
        LOAD(fmi2EnterInitializationMode)
        LOAD(fmi2ExitInitializationMode)
        LOAD(fmi2DoStep)
        LOAD(fmi2GetReal)
        LOAD(fmi2Terminate)
        LOAD(fmi2FreeInstance)
        c = fmi2Instantiate("host", fmi2CoSimulation, argv[2], "", &cb, fmi2False, fmi2False);
#define ENTER_INIT() (fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2True, stop) != OK \
                      ? fmi2Error : fmi2EnterInitializationMode(c))
#define EXIT_INIT() fmi2ExitInitializationMode(c)
#define DO_STEP() fmi2DoStep(c, t, h, fmi2True)
#define GET() fmi2GetReal(c, &vr, 1, &v)
#define TERMINATE() fmi2Terminate(c)
#define FREE() fmi2FreeInstance(c)
#endif
        if (!c) {
            fprintf(stderr, "instantiation failed\n");
            return 1;
        }
        CHECK(ENTER_INIT())
        CHECK(EXIT_INIT())
        n = (long)(stop / h + 0.5);
        for (k = 0; k <= n; k++) {
            if (k > 0) {
                CHECK(DO_STEP())
                t = k * h;   /* as fmpy counts: no accumulated round-off */
            }
            CHECK(GET())
            if (v > peak) {
                peak = v;
                t_peak = t;
            }
        }
        CHECK(TERMINATE())
        FREE();
    }
    printf("peak %.17g at %.17g\n", peak, t_peak);
    return 0;
}
