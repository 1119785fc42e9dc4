/*
 * pdbfs_batch_run over the segments of a run's piecewise-linear inputs
 * (pdbfs.simulation.setup.input_traces): on segment k, [edges[k],
 * edges[k+1]], every input is u + du (t - t_ref), and p holds them: its
 * rows u0 .. u0 + n_in - 1 the values at t_ref = edges[k], the next n_in
 * the slopes, then t_ref.  Each segment is an ordinary run of the rig from
 * the state the one before ended in (the integrator restarted there, as at
 * a time event), its grid the segment's ends and the output times inside.
 * One call for every segment: a trace of millions of samples costs the
 * integration, not a call from Python per sample.
 *
 * coef: nseg rows of 2 n_in numbers (the values, then the slopes).  The
 * output grid t (nt points) starts at edges[0] and ends at edges[nseg]; an
 * edge on an output time is that time exactly (the caller moved it there).
 * X (nx x nt, row-major as pdbfs_batch_run's) gets the states at the output
 * times; a time shared by two segments is written by the later one.  Codes
 * and info[] as pdbfs_batch_run's, info summed over the segments, INFO_T
 * the time reached; info[INFO_N_SEG] is not kept: the caller knows nseg.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define API __attribute__((visibility("default")))   /* as pdbfs_batch.c */

#define RC_BAD_INPUT 1
#define RC_SETUP 2
enum { INFO_T, INFO_STEPS, INFO_ROOTS, INFO_RHS, INFO_FLAG, INFO_JAC, INFO_METHOD, INFO_N };

int pdbfs_batch_run(long long nx, long long np, const double *p, const double *x0,
                    long long nt, const double *t, double *X, double rtol, double atol,
                    int method, double max_step, long long max_num_steps, double *info,
                    char *msg, long long msglen);

API int pdbfs_batch_run_segments(long long nx, long long np, const double *p, const double *x0,
                                 long long nseg, const double *edges, const double *coef,
                                 long long n_in, long long u0, long long nt, const double *t,
                                 double *X, double rtol, double atol, int method,
                                 double max_step, long long max_num_steps, double *info,
                                 char *msg, long long msglen) {
    double part[INFO_N], *q, *tk, *Xk, *x;
    long long k, i, j, lo, most = 0, at, n, rc = 0;

    if (info) for (i = 0; i < INFO_N; i++) info[i] = 0.0;
    if (!info || !p || !x0 || !edges || !coef || !t || !X || nseg < 1 || nt < 2 || n_in < 1
        || u0 < 0 || u0 + 2 * n_in + 1 > np || edges[0] != t[0] || edges[nseg] != t[nt - 1]) {
        if (msg && msglen > 0) snprintf(msg, (size_t)msglen, "segments: bad arguments");
        return RC_BAD_INPUT;
    }
    /* the most output times inside one segment: the size of its grid */
    for (k = 0, lo = 1; k < nseg; k++) {
        if (!(edges[k + 1] > edges[k])) {
            if (msg && msglen > 0)
                snprintf(msg, (size_t)msglen, "segments: edge %lld (%g) not after the one before",
                         k + 1, edges[k + 1]);
            return RC_BAD_INPUT;
        }
        for (n = 0; lo < nt && t[lo] < edges[k + 1]; lo++) n++;
        if (n > most) most = n;
        if (lo < nt && t[lo] == edges[k + 1]) lo++;
    }
    q = malloc(sizeof(double) * ((size_t)np + (size_t)(most + 2) * (1 + (size_t)nx) + (size_t)nx));
    if (!q) {
        if (msg && msglen > 0) snprintf(msg, (size_t)msglen, "out of memory");
        return RC_SETUP;
    }
    tk = q + np;
    Xk = tk + most + 2;
    x = Xk + (most + 2) * nx;
    memcpy(q, p, sizeof(double) * (size_t)np);
    memcpy(x, x0, sizeof(double) * (size_t)nx);
    for (i = 0; i < nx; i++) X[i * nt] = x0[i];
    info[INFO_T] = t[0];
    for (k = 0, lo = 1; k < nseg && !rc; k++) {
        const double *c = coef + 2 * n_in * k;
        memcpy(q + u0, c, sizeof(double) * (size_t)(2 * n_in));
        q[u0 + 2 * n_in] = edges[k];
        n = 0;
        tk[n++] = edges[k];
        for (at = lo; at < nt && t[at] < edges[k + 1]; at++) tk[n++] = t[at];
        tk[n++] = edges[k + 1];
        rc = pdbfs_batch_run(nx, np, q, x, n, tk, Xk, rtol, atol, method, max_step,
                             max_num_steps, part, msg, msglen);
        for (i = INFO_STEPS; i < INFO_N; i++)
            info[i] = (i == INFO_METHOD || i == INFO_FLAG) ? part[i] : info[i] + part[i];
        info[INFO_T] = part[INFO_T];
        if (rc) break;
        /* the output times inside, then the segment's end where it is one */
        for (j = 1; j < n - 1; j++, lo++)
            for (i = 0; i < nx; i++) X[i * nt + lo] = Xk[i * n + j];
        if (lo < nt && t[lo] == edges[k + 1]) {
            for (i = 0; i < nx; i++) X[i * nt + lo] = Xk[i * n + n - 1];
            lo++;
        }
        for (i = 0; i < nx; i++) x[i] = Xk[i * n + n - 1];
    }
    free(q);
    return (int)rc;
}
