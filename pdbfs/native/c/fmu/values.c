/* Variables of a pdbfs FMU by value reference, for every FMI version: the
 * parameters (checked against their bounds; fixed ones only before
 * initialisation, tunable ones in event mode or between steps, and then
 * only to values that keep the components' conditions), the solver
 * settings, calculated parameters, states, derivatives, outputs, and the
 * inputs (held from the time they are set, or running linearly from there
 * with the slope FMI 2.0's fmi2SetRealInputDerivatives gives, in either
 * order at one communication point; setting an input to the value it has
 * changes nothing).  A call that is refused changes nothing. */
#include <math.h>
#include <stdio.h>

#include "fmu_instance.h"

#define VR_P_END (PDBFS_VR_P + NPAR)
#define VR_C_END (PDBFS_VR_C + NC)
#define VR_X_END (PDBFS_VR_X + NX)
#define VR_DX_END (PDBFS_VR_DX + NX)
#define VR_Y_END (PDBFS_VR_Y + NYV)
#define VR_U_END (PDBFS_VR_U + NU)
#define IS_INPUT(r) ((r) >= PDBFS_VR_U && (r) < VR_U_END)

/* ------------------------------------------------------------------ inputs */

double values_input(const Inst *m, int k) {
#if PDBFS_NU > 0
    const double *p = m->s.p;
    return p[PDBFS_P_U0 + k] + p[PDBFS_P_DU0 + k] * (m->s.time - p[PDBFS_P_TREF]);
#else
    (void)m; (void)k;
    return 0.0;
#endif
}

/* every input's segment made to start now (t_ref = time): the same lines,
 * so that one input can be given a new value or slope from here */
static void inputs_from_now(Inst *m) {
#if PDBFS_NU > 0
    double *p = m->s.p;
    int k;
    if (p[PDBFS_P_TREF] == m->s.time) return;
    for (k = 0; k < NU; k++) p[PDBFS_P_U0 + k] = values_input(m, k);
    p[PDBFS_P_TREF] = m->s.time;
#else
    (void)m;
#endif
}

/* input k from now: ``value``, then ``slope`` (1/s in its unit); 1 if that changes it */
static int input_set(Inst *m, int k, double value, double slope) {
#if PDBFS_NU > 0
    double *p = m->s.p;
    int changed = p[PDBFS_P_U0 + k] != value || p[PDBFS_P_DU0 + k] != slope;
    p[PDBFS_P_U0 + k] = value;
    p[PDBFS_P_DU0 + k] = slope;
    return changed;
#else
    (void)m; (void)k; (void)value; (void)slope;
    return 0;
#endif
}

/* input k set to ``value`` now: the value it has changes nothing (a line
 * stays a line); another value keeps a slope given at this same time (a
 * master may give slope and value in either order), else the input is held
 * from now (a slope given at an earlier communication point belonged to the
 * value of then). 1 if that changes it */
static int input_value(Inst *m, int k, double value) {
    double slope;
    if (value == values_input(m, k)) return 0;
#if PDBFS_NU > 0
    slope = m->s.slope_time[k] == m->s.time ? m->s.p[PDBFS_P_DU0 + k] : 0.0;
#else
    slope = 0.0;
#endif
    return input_set(m, k, value, slope);
}

int values_set_input_slopes(Inst *m, const char *fn, const unsigned vr[], size_t n, const int order[],
                            const double v[]) {
    size_t i;
    int changed = 0;
    if (n > 0 && (!vr || !order || !v)) return ERR(m, "%s: NULL argument", fn);
    for (i = 0; i < n; i++) {
        if (!IS_INPUT(vr[i])) return ERR(m, "%s: value reference %u is not an input", fn, vr[i]);
        if (order[i] != 1)
            return ERR(m, "%s: order %d of input %s: only the first derivative is taken (an input is linear "
                       "over a communication step)", fn, order[i], PDBFS_U_NAME[vr[i] - PDBFS_VR_U]);
        if (!isfinite(v[i]))
            return ERR(m, "%s: the derivative of input %s is %g, not finite", fn, PDBFS_U_NAME[vr[i] - PDBFS_VR_U],
                       v[i]);
    }
    inputs_from_now(m);
    for (i = 0; i < n; i++) {
        int k = (int)(vr[i] - PDBFS_VR_U);
        changed |= input_set(m, k, values_input(m, k), v[i]);
        m->s.slope_time[k] = m->s.time;
    }
    m->derived_ok = 0;
    if (changed && m->s.mode == ST_STEPDONE && !m->need_restart) m->need_restart = RESTART_CHANGED;
    return FMU_OK;
}

/* a computed value that is not finite (an importer's state or parameters the
 * model cannot run at) is an error naming it, never returned as OK */
static int not_finite(Inst *m, const char *fn, unsigned r, double x) {
    if (r >= PDBFS_VR_X && r < VR_X_END)
        return ERR(m, "%s: state %s = %g at t=%.17g: check the parameters", fn, PDBFS_X_NAME[r - PDBFS_VR_X], x,
                   m->s.time);
    if (r >= PDBFS_VR_DX && r < VR_DX_END)
        return ERR(m, "%s: der(%s) = %g at t=%.17g: check the parameters and states", fn,
                   PDBFS_X_NAME[r - PDBFS_VR_DX], x, m->s.time);
    return ERR(m, "%s: the variable of value reference %u is %g at t=%.17g: check the parameters and states", fn, r,
               x, m->s.time);
}

/* whether modelDescription.xml declares a start value of r: the parameters
 * and the solver settings (the rest has initial="calculated") */
static int has_start(unsigned r) {
    return (r >= PDBFS_VR_P && r < VR_P_END) || r == PDBFS_VR_RTOL || r == PDBFS_VR_MAXSTEP ||
           r == PDBFS_VR_METHOD || r == PDBFS_VR_MAXNUMSTEPS || IS_INPUT(r);
}

/* a calculated variable's name for a message: "state hammer.s", ... */
static void calculated_name(char *buf, size_t size, unsigned r) {
    if (r >= PDBFS_VR_X && r < VR_X_END) snprintf(buf, size, "state %s", PDBFS_X_NAME[r - PDBFS_VR_X]);
    else if (r >= PDBFS_VR_DX && r < VR_DX_END) snprintf(buf, size, "der(%s)", PDBFS_X_NAME[r - PDBFS_VR_DX]);
    else if (r >= PDBFS_VR_Y && r < VR_Y_END) snprintf(buf, size, "%s", PDBFS_Y_NAME[r - PDBFS_VR_Y]);
#ifdef PDBFS_VR_TIME
    else if (r == PDBFS_VR_TIME) snprintf(buf, size, "time");
#endif
    else snprintf(buf, size, "the variable of value reference %u", r);
}

int values_intermediate(unsigned r) {
    if (r >= PDBFS_VR_X && r < VR_X_END) return PDBFS_X_OUTPUT[r - PDBFS_VR_X];
    return r >= PDBFS_VR_Y && r < VR_Y_END && PDBFS_YO_ROW[r - PDBFS_VR_Y] >= 0;
}

/* May ``vr`` be read now? The FMI state tables allow no reading in
 * Instantiated (FMI 2.0), or there only the start values that
 * modelDescription.xml declares (FMI 3.0, ``starts``): everything else is
 * calculated in Initialization Mode. An unknown reference is the reader's
 * error to report. */
int values_check_get(Inst *m, const char *fn, const unsigned vr[], size_t n, int starts) {
    size_t i;
    char name[160];
    if (fmu_check(m, fn, starts ? ST_ANY | ST_INTERMEDIATE : ST_ANY & ~ST_INSTANTIATED, -1) != FMU_OK)
        return FMU_ERROR;
    if (n > 0 && !vr) return ERR(m, "%s: NULL argument", fn);
    if (m->s.mode == ST_INTERMEDIATE) {   /* inside fmi3DoStep: the outputs only */
        for (i = 0; i < n; i++)
            if (!values_intermediate(vr[i]))
                return ERR(m, "%s: value reference %u is not an output: in an intermediate update only the "
                           "outputs (intermediateUpdate=\"true\") are read", fn, vr[i]);
        return FMU_OK;
    }
    if (m->s.mode != ST_INSTANTIATED) return FMU_OK;
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        int known = r < VR_U_END;
#ifdef PDBFS_VR_TIME
        known = known || (r >= PDBFS_VR_TIME && r < PDBFS_VR_E + NE);
#endif
        if (known && !has_start(r)) {
            calculated_name(name, sizeof name, r);
            return ERR(m, "%s: %s has no start value; it is calculated in Initialization Mode", fn, name);
        }
    }
    return FMU_OK;
}

int values_get_real(Inst *m, const char *fn, const unsigned vr[], size_t n, double v[], int starts) {
    size_t i;
    if (values_check_get(m, fn, vr, n, starts) != FMU_OK) return FMU_ERROR;
    if (n > 0 && !v) return ERR(m, "%s: NULL argument", fn);
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (r >= PDBFS_VR_P && r < VR_P_END) {
            v[i] = m->s.p[r - PDBFS_VR_P];
        } else if (r == PDBFS_VR_RTOL) {
            v[i] = model_rtol(m);
        } else if (r == PDBFS_VR_MAXSTEP) {
            v[i] = m->s.max_step;
        } else if (r >= PDBFS_VR_C && r < VR_C_END) {
            model_update(m);
            v[i] = m->c[r - PDBFS_VR_C];
        } else if (r >= PDBFS_VR_X && r < VR_X_END) {
            v[i] = model_x(m)[r - PDBFS_VR_X];
        } else if (r >= PDBFS_VR_DX && r < VR_DX_END) {
            model_update(m);
            v[i] = m->xdot[r - PDBFS_VR_DX];
        } else if (r >= PDBFS_VR_Y && r < VR_Y_END) {
            model_update(m);
            v[i] = m->y[PDBFS_Y_INDEX[r - PDBFS_VR_Y]];
            if (!isfinite(v[i]))
                return ERR(m, "%s: output %s = %g at t=%.17g: check the parameters", fn,
                           PDBFS_Y_NAME[r - PDBFS_VR_Y], v[i], m->s.time);
        } else if (IS_INPUT(r)) {
            v[i] = values_input(m, (int)(r - PDBFS_VR_U));
#ifdef PDBFS_VR_TIME
        } else if (r == PDBFS_VR_TIME) {
            v[i] = m->s.time;
        } else if (r >= PDBFS_VR_E && r < PDBFS_VR_E + NE) {
            model_update(m);
            v[i] = m->e[r - PDBFS_VR_E];
#endif
        } else {
            return ERR(m, "%s: unknown value reference %u", fn, r);
        }
        if (!isfinite(v[i])) return not_finite(m, fn, r, v[i]);
    }
    return FMU_OK;
}

/* a value reference of the model that is not settable */
static int read_only(unsigned r) {
#ifdef PDBFS_VR_TIME
    if (r == PDBFS_VR_TIME || (r >= PDBFS_VR_E && r < PDBFS_VR_E + NE)) return 1;
#endif
    return r >= PDBFS_VR_P && r < VR_Y_END;
}

/* "name = value, ..." of the parameters among vr: for a message */
static void param_list(char *buf, size_t size, const unsigned vr[], size_t n, const double v[]) {
    size_t i, used = 0;
    buf[0] = 0;
    for (i = 0; i < n && used + 1 < size; i++) {
        int w;
        if (vr[i] < PDBFS_VR_P || vr[i] >= VR_P_END) continue;
        w = snprintf(buf + used, size - used, "%s%s = %g", used ? ", " : "", PDBFS_P_NAME[vr[i] - PDBFS_VR_P], v[i]);
        if (w < 0) break;
        used += (size_t)w < size - used ? (size_t)w : size - used - 1;
    }
}

/* tunable parameters changed during a run, in one call: refused (changing
 * nothing) unless the new values keep the components' conditions
 * (Component.conditions, checked at initialisation too) and the model finite
 * at the current time and state; pdbfs refuses such settings per run, so the
 * FMU must not integrate with them either */
static int check_tunable_change(Inst *m, const char *fn, const unsigned vr[], size_t n, const double v[]) {
    double old[NP + 1];
    char what[512];
    size_t i;
    int bad, finite;
    for (i = 0; i < (size_t)NP; i++) old[i] = m->s.p[i];
    for (i = 0; i < n; i++)
        if (vr[i] >= PDBFS_VR_P && vr[i] < VR_P_END) m->s.p[vr[i] - PDBFS_VR_P] = v[i];
    bad = model_failed_condition(m, m->s.p);
    m->derived_ok = 0;
    finite = bad < 0 ? model_finite(m) : 1;
    for (i = 0; i < (size_t)NP; i++) m->s.p[i] = old[i];
    m->derived_ok = 0;
    if (bad < 0 && finite) return FMU_OK;
    param_list(what, sizeof what, vr, n, v);
    if (bad >= 0)
        return ERR(m, "%s: %s refused at t=%.17g: %s; the parameters keep their values", fn, what, m->s.time,
                   PDBFS_COND_TEXT[bad]);
    return ERR(m, "%s: %s refused at t=%.17g: the derivatives or outputs would not be finite there; the "
               "parameters keep their values", fn, what, m->s.time);
}

/* an input set outside the range where the signals it drives take it as it
 * is: said in the log (a warning), the value kept (the model clamps it) */
static int clamped_warning(Inst *m, const char *fn, int k, double v) {
    if (v >= PDBFS_U_MIN[k] && v <= PDBFS_U_MAX[k]) return FMU_OK;
    fmu_log(m, FMU_WARNING, "logStatusWarning", "%s: input %s = %g at t=%.17g is %s %g: %s clamps it there, so it "
            "acts as %g", fn, PDBFS_U_NAME[k], v, m->s.time, v < PDBFS_U_MIN[k] ? "below its min" : "above its max",
            v < PDBFS_U_MIN[k] ? PDBFS_U_MIN[k] : PDBFS_U_MAX[k], PDBFS_U_CLAMP[k],
            v < PDBFS_U_MIN[k] ? PDBFS_U_MIN[k] : PDBFS_U_MAX[k]);
    return FMU_WARNING;
}

int values_set_real(Inst *m, const char *fn, const unsigned vr[], size_t n, const double v[]) {
    size_t i;
    int before_init, tunable_ok, changed = 0, params = 0, status = FMU_OK;
    if (fmu_check(m, fn, ST_SET_REAL, -1) != FMU_OK) return FMU_ERROR;
    if (n > 0 && (!vr || !v)) return ERR(m, "%s: NULL argument", fn);
    before_init = (m->s.mode & (ST_INSTANTIATED | ST_INIT)) != 0;
    tunable_ok = before_init || (m->s.mode & (ST_EVENT | ST_STEPDONE)) != 0;
    /* validate everything first: a rejected call changes nothing */
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        double x = v[i];
        if (r >= PDBFS_VR_P && r < VR_P_END) {
            int k = (int)(r - PDBFS_VR_P);
            if (!before_init && !PDBFS_P_TUNABLE[k])
                return ERR(m, "%s: parameter %s is fixed and cannot be changed after initialization", fn,
                           PDBFS_P_NAME[k]);
            if (!tunable_ok)
                return ERR(m, "%s: tunable parameter %s can only be changed in %s", fn, PDBFS_P_NAME[k],
                           m->s.type == FMU_CS ? "between steps" : "event mode");
            if (model_check_param(m, k, x) != FMU_OK) return FMU_ERROR;
            params = 1;
        } else if (IS_INPUT(r)) {
            if (!isfinite(x)) return ERR(m, "%s: input %s = %g is not finite", fn, PDBFS_U_NAME[r - PDBFS_VR_U], x);
        } else if (r == PDBFS_VR_RTOL || r == PDBFS_VR_MAXSTEP) {
            const char *nm = r == PDBFS_VR_RTOL ? "solver.rtol" : "solver.max_step";
            if (!before_init)
                return ERR(m, "%s: %s is fixed and cannot be changed after initialization", fn, nm);
            if (!isfinite(x)) return ERR(m, "%s: %s = %g is not finite", fn, nm, x);
            if (r == PDBFS_VR_RTOL && !(x >= PDBFS_RTOL_MIN && x <= PDBFS_RTOL_MAX))
                return ERR(m, "%s: solver.rtol = %g must be in [%g, %g]", fn, x, PDBFS_RTOL_MIN, PDBFS_RTOL_MAX);
            if (r == PDBFS_VR_MAXSTEP && x < 0)
                return ERR(m, "%s: solver.max_step = %g must be >= 0 (0: no limit)", fn, x);
        } else if (read_only(r)) {
            return ERR(m, "%s: variable with value reference %u is not settable", fn, r);
        } else {
            return ERR(m, "%s: unknown value reference %u", fn, r);
        }
    }
    if (!before_init && params && check_tunable_change(m, fn, vr, n, v) != FMU_OK) return FMU_ERROR;
    inputs_from_now(m);
    for (i = 0; i < n; i++) {
        unsigned r = vr[i];
        if (IS_INPUT(r)) {
            if (input_value(m, (int)(r - PDBFS_VR_U), v[i])) {
                changed = 1;
                if (clamped_warning(m, fn, (int)(r - PDBFS_VR_U), v[i]) != FMU_OK) status = FMU_WARNING;
            }
        } else if (r >= PDBFS_VR_P && r < VR_P_END) {
            if (m->s.p[r - PDBFS_VR_P] != v[i]) changed = 1;
            m->s.p[r - PDBFS_VR_P] = v[i];
        } else if (r == PDBFS_VR_RTOL) {
            m->s.rtol = v[i];
            m->s.rtol_user = 1;
        } else if (r == PDBFS_VR_MAXSTEP) {
            m->s.max_step = v[i];
        }
    }
    m->derived_ok = 0;
    if (changed && !before_init && !m->need_restart) m->need_restart = RESTART_CHANGED;
    return status;
}

/* solver.method and solver.max_num_steps, one at a time (the wrapper loops:
 * check all, then set all) */
int values_get_int(Inst *m, const char *fn, unsigned vr, long long *v) {
    if (vr == PDBFS_VR_METHOD) *v = m->s.method;
    else if (vr == PDBFS_VR_MAXNUMSTEPS) *v = m->s.max_num_steps;
    else return ERR(m, "%s: unknown value reference %u", fn, vr);
    return FMU_OK;
}

int values_check_int(Inst *m, const char *fn, unsigned vr, long long v) {
    const char *nm = vr == PDBFS_VR_METHOD ? "solver.method" : "solver.max_num_steps";
    if (vr != PDBFS_VR_METHOD && vr != PDBFS_VR_MAXNUMSTEPS)
        return ERR(m, "%s: unknown value reference %u", fn, vr);
    if (!(m->s.mode & (ST_INSTANTIATED | ST_INIT)))
        return ERR(m, "%s: %s is fixed and cannot be changed after initialization", fn, nm);
    if (vr == PDBFS_VR_METHOD && !METHOD_VALID(v))
        return ERR(m, "%s: solver.method = %lld must be 0 (auto), 1 (BDF), 2 (Adams) or 3 (explicit "
                   "Runge-Kutta)", fn, v);
    if (vr == PDBFS_VR_MAXNUMSTEPS && (v < 1 || v > 2147483647LL))
        return ERR(m, "%s: solver.max_num_steps = %lld must be >= 1", fn, v);
    return FMU_OK;
}

void values_set_int(Inst *m, unsigned vr, long long v) {
    if (vr == PDBFS_VR_METHOD) m->s.method = (int)v;
    else m->s.max_num_steps = (int)v;
}

/* a type the model has no variables of, called in one of the ``allowed`` modes */
int values_none(Inst *m, const char *fn, const unsigned vr[], size_t n, int allowed) {
    if (fmu_check(m, fn, allowed, -1) != FMU_OK) return FMU_ERROR;
    if (n > 0) return ERR(m, "%s: unknown value reference %u", fn, vr ? vr[0] : 0u);
    return FMU_OK;
}
