/* What Model Exchange asks of a pdbfs FMU, for every FMI version: the
 * importer integrates; the event indicators only mark kinks of the
 * right-hand side (no discrete states). */
#include <math.h>

#include "fmu_instance.h"

int me_enter_event_mode(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_EVENT | ST_CONT, FMU_ME) != FMU_OK) return FMU_ERROR;
    m->s.mode = ST_EVENT;
    fmu_log(m, FMU_OK, "logEvents", "event mode at t=%.17g", m->s.time);
    return FMU_OK;
}

/* no discrete states: nothing changes at an event */
int me_new_discrete_states(Inst *m, const char *fn) {
    return fmu_check(m, fn, ST_EVENT, FMU_ME);
}

/* the next time event after the current time (the first PDBFS_NTE event
 * indicators are t - t_i), for the importer's nextEventTime; INFINITY if none */
double me_next_event_time(Inst *m) {
    double next = INFINITY, ti, t = m->s.time;
    int i;
    model_update(m);
    for (i = 0; i < PDBFS_NTE && i < NE; i++) {
        ti = t - m->e[i];
        if (isfinite(ti) && ti > t + 64 * 2.220446049250313e-16 * fmax(fabs(t), fabs(ti)) && ti < next)
            next = ti;
    }
    return next;
}

int me_enter_continuous_mode(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_EVENT, FMU_ME) != FMU_OK) return FMU_ERROR;
    m->s.mode = ST_CONT;
    return FMU_OK;
}

int me_completed_step(Inst *m, const char *fn, int *enter_event, int *terminate) {
    if (fmu_check(m, fn, ST_CONT, FMU_ME) != FMU_OK) return FMU_ERROR;
    *enter_event = 0;
    *terminate = 0;
    return FMU_OK;
}

int me_set_time(Inst *m, const char *fn, double t) {
    if (fmu_check(m, fn, ST_EVENT | ST_CONT, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (!isfinite(t)) return ERR(m, "%s: time is not finite", fn);
    m->s.time = t;
    m->derived_ok = 0;
    return FMU_OK;
}

int me_set_states(Inst *m, const char *fn, const double x[], size_t nx) {
    size_t i;
    if (fmu_check(m, fn, ST_EVENT | ST_CONT, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (nx != NX) return ERR(m, "%s: nx = %zu, expected %d", fn, nx, NX);
    if (!x) return ERR(m, "%s: NULL argument", fn);
    if (!fmu_all_finite(x, NX)) return ERR(m, "%s: state is not finite", fn);
    for (i = 0; i < NX; i++) m->s.x[i] = x[i];
    m->derived_ok = 0;
    return FMU_OK;
}

int me_get_derivatives(Inst *m, const char *fn, double dx[], size_t nx) {
    size_t i;
    if (fmu_check(m, fn, ST_ANY & ~ST_INSTANTIATED, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (nx != NX) return ERR(m, "%s: nx = %zu, expected %d", fn, nx, NX);
    if (!dx) return ERR(m, "%s: NULL argument", fn);
    model_update(m);
    for (i = 0; i < NX; i++) dx[i] = m->xdot[i];
    if (!fmu_all_finite(m->xdot, NX)) return ERR(m, "%s: derivatives are not finite at t=%g", fn, m->s.time);
    return FMU_OK;
}

int me_get_event_indicators(Inst *m, const char *fn, double e[], size_t ne) {
    size_t i;
    if (fmu_check(m, fn, ST_ANY & ~ST_INSTANTIATED, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (ne != NE) return ERR(m, "%s: ni = %zu, expected %d", fn, ne, NE);
    if (ne > 0 && !e) return ERR(m, "%s: NULL argument", fn);
    model_update(m);
    for (i = 0; i < ne; i++) e[i] = m->e[i];
    if (!fmu_all_finite(m->e, NE)) return ERR(m, "%s: event indicators are not finite at t=%g", fn, m->s.time);
    return FMU_OK;
}

int me_get_states(Inst *m, const char *fn, double x[], size_t nx) {
    size_t i;
    const double *xs;
    if (fmu_check(m, fn, ST_ANY & ~ST_INSTANTIATED, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (nx != NX) return ERR(m, "%s: nx = %zu, expected %d", fn, nx, NX);
    if (!x) return ERR(m, "%s: NULL argument", fn);
    xs = model_x(m);
    for (i = 0; i < NX; i++) x[i] = xs[i];
    if (!fmu_all_finite(xs, NX)) return ERR(m, "%s: states are not finite: check the parameters", fn);
    return FMU_OK;
}

int me_get_nominals(Inst *m, const char *fn, double nominals[], size_t nx) {
    size_t i;
    if (fmu_check(m, fn, ST_ANY, FMU_ME) != FMU_OK) return FMU_ERROR;
    if (nx != NX) return ERR(m, "%s: nx = %zu, expected %d", fn, nx, NX);
    if (!nominals) return ERR(m, "%s: NULL argument", fn);
    for (i = 0; i < NX; i++) nominals[i] = PDBFS_X_NOMINAL[i];
    return FMU_OK;
}
