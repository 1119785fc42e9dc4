/* The FMU state of a pdbfs FMU, for every FMI version: a plain copy of the
 * Snapshot (time, states, parameters, settings); CVODE restarts from a
 * restored state. */
#include <string.h>

#include "fmu_instance.h"

int snapshot_get(Inst *m, const char *fn, void **state) {
    Snapshot *s;
    if (fmu_check(m, fn, ST_ANY & ~ST_ERROR, -1) != FMU_OK) return FMU_ERROR;
    if (!state) return ERR(m, "%s: NULL argument", fn);
    s = (Snapshot *)*state;
    if (!s) {
        s = (Snapshot *)m->host.alloc(1, sizeof(Snapshot));
        if (!s) return ERR(m, "%s: out of memory", fn);
    } else if (s->magic != SNAP_MAGIC) {
        return ERR(m, "%s: invalid FMU state", fn);
    }
    model_x(m);
    *s = m->s;
    *state = s;
    return FMU_OK;
}

int snapshot_set(Inst *m, const char *fn, const void *state) {
    const Snapshot *s = (const Snapshot *)state;
    if (fmu_check(m, fn, ST_ANY & ~ST_ERROR, -1) != FMU_OK) return FMU_ERROR;
    if (!s || s->magic != SNAP_MAGIC || s->size != sizeof(Snapshot) || strcmp(s->token, PDBFS_GUID) != 0)
        return ERR(m, "%s: invalid FMU state", fn);
    if (s->type != m->s.type) return ERR(m, "%s: state belongs to another interface type", fn);
    m->s = *s;
    m->derived_ok = 0;
    m->need_restart = 1;
    return FMU_OK;
}

int snapshot_free(Inst *m, void **state) {
    if (!m || m->s.magic != SNAP_MAGIC) return FMU_ERROR;
    if (!state || !*state) return FMU_OK;
    ((Snapshot *)*state)->magic = 0;
    m->host.free(*state);
    *state = NULL;
    return FMU_OK;
}

int snapshot_size(Inst *m, const char *fn, const void *state, size_t *size) {
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!state || !size) return ERR(m, "%s: NULL argument", fn);
    *size = sizeof(Snapshot);
    return FMU_OK;
}

int snapshot_serialize(Inst *m, const char *fn, const void *state, unsigned char *bytes, size_t size) {
    const Snapshot *s = (const Snapshot *)state;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!s || !bytes || s->magic != SNAP_MAGIC) return ERR(m, "%s: invalid argument", fn);
    if (size < sizeof(Snapshot)) return ERR(m, "%s: buffer too small", fn);
    memcpy(bytes, s, sizeof(Snapshot));
    return FMU_OK;
}

int snapshot_deserialize(Inst *m, const char *fn, const unsigned char *bytes, size_t size, void **state) {
    Snapshot tmp;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!bytes || !state) return ERR(m, "%s: NULL argument", fn);
    if (size != sizeof(Snapshot)) return ERR(m, "%s: wrong size %zu", fn, size);
    memcpy(&tmp, bytes, sizeof tmp);
    tmp.token[sizeof tmp.token - 1] = 0;
    if (tmp.magic != SNAP_MAGIC || tmp.size != sizeof(Snapshot) || strcmp(tmp.token, PDBFS_GUID) != 0)
        return ERR(m, "%s: not a state of this FMU", fn);
    if (!*state) {
        *state = m->host.alloc(1, sizeof(Snapshot));
        if (!*state) return ERR(m, "%s: out of memory", fn);
    }
    memcpy(*state, &tmp, sizeof tmp);
    return FMU_OK;
}
