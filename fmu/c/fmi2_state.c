/* FMU state of a pdbfs FMU: a plain copy of the Snapshot (time, states,
 * parameters, settings); CVODE restarts from a restored state. */
#include <string.h>

#include "fmu_instance.h"

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
    if (!s || s->magic != SNAP_MAGIC || s->size != sizeof(Snapshot) || strcmp(s->token, PDBFS_GUID) != 0)
        return ERR(m, "fmi2SetFMUstate: invalid FMU state");
    if (s->type != m->s.type) return ERR(m, "fmi2SetFMUstate: state belongs to another interface type");
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
    tmp.token[sizeof tmp.token - 1] = 0;
    if (tmp.magic != SNAP_MAGIC || tmp.size != sizeof(Snapshot) || strcmp(tmp.token, PDBFS_GUID) != 0)
        return ERR(m, "fmi2DeSerializeFMUstate: not a state of this FMU");
    if (!*state) {
        *state = m->cb.allocateMemory(1, sizeof(Snapshot));
        if (!*state) return ERR(m, "fmi2DeSerializeFMUstate: out of memory");
    }
    memcpy(*state, &tmp, sizeof tmp);
    return fmi2OK;
}
