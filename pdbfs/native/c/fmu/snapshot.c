/* The FMU state of a pdbfs FMU, for every FMI version: a plain copy of the
 * Snapshot (time, states, parameters, the inputs' values and slopes,
 * settings); CVODE restarts from a
 * restored state.  A state given back (restored or deserialised) is checked
 * as setting its values would check them: it may come from another process
 * or a corrupted file.
 *
 * Serialised, a state is the Snapshot's bytes followed by their CRC-32 (the
 * zip and PNG checksum; 4 bytes, least significant first): a corrupted copy
 * is refused before its contents are looked at, and every change of up to 32
 * consecutive bits is caught. The Snapshot's token is the FMU's GUID, a hash
 * of its model and of these C files: a state of another FMU, or of another
 * layout of the Snapshot, is refused by it. */
#include <math.h>
#include <string.h>

#include "fmu_instance.h"

/* the modes a state of each interface can be taken in */
#define MODES_CS (ST_INSTANTIATED | ST_INIT | ST_STEPDONE | ST_TERMINATED)
#define MODES_ME (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_TERMINATED)

/* FMU_OK if ``s`` is a state this instance can take, else an error naming the fault */
static int check_snapshot(Inst *m, const Snapshot *s, const char *fn) {
    int k, modes = m->s.type == FMU_CS ? MODES_CS : MODES_ME;
    if (s->magic != SNAP_MAGIC || s->size != sizeof(Snapshot) || memchr(s->token, 0, sizeof s->token) == NULL ||
        strcmp(s->token, PDBFS_GUID) != 0)
        return ERR(m, "%s: not a state of this FMU", fn);
    if (s->type != m->s.type) return ERR(m, "%s: state belongs to another interface type", fn);
    /* exactly one mode bit, one this interface has (never the error mode) */
    if (!(s->mode & modes) || (s->mode & (s->mode - 1)))
        return ERR(m, "%s: invalid mode %d in the state", fn, s->mode);
    if ((s->mode & (ST_STEPDONE | ST_EVENT | ST_CONT | ST_TERMINATED)) && !s->x_fixed)
        return ERR(m, "%s: a state after initialization without its continuous states", fn);
    for (k = 0; k < NPAR; k++)
        if (model_check_param(m, k, s->p[k]) != FMU_OK) return ERR(m, "%s: the state's parameters are invalid", fn);
    if (!fmu_all_finite(s->p + NPAR, NP - NPAR)) return ERR(m, "%s: the state's inputs are not finite", fn);
    for (k = 0; k < NU; k++)
        if (isnan(s->slope_time[k]) || s->slope_time[k] > s->time)
            return ERR(m, "%s: invalid input slope times in the state", fn);
    /* after initialisation the parameters keep the components' conditions (before: checked on leaving it) */
    if ((s->mode & (ST_STEPDONE | ST_EVENT | ST_CONT | ST_TERMINATED)) && (k = model_failed_condition(m, s->p)) >= 0)
        return ERR(m, "%s: the state's parameters break a condition: %s", fn, PDBFS_COND_TEXT[k]);
    if (!(s->rtol >= PDBFS_RTOL_MIN && s->rtol <= PDBFS_RTOL_MAX))
        return ERR(m, "%s: solver.rtol = %g in the state is outside [%g, %g]", fn, s->rtol, PDBFS_RTOL_MIN,
                   PDBFS_RTOL_MAX);
    if (!(isfinite(s->max_step) && s->max_step >= 0)) return ERR(m, "%s: invalid solver.max_step in the state", fn);
    if (!METHOD_VALID(s->method) || !METHOD_VALID(s->method_used) || s->method_used == METHOD_AUTO)
        return ERR(m, "%s: invalid solver.method", fn);
    if (s->max_num_steps < 1) return ERR(m, "%s: invalid solver.max_num_steps in the state", fn);
    if (s->tol_defined && !(isfinite(s->tol) && s->tol > 0 && s->tol < 1))
        return ERR(m, "%s: invalid tolerance in the state", fn);
    if (!isfinite(s->time) || !isfinite(s->t_start) || (s->stop_defined && !(isfinite(s->t_stop) &&
                                                                            s->t_stop >= s->t_start)))
        return ERR(m, "%s: invalid times in the state", fn);
    if (s->x_fixed && !fmu_all_finite(s->x, NX)) return ERR(m, "%s: non-finite states in the state", fn);
    return FMU_OK;
}

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
    memcpy(s, &m->s, sizeof(Snapshot));   /* padding too: a state serialises bit for bit */
    *state = s;
    return FMU_OK;
}

int snapshot_set(Inst *m, const char *fn, const void *state) {
    const Snapshot *s = (const Snapshot *)state;
    if (fmu_check(m, fn, ST_ANY & ~ST_ERROR, -1) != FMU_OK) return FMU_ERROR;
    if (!s) return ERR(m, "%s: NULL state", fn);
    if (check_snapshot(m, s, fn) != FMU_OK) return FMU_ERROR;
    memcpy(&m->s, s, sizeof(Snapshot));
    m->derived_ok = 0;
    m->need_restart = RESTART_FRESH;
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

/* the serialised state: the Snapshot, then the CRC-32 of its bytes */
#define SERIAL_SIZE (sizeof(Snapshot) + 4)

/* CRC-32 (IEEE 802.3, reflected, as zlib's crc32) of n bytes, bit by bit: a
 * state is a few hundred bytes */
static unsigned long crc32_of(const unsigned char *p, size_t n) {
    unsigned long crc = 0xFFFFFFFFul;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        crc ^= p[i];
        for (k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320ul & (0ul - (crc & 1ul)));
    }
    return crc ^ 0xFFFFFFFFul;
}

int snapshot_size(Inst *m, const char *fn, const void *state, size_t *size) {
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!state || !size) return ERR(m, "%s: NULL argument", fn);
    *size = SERIAL_SIZE;
    return FMU_OK;
}

int snapshot_serialize(Inst *m, const char *fn, const void *state, unsigned char *bytes, size_t size) {
    const Snapshot *s = (const Snapshot *)state;
    unsigned long crc;
    int k;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!s || !bytes || s->magic != SNAP_MAGIC) return ERR(m, "%s: invalid argument", fn);
    if (size < SERIAL_SIZE) return ERR(m, "%s: buffer too small (%zu bytes, %zu needed)", fn, size, SERIAL_SIZE);
    memcpy(bytes, s, sizeof(Snapshot));
    crc = crc32_of(bytes, sizeof(Snapshot));
    for (k = 0; k < 4; k++) bytes[sizeof(Snapshot) + k] = (unsigned char)((crc >> (8 * k)) & 0xFFu);
    return FMU_OK;
}

int snapshot_deserialize(Inst *m, const char *fn, const unsigned char *bytes, size_t size, void **state) {
    Snapshot tmp;
    unsigned long stored = 0, crc;
    int k;
    if (fmu_check(m, fn, ST_ANY, -1) != FMU_OK) return FMU_ERROR;
    if (!bytes || !state) return ERR(m, "%s: NULL argument", fn);
    if (size != SERIAL_SIZE)
        return ERR(m, "%s: %zu bytes, but a serialized state of this FMU has %zu", fn, size, SERIAL_SIZE);
    for (k = 0; k < 4; k++) stored |= (unsigned long)bytes[sizeof(Snapshot) + k] << (8 * k);
    crc = crc32_of(bytes, sizeof(Snapshot));
    if (crc != stored)
        return ERR(m, "%s: the serialized state is corrupted (its CRC-32 is %08lx, its bytes give %08lx); "
                   "nothing was restored", fn, stored, crc);
    memcpy(&tmp, bytes, sizeof tmp);
    if (check_snapshot(m, &tmp, fn) != FMU_OK) return FMU_ERROR;
    if (!*state) {
        *state = m->host.alloc(1, sizeof(Snapshot));
        if (!*state) return ERR(m, "%s: out of memory", fn);
    }
    memcpy(*state, &tmp, sizeof tmp);
    return FMU_OK;
}
