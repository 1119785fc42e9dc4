/*
 * The generic FMI 2.0 plumbing of a pdbfs FMU (the same for every rig): life
 * cycle, the state machine, variables by value reference, logging.  See
 * fmu_instance.h for the other files.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmu_instance.h"

/* ------------------------------------------------------------------ logging */

void fmu_log(Inst *m, fmi2Status st, const char *cat, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->cb.logger) return;
    if (st == fmi2OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    m->cb.logger(m->cb.componentEnvironment, m->name ? m->name : "?", st, cat, "%s", buf);
}

static const char *mode_name(int mode) {
    switch (mode) {
    case ST_INSTANTIATED: return "instantiated";
    case ST_INIT: return "initialization mode";
    case ST_EVENT: return "event mode";
    case ST_CONT: return "continuous-time mode";
    case ST_STEPDONE: return "step complete";
    case ST_TERMINATED: return "terminated";
    case ST_ERROR: return "error";
    default: return "unknown";
    }
}

/* check the instance pointer, the interface type and the state machine */
fmi2Status fmu_check(Inst *m, const char *fn, int allowed, int needType) {
    if (!m) return fmi2Error;
    if (m->s.magic != SNAP_MAGIC) return fmi2Error;
    if (needType >= 0 && m->s.type != needType) {
        return ERR(m, "%s: not available for %s", fn,
                   m->s.type == fmi2CoSimulation ? "Co-Simulation" : "Model Exchange");
    }
    if (!(m->s.mode & allowed)) {
        return ERR(m, "%s: must not be called in state '%s'", fn, mode_name(m->s.mode));
    }
    return fmi2OK;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    Inst *m;
    size_t n;
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
    m = (Inst *)functions->allocateMemory(1, sizeof(Inst));
    if (!m) EARLY_ERR("fmi2Instantiate: out of memory");
    memset(m, 0, sizeof(Inst));
    m->cb = *functions;
    n = strlen(instanceName) + 1;
    m->name = (char *)functions->allocateMemory(n, 1);
    if (!m->name) {
        functions->freeMemory(m);
        EARLY_ERR("fmi2Instantiate: out of memory");
    }
    memcpy(m->name, instanceName, n);
    m->logging = loggingOn ? 1 : 0;
    m->s.magic = SNAP_MAGIC;
    m->s.size = (unsigned)sizeof(Snapshot);
    strncpy(m->s.token, PDBFS_GUID, sizeof m->s.token - 1);
    m->s.type = fmuType;
    model_defaults(m);
    fmu_log(m, fmi2OK, "logAll", "instantiated %s (%s)", PDBFS_MODEL_IDENTIFIER,
           fmuType == fmi2CoSimulation ? "CoSimulation" : "ModelExchange");
    return m;
#undef EARLY_ERR
}

void fmi2FreeInstance(fmi2Component c) {
    Inst *m = (Inst *)c;
    fmi2CallbackFreeMemory freeMemory;
    if (!m || m->s.magic != SNAP_MAGIC) return;
    cosim_free(m);
    freeMemory = m->cb.freeMemory;
    m->s.magic = 0;
    freeMemory(m->name);
    freeMemory(m);
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2SetDebugLogging", ST_ANY, -1) != fmi2OK) return fmi2Error;
    for (i = 0; i < nCategories; i++) {
        const char *k = categories ? categories[i] : NULL;
        if (!k || (strcmp(k, "logEvents") && strcmp(k, "logStatusWarning") && strcmp(k, "logStatusError") &&
                   strcmp(k, "logAll")))
            return ERR(m, "fmi2SetDebugLogging: unknown log category '%s'", k ? k : "(null)");
    }
    m->logging = loggingOn ? 1 : 0;
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2SetupExperiment", ST_INSTANTIATED, -1) != fmi2OK) return fmi2Error;
    if (toleranceDefined && !(isfinite(tolerance) && tolerance > 0 && tolerance < 1))
        return ERR(m, "fmi2SetupExperiment: tolerance %g must be in (0, 1)", tolerance);
    if (!isfinite(startTime)) return ERR(m, "fmi2SetupExperiment: startTime is not finite");
    if (stopTimeDefined && !(isfinite(stopTime) && stopTime >= startTime))
        return ERR(m, "fmi2SetupExperiment: stopTime %g must be finite and >= startTime %g", stopTime, startTime);
    m->s.tol_defined = toleranceDefined ? 1 : 0;
    if (toleranceDefined) m->s.tol = tolerance;
    m->s.t_start = startTime;
    m->s.time = startTime;
    m->s.stop_defined = stopTimeDefined ? 1 : 0;
    m->s.t_stop = stopTime;
    m->derived_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2EnterInitializationMode", ST_INSTANTIATED, -1) != fmi2OK) return fmi2Error;
    m->s.mode = ST_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2ExitInitializationMode", ST_INIT, -1) != fmi2OK) return fmi2Error;
    model_start(m, m->s.x);
    if (!fmu_all_finite(m->s.x, NX)) return ERR(m, "start values are not finite: check the parameters");
    m->s.x_fixed = 1;
    m->derived_ok = 0;
    m->need_restart = 1;
    m->s.mode = m->s.type == fmi2CoSimulation ? ST_STEPDONE : ST_EVENT;
    if (m->s.type == fmi2CoSimulation) return cosim_start(m);
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2Terminate", ST_RUNNING, -1) != fmi2OK) return fmi2Error;
    m->s.mode = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2Reset", ST_ANY, -1) != fmi2OK) return fmi2Error;
    cosim_free(m); /* a fresh CVODE: the second run is the first again */
    model_defaults(m);
    return fmi2OK;
}

/* --------------------------------------------------------- getters/setters */

#define VR_P_END (PDBFS_VR_P + NP)
#define VR_C_END (PDBFS_VR_C + NC)
#define VR_X_END (PDBFS_VR_X + NX)
#define VR_DX_END (PDBFS_VR_DX + NX)
#define VR_Y_END (PDBFS_VR_Y + NYV)

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2GetReal", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2GetReal: NULL argument");
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r >= PDBFS_VR_P && r < VR_P_END) {
            value[i] = m->s.p[r - PDBFS_VR_P];
        } else if (r == PDBFS_VR_RTOL) {
            value[i] = model_rtol(m);
        } else if (r == PDBFS_VR_MAXSTEP) {
            value[i] = m->s.max_step;
        } else if (r >= PDBFS_VR_C && r < VR_C_END) {
            model_update(m);
            value[i] = m->c[r - PDBFS_VR_C];
        } else if (r >= PDBFS_VR_X && r < VR_X_END) {
            value[i] = model_x(m)[r - PDBFS_VR_X];
        } else if (r >= PDBFS_VR_DX && r < VR_DX_END) {
            model_update(m);
            value[i] = m->xdot[r - PDBFS_VR_DX];
        } else if (r >= PDBFS_VR_Y && r < VR_Y_END) {
            model_update(m);
            value[i] = m->y[PDBFS_Y_INDEX[r - PDBFS_VR_Y]];
        } else {
            return ERR(m, "fmi2GetReal: unknown value reference %u", r);
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    int before_init, tunable_ok, changed = 0;
    if (fmu_check(m, "fmi2SetReal", ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEPDONE, -1) != fmi2OK)
        return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2SetReal: NULL argument");
    before_init = (m->s.mode & (ST_INSTANTIATED | ST_INIT)) != 0;
    tunable_ok = before_init || (m->s.mode & (ST_EVENT | ST_STEPDONE)) != 0;
    /* validate everything first: a rejected call changes nothing */
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        double v = value[i];
        if (r >= PDBFS_VR_P && r < VR_P_END) {
            int k = (int)(r - PDBFS_VR_P);
            if (!before_init && !PDBFS_P_TUNABLE[k])
                return ERR(m, "fmi2SetReal: parameter %s is fixed and cannot be changed after initialization",
                           PDBFS_P_NAME[k]);
            if (!tunable_ok)
                return ERR(m, "fmi2SetReal: tunable parameter %s can only be changed in %s", PDBFS_P_NAME[k],
                           m->s.type == fmi2CoSimulation ? "between steps" : "event mode");
            if (model_check_param(m, k, v) != fmi2OK) return fmi2Error;
        } else if (r == PDBFS_VR_RTOL || r == PDBFS_VR_MAXSTEP) {
            const char *nm = r == PDBFS_VR_RTOL ? "solver.rtol" : "solver.max_step";
            if (!before_init)
                return ERR(m, "fmi2SetReal: %s is fixed and cannot be changed after initialization", nm);
            if (!isfinite(v)) return ERR(m, "fmi2SetReal: %s = %g is not finite", nm, v);
            if (r == PDBFS_VR_RTOL && !(v >= PDBFS_RTOL_MIN && v <= PDBFS_RTOL_MAX))
                return ERR(m, "fmi2SetReal: solver.rtol = %g must be in [%g, %g]", v, PDBFS_RTOL_MIN,
                           PDBFS_RTOL_MAX);
            if (r == PDBFS_VR_MAXSTEP && v < 0)
                return ERR(m, "fmi2SetReal: solver.max_step = %g must be >= 0 (0: no limit)", v);
        } else if (r >= PDBFS_VR_P && r < VR_Y_END) {
            return ERR(m, "fmi2SetReal: variable with value reference %u is not settable", r);
        } else {
            return ERR(m, "fmi2SetReal: unknown value reference %u", r);
        }
    }
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference r = vr[i];
        if (r >= PDBFS_VR_P && r < VR_P_END) {
            if (m->s.p[r - PDBFS_VR_P] != value[i]) changed = 1;
            m->s.p[r - PDBFS_VR_P] = value[i];
        } else if (r == PDBFS_VR_RTOL) {
            m->s.rtol = value[i];
            m->s.rtol_user = 1;
        } else if (r == PDBFS_VR_MAXSTEP) {
            m->s.max_step = value[i];
        }
    }
    m->derived_ok = 0;
    if (changed && !before_init) m->need_restart = 1; /* restart: the right-hand side changed */
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2GetInteger", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2GetInteger: NULL argument");
    for (i = 0; i < nvr; i++) {
        if (vr[i] == PDBFS_VR_METHOD) value[i] = m->s.method;
        else if (vr[i] == PDBFS_VR_MAXNUMSTEPS) value[i] = m->s.max_num_steps;
        else return ERR(m, "fmi2GetInteger: unknown value reference %u", vr[i]);
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    Inst *m = (Inst *)c;
    size_t i;
    if (fmu_check(m, "fmi2SetInteger", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0 && (!vr || !value)) return ERR(m, "fmi2SetInteger: NULL argument");
    for (i = 0; i < nvr; i++) {
        const char *nm = vr[i] == PDBFS_VR_METHOD ? "solver.method" : "solver.max_num_steps";
        if (vr[i] != PDBFS_VR_METHOD && vr[i] != PDBFS_VR_MAXNUMSTEPS)
            return ERR(m, "fmi2SetInteger: unknown value reference %u", vr[i]);
        if (!(m->s.mode & (ST_INSTANTIATED | ST_INIT)))
            return ERR(m, "fmi2SetInteger: %s is fixed and cannot be changed after initialization", nm);
        if (vr[i] == PDBFS_VR_METHOD && value[i] != METHOD_BDF && value[i] != METHOD_ADAMS)
            return ERR(m, "fmi2SetInteger: solver.method = %d must be 1 (BDF) or 2 (Adams)", value[i]);
        if (vr[i] == PDBFS_VR_MAXNUMSTEPS && value[i] < 1)
            return ERR(m, "fmi2SetInteger: solver.max_num_steps = %d must be >= 1", value[i]);
    }
    for (i = 0; i < nvr; i++) {
        if (vr[i] == PDBFS_VR_METHOD) m->s.method = value[i];
        else m->s.max_num_steps = value[i];
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2GetBoolean", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2SetBoolean", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetBoolean: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2GetString", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    Inst *m = (Inst *)c;
    (void)value;
    if (fmu_check(m, "fmi2SetString", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetString: unknown value reference %u", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    Inst *m = (Inst *)c;
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    if (fmu_check(m, "fmi2GetDirectionalDerivative", ST_ANY, -1) != fmi2OK) return fmi2Error;
    return ERR(m, "fmi2GetDirectionalDerivative is not provided (providesDirectionalDerivative=false)");
}
