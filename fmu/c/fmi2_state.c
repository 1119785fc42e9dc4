/* FMU state of a pdbfs FMU: a plain copy of the Snapshot (time, states,
 * parameters, settings); CVODE restarts from a restored state.  A state given
 * back (restored or deserialised) is checked as fmi2SetReal would check its
 * values: it may come from another process or a corrupted file. */
#include <math.h>
#include <string.h>

#include "fmu_instance.h"

/* the modes a state of each interface can be taken in */
#define MODES_CS (ST_INSTANTIATED | ST_INIT | ST_STEPDONE | ST_TERMINATED)
#define MODES_ME (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_TERMINATED)

/* fmi2OK if ``s`` is a state this instance can take, else an error naming the fault */
static fmi2Status check_snapshot(Inst *m, const Snapshot *s, const char *fn) {
    int k, modes = m->s.type == fmi2CoSimulation ? MODES_CS : MODES_ME;
    if (s->magic != SNAP_MAGIC || s->size != sizeof(Snapshot) || memchr(s->token, 0, sizeof s->token) == NULL ||
        strcmp(s->token, PDBFS_GUID) != 0)
        return ERR(m, "%s: not a state of this FMU", fn);
    if (s->type != m->s.type) return ERR(m, "%s: state belongs to another interface type", fn);
    /* exactly one mode bit, one this interface has (never the error mode) */
    if (!(s->mode & modes) || (s->mode & (s->mode - 1)))
        return ERR(m, "%s: invalid mode %d in the state", fn, s->mode);
    if ((s->mode & (ST_STEPDONE | ST_EVENT | ST_CONT | ST_TERMINATED)) && !s->x_fixed)
        return ERR(m, "%s: a state after initialization without its continuous states", fn);
    for (k = 0; k < NP; k++)
        if (model_check_param(m, k, s->p[k]) != fmi2OK) return ERR(m, "%s: the state's parameters are invalid", fn);
    if (!(s->rtol >= PDBFS_RTOL_MIN && s->rtol <= PDBFS_RTOL_MAX))
        return ERR(m, "%s: solver.rtol = %g in the state is outside [%g, %g]", fn, s->rtol, PDBFS_RTOL_MIN,
                   PDBFS_RTOL_MAX);
    if (!(isfinite(s->max_step) && s->max_step >= 0)) return ERR(m, "%s: invalid solver.max_step in the state", fn);
    if (s->method != METHOD_BDF && s->method != METHOD_ADAMS) return ERR(m, "%s: invalid solver.method", fn);
    if (s->max_num_steps < 1) return ERR(m, "%s: invalid solver.max_num_steps in the state", fn);
    if (s->tol_defined && !(isfinite(s->tol) && s->tol > 0 && s->tol < 1))
        return ERR(m, "%s: invalid tolerance in the state", fn);
    if (!isfinite(s->time) || !isfinite(s->t_start) || (s->stop_defined && !(isfinite(s->t_stop) &&
                                                                            s->t_stop >= s->t_start)))
        return ERR(m, "%s: invalid times in the state", fn);
    if (s->x_fixed && !fmu_all_finite(s->x, NX)) return ERR(m, "%s: non-finite states in the state", fn);
    return fmi2OK;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    Snapshot *s;
    if (fmu_check(m, "fmi2GetFMUstate", ST_ANY & ~ST_ERROR, -1) != fmi2OK) return fmi2Error;
    if (!state) return ERR(m, "fmi2GetFMUstate: NULL argument");
    s = (Snapshot *)*state;
    if (!s) {
        s = (Snapshot *)m->cb.allocateMemory(1, sizeof(Snapshot));
        if (!s) return ERR(m, "fmi2GetFMUstate: out of memory");
    } else if (s->magic != SNAP_MAGIC) {
        return ERR(m, "fmi2GetFMUstate: invalid FMU state");
    }
    model_x(m);
    *s = m->s;
    *state = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate state) {
    Inst *m = (Inst *)c;
    const Snapshot *s = (const Snapshot *)state;
    if (fmu_check(m, "fmi2SetFMUstate", ST_ANY & ~ST_ERROR, -1) != fmi2OK) return fmi2Error;
    if (!s) return ERR(m, "fmi2SetFMUstate: NULL state");
    if (check_snapshot(m, s, "fmi2SetFMUstate") != fmi2OK) return fmi2Error;
    m->s = *s;
    m->derived_ok = 0;
    m->need_restart = 1;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    if (!m || m->s.magic != SNAP_MAGIC) return fmi2Error;
    if (!state || !*state) return fmi2OK;
    ((Snapshot *)*state)->magic = 0;
    m->cb.freeMemory(*state);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate state, size_t *size) {
    Inst *m = (Inst *)c;
    if (fmu_check(m, "fmi2SerializedFMUstateSize", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!state || !size) return ERR(m, "fmi2SerializedFMUstateSize: NULL argument");
    *size = sizeof(Snapshot);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate state, fmi2Byte bytes[], size_t size) {
    Inst *m = (Inst *)c;
    const Snapshot *s = (const Snapshot *)state;
    if (fmu_check(m, "fmi2SerializeFMUstate", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!s || !bytes || s->magic != SNAP_MAGIC) return ERR(m, "fmi2SerializeFMUstate: invalid argument");
    if (size < sizeof(Snapshot)) return ERR(m, "fmi2SerializeFMUstate: buffer too small");
    memcpy(bytes, s, sizeof(Snapshot));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *state) {
    Inst *m = (Inst *)c;
    Snapshot tmp;
    if (fmu_check(m, "fmi2DeSerializeFMUstate", ST_ANY, -1) != fmi2OK) return fmi2Error;
    if (!bytes || !state) return ERR(m, "fmi2DeSerializeFMUstate: NULL argument");
    if (size != sizeof(Snapshot)) return ERR(m, "fmi2DeSerializeFMUstate: wrong size %zu", size);
    memcpy(&tmp, bytes, sizeof tmp);
    if (check_snapshot(m, &tmp, "fmi2DeSerializeFMUstate") != fmi2OK) return fmi2Error;
    if (!*state) {
        *state = m->cb.allocateMemory(1, sizeof(Snapshot));
        if (!*state) return ERR(m, "fmi2DeSerializeFMUstate: out of memory");
    }
    memcpy(*state, &tmp, sizeof tmp);
    return fmi2OK;
}
