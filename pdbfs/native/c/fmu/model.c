/* The model of a pdbfs FMU on its CasADi-generated functions (defaults,
 * start values, derivatives, outputs, event indicators, calculated
 * parameters), logging and the state machine's check: the bottom of the
 * version-neutral files, calling none of them (lifecycle.c, values.c,
 * snapshot.c, model_exchange.c and cosimulation.c call it). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmu_instance.h"

/* ------------------------------------------------------------ logging */

void fmu_log(Inst *m, int st, const char *cat, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!m || !m->host.hook || !m->host.logger) return;
    if (st == FMU_OK && !m->logging) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    m->host.hook(m, st, cat, buf);
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
    case ST_INTERMEDIATE: return "intermediate update";
    default: return "unknown";
    }
}

/* check the instance pointer, the interface type and the state machine */
int fmu_check(Inst *m, const char *fn, int allowed, int needType) {
    if (!m) return FMU_ERROR;
    if (m->s.magic != SNAP_MAGIC) return FMU_ERROR;
    if (needType >= 0 && m->s.type != needType) {
        return ERR(m, "%s: not available for %s", fn, m->s.type == FMU_CS ? "Co-Simulation" : "Model Exchange");
    }
    if (!(m->s.mode & allowed)) {
        return ERR(m, "%s: must not be called in state '%s'", fn, mode_name(m->s.mode));
    }
    return FMU_OK;
}

/* ------------------------------------------------------------- model */

int fmu_all_finite(const double *v, int n) {
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

void model_defaults(Inst *m) {
    int i;
    for (i = 0; i < NP; i++) m->s.p[i] = PDBFS_P_DEFAULT[i];
    m->s.rtol = PDBFS_DEFAULT_RTOL;
    m->s.max_step = PDBFS_DEFAULT_MAXSTEP;
    m->s.method = PDBFS_DEFAULT_METHOD;
    m->s.method_used = METHOD_BDF;   /* resolved at initialisation */
    m->s.max_num_steps = PDBFS_DEFAULT_MAXNUMSTEPS;
    m->s.rtol_user = 0;
    m->s.tol_defined = 0;
    m->s.tol = PDBFS_DEFAULT_RTOL;
    m->s.t_start = 0.0;
    m->s.stop_defined = 0;
    m->s.t_stop = 0.0;
    m->s.time = 0.0;
    m->s.x_fixed = 0;
    for (i = 0; i < NX; i++) m->s.x[i] = 0.0;
    for (i = 0; i < NU; i++) m->s.slope_time[i] = -INFINITY;
    m->s.mode = ST_INSTANTIATED;
    m->derived_ok = 0;
    m->need_restart = RESTART_FRESH;
    m->ev.p = m->s.p;
    m->ev.arg = m->arg;
    m->ev.res = m->res;
    m->ev.iw = m->iw;
    m->ev.w = m->w;
}

/* the tolerance in force: solver.rtol if set, else the experiment's, else the default */
double model_rtol(const Inst *m) {
    if (m->s.rtol_user) return m->s.rtol;
    if (m->s.tol_defined) return m->s.tol;
    return m->s.rtol;
}

int model_start(Inst *m, double *x0) {
    m->arg[0] = m->s.p;
    m->res[0] = x0;
    return pdbfs_start(m->arg, m->res, m->iw, m->w, 0);
}

/* the state: x0(p) until initialisation has fixed it */
const double *model_x(Inst *m) {
    if (!m->s.x_fixed) model_start(m, m->s.x);
    return m->s.x;
}

void model_update(Inst *m) {
    const double *x;
    if (m->derived_ok) return;
    x = model_x(m);
    pdbfs_eval_txp(&m->ev, pdbfs_ode, m->s.time, x, m->xdot);
    pdbfs_eval_txp(&m->ev, pdbfs_out, m->s.time, x, m->y);
    if (NE > 0) pdbfs_eval_txp(&m->ev, pdbfs_events, m->s.time, x, m->e);
    if (NC > 0) {
        m->arg[0] = m->s.p;
        m->res[0] = m->c;
        pdbfs_calc(m->arg, m->res, m->iw, m->w, 0);
    }
    m->derived_ok = 1;
}

/* the state, its derivatives and the outputs at (time, x, p) finite, else one
 * error naming the first that is not: a parameter at a value the model cannot
 * run at (an area of 1e-308 m2: an infinite pressure) must not pass as OK */
int model_check_finite(Inst *m, const char *fn) {
    int i;
    const double *x = model_x(m);
    for (i = 0; i < NX; i++)
        if (!isfinite(x[i]))
            return ERR(m, "%s: state %s = %g at t=%.17g: check the parameters", fn, PDBFS_X_NAME[i], x[i],
                       m->s.time);
    model_update(m);
    for (i = 0; i < NX; i++)
        if (!isfinite(m->xdot[i]))
            return ERR(m, "%s: der(%s) = %g at t=%.17g: check the parameters", fn, PDBFS_X_NAME[i],
                       m->xdot[i], m->s.time);
    for (i = 0; i < NYV; i++)
        if (!isfinite(m->y[PDBFS_Y_INDEX[i]]))
            return ERR(m, "%s: output %s = %g at t=%.17g: check the parameters", fn, PDBFS_Y_NAME[i],
                       m->y[PDBFS_Y_INDEX[i]], m->s.time);
    return FMU_OK;
}

/* the derivatives and the outputs at (time, x, p) all finite (no message) */
int model_finite(Inst *m) {
    int i;
    model_update(m);
    if (!fmu_all_finite(m->xdot, NX)) return 0;
    for (i = 0; i < NYV; i++)
        if (!isfinite(m->y[PDBFS_Y_INDEX[i]])) return 0;
    return 1;
}

/* the components' physical consistency (Component.conditions, each >= 0) at
 * parameters p: the index of the first that fails, else -1 */
int model_failed_condition(Inst *m, const double *p) {
    double c[PDBFS_NCOND + 1];
    int i;
    if (PDBFS_NCOND == 0) return -1;
    m->arg[0] = p;
    m->res[0] = c;
    pdbfs_conditions(m->arg, m->res, m->iw, m->w, 0);
    for (i = 0; i < PDBFS_NCOND; i++)
        if (!(c[i] >= 0)) return i;
    return -1;
}

/* the declared start of each state index reduction made algebraic equal to
 * what its constraint gives at the start (the outputs y at time and x), else
 * one error naming it: the start of such a state is not free, and a value set
 * for it must not be ignored silently (as pdbfs.modelling.reduced_start) */
int model_check_reduced(Inst *m, const char *fn) {
    double s[PDBFS_NRS + 1], a, b;
    int i;
    if (PDBFS_NRS == 0) return FMU_OK;
    model_update(m);
    m->arg[0] = m->s.p;
    m->res[0] = s;
    pdbfs_reduced(m->arg, m->res, m->iw, m->w, 0);
    for (i = 0; i < PDBFS_NRS; i++) {
        a = s[i];
        b = m->y[PDBFS_RS_Y[i]];
        if (isfinite(b) && !(fabs(a - b) <= 1e-8 * (1.0 + fabs(a) + fabs(b))))
            return ERR(m, "%s: %s starts at %g %s, but the constraint that index reduction solves for it (%s) "
                       "gives %g %s at the start: its start is not free; give start values that satisfy the "
                       "constraint", fn, PDBFS_RS_NAME[i], a, PDBFS_RS_UNIT[i], PDBFS_RS_BY, b, PDBFS_RS_UNIT[i]);
    }
    return FMU_OK;
}

int model_check_param(Inst *m, int k, double v) {
    if (!isfinite(v)) return ERR(m, "parameter %s: value %g is not finite", PDBFS_P_NAME[k], v);
    if (PDBFS_P_POSITIVE[k] && !(v > 0))
        return ERR(m, "parameter %s: value %g must be positive", PDBFS_P_NAME[k], v);
    if (v < PDBFS_P_MIN[k] || v > PDBFS_P_MAX[k])
        return ERR(m, "parameter %s: value %g outside [%g, %g]", PDBFS_P_NAME[k], v, PDBFS_P_MIN[k],
                   PDBFS_P_MAX[k]);
    return FMU_OK;
}
