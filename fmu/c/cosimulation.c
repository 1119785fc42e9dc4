/* The co-simulation loop of a pdbfs FMU, for every FMI version: CVODE
 * through the rig's non-smooth points (native/c/pdbfs_cvode.c).  Communication points are served from CVODE's
 * dense output, so the trajectory does not depend on the communication
 * step; a tunable parameter changed between steps restarts CVODE. */
#include <float.h>
#include <math.h>

#include "fmu_instance.h"

static void solver_log(void *env, int kind, const char *text) {
    Inst *m = (Inst *)env;
    if (kind == PDBFS_LOG_ERROR) fmu_log(m, FMU_ERROR, "logStatusError", "CVODE: %s", text);
    else if (kind == PDBFS_LOG_WARNING) fmu_log(m, FMU_WARNING, "logStatusWarning", "CVODE: %s", text);
    else fmu_log(m, FMU_OK, "logEvents", "%s", text);
}

void cosim_free(Inst *m) {
    pdbfs_cvode_free(&m->solver);
    m->need_restart = 1;
}

/* (Re)start CVODE at (time, x); absolute tolerance = rtol * nominal */
int cosim_start(Inst *m) {
    PdbfsCvodeSettings set = {0};
    double atol[NX + 1];
    int i;
    if (!m->solver.ev) {
        pdbfs_cvode_init(&m->solver, NX, NE, &m->ev, solver_log, m);
        m->solver.nte = PDBFS_NTE;   /* CVODE stops at each switch time */
    }
    set.method = m->s.method == METHOD_ADAMS ? PDBFS_ADAMS : PDBFS_BDF;
    set.rtol = model_rtol(m);
    for (i = 0; i < NX; i++) atol[i] = set.rtol * PDBFS_X_NOMINAL[i];
    set.atol = atol;
    set.max_step = m->s.max_step > 0 ? m->s.max_step : 0.0;
    set.t_stop = INFINITY;
    if (pdbfs_cvode_start(&m->solver, &set, m->s.time, m->s.x)) return ERR(m, "CVODE setup failed");
    m->need_restart = 0;
    return FMU_OK;
}

/* how far CVODE may look ahead, the same whatever the communication step (it
 * bounds the first step after each (re)start): the stop time, else INFINITY,
 * for which pdbfs_cvode_advance takes 1 s beyond each (re)start */
static double horizon(const Inst *m) {
    if (m->s.stop_defined && m->s.t_stop > m->solver.tn) return m->s.t_stop;
    return INFINITY;
}

/* integrate to tEnd; on success m->s.x is the state at tEnd */
static int integrate_to(Inst *m, double tEnd) {
    int flag;
    if (m->need_restart) {
        int st = cosim_start(m);
        if (st != FMU_OK) return st;
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
    return FMU_OK;
}

/* one communication step from t to t + h (the wrapper has checked the
 * state machine); a solver failure leaves the instance in the error state */
int cosim_do_step(Inst *m, const char *fn, double t, double h) {
    int st;
    double tol;
    if (!(h > 0) || !isfinite(h))
        return ERR(m, "%s: communicationStepSize %g must be positive and finite", fn, h);
    tol = 1e-9 * h + 64 * DBL_EPSILON * fabs(m->s.time);
    if (!isfinite(t) || fabs(t - m->s.time) > tol)
        return ERR(m, "%s: currentCommunicationPoint %.17g does not match the FMU time %.17g", fn, t, m->s.time);
    if (m->s.stop_defined && t + h > m->s.t_stop + tol)
        return ERR(m, "%s: the step to t=%.17g goes past stopTime %.17g", fn, t + h, m->s.t_stop);
    st = integrate_to(m, t + h);
    m->derived_ok = 0;
    if (st != FMU_OK) {
        m->s.mode = ST_ERROR;
        return FMU_ERROR;
    }
    m->s.time = t + h;
    if (model_check_finite(m, fn) != FMU_OK) {
        m->s.mode = ST_ERROR;
        return FMU_ERROR;
    }
    return FMU_OK;
}
