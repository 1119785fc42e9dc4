/*
 * The pulse of a summary (pdbfs_summary.c), free of any model: its duration
 * from the crossings of its level, and the notes a point collects.
 */
#ifndef PDBFS_PULSE_H
#define PDBFS_PULSE_H

#include <stddef.h>

#define PULSE_LEVEL 0.01     /* the pulse lasts while the pressure exceeds 1 % of its peak */

/* pdbfs_pulse_pairs' answers */
#define PULSE_OK 0
#define PULSE_CUT 1          /* begun before t0 or not ended by t1: no duration */
#define PULSE_BAD 2          /* crossings that do not alternate */

/*
 * The pulse's duration from its crossings of the level: times t (n, in time
 * order) and directions dir (+1 up, -1 down); above0, above1: whether the
 * signal is above the level at t0 and at t1.  Pulses are paired by
 * direction, up then down, and their durations summed.  PULSE_OK with the
 * duration; PULSE_CUT (duration NaN) when a pulse began before t0 or has not
 * ended by t1; PULSE_BAD (NaN) when the crossings do not alternate.  A
 * message for the last two (msglen bytes, may be NULL).  Exported: the
 * tests call it.
 */
__attribute__((visibility("default")))
int pdbfs_pulse_pairs(long n, const double *t, const int *dir, int above0, int above1, double t0,
                      double t1, double *duration, char *msg, long msglen);

/* the warnings (or the failure) of one point: text of len bytes, or NULL */
typedef struct {
    char *text;
    size_t len;
} Note;

/* add a sentence to the note, after any before it ("; ") */
void pdbfs_note(Note *m, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
