/* pdbfs_modes: see pdbfs_modes.h.  Never aborts, never prints. */
#include <float.h>
#include <math.h>

#include "pdbfs_modes.h"

#define QR_STEPS 60    /* Francis steps allowed per eigenvalue (a few are usual) */
#define A_(i, j) a[(size_t)(i) * (size_t)n + (size_t)(j)]

/* u (length k, 2 or 3) made the vector of the reflection I - 2 u u'/u'u that
 * takes it to a multiple of e1; 0 when it is zero (nothing to reflect) */
static int reflector(double *u, int k) {
    double norm = sqrt(u[0] * u[0] + u[1] * u[1] + (k == 3 ? u[2] * u[2] : 0.0));
    if (norm == 0.0) return 0;
    u[0] += u[0] >= 0 ? norm : -norm;
    return 1;
}

/* the reflection of u (length k) on rows r.. r+k-1, columns c0..c1 */
static void reflect_rows(double *a, int n, const double *u, int k, int r, int c0, int c1) {
    double uu = 0.0;
    int i, j;
    for (i = 0; i < k; i++) uu += u[i] * u[i];
    for (j = c0; j <= c1; j++) {
        double d = 0.0;
        for (i = 0; i < k; i++) d += u[i] * A_(r + i, j);
        d *= 2.0 / uu;
        for (i = 0; i < k; i++) A_(r + i, j) -= d * u[i];
    }
}

/* ... and on columns c.. c+k-1, rows r0..r1 */
static void reflect_cols(double *a, int n, const double *u, int k, int c, int r0, int r1) {
    double uu = 0.0;
    int i, j;
    for (j = 0; j < k; j++) uu += u[j] * u[j];
    for (i = r0; i <= r1; i++) {
        double d = 0.0;
        for (j = 0; j < k; j++) d += A_(i, c + j) * u[j];
        d *= 2.0 / uu;
        for (j = 0; j < k; j++) A_(i, c + j) -= d * u[j];
    }
}

/* a (n x n, row major) to upper Hessenberg form by a similarity: the same
 * eigenvalues; v: n of work */
static void hessenberg(double *a, int n, double *v) {
    int k, i;
    for (k = 0; k + 2 < n; k++) {
        double norm = 0.0;
        for (i = k + 1; i < n; i++) norm += A_(i, k) * A_(i, k);
        if (norm == 0.0) continue;
        for (i = k + 1; i < n; i++) v[i - k - 1] = A_(i, k);
        v[0] += v[0] >= 0 ? sqrt(norm) : -sqrt(norm);
        /* the whole reflection at once: rows k+1.., then columns k+1.. */
        {
            double uu = 0.0;
            int j, m = n - k - 1;
            for (i = 0; i < m; i++) uu += v[i] * v[i];
            for (j = k; j < n; j++) {
                double d = 0.0;
                for (i = 0; i < m; i++) d += v[i] * A_(k + 1 + i, j);
                d *= 2.0 / uu;
                for (i = 0; i < m; i++) A_(k + 1 + i, j) -= d * v[i];
            }
            for (i = 0; i < n; i++) {
                double d = 0.0;
                for (j = 0; j < m; j++) d += A_(i, k + 1 + j) * v[j];
                d *= 2.0 / uu;
                for (j = 0; j < m; j++) A_(i, k + 1 + j) -= d * v[j];
            }
        }
        for (i = k + 2; i < n; i++) A_(i, k) = 0.0;
    }
}

/* the eigenvalues of [[p, q], [r, s]] */
static void two_by_two(double p, double q, double r, double s, double *wr, double *wi) {
    double half = 0.5 * (p - s), disc = half * half + q * r, mean = 0.5 * (p + s);
    if (disc >= 0) {
        wr[0] = mean + sqrt(disc);
        wr[1] = mean - sqrt(disc);
        wi[0] = wi[1] = 0.0;
    } else {
        wr[0] = wr[1] = mean;
        wi[0] = sqrt(-disc);
        wi[1] = -wi[0];
    }
}

/* the eigenvalues of an upper Hessenberg a (destroyed) into wr + i wi:
 * Francis double-shift steps on the unreduced window [lo, hi], deflating
 * at negligible subdiagonals.  0, or -1 without convergence */
static int hessenberg_eigenvalues(double *a, int n, double *wr, double *wi) {
    int hi = n - 1, steps = 0, i, j;
    double anorm = 0.0;
    for (i = 0; i < n; i++)
        for (j = i > 0 ? i - 1 : 0; j < n; j++) anorm += fabs(A_(i, j));
    while (hi >= 0) {
        int lo, k;
        double s, t, x, y, z;
        for (lo = hi; lo > 0; lo--) {
            double d = fabs(A_(lo - 1, lo - 1)) + fabs(A_(lo, lo));
            if (fabs(A_(lo, lo - 1)) <= DBL_EPSILON * (d > 0 ? d : anorm)) {
                A_(lo, lo - 1) = 0.0;
                break;
            }
        }
        if (lo == hi) {
            wr[hi] = A_(hi, hi);
            wi[hi] = 0.0;
            hi--;
            steps = 0;
            continue;
        }
        if (lo == hi - 1) {
            two_by_two(A_(hi - 1, hi - 1), A_(hi - 1, hi), A_(hi, hi - 1), A_(hi, hi), wr + hi - 1, wi + hi - 1);
            hi -= 2;
            steps = 0;
            continue;
        }
        if (++steps > QR_STEPS) return -1;
        if (steps % 10 == 0) {   /* an exceptional shift breaks a cycle */
            double e = fabs(A_(hi, hi - 1)) + fabs(A_(hi - 1, hi - 2));
            s = 1.5 * e;
            t = e * e;
        } else {                 /* the trailing 2 x 2's eigenvalues: their sum and product */
            s = A_(hi - 1, hi - 1) + A_(hi, hi);
            t = A_(hi - 1, hi - 1) * A_(hi, hi) - A_(hi - 1, hi) * A_(hi, hi - 1);
        }
        /* the first column of (A - s1)(A - s2), then the bulge chased down */
        x = A_(lo, lo) * A_(lo, lo) + A_(lo, lo + 1) * A_(lo + 1, lo) - s * A_(lo, lo) + t;
        y = A_(lo + 1, lo) * (A_(lo, lo) + A_(lo + 1, lo + 1) - s);
        z = A_(lo + 1, lo) * A_(lo + 2, lo + 1);
        for (k = lo; k <= hi - 2; k++) {
            double u[3];
            u[0] = x;
            u[1] = y;
            u[2] = z;
            if (reflector(u, 3)) {
                reflect_rows(a, n, u, 3, k, k > lo ? k - 1 : lo, hi);
                reflect_cols(a, n, u, 3, k, lo, k + 3 < hi ? k + 3 : hi);
                if (k > lo) A_(k + 1, k - 1) = A_(k + 2, k - 1) = 0.0;
            }
            x = A_(k + 1, k);
            y = A_(k + 2, k);
            if (k < hi - 2) z = A_(k + 3, k);
        }
        {
            double u[2];
            u[0] = x;
            u[1] = y;
            if (reflector(u, 2)) {
                reflect_rows(a, n, u, 2, hi - 1, hi - 2, hi);
                reflect_cols(a, n, u, 2, hi - 1, lo, hi);
                A_(hi, hi - 2) = 0.0;
            }
        }
    }
    return 0;
}

/* CasADi's pattern of pdbfs_jac: {nrow, ncol, colind[ncol + 1], row[nnz]}, a
 * dense one compressed to {nrow, ncol, 1} (its nonzeros column by column) */
static casadi_int jac_nnz(int n, const casadi_int *sp) {
    return sp[2] == 1 ? (casadi_int)n * n : sp[2 + n];
}

size_t pdbfs_modes_work(int n) {
    return (size_t)jac_nnz(n, pdbfs_jac_sparsity_out(0)) + (size_t)n * (size_t)(n + 3) + 1;
}

int pdbfs_modes_at(PdbfsEval *ev, int n, double t, const double *x, double *work,
                   double *fastest, double *rate, double *osc) {
    const casadi_int *sp = pdbfs_jac_sparsity_out(0);
    const int dense = sp[2] == 1;
    double *nz = work, *a = nz + jac_nnz(n, sp) + 1, *wr = a + (size_t)n * (size_t)n, *wi = wr + n;
    int i, bad = 0;
    *fastest = *rate = *osc = 0.0;
    for (i = 0; i < n * n; i++) a[i] = 0.0;
    if (pdbfs_eval_txp(ev, pdbfs_jac, t, x, nz)) bad = 1;
    for (i = 0; i < n; i++) {
        casadi_int k, k0 = dense ? (casadi_int)i * n : sp[2 + i], k1 = dense ? k0 + n : sp[3 + i];
        for (k = k0; k < k1; k++) {
            if (!isfinite(nz[k])) bad = 1;
            A_(dense ? k - k0 : sp[3 + n + k], i) = nz[k];
        }
    }
    if (bad) return 1;
    hessenberg(a, n, wi);
    if (hessenberg_eigenvalues(a, n, wr, wi)) return -1;
    for (i = 0; i < n; i++) {
        double mod = hypot(wr[i], wi[i]);
        if (mod > *fastest) *fastest = mod;
        if (fabs(wr[i]) > fabs(wi[i])) {
            if (-wr[i] > *rate) *rate = -wr[i];
        } else if (mod > *osc) {
            *osc = mod;
        }
    }
    return 0;
}
