/* Co-Simulation of a pdbfs FMU: CVODE through the rig's non-smooth points
 * (native/c/pdbfs_cvode.c).  Communication points are served from CVODE's
 * dense output, so the trajectory does not depend on the communication
 * step; a tunable parameter changed between steps restarts CVODE. */
#include <float.h>
#include <math.h>

#include "fmu_instance.h"

static void solver_log(void *env, int kind, const char *text) {
    Inst *m = (Inst *)env;
    if (kind == PDBFS_LOG_ERROR) fmu_log(m, fmi2Error, "logStatusError", "CVODE: %s", text);
    else if (kind == PDBFS_LOG_WARNING) fmu_log(m, fmi2Warning, "logStatusWarning", "CVODE: %s", text);
    else fmu_log(m, fmi2OK, "logEvents", "%s", text);
}

void cosim_free(Inst *m) {
    pdbfs_cvode_free(&m->solver);
    m->need_restart = 1;
}

/* (Re)start CVODE at (time, x); absolute tolerance = rtol * nominal */
fmi2Status cosim_start(Inst *m) {
    PdbfsCvodeSettings set = {0};
    double atol[NX + 1];
    int i;
    if (!m->solver.ev) pdbfs_cvode_init(&m->solver, NX, NE, &m->ev, solver_log, m);
    set.method = m->s.method == METHOD_ADAMS ? PDBFS_ADAMS : PDBFS_BDF;
    set.rtol = model_rtol(m);
    for (i = 0; i < NX; i++) atol[i] = set.rtol * PDBFS_X_NOMINAL[i];
    set.atol = atol;
    set.max_step = m->s.max_step > 0 ? m->s.max_step : 0.0;
    set.t_stop = INFINITY;
    if (pdbfs_cvode_start(&m->solver, &set, m->s.time, m->s.x)) return ERR(m, "CVODE setup failed");
    m->need_restart = 0;
    return fmi2OK;
}

/* how far CVODE may look ahead, the same whatever the communication step (it
 * bounds the first step after each (re)start): the stop time, else INFINITY,
 * for which pdbfs_cvode_advance takes 1 s beyond each (re)start */
static double horizon(const Inst *m) {
    if (m->s.stop_defined && m->s.t_stop > m->solver.tn) return m->s.t_stop;
    return INFINITY;
}

/* integrate to tEnd; on success m->s.x is the state at tEnd */
static fmi2Status integrate_to(Inst *m, double tEnd) {
    int flag;
    if (m->need_restart) {
        fmi2Status st = cosim_start(m);
        if (st != fmi2OK) return st;
    }
    flag = pdbfs_cvode_advance(&m->solver, tEnd, horizon(m), m->s.max_num_steps, m->s.x);
    if (flag == PDBFS_CV_TOO_MUCH_WORK) {
        m->need_restart = 1;
        return ERR(m, "CVODE failed (too much work: solver.max_num_steps = %d internal steps) at t=%.17g "
                   "while integrating to t=%.17g", m->s.max_num_steps, m->solver.tn, tEnd);
    }
    if (flag) {
        m->need_restart = 1;
        return ERR(m, "CVODE failed (flag %d) at t=%.17g while integrating to t=%.17g", flag, m->solver.tn,
                   tEnd);
    }
    return fmi2OK;
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    Inst *m = (Inst *)c;
    (void)order; (void)value;
    if (fmu_check(m, "fmi2SetRealInputDerivatives", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2SetRealInputDerivatives: the model has no inputs (vr %u)", vr ? vr[0] : 0u);
    return fmi2OK;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    Inst *m = (Inst *)c;
    (void)vr; (void)order; (void)value;
    if (fmu_check(m, "fmi2GetRealOutputDerivatives", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (nvr > 0) return ERR(m, "fmi2GetRealOutputDerivatives: not provided (maxOutputDerivativeOrder=0)");
    return fmi2OK;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Inst *m = (Inst *)c;
    fmi2Status st;
    double tol;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_check(m, "fmi2DoStep", ST_STEPDONE, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    if (!(h > 0) || !isfinite(h))
        return ERR(m, "fmi2DoStep: communicationStepSize %g must be positive and finite", h);
    tol = 1e-9 * h + 64 * DBL_EPSILON * fabs(m->s.time);
    if (!isfinite(t) || fabs(t - m->s.time) > tol)
        return ERR(m, "fmi2DoStep: currentCommunicationPoint %.17g does not match the FMU time %.17g", t,
                   m->s.time);
    if (m->s.stop_defined && t + h > m->s.t_stop + tol)
        return ERR(m, "fmi2DoStep: the step to t=%.17g goes past stopTime %.17g", t + h, m->s.t_stop);
    st = integrate_to(m, t + h);
    m->derived_ok = 0;
    if (st != fmi2OK) {
        m->s.mode = ST_ERROR;
        return fmi2Error;
    }
    m->s.time = t + h;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2CancelStep", ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;
    return ERR(m, "fmi2CancelStep: fmi2DoStep never runs asynchronously");
}

/* the status calls: only the last successful time and 'not terminated' are known */
#define STATUS_CALL(NAME, TYPE, KIND, VALUE)                                                     \
    fmi2Status NAME(fmi2Component c, const fmi2StatusKind s, TYPE *value) {                    \
        Inst *m = (Inst *)c;                                                                   \
        if (fmu_check(m, #NAME, ST_ANY, fmi2CoSimulation) != fmi2OK) return fmi2Error;         \
        if ((int)s == (int)(KIND) && value) {                                                  \
            *value = (VALUE);                                                                  \
            return fmi2OK;                                                                     \
        }                                                                                      \
        return fmi2Discard;                                                                    \
    }

STATUS_CALL(fmi2GetStatus, fmi2Status, -1, fmi2OK)
STATUS_CALL(fmi2GetRealStatus, fmi2Real, fmi2LastSuccessfulTime, m->s.time)
STATUS_CALL(fmi2GetIntegerStatus, fmi2Integer, -1, 0)
STATUS_CALL(fmi2GetBooleanStatus, fmi2Boolean, fmi2Terminated, fmi2False)
STATUS_CALL(fmi2GetStringStatus, fmi2String, -1, "")
