/* The co-simulation loop of a pdbfs FMU, for every FMI version: CVODE
 * (native/c/pdbfs_cvode.c) or the explicit Runge-Kutta method 8(5,3)
 * (native/c/pdbfs_erk.c, the compiled backend's "erk") through the rig's
 * non-smooth points.  Communication points are served from the solver's
 * dense output, so the trajectory does not depend on the communication
 * step; a tunable parameter changed between steps restarts the solver.
 * solver.method auto switches between the explicit method and BDF at the
 * solvers' own steps (stiffness.c). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "fmu_instance.h"

static void solver_log(void *env, int kind, const char *text) {
    Inst *m = (Inst *)env;
    if (kind == PDBFS_LOG_ERROR) fmu_log(m, FMU_ERROR, "logStatusError", "CVODE: %s", text);
    else if (kind == PDBFS_LOG_WARNING) fmu_log(m, FMU_WARNING, "logStatusWarning", "CVODE: %s", text);
    else fmu_log(m, FMU_OK, "logEvents", "%s", text);
}

void cosim_free(Inst *m) {
    pdbfs_cvode_free(&m->solver);
    if (m->rk.y) pdbfs_erk_free(&m->rk);
    m->need_restart = RESTART_FRESH;
}

/* how far the solver may look ahead, the same whatever the communication
 * step (it bounds the first step after each (re)start): the stop time,
 * else INFINITY, for which pdbfs_cvode_advance takes 1 s beyond each
 * (re)start */
static double horizon(const Inst *m, double t) {
    if (m->s.stop_defined && m->s.t_stop > t) return m->s.t_stop;
    return INFINITY;
}

/* (Re)start the explicit method at (t, x): it never steps past the next
 * time event (a valve's switch: the right-hand side jumps there) nor the
 * stop time, where it is started again; under auto's switching it stops
 * where its steps are held by stability (PDBFS_ERK_STIFF) */
static int erk_start(Inst *m, double t, const double *x) {
    PdbfsCvodeSettings set = {0};
    double stop = horizon(m, t);
    m->rk.stiff_after = m->switching && m->lambda_ref > 0 ? PDBFS_AUTO_SWITCH_STEPS : 0;
    m->rk.stiff_h = m->lambda_ref > 0 ? PDBFS_AUTO_SWITCH_TO_BDF / m->lambda_ref : INFINITY;
    m->t_break = pdbfs_next_time_event(&m->solver, t, x);
    set.rtol = model_rtol(m);
    set.atol = m->atol;
    set.max_step = m->s.max_step > 0 ? m->s.max_step : 0.0;
    set.t_stop = m->t_break < stop ? m->t_break : stop;
    if (pdbfs_erk_start(&m->rk, &set, t, x)) return ERR(m, "explicit Runge-Kutta: %s", m->rk.msg);
    return FMU_OK;
}

/* auto's switch back from BDF, at a root (a kink: a blow or a valve's switch
 * begins there, which the explicit method resolves in fewer steps), or after
 * BDF_SETTLE steps of a (re)start (its first steps are short whatever the
 * rig) once PDBFS_AUTO_SWITCH_STEPS steps in a row, over a period of the
 * fastest mode at least (not the few short steps before a kink), were
 * shorter than PDBFS_AUTO_SWITCH_TO_ERK / lambda_ref: CVODE pauses where the
 * step ended and the explicit method starts there (integrate_to), whatever
 * the communication points */
#define BDF_SETTLE (2 * PDBFS_AUTO_SWITCH_STEPS)
#define TWO_PI 6.283185307179586
static int bdf_watch(void *env, double t, const double *x) {
    Inst *m = (Inst *)env;
    double h = 0.0;
    if (!m->solver.root_pending) {
        if (m->solver.steps_since_start <= BDF_SETTLE || CVodeGetLastStep(m->solver.cv, &h) != CV_SUCCESS)
            return 0;
        if (h * m->lambda_ref < PDBFS_AUTO_SWITCH_TO_ERK) {
            m->bdf_short++;
            m->bdf_short_time += h;
        } else {
            m->bdf_short = 0;
            m->bdf_short_time = 0.0;
        }
        if (m->bdf_short < PDBFS_AUTO_SWITCH_STEPS || m->bdf_short_time * m->lambda_ref < TWO_PI) return 0;
    }
    m->switch_pending = 1;
    m->t_switch = t;
    memcpy(m->x_switch, x, sizeof(double) * NX);
    return PDBFS_STEP_PAUSE;
}

/* The importer's intermediate update (FMI 3.0) after an internal step that
 * ended at t with the state x, inside the DoStep to m->t_end: the outputs
 * are read at (t, x) in Intermediate Update Mode, the instance as it was
 * afterwards. 1 where the importer asks to return early: at the time it
 * asks, kept to what the step's dense output and the DoStep cover ([step_from
 * or the DoStep's start, t_end]; a time past t: the run goes on to it) */
#define STOPPED_EARLY 100     /* integrate_to: stopped where the importer asked (m->t_early) */
static int intermediate_update(Inst *m, double t, const double *x, double step_from) {
    double saved_time = m->s.time, saved_x[NX + 1], when = t, lo;
    int ask;
    if (!(t > m->t_seen && t < (m->early ? m->t_early : m->t_end))) return 0;   /* (none past the return) */
    memcpy(saved_x, m->s.x, sizeof(double) * NX);
    m->s.time = t;
    memcpy(m->s.x, x, sizeof(double) * NX);
    m->derived_ok = 0;
    m->s.mode = ST_INTERMEDIATE;
    ask = m->host.intermediate(m, t, m->host.early_allowed, &when) && m->host.early_allowed;
    m->s.mode = ST_STEPDONE;
    m->s.time = saved_time;
    memcpy(m->s.x, saved_x, sizeof(double) * NX);
    m->derived_ok = 0;
    if (!ask) return 0;
    lo = step_from > m->t_seen ? step_from : m->t_seen;
    m->t_early = !(when >= lo) ? lo : when > m->t_end ? m->t_end : when;   /* (NaN: lo) */
    m->early = 1;
    fmu_log(m, FMU_OK, "logEvents", "intermediate update at t=%.17g: return early at t=%.17g", t, m->t_early);
    return 1;
}

/* after each of CVODE's steps: auto's watch of BDF (every step, so that an
 * early return changes no switch), the intermediate update */
static int cvode_step(void *env, double t, const double *x) {
    Inst *m = (Inst *)env;
    double hu = 0.0;
    int watched = m->watch_bdf ? bdf_watch(env, t, x) : 0;
    if (m->host.intermediate) {
        CVodeGetLastStep(m->solver.cv, &hu);
        if (intermediate_update(m, t, x, m->solver.tn - hu)) return PDBFS_STEP_PAUSE;
    }
    return watched;
}

/* after each of the explicit method's steps (its dense output made) */
static int erk_step(void *env, double t, const double *x) {
    Inst *m = (Inst *)env;
    return intermediate_update(m, t, x, m->rk.t_old);
}

/* (Re)start the solver at (t, x); absolute tolerance = rtol * nominal */
static int start_at(Inst *m, double t, const double *x) {
    PdbfsCvodeSettings set = {0};
    int i;
    if (!m->solver.ev) {
        pdbfs_cvode_init(&m->solver, NX, NE, &m->ev, solver_log, m);
        m->solver.nte = PDBFS_NTE;   /* CVODE stops at each switch time */
    }
    set.rtol = model_rtol(m);
    for (i = 0; i < NX; i++) m->atol[i] = set.rtol * PDBFS_X_NOMINAL[i];
    m->bdf_short = 0;
    m->bdf_short_time = 0.0;
    m->switch_pending = 0;
    if (m->s.method_used == METHOD_ERK) {
        if (!m->rk.y && pdbfs_erk_init(&m->rk, NX, NE, &m->ev)) return ERR(m, "out of memory");
        m->rk.on_step = m->host.intermediate ? erk_step : NULL;   /* (a watched step makes its dense output) */
        m->rk.step_env = m;
        if (erk_start(m, t, x) != FMU_OK) return FMU_ERROR;
        m->need_restart = 0;
        return FMU_OK;
    }
    set.method = m->s.method_used == METHOD_ADAMS ? PDBFS_ADAMS : PDBFS_BDF;
    set.atol = m->atol;
    set.max_step = m->s.max_step > 0 ? m->s.max_step : 0.0;
    set.t_stop = INFINITY;
    m->watch_bdf = m->switching && m->s.method_used == METHOD_BDF && m->lambda_ref > 0;
    m->solver.on_step = m->watch_bdf || m->host.intermediate ? cvode_step : NULL;
    m->solver.step_env = m;
    if (pdbfs_cvode_start(&m->solver, &set, t, x)) return ERR(m, "CVODE setup failed");
    m->need_restart = 0;
    return FMU_OK;
}

int cosim_start(Inst *m) {
    return start_at(m, m->s.time, m->s.x);
}

/* integrate_to's restart at the current time: afresh, or (RESTART_CHANGED)
 * where an input or a tunable parameter changed between steps. The solution
 * is smooth on either side of such a change, so the explicit method goes on
 * with the step it had (its fresh estimate overshot, and a rejected attempt
 * at each communication point cost evaluations and accuracy); BDF under
 * auto's switching hands over to the explicit method, as at an event: a
 * multistep method restarts at order 1, and restarted at every communication
 * step (a master feeding inputs) its error grows with the restarts (BDF at
 * rtol 1e-8: 8.7e-7 of the closed loop's peak after 3,200 of them, against
 * 3e-8 without), while its own way back (short steps, bdf_watch) needs more
 * steps than a communication step then holds */
static int restart(Inst *m) {
    double h = 0.0;
    int st;
    if (m->need_restart == RESTART_CHANGED) {
        if (m->s.method_used == METHOD_ERK && m->rk.y && !m->rk.fresh) h = m->rk.h;
        else if (m->switching && m->s.method_used == METHOD_BDF && m->lambda_ref > 0) {
            fmu_log(m, FMU_OK, "logEvents", "solver.method auto: explicit Runge-Kutta 8(5,3) from t=%.17g (an "
                    "input or a parameter changed)", m->s.time);
            m->s.method_used = METHOD_ERK;
        }
    }
    st = start_at(m, m->s.time, m->s.x);
    if (st == FMU_OK && h > 0 && m->s.method_used == METHOD_ERK && !m->rk.kink_steps)
        m->rk.h = m->s.max_step > 0 && h > m->s.max_step ? m->s.max_step : h;
    return st;
}

/* auto's switches: to BDF where the explicit method stopped (its steps held
 * by stability), to the explicit method where BDF paused (its steps short) */
static int switch_method(Inst *m, int to, double t, const double *x) {
    fmu_log(m, FMU_OK, "logEvents", "solver.method auto: %s from t=%.17g (%s)",
            to == METHOD_BDF ? "CVODE BDF" : "explicit Runge-Kutta 8(5,3)", t,
            to == METHOD_BDF ? m->rk.msg
            : m->solver.root_pending ? "an event" : "BDF's steps short against the fastest mode");
    m->s.method_used = to;
    return start_at(m, t, x);
}

/* the explicit method to tEnd, through the time events on the way (each a
 * restart); at most max_num_steps steps */
static int erk_to(Inst *m, double tEnd) {
    long steps0 = m->rk.steps, left;
    int flag = 0;
    for (;;) {
        double target = m->t_break < tEnd ? m->t_break : tEnd;
        /* a last step may end within roundoff past the stop time (DoStep allows it) */
        int at_stop = target > m->rk.t_stop && m->rk.t_stop < m->t_break;
        if (at_stop) target = m->rk.t_stop;
        left = (long)m->s.max_num_steps - (m->rk.steps - steps0);
        flag = left > 0 ? pdbfs_erk_advance(&m->rk, target, left, m->s.x) : PDBFS_CV_TOO_MUCH_WORK;
        if (flag || target == tEnd || at_stop) break;
        fmu_log(m, FMU_OK, "logEvents", "time event at t=%.17g, explicit Runge-Kutta restarted", target);
        if (erk_start(m, target, m->s.x) != FMU_OK) return FMU_ERROR;
    }
    if (flag == PDBFS_CV_STOPPED && m->early) return STOPPED_EARLY;
    if (flag == PDBFS_ERK_STIFF) return PDBFS_ERK_STIFF;     /* (auto: to BDF, integrate_to) */
    if (flag == PDBFS_CV_TOO_MUCH_WORK)
        return ERR(m, "explicit Runge-Kutta failed (too much work: solver.max_num_steps = %d steps) at "
                   "t=%.17g while integrating to t=%.17g", m->s.max_num_steps, m->rk.t, tEnd);
    if (flag)
        return ERR(m, "explicit Runge-Kutta failed at t=%.17g while integrating to t=%.17g: %s", m->rk.t, tEnd,
                   m->rk.msg);
    return FMU_OK;
}

/* integrate to tEnd; on success m->s.x is the state at tEnd */
static int integrate_to(Inst *m, double tEnd) {
    int flag;
    if (m->need_restart) {
        int st = restart(m);
        if (st != FMU_OK) return st;
    }
    for (;;) {
        if (m->s.method_used == METHOD_ERK) {
            flag = erk_to(m, tEnd);
            if (flag == PDBFS_ERK_STIFF) {
                if (switch_method(m, METHOD_BDF, m->rk.t, m->rk.y) == FMU_OK) continue;
                flag = FMU_ERROR;
            }
            if (flag != FMU_OK && flag != STOPPED_EARLY) m->need_restart = RESTART_FRESH;
            return flag;
        }
        if (m->switch_pending && m->t_switch < tEnd) {
            if (switch_method(m, METHOD_ERK, m->t_switch, m->x_switch) == FMU_OK) continue;
            m->need_restart = RESTART_FRESH;
            return FMU_ERROR;
        }
        /* (a pause past tEnd: no step taken, tEnd served from CVODE's last step) */
        flag = pdbfs_cvode_advance(&m->solver, tEnd, horizon(m, m->solver.tn), m->s.max_num_steps, m->s.x);
        if (flag == PDBFS_CV_STOPPED && m->early) return STOPPED_EARLY;   /* (paused: its dense output holds) */
        if (flag != PDBFS_CV_STOPPED || !m->switch_pending) break;
    }
    if (flag == PDBFS_CV_TOO_MUCH_WORK) {
        m->need_restart = RESTART_FRESH;
        return ERR(m, "CVODE failed (too much work: solver.max_num_steps = %d internal steps) at t=%.17g "
                   "while integrating to t=%.17g", m->s.max_num_steps, m->solver.tn, tEnd);
    }
    if (flag) {
        m->need_restart = RESTART_FRESH;
        return ERR(m, "CVODE failed (flag %d) at t=%.17g while integrating to t=%.17g", flag, m->solver.tn,
                   tEnd);
    }
    return FMU_OK;
}

/* integrate_to tEnd, or to where an intermediate update asked to return */
static int integrate(Inst *m, double tEnd) {
    int st;
    m->early = 0;
    m->t_end = tEnd;
    m->t_seen = m->s.time;
    do st = integrate_to(m, m->early ? m->t_early : tEnd);
    while (st == STOPPED_EARLY);
    return st;
}

/* one communication step from t to t + h (the wrapper has checked the
 * state machine); a solver failure leaves the instance in the error state */
int cosim_do_step(Inst *m, const char *fn, double t, double h, int *early) {
    int st;
    double tol;
    if (!(h > 0) || !isfinite(h))
        return ERR(m, "%s: communicationStepSize %g must be positive and finite", fn, h);
    tol = 1e-9 * h + 64 * DBL_EPSILON * fabs(m->s.time);
    if (!isfinite(t) || fabs(t - m->s.time) > tol)
        return ERR(m, "%s: currentCommunicationPoint %.17g does not match the FMU time %.17g", fn, t, m->s.time);
    if (m->s.stop_defined && t + h > m->s.t_stop + tol)
        return ERR(m, "%s: the step to t=%.17g goes past stopTime %.17g", fn, t + h, m->s.t_stop);
    st = integrate(m, t + h);
    m->derived_ok = 0;
    if (st != FMU_OK) {
        m->s.mode = ST_ERROR;
        return FMU_ERROR;
    }
    m->s.time = m->early && m->t_early < t + h ? m->t_early : t + h;
    if (early) *early = m->s.time < t + h;
    if (model_check_finite(m, fn) != FMU_OK) {
        m->s.mode = ST_ERROR;
        return FMU_ERROR;
    }
    return FMU_OK;
}
