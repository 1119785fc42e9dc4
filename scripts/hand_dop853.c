/*
 * The paper rig written by hand in C, the baseline of the speed targets
 * (bench_hand.py): hammer, piston and breech (three masses, six states),
 * Dormand & Prince's 8(5,3) pair with its 7th-order dense output (the
 * DOP853 method of Hairer, Norsett & Wanner, Solving ODEs I, 1993; its
 * published coefficients), Hairer's step-size control and first step, and
 * the peak oil pressure located on the dense output of the step in which
 * the column's compression turns.  No event location at the kinks (contact
 * onset, the oil going slack): a person's straightforward program.
 *
 *   hand_peak(p, v0, rtol, atol, t_end, out)   one run: out = {peak, t_peak, steps, evals}
 *   hand_sweep(n, V, K, p, rtol, atol, t_end, peaks, threads)
 *       the peaks of n runs (hammer speed V[i], oil stiffness K[i]) in an
 *       OpenMP loop (a pthreads loop where the compiler has no OpenMP)
 *
 * p: m1, m2, m3, k1, D, k2, k3, c2, A (SI).  Build:
 *   gcc -O2 -fopenmp -fPIC -shared hand_dop853.c -o hand.so -lm
 */
#include <math.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#else
#include <pthread.h>
#endif

#define N 6

typedef struct { double m1, m2, m3, k1, D, k2, k3, c2, A; } Rig;

/* hammer-piston contact k1 d^1.5 + D d^1.5 (v1 - v2), never pulling; a
 * linear oil column that cannot pull; viscous seal; linear mount */
static inline void rhs(const Rig *r, const double *y, double *f) {
    const double d = y[0] - y[2], s = y[2] - y[4];
    double fc = 0.0, fo = 0.0;
    if (d > 0) {
        fc = d * sqrt(d) * (r->k1 + r->D * (y[1] - y[3]));
        if (fc < 0) fc = 0.0;
    }
    if (s > 0) fo = r->k2 * s;
    f[0] = y[1];
    f[1] = -fc / r->m1;
    f[2] = y[3];
    f[3] = (fc - fo - r->c2 * y[3]) / r->m2;
    f[4] = y[5];
    f[5] = (fo - r->k3 * y[4]) / r->m3;
}

/* the method's coefficients: nodes c, stages a (nonzero entries only),
 * weights b, the 5th- and 3rd-order error estimators e5, e3, and the dense
 * output's d (rows 4 to 7 of the interpolant) */
static const double
    c2 = 0.05260015195876773, c3 = 0.0789002279381516, c4 = 0.1183503419072274,
    c5 = 0.2816496580927726, c6 = 0.3333333333333333, c7 = 0.25, c8 = 0.3076923076923077,
    c9 = 0.6512820512820513, c10 = 0.6, c11 = 0.8571428571428571, c14 = 0.1, c15 = 0.2,
    c16 = 0.7777777777777778,
    a21 = 0.05260015195876773,
    a31 = 0.0197250569845379, a32 = 0.0591751709536137,
    a41 = 0.02958758547680685, a43 = 0.08876275643042054,
    a51 = 0.2413651341592667, a53 = -0.8845494793282861, a54 = 0.924834003261792,
    a61 = 0.037037037037037035, a64 = 0.17082860872947386, a65 = 0.12546768756682242,
    a71 = 0.037109375, a74 = 0.17025221101954405, a75 = 0.06021653898045596, a76 = -0.017578125,
    a81 = 0.03709200011850479, a84 = 0.17038392571223998, a85 = 0.10726203044637328,
    a86 = -0.015319437748624402, a87 = 0.008273789163814023,
    a91 = 0.6241109587160757, a94 = -3.3608926294469414, a95 = -0.868219346841726,
    a96 = 27.59209969944671, a97 = 20.154067550477894, a98 = -43.48988418106996,
    a101 = 0.47766253643826434, a104 = -2.4881146199716677, a105 = -0.590290826836843,
    a106 = 21.230051448181193, a107 = 15.279233632882423, a108 = -33.28821096898486,
    a109 = -0.020331201708508627,
    a111 = -0.9371424300859873, a114 = 5.186372428844064, a115 = 1.0914373489967295,
    a116 = -8.149787010746927, a117 = -18.52006565999696, a118 = 22.739487099350505,
    a119 = 2.4936055526796523, a1110 = -3.0467644718982196,
    a121 = 2.273310147516538, a124 = -10.53449546673725, a125 = -2.0008720582248625,
    a126 = -17.9589318631188, a127 = 27.94888452941996, a128 = -2.8589982771350235,
    a129 = -8.87285693353063, a1210 = 12.360567175794303, a1211 = 0.6433927460157636,
    b1 = 0.054293734116568765, b6 = 4.450312892752409, b7 = 1.8915178993145003,
    b8 = -5.801203960010585, b9 = 0.3111643669578199, b10 = -0.1521609496625161,
    b11 = 0.20136540080403034, b12 = 0.04471061572777259,
    e51 = 0.01312004499419488, e56 = -1.2251564463762044, e57 = -0.4957589496572502,
    e58 = 1.6643771824549864, e59 = -0.35032884874997366, e510 = 0.3341791187130175,
    e511 = 0.08192320648511571, e512 = -0.022355307863886294,
    e31 = -0.18980075407240762, e39 = -0.4226823213237919, e312 = 0.02265179219836082,
    a141 = 0.056167502283047954, a147 = 0.25350021021662483, a148 = -0.2462390374708025,
    a149 = -0.12419142326381637, a1410 = 0.15329179827876568, a1411 = 0.00820105229563469,
    a1412 = 0.007567897660545699, a1413 = -0.008298,
    a151 = 0.03183464816350214, a156 = 0.028300909672366776, a157 = 0.053541988307438566,
    a158 = -0.05492374857139099, a1511 = -0.00010834732869724932,
    a1512 = 0.0003825710908356584, a1513 = -0.00034046500868740456, a1514 = 0.1413124436746325,
    a161 = -0.42889630158379194, a166 = -4.697621415361164, a167 = 7.683421196062599,
    a168 = 4.06898981839711, a169 = 0.3567271874552811, a1613 = -0.0013990241651590145,
    a1614 = 2.9475147891527724, a1615 = -9.15095847217987;

static const double D4[16] = {-8.428938276109013, 0, 0, 0, 0, 0.5667149535193777,
    -3.0689499459498917, 2.38466765651207, 2.117034582445028, -0.871391583777973,
    2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727,
    -9.194632392478356, -4.436036387594894};
static const double D5[16] = {10.427508642579134, 0, 0, 0, 0, 242.28349177525817,
    165.20045171727028, -374.5467547226902, -22.113666853125306, 7.733432668472264,
    -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178,
    -9.35292435884448, 35.81684148639408};
static const double D6[16] = {19.985053242002433, 0, 0, 0, 0, -387.0373087493518,
    -189.17813819516758, 527.8081592054236, -11.57390253995963, 6.8812326946963,
    -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412,
    84.32040550667716, 11.99229113618279};
static const double D7[16] = {-25.69393346270375, 0, 0, 0, 0, -154.18974869023643,
    -231.5293791760455, 357.6391179106141, 93.40532418362432, -37.45832313645163,
    104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828,
    -39.17726167561544, -149.72683625798564};

typedef struct { double peak, t_peak; long steps, evals; } Answer;

/* the dense output's seven rows of one quantity q (a linear combination
 * w of the states: the compression, or its rate) over the step */
static void rows(const double *w, const double *y0, const double *y1, double h,
                 double k[16][N], double F[7]) {
    double q0 = 0, q1 = 0, f0 = 0, f1 = 0, d[4] = {0, 0, 0, 0};
    int i, j;
    for (i = 0; i < N; i++) {
        if (w[i] == 0) continue;
        q0 += w[i] * y0[i];
        q1 += w[i] * y1[i];
        f0 += w[i] * k[0][i];
        f1 += w[i] * k[12][i];
        for (j = 0; j < 16; j++) {
            d[0] += w[i] * D4[j] * k[j][i];
            d[1] += w[i] * D5[j] * k[j][i];
            d[2] += w[i] * D6[j] * k[j][i];
            d[3] += w[i] * D7[j] * k[j][i];
        }
    }
    F[0] = q1 - q0;
    F[1] = h * f0 - F[0];
    F[2] = 2 * F[0] - h * (f1 + f0);
    for (j = 0; j < 4; j++) F[3 + j] = h * d[j];
}

/* the quantity of rows F (starting at q0) at theta in [0, 1] */
static double at(const double F[7], double q0, double x) {
    double v = F[6];
    v = v * x + F[5];
    v = v * (1 - x) + F[4];
    v = v * x + F[3];
    v = v * (1 - x) + F[2];
    v = v * x + F[1];
    v = v * (1 - x) + F[0];
    return q0 + v * x;
}

/* the compression's peak on a step where its rate goes from + to -: the
 * rate's root on the dense output (Illinois), and the compression there */
static void peak_in_step(const Rig *r, double t, double h, const double *y0, const double *y1,
                         double k[16][N], Answer *a) {
    static const double ws[N] = {0, 0, 1, 0, -1, 0}, wu[N] = {0, 0, 0, 1, 0, -1};
    double yy[N], Fs[7], Fu[7], lo = 0, hi = 1, ulo, uhi;
    const double s0 = y0[2] - y0[4], u0 = y0[3] - y0[5];
    int i, side = 0, it;
    /* the dense output's three extra stages */
    for (i = 0; i < N; i++)
        yy[i] = y0[i] + h * (a141 * k[0][i] + a147 * k[6][i] + a148 * k[7][i] + a149 * k[8][i] +
                             a1410 * k[9][i] + a1411 * k[10][i] + a1412 * k[11][i] +
                             a1413 * k[12][i]);
    rhs(r, yy, k[13]);
    for (i = 0; i < N; i++)
        yy[i] = y0[i] + h * (a151 * k[0][i] + a156 * k[5][i] + a157 * k[6][i] + a158 * k[7][i] +
                             a1511 * k[10][i] + a1512 * k[11][i] + a1513 * k[12][i] +
                             a1514 * k[13][i]);
    rhs(r, yy, k[14]);
    for (i = 0; i < N; i++)
        yy[i] = y0[i] + h * (a161 * k[0][i] + a166 * k[5][i] + a167 * k[6][i] + a168 * k[7][i] +
                             a169 * k[8][i] + a1613 * k[12][i] + a1614 * k[13][i] +
                             a1615 * k[14][i]);
    rhs(r, yy, k[15]);
    a->evals += 3;
    rows(ws, y0, y1, h, k, Fs);
    rows(wu, y0, y1, h, k, Fu);
    ulo = u0;
    uhi = y1[3] - y1[5];
    for (it = 0; it < 60 && hi - lo > 1e-15; it++) {
        double m = hi - uhi * (hi - lo) / (uhi - ulo), um;
        if (!(m > lo && m < hi)) m = 0.5 * (lo + hi);
        um = at(Fu, u0, m);
        if (um > 0) {
            lo = m;
            ulo = um;
            if (side == 1) uhi *= 0.5;
            side = 1;
        } else {
            hi = m;
            uhi = um;
            if (side == -1) ulo *= 0.5;
            side = -1;
        }
    }
    {
        const double th = 0.5 * (lo + hi), s = at(Fs, s0, th);
        if (s > a->peak) {
            a->peak = s;
            a->t_peak = t + th * h;
        }
    }
}

static double wrms(const double *v, const double *y0, const double *y1, double rtol, double atol) {
    double sum = 0;
    int i;
    for (i = 0; i < N; i++) {
        const double sk = atol + rtol * fmax(fabs(y0[i]), fabs(y1[i])), w = v[i] / sk;
        sum += w * w;
    }
    return sum;
}

static int solve(const Rig *r, double v0, double rtol, double atol, double t_end, Answer *a) {
    double y[N] = {0, v0, 0, 0, 0, 0}, y1[N], yy[N], k[16][N], e5[N], e3[N];
    double t = 0, h, facold = 1e-4;
    int i, reject = 0;
    a->peak = 0;
    a->t_peak = 0;
    a->steps = 0;
    a->evals = 2;
    rhs(r, y, k[0]);
    {   /* Hairer's first step */
        double dnf = 0, dny = 0, der2 = 0, der12;
        for (i = 0; i < N; i++) {
            const double sk = atol + rtol * fabs(y[i]);
            dnf += (k[0][i] / sk) * (k[0][i] / sk);
            dny += (y[i] / sk) * (y[i] / sk);
        }
        h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : 0.01 * sqrt(dny / dnf);
        for (i = 0; i < N; i++) yy[i] = y[i] + h * k[0][i];
        rhs(r, yy, k[1]);
        for (i = 0; i < N; i++) {
            const double sk = atol + rtol * fabs(y[i]), d = (k[1][i] - k[0][i]) / sk;
            der2 += d * d;
        }
        der2 = sqrt(der2) / h;
        der12 = fmax(der2, sqrt(dnf));
        h = fmin(100 * h, der12 <= 1e-15 ? fmax(1e-6, 1e-3 * h) : pow(0.01 / der12, 1.0 / 8.0));
    }
    while (t < t_end) {
        double err, err2, deno, fac11, fac;
        if (t + 1.01 * h >= t_end) h = t_end - t;
        for (i = 0; i < N; i++) yy[i] = y[i] + h * a21 * k[0][i];
        rhs(r, yy, k[1]);
        for (i = 0; i < N; i++) yy[i] = y[i] + h * (a31 * k[0][i] + a32 * k[1][i]);
        rhs(r, yy, k[2]);
        for (i = 0; i < N; i++) yy[i] = y[i] + h * (a41 * k[0][i] + a43 * k[2][i]);
        rhs(r, yy, k[3]);
        for (i = 0; i < N; i++) yy[i] = y[i] + h * (a51 * k[0][i] + a53 * k[2][i] + a54 * k[3][i]);
        rhs(r, yy, k[4]);
        for (i = 0; i < N; i++) yy[i] = y[i] + h * (a61 * k[0][i] + a64 * k[3][i] + a65 * k[4][i]);
        rhs(r, yy, k[5]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a71 * k[0][i] + a74 * k[3][i] + a75 * k[4][i] + a76 * k[5][i]);
        rhs(r, yy, k[6]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a81 * k[0][i] + a84 * k[3][i] + a85 * k[4][i] + a86 * k[5][i] +
                                a87 * k[6][i]);
        rhs(r, yy, k[7]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a91 * k[0][i] + a94 * k[3][i] + a95 * k[4][i] + a96 * k[5][i] +
                                a97 * k[6][i] + a98 * k[7][i]);
        rhs(r, yy, k[8]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a101 * k[0][i] + a104 * k[3][i] + a105 * k[4][i] +
                                a106 * k[5][i] + a107 * k[6][i] + a108 * k[7][i] + a109 * k[8][i]);
        rhs(r, yy, k[9]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a111 * k[0][i] + a114 * k[3][i] + a115 * k[4][i] +
                                a116 * k[5][i] + a117 * k[6][i] + a118 * k[7][i] +
                                a119 * k[8][i] + a1110 * k[9][i]);
        rhs(r, yy, k[10]);
        for (i = 0; i < N; i++)
            yy[i] = y[i] + h * (a121 * k[0][i] + a124 * k[3][i] + a125 * k[4][i] +
                                a126 * k[5][i] + a127 * k[6][i] + a128 * k[7][i] +
                                a129 * k[8][i] + a1210 * k[9][i] + a1211 * k[10][i]);
        rhs(r, yy, k[11]);
        for (i = 0; i < N; i++) {
            const double inc = b1 * k[0][i] + b6 * k[5][i] + b7 * k[6][i] + b8 * k[7][i] +
                               b9 * k[8][i] + b10 * k[9][i] + b11 * k[10][i] + b12 * k[11][i];
            y1[i] = y[i] + h * inc;
            e5[i] = e51 * k[0][i] + e56 * k[5][i] + e57 * k[6][i] + e58 * k[7][i] +
                    e59 * k[8][i] + e510 * k[9][i] + e511 * k[10][i] + e512 * k[11][i];
            /* the 3rd-order estimate: the weights but at stages 1, 9 and 12 */
            e3[i] = inc - b1 * k[0][i] - b9 * k[8][i] - b12 * k[11][i] +
                    e31 * k[0][i] + e39 * k[8][i] + e312 * k[11][i];
        }
        a->evals += 11;
        err = wrms(e5, y, y1, rtol, atol);
        err2 = wrms(e3, y, y1, rtol, atol);
        deno = err + 0.01 * err2;
        if (deno <= 0) deno = 1;
        err = fabs(h) * err * sqrt(1.0 / (N * deno));
        fac11 = sqrt(sqrt(sqrt(err)));
        fac = fmax(1.0 / 6.0, fmin(1.0 / 0.333, fac11 / 0.9));
        if (err <= 1.0) {
            double hnew = h / fac;
            facold = fmax(err, 1e-4);
            rhs(r, y1, k[12]);         /* the next step's first stage */
            a->evals++;
            a->steps++;
            {
                const double u0 = y[3] - y[5], u1 = y1[3] - y1[5];
                if (y1[2] - y1[4] > a->peak) {
                    a->peak = y1[2] - y1[4];
                    a->t_peak = t + h;
                }
                if (u0 > 0 && u1 <= 0) peak_in_step(r, t, h, y, y1, k, a);
            }
            memcpy(k[0], k[12], sizeof k[0]);
            memcpy(y, y1, sizeof y);
            t += h;
            if (reject && hnew > h) hnew = h;
            reject = 0;
            h = hnew;
        } else {
            h /= fmin(1.0 / 0.333, fac11 / 0.9);
            reject = 1;
        }
        if (!(h > 1e-16 * t_end) || a->steps > 1000000) return 1;
    }
    (void)facold;
    a->peak *= r->k2 / r->A;
    return 0;
}

static Rig rig_of(const double *p) {
    Rig r = {p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]};
    return r;
}

int hand_peak(const double *p, double v0, double rtol, double atol, double t_end, double *out) {
    Rig r = rig_of(p);
    Answer a;
    int rc = solve(&r, v0, rtol, atol, t_end, &a);
    out[0] = a.peak;
    out[1] = a.t_peak;
    out[2] = (double)a.steps;
    out[3] = (double)a.evals;
    return rc;
}

static void one_point(const double *p, double v, double k2, double rtol, double atol,
                      double t_end, double *peak) {
    Rig r = rig_of(p);
    Answer a;
    r.k2 = k2;
    *peak = solve(&r, v, rtol, atol, t_end, &a) ? NAN : a.peak;
}

#ifndef _OPENMP
typedef struct {
    long n, *next;
    const double *V, *K, *p;
    double rtol, atol, t_end, *peaks;
    pthread_mutex_t *lock;
} Work;

static void *worker(void *arg) {
    Work *w = (Work *)arg;
    for (;;) {
        long i0, i;
        pthread_mutex_lock(w->lock);
        i0 = *w->next;
        *w->next += 8;
        pthread_mutex_unlock(w->lock);
        if (i0 >= w->n) return NULL;
        for (i = i0; i < i0 + 8 && i < w->n; i++)
            one_point(w->p, w->V[i], w->K[i], w->rtol, w->atol, w->t_end, w->peaks + i);
    }
}
#endif

/* 1 with OpenMP, 0 with pthreads: how the loop below runs */
int hand_openmp(void) {
#ifdef _OPENMP
    return 1;
#else
    return 0;
#endif
}

void hand_sweep(long n, const double *V, const double *K, const double *p, double rtol,
                double atol, double t_end, double *peaks, int threads) {
#ifdef _OPENMP
    long i;
#pragma omp parallel for schedule(dynamic, 8) num_threads(threads)
    for (i = 0; i < n; i++) one_point(p, V[i], K[i], rtol, atol, t_end, peaks + i);
#else
    pthread_t tid[64];
    pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    long next = 0;
    Work w = {n, &next, V, K, p, rtol, atol, t_end, peaks, &lock};
    int j;
    if (threads > 64) threads = 64;
    for (j = 0; j < threads; j++) pthread_create(&tid[j], NULL, worker, &w);
    for (j = 0; j < threads; j++) pthread_join(tid[j], NULL);
#endif
}
