/* The life cycle of a pdbfs FMU, for every FMI version: instantiate, set up,
 * initialise, terminate, reset, free. The top of the version-neutral files:
 * it calls down into the model (model.c) and the co-simulation loop
 * (cosimulation.c), which never call back. */
#include <math.h>
#include <string.h>

#include "fmu_instance.h"

/* a new instance, or NULL without memory (the wrapper has checked the rest) */
Inst *fmu_new(const char *name, int type, const FmuHost *host, int logging) {
    size_t n = strlen(name) + 1;
    Inst *m = (Inst *)host->alloc(1, sizeof(Inst));
    if (!m) return NULL;
    memset(m, 0, sizeof(Inst));
    m->host = *host;
    m->name = (char *)host->alloc(n, 1);
    if (!m->name) {
        host->free(m);
        return NULL;
    }
    memcpy(m->name, name, n);
    m->logging = logging ? 1 : 0;
    m->s.magic = SNAP_MAGIC;
    m->s.size = (unsigned)sizeof(Snapshot);
    strncpy(m->s.token, PDBFS_GUID, sizeof m->s.token - 1);
    m->s.type = type;
    model_defaults(m);
    fmu_log(m, FMU_OK, "logAll", "instantiated %s (%s)", PDBFS_MODEL_IDENTIFIER,
            type == FMU_CS ? "CoSimulation" : "ModelExchange");
    return m;
}

void fmu_free(Inst *m) {
    void (*release)(void *);
    if (!m || m->s.magic != SNAP_MAGIC) return;
    cosim_free(m);
    release = m->host.free;
    m->s.magic = 0;
    release(m->name);
    release(m);
}

int fmu_set_logging(Inst *m, const char *fn, int on, size_t n, const char *const categories[]) {
    size_t i;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    for (i = 0; i < n; i++) {
        const char *k = categories ? categories[i] : NULL;
        if (!k || (strcmp(k, "logEvents") && strcmp(k, "logStatusWarning") && strcmp(k, "logStatusError") &&
                   strcmp(k, "logAll")))
            return ERR(m, "%s: unknown log category '%s'", fn, k ? k : "(null)");
    }
    m->logging = on ? 1 : 0;
    return FMU_OK;
}

int fmu_setup(Inst *m, const char *fn, int tol_defined, double tol, double start, int stop_defined, double stop) {
    if (fmu_check(m, fn, ST_INSTANTIATED, -1) != FMU_OK) return FMU_ERROR;
    if (tol_defined && !(tol >= PDBFS_RTOL_MIN && tol <= PDBFS_RTOL_MAX))   /* solver.rtol's rule */
        return ERR(m, "%s: tolerance %g must be in [%g, %g]", fn, tol, PDBFS_RTOL_MIN, PDBFS_RTOL_MAX);
    if (!isfinite(start)) return ERR(m, "%s: startTime is not finite", fn);
    if (stop_defined && !(isfinite(stop) && stop >= start))
        return ERR(m, "%s: stopTime %g must be finite and >= startTime %g", fn, stop, start);
    m->s.tol_defined = tol_defined ? 1 : 0;
    if (tol_defined) m->s.tol = tol;
    m->s.t_start = start;
    m->s.time = start;
    m->s.stop_defined = stop_defined ? 1 : 0;
    m->s.t_stop = stop;
    m->derived_ok = 0;
    return FMU_OK;
}

int fmu_enter_init(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_INSTANTIATED, -1) != FMU_OK) return FMU_ERROR;
    m->s.mode = ST_INIT;
    return FMU_OK;
}

/* the components' physical consistency (Component.conditions): each >= 0 */
static int check_conditions(Inst *m, const char *fn) {
    int i = model_failed_condition(m, m->s.p);
    if (i >= 0) return ERR(m, "%s: %s", fn, PDBFS_COND_TEXT[i]);
    return FMU_OK;
}

static const char *method_name(int method) {
    return method == METHOD_ERK ? "explicit Runge-Kutta 8(5,3)" : method == METHOD_ADAMS ? "CVODE Adams" : "CVODE BDF";
}

/* the start values fix the state; Co-Simulation resolves solver.method "auto"
 * (now that the parameters, start and stop time of the run are known) and
 * starts the solver */
int fmu_exit_init(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_INIT, -1) != FMU_OK) return FMU_ERROR;
    if (check_conditions(m, fn) != FMU_OK) return FMU_ERROR;
    model_start(m, m->s.x);
    if (!fmu_all_finite(m->s.x, NX)) return ERR(m, "start values are not finite: check the parameters");
    m->s.x_fixed = 1;
    m->derived_ok = 0;
    if (model_check_finite(m, fn) != FMU_OK || model_check_reduced(m, fn) != FMU_OK) {
        m->s.x_fixed = 0;   /* still in initialisation: the start follows the parameters */
        m->derived_ok = 0;
        return FMU_ERROR;
    }
    m->need_restart = RESTART_FRESH;
    m->s.method_used = m->s.method == METHOD_AUTO ? METHOD_BDF : m->s.method;   /* (Model Exchange: unused) */
    m->switching = 0;        /* (auto's switching: stiffness_choose) */
    if (m->s.type == FMU_CS && m->s.method == METHOD_AUTO) {
        char why[640];
        /* the run: to the stop time, else of unknown length (no length assumed) */
        double span = m->s.stop_defined ? m->s.t_stop - m->s.t_start : INFINITY;
        m->s.method_used = stiffness_choose(m, span, why, sizeof why);
        fmu_log(m, FMU_OK, "logAll", "solver.method auto: %s; %s", method_name(m->s.method_used), why);
    }
    m->s.mode = m->s.type == FMU_CS ? ST_STEPDONE : ST_EVENT;
    if (m->s.type == FMU_CS) return cosim_start(m);
    return FMU_OK;
}

int fmu_terminate(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_RUNNING, -1) != FMU_OK) return FMU_ERROR;
    m->s.mode = ST_TERMINATED;
    return FMU_OK;
}

int fmu_reset(Inst *m, const char *fn) {
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    cosim_free(m); /* a fresh CVODE: the second run is the first again */
    model_defaults(m);
    return FMU_OK;
}

