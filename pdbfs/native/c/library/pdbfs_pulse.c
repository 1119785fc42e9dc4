/* pdbfs_pulse: see pdbfs_pulse.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "pdbfs_pulse.h"

int pdbfs_pulse_pairs(long n, const double *t, const int *dir, int above0, int above1, double t0,
                      double t1, double *duration, char *msg, long msglen) {
    long i;
    int above = above0 != 0;
    double sum = 0.0, t_up = t0;
    *duration = NAN;
    if (msg && msglen > 0) msg[0] = 0;
    for (i = 0; i < n; i++) {
        if ((dir[i] > 0) == above || (i > 0 && t[i] < t[i - 1])) {
            if (msg && msglen > 0)
                snprintf(msg, (size_t)msglen, "the pressure's crossings of %g %% of its peak do not "
                         "alternate (%s at t = %.9g s after %s at t = %.9g s)", 100 * PULSE_LEVEL,
                         dir[i] > 0 ? "up" : "down", t[i], i == 0 ? (above ? "above" : "below")
                         : dir[i - 1] > 0 ? "up" : "down", i == 0 ? t0 : t[i - 1]);
            return PULSE_BAD;
        }
        above = dir[i] > 0;
        if (above) t_up = t[i];
        else if (i > 0 || !above0) sum += t[i] - t_up;
    }
    if (above != (above1 != 0)) {
        if (msg && msglen > 0)
            snprintf(msg, (size_t)msglen, "the pressure's crossings of %g %% of its peak do not "
                     "match its value at t_end = %.9g s (%s the level after %s)", 100 * PULSE_LEVEL,
                     t1, above1 ? "above" : "below", n == 0 ? "no crossing" : above
                     ? "an upward crossing" : "a downward crossing");
        return PULSE_BAD;
    }
    if (above0 || above1) {
        if (msg && msglen > 0)
            snprintf(msg, (size_t)msglen, "pulse %s: the pressure is above %g %% of its peak at "
                     "t = %.6g s; pulse_duration undefined%s", above1 ? "cut off at t_end"
                     : "begun before the start", 100 * PULSE_LEVEL, above1 ? t1 : t0,
                     above1 ? " (run longer)" : "");
        return PULSE_CUT;
    }
    *duration = sum;
    return PULSE_OK;
}

void pdbfs_note(Note *m, const char *fmt, ...) {
    va_list ap;
    size_t used;
    if (!m->text || m->len == 0) return;
    used = strlen(m->text);
    if (used && used + 3 < m->len) {
        strcpy(m->text + used, "; ");
        used += 2;
    }
    if (used + 1 >= m->len) return;
    va_start(ap, fmt);
    vsnprintf(m->text + used, m->len - used, fmt, ap);
    va_end(ap);
}
