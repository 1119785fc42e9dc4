/*
 * The record's memory, kept from one run of a library to the next
 * (pdbfs_record.h): a run's record grows to the size its steps need, and the
 * next run of the same rig needs about as much.  Freed at every run, a large
 * record (past glibc's mmap threshold) was fresh pages from the kernel each
 * time, every page faulted in again; kept, the next run writes into memory
 * it has, and grows from the size the run before reached.
 *
 * SLOTS records are kept (the last ones released, each up to SPARE_MAX
 * bytes: a sweep's threads each find one), for any thread: taken and given
 * with atomic exchanges.
 */
#include <stdlib.h>
#include <string.h>

#include "pdbfs_record.h"

/* a larger record is freed: idle memory the process would hold on to */
#define SPARE_MAX (128.0 * 1048576.0)
#define SLOTS 2

static History *spare[SLOTS];

static double record_bytes(const History *H) {
    return 8.0 * (double)H->cap * (1 + NXQ + NRX + (H->dn ? DNREC + NRX : 0));
}

/* the arrays of the kept record into H (a new record: H's arrays NULL, H->rk
 * set as the run needs): an explicit run's record has its dense-output
 * arrays, another's has none (the invariant pdbfs_record_step relies on:
 * dn and rdot, where present, hold cap records) */
void pdbfs_record_adopt(History *H) {
    History *s = NULL;
    int i;
    for (i = 0; i < SLOTS && !s; i++) s = __atomic_exchange_n(&spare[i], NULL, __ATOMIC_ACQ_REL);
    if (!s) return;
    if (H->rk && !s->dn) {
        s->dn = malloc(sizeof(double) * (size_t)s->cap * DNREC);
        s->rdot = s->dn ? malloc(sizeof(double) * (size_t)s->cap * NRX) : NULL;
        if (!s->rdot) {
            pdbfs_free_history(s);
            free(s);
            return;
        }
    } else if (!H->rk && s->dn) {
        free(s->dn);
        free(s->rdot);
        s->dn = s->rdot = NULL;
    }
    H->t = s->t;
    H->x = s->x;
    H->r = s->r;
    H->dn = s->dn;
    H->rdot = s->rdot;
    H->cap = s->cap;
    H->rt = s->rt;
    H->rx = s->rx;
    H->rd = s->rd;
    H->rcap = s->rcap;
    free(s);
}

/* H's arrays kept for the next run (in an empty slot, else in place of the
 * first slot's record, freed), or
 * freed when larger than SPARE_MAX; H's arrays are NULL after */
void pdbfs_record_release(History *H) {
    History *empty = NULL;
    int i;
    History *s = H->cap > 0 && record_bytes(H) <= SPARE_MAX ? calloc(1, sizeof(History)) : NULL;
    if (!s) {
        pdbfs_free_history(H);
        H->cap = H->rcap = 0;
        return;
    }
    s->t = H->t;
    s->x = H->x;
    s->r = H->r;
    s->dn = H->dn;
    s->rdot = H->rdot;
    s->cap = H->cap;
    s->rt = H->rt;
    s->rx = H->rx;
    s->rd = H->rd;
    s->rcap = H->rcap;
    H->t = H->x = H->r = H->dn = H->rdot = H->rt = H->rx = NULL;
    H->rd = NULL;
    H->cap = H->rcap = 0;
    for (i = 0; i < SLOTS; i++, empty = NULL)      /* an empty slot, else the first one's */
        if (__atomic_compare_exchange_n(&spare[i], &empty, s, 0, __ATOMIC_ACQ_REL,
                                        __ATOMIC_ACQUIRE))
            return;
    s = __atomic_exchange_n(&spare[0], s, __ATOMIC_ACQ_REL);
    if (s) {
        pdbfs_free_history(s);
        free(s);
    }
}
