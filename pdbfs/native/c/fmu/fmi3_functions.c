/*
 * The generic FMI 3.0 plumbing of a pdbfs FMU (the same for every rig): life
 * cycle, variables by value reference, logging, on the version-neutral
 * files (see fmu_instance.h).  Model Exchange and Co-Simulation are in
 * fmi3_interfaces.c, the FMU state and the calls the FMU does not offer in
 * fmi3_state.c.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fmu_instance.h"

/* the instance's messages go to the host's fmi3 logger */
static void log_hook(const Inst *m, int st, const char *cat, const char *msg) {
    fmi3LogMessageCallback logger = (fmi3LogMessageCallback)m->host.logger;
    logger(m->host.env, (fmi3Status)st, cat, msg);
}

_Static_assert(FMU_OK == fmi3OK && FMU_WARNING == fmi3Warning && FMU_ERROR == fmi3Error,
               "status numbers shared with the version-neutral files");

const char *fmi3GetVersion(void) { return fmi3Version; }

/* refuse before an instance exists: the message goes straight to the host */
static fmi3Instance refuse(fmi3InstanceEnvironment env, fmi3LogMessageCallback log, const char *msg) {
    if (log) log(env, fmi3Error, "logStatusError", msg);
    return NULL;
}

/* the importer's intermediate update, in Intermediate Update Mode: the
 * outputs may be read, no input set (intermediateVariableSetRequested false),
 * the step accepted; 1 where it asks to return early, at *early_time */
static int intermediate_hook(const Inst *m, double t, int can_return_early, double *early_time) {
    fmi3IntermediateUpdateCallback update = (fmi3IntermediateUpdateCallback)m->host.update;
    fmi3Boolean asked = fmi3False;
    fmi3Float64 when = t;
    update(m->host.env, t, fmi3False, fmi3True, fmi3True, can_return_early ? fmi3True : fmi3False, &asked, &when);
    *early_time = when;
    return asked ? 1 : 0;
}

static fmi3Instance instantiate(const char *fn, int type, fmi3String name, fmi3String token, fmi3Boolean logging,
                                fmi3InstanceEnvironment env, fmi3LogMessageCallback log,
                                fmi3IntermediateUpdateCallback update, fmi3Boolean early_allowed) {
    FmuHost host = {0};
    Inst *m;
    char msg[256];
    if (!name || !name[0]) {
        snprintf(msg, sizeof msg, "%s: missing instance name", fn);
        return refuse(env, log, msg);
    }
    if (!token || strcmp(token, PDBFS_GUID) != 0) {
        snprintf(msg, sizeof msg, "%s: instantiationToken does not match this binary (%s)", fn, PDBFS_GUID);
        return refuse(env, log, msg);
    }
    host.alloc = calloc;
    host.free = free;
    host.hook = log_hook;
    host.logger = (void (*)(void))log;
    host.env = env;
    if (update) {
        host.update = (void (*)(void))update;
        host.intermediate = intermediate_hook;
        host.early_allowed = early_allowed ? 1 : 0;
    }
    m = fmu_new(name, type, &host, logging);
    if (!m) {
        snprintf(msg, sizeof msg, "%s: out of memory", fn);
        return refuse(env, log, msg);
    }
    return m;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)resourcePath; (void)visible;
    return instantiate("fmi3InstantiateModelExchange", FMU_ME, instanceName, instantiationToken, loggingOn,
                       instanceEnvironment, logMessage, NULL, fmi3False);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
    size_t i;
    char msg[256];
    (void)resourcePath; (void)visible;
    if (eventModeUsed)
        return refuse(instanceEnvironment, logMessage,
                      "fmi3InstantiateCoSimulation: the FMU has no event mode (hasEventMode=false)");
    if (nRequiredIntermediateVariables > 0 && !requiredIntermediateVariables)
        return refuse(instanceEnvironment, logMessage, "fmi3InstantiateCoSimulation: NULL argument");
    for (i = 0; i < nRequiredIntermediateVariables; i++)
        if (!values_intermediate(requiredIntermediateVariables[i])) {
            snprintf(msg, sizeof msg, "fmi3InstantiateCoSimulation: value reference %u is not an intermediate "
                     "variable: the outputs are read in intermediate updates, no input is set there",
                     requiredIntermediateVariables[i]);
            return refuse(instanceEnvironment, logMessage, msg);
        }
    return instantiate("fmi3InstantiateCoSimulation", FMU_CS, instanceName, instantiationToken, loggingOn,
                       instanceEnvironment, logMessage, intermediateUpdate, earlyReturnAllowed);
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible,
                                               fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    return refuse(instanceEnvironment, logMessage,
                  "fmi3InstantiateScheduledExecution: the FMU offers Model Exchange and Co-Simulation only");
}

void fmi3FreeInstance(fmi3Instance instance) { fmu_free((Inst *)instance); }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    return fmu_set_logging((Inst *)instance, "fmi3SetDebugLogging", loggingOn, nCategories, categories);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    Inst *m = (Inst *)instance;
    const char *fn = "fmi3EnterInitializationMode";
    if (fmu_setup(m, fn, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) != FMU_OK)
        return fmi3Error;
    return fmu_enter_init(m, fn);
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    return fmu_exit_init((Inst *)instance, "fmi3ExitInitializationMode");
}

fmi3Status fmi3Terminate(fmi3Instance instance) { return fmu_terminate((Inst *)instance, "fmi3Terminate"); }

fmi3Status fmi3Reset(fmi3Instance instance) { return fmu_reset((Inst *)instance, "fmi3Reset"); }

/* --------------------------------------------------------- getters/setters */

/* scalar variables only: one value per value reference; called in one of the
 * ``allowed`` modes (reading: any, Instantiated for start values only, as
 * values_check_get says; setting: FMI 3.0's state tables) */
static int check_sizes(Inst *m, const char *fn, size_t nvr, size_t nv, int allowed) {
    if (fmu_check(m, fn, allowed, -1) != FMU_OK) return FMU_ERROR;
    if (nv != nvr) return ERR(m, "%s: nValues = %zu, expected %zu (all variables are scalars)", fn, nv, nvr);
    return FMU_OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 values[],
                          size_t nValues) {
    Inst *m = (Inst *)instance;
    if (check_sizes(m, "fmi3GetFloat64", nvr, nValues, ST_ANY | ST_INTERMEDIATE) != FMU_OK) return fmi3Error;
    return values_get_real(m, "fmi3GetFloat64", vr, nvr, values, 1);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
    Inst *m = (Inst *)instance;
    if (check_sizes(m, "fmi3SetFloat64", nvr, nValues, ST_SET_REAL) != FMU_OK) return fmi3Error;
    return values_set_real(m, "fmi3SetFloat64", vr, nvr, values);
}

/* solver.max_num_steps is the Int32, solver.method (an enumeration) the Int64 */
#define INT_CALLS(TYPE, SUFFIX, VR)                                                                       \
    fmi3Status fmi3Get##SUFFIX(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,          \
                               TYPE values[], size_t nValues) {                                           \
        Inst *m = (Inst *)instance;                                                                       \
        size_t i;                                                                                         \
        long long v;                                                                                      \
        if (check_sizes(m, "fmi3Get" #SUFFIX, nvr, nValues, ST_ANY) != FMU_OK) return fmi3Error;          \
        if (values_check_get(m, "fmi3Get" #SUFFIX, vr, nvr, 1) != FMU_OK) return fmi3Error;              \
        if (nvr > 0 && !values) return ERR(m, "fmi3Get" #SUFFIX ": NULL argument");                      \
        for (i = 0; i < nvr; i++) {                                                                       \
            if (vr[i] != (VR)) return ERR(m, "fmi3Get" #SUFFIX ": unknown value reference %u", vr[i]);   \
            if (values_get_int(m, "fmi3Get" #SUFFIX, vr[i], &v) != FMU_OK) return fmi3Error;             \
            values[i] = (TYPE)v;                                                                          \
        }                                                                                                 \
        return fmi3OK;                                                                                    \
    }                                                                                                     \
    fmi3Status fmi3Set##SUFFIX(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,          \
                               const TYPE values[], size_t nValues) {                                     \
        Inst *m = (Inst *)instance;                                                                       \
        size_t i;                                                                                         \
        if (check_sizes(m, "fmi3Set" #SUFFIX, nvr, nValues, ST_SET_DISCRETE) != FMU_OK) return fmi3Error; \
        if (nvr > 0 && (!vr || !values)) return ERR(m, "fmi3Set" #SUFFIX ": NULL argument");             \
        for (i = 0; i < nvr; i++) {                                                                       \
            if (vr[i] != (VR)) return ERR(m, "fmi3Set" #SUFFIX ": unknown value reference %u", vr[i]);   \
            if (values_check_int(m, "fmi3Set" #SUFFIX, vr[i], (long long)values[i]) != FMU_OK)            \
                return fmi3Error;                                                                         \
        }                                                                                                 \
        for (i = 0; i < nvr; i++) values_set_int(m, vr[i], (long long)values[i]);                         \
        return fmi3OK;                                                                                    \
    }

INT_CALLS(fmi3Int32, Int32, PDBFS_VR_MAXNUMSTEPS)
INT_CALLS(fmi3Int64, Int64, PDBFS_VR_METHOD)

/* types the model has no variables of: every value reference is unknown */
#define NO_VARIABLES(SUFFIX, TYPE, SET_MODES)                                                             \
    fmi3Status fmi3Get##SUFFIX(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,          \
                               TYPE values[], size_t nValues) {                                           \
        (void)values; (void)nValues;                                                                      \
        return values_none((Inst *)instance, "fmi3Get" #SUFFIX, vr, nvr, ST_ANY);                         \
    }                                                                                                     \
    fmi3Status fmi3Set##SUFFIX(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,          \
                               const TYPE values[], size_t nValues) {                                     \
        (void)values; (void)nValues;                                                                      \
        return values_none((Inst *)instance, "fmi3Set" #SUFFIX, vr, nvr, SET_MODES);                      \
    }

NO_VARIABLES(Float32, fmi3Float32, ST_SET_REAL)
NO_VARIABLES(Int8, fmi3Int8, ST_SET_DISCRETE)
NO_VARIABLES(UInt8, fmi3UInt8, ST_SET_DISCRETE)
NO_VARIABLES(Int16, fmi3Int16, ST_SET_DISCRETE)
NO_VARIABLES(UInt16, fmi3UInt16, ST_SET_DISCRETE)
NO_VARIABLES(UInt32, fmi3UInt32, ST_SET_DISCRETE)
NO_VARIABLES(UInt64, fmi3UInt64, ST_SET_DISCRETE)
NO_VARIABLES(Boolean, fmi3Boolean, ST_SET_DISCRETE)
NO_VARIABLES(String, fmi3String, ST_SET_DISCRETE)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t valueSizes[],
                         fmi3Binary values[], size_t nValues) {
    (void)valueSizes; (void)values; (void)nValues;
    return values_none((Inst *)instance, "fmi3GetBinary", vr, nvr, ST_ANY);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues) {
    (void)valueSizes; (void)values; (void)nValues;
    return values_none((Inst *)instance, "fmi3SetBinary", vr, nvr, ST_SET_DISCRETE);
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[]) {
    (void)values;
    return values_none((Inst *)instance, "fmi3GetClock", vr, nvr, ST_ANY);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Clock values[]) {
    (void)values;
    return values_none((Inst *)instance, "fmi3SetClock", vr, nvr, ST_ANY);
}
