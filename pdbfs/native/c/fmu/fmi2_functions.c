/*
 * The generic FMI 2.0 plumbing of a pdbfs FMU (the same for every rig): life
 * cycle, variables by value reference, logging, on the version-neutral files
 * (see fmu_instance.h); Model Exchange and Co-Simulation in fmi2_interfaces.c.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2_prefix.h"
#include "fmu_instance.h"

/* ------------------------------------------------------------------ logging */

/* the instance's messages go to the host's fmi2 logger */
static void log_hook(const Inst *m, int st, const char *cat, const char *msg) {
    fmi2CallbackLogger logger = (fmi2CallbackLogger)m->host.logger;
    logger(m->host.env, m->name ? m->name : "?", (fmi2Status)st, cat, "%s", msg);
}

_Static_assert(FMU_ERROR == fmi2Error && FMU_CS == fmi2CoSimulation && FMU_ME == fmi2ModelExchange,
               "status and interface numbers shared with the version-neutral files");

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    Inst *m;
    FmuHost host = {0};
    (void)fmuResourceLocation; (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) {
        if (functions && functions->logger)
            functions->logger(functions->componentEnvironment, instanceName ? instanceName : "?", fmi2Error,
                              "logStatusError", "fmi2Instantiate: allocateMemory and freeMemory are required");
        return NULL;
    }
#define EARLY_ERR(msg)                                                                         \
    do {                                                                                       \
        if (functions->logger)                                                                 \
            functions->logger(functions->componentEnvironment, instanceName ? instanceName : "?", \
                              fmi2Error, "logStatusError", "%s", msg);                          \
        return NULL;                                                                           \
    } while (0)
    if (!instanceName || !instanceName[0]) EARLY_ERR("fmi2Instantiate: missing instance name");
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation)
        EARLY_ERR("fmi2Instantiate: unknown fmuType");
    if (!fmuGUID || strcmp(fmuGUID, PDBFS_GUID) != 0)
        EARLY_ERR("fmi2Instantiate: GUID does not match this binary (" PDBFS_GUID ")");
    host.alloc = functions->allocateMemory;
    host.free = functions->freeMemory;
    host.hook = log_hook;
    host.logger = (void (*)(void))functions->logger;
    host.env = functions->componentEnvironment;
    m = fmu_new(instanceName, fmuType, &host, loggingOn);
    if (!m) EARLY_ERR("fmi2Instantiate: out of memory");
    return m;
#undef EARLY_ERR
}

void fmi2FreeInstance(fmi2Component c) {
    fmu_free((Inst *)c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    return fmu_set_logging((Inst *)c, "fmi2SetDebugLogging", loggingOn, nCategories, categories);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    return fmu_setup((Inst *)c, "fmi2SetupExperiment", toleranceDefined, tolerance, startTime, stopTimeDefined,
                     stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    return fmu_enter_init((Inst *)c, "fmi2EnterInitializationMode");
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    return fmu_exit_init((Inst *)c, "fmi2ExitInitializationMode");
}

fmi2Status fmi2Terminate(fmi2Component c) {
    return fmu_terminate((Inst *)c, "fmi2Terminate");
}

fmi2Status fmi2Reset(fmi2Component c) {
    return fmu_reset((Inst *)c, "fmi2Reset");
}

/* --------------------------------------------------------- getters/setters */
/* the state table (FMI 2.0, 4.2.4 and 3.2.3): nothing is read in
 * Instantiated; Integer, Boolean and String are set in Instantiated,
 * Initialization Mode, Event Mode and between steps */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    return values_get_real((Inst *)c, "fmi2GetReal", vr, nvr, value, 0);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    return values_set_real((Inst *)c, "fmi2SetReal", vr, nvr, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    long long v;
    if (values_check_get(m, "fmi2GetInteger", vr, nvr, 0) != fmi2OK) return fmi2Error;
    if (nvr > 0 && !value) return ERR(m, "fmi2GetInteger: NULL argument");
    for (i = 0; i < nvr; i++) {
        if (values_get_int(m, "fmi2GetInteger", vr[i], &v) != fmi2OK) return fmi2Error;
        value[i] = (fmi2Integer)v;
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2SetInteger", ST_SET_DISCRETE, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2SetInteger: NULL argument");
    for (i = 0; i < nvr; i++)
        if (values_check_int(m, "fmi2SetInteger", vr[i], value[i]) != fmi2OK) return fmi2Error;
    for (i = 0; i < nvr; i++) values_set_int(m, vr[i], value[i]);
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (values_check_get(m, "fmi2GetBoolean", vr, nvr, 0) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2SetBoolean", ST_SET_DISCRETE, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (values_check_get(m, "fmi2GetString", vr, nvr, 0) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2SetString", ST_SET_DISCRETE, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    return (fmi2Status)deriv_forward((Inst *)c, "fmi2GetDirectionalDerivative", vUnknown_ref, nUnknown, vKnown_ref,
                                     nKnown, dvKnown, dvUnknown);
}
