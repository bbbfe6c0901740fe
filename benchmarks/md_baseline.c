/* Sequential C baseline for the MD benchmark (benchmarks/md.py compiles it with cc -O2).
 *
 * Not part of the package: a plain event loop to measure the NumPy engine against.
 * Same model and the same floating-point formulas as particles/md.py: point particles on a
 * ring of length lr, pair b = (b, b+1), seam pair (n-1, 0); lazy per-particle positions;
 * a tournament tree (complete binary tree of pair indices, min of (time, index) at each node).
 *
 * usage: md_baseline IN OUT lr restitution delta until
 *   IN : raw float64 arrays x[n], t_last[n], v[n] (n = filesize / 24)
 *   OUT: the same three arrays after the run
 * stdout: "collisions seconds" (seconds of the event loop only, CLOCK_MONOTONIC)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static long n, size;
static double *x, *tl, *v, *ct, lr;
static long *tree; /* tree[k] = pair index with the smallest (ct, index) under node k */

static double predict(long b) {
    long i = b, j = (b + 1 == n) ? 0 : b + 1;
    double vi = v[i], vj = v[j];
    if (!(vi > vj)) return INFINITY;
    double ti = tl[i], tj = tl[j];
    double tt = ti > tj ? ti : tj;
    double xi = x[i] + vi * (tt - ti);
    double xj = x[j] + vj * (tt - tj);
    if (j == 0) xj = xj + lr;
    double g = xj - xi;
    if (g < 0.0) g = 0.0;
    return tt + g / (vi - vj);
}

static inline long better(long a, long b) {
    if (a < 0) return b;
    if (b < 0) return a;
    if (ct[a] < ct[b] || (ct[a] == ct[b] && a < b)) return a;
    return b;
}

static void update(long b) {
    long k = size + b;
    k >>= 1;
    while (k >= 1) {
        tree[k] = better(tree[2 * k], tree[2 * k + 1]);
        k >>= 1;
    }
}

int main(int argc, char **argv) {
    if (argc != 7) {
        fprintf(stderr, "usage: %s IN OUT lr restitution delta until\n", argv[0]);
        return 2;
    }
    lr = atof(argv[3]);
    double r = atof(argv[4]), delta = atof(argv[5]), until = atof(argv[6]);
    double p = 0.5 * (1.0 + r);
    int elastic_only = (r == 1.0);
    FILE *f = fopen(argv[1], "rb");
    if (!f) return 3;
    fseek(f, 0, SEEK_END);
    n = ftell(f) / 24;
    fseek(f, 0, SEEK_SET);
    x = malloc(n * sizeof(double));
    tl = malloc(n * sizeof(double));
    v = malloc(n * sizeof(double));
    ct = malloc(n * sizeof(double));
    if (fread(x, 8, n, f) != (size_t)n || fread(tl, 8, n, f) != (size_t)n ||
        fread(v, 8, n, f) != (size_t)n)
        return 3;
    fclose(f);
    size = 1;
    while (size < n) size <<= 1;
    tree = malloc(2 * size * sizeof(long));
    for (long k = 0; k < size; k++) tree[size + k] = k < n ? k : -1;

    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (long b = 0; b < n; b++) ct[b] = predict(b);
    for (long k = size - 1; k >= 1; k--) tree[k] = better(tree[2 * k], tree[2 * k + 1]);
    long count = 0;
    for (;;) {
        long b = tree[1];
        double c = ct[b];
        if (!(c <= until)) break;
        long i = b, j = (b + 1 == n) ? 0 : b + 1;
        double vi = v[i], vj = v[j];
        double xc = x[i] + vi * (c - tl[i]);
        x[i] = xc;
        x[j] = (j == 0) ? xc - lr : xc;
        tl[i] = c;
        tl[j] = c;
        double d = vi - vj;
        if (elastic_only || d < delta) {
            v[i] = vj;
            v[j] = vi;
        } else {
            double pd = p * d;
            double a = vi - pd, e = vj + pd;
            a = fmin(fmax(a, vj), vi);
            e = fmin(fmax(e, vj), vi);
            if (a > e) { double s = a; a = e; e = s; }
            v[i] = a;
            v[j] = e;
        }
        count++;
        long bl = b > 0 ? b - 1 : n - 1, br = b + 1 < n ? b + 1 : 0;
        ct[bl] = predict(bl);
        update(bl);
        ct[b] = predict(b);
        update(b);
        ct[br] = predict(br);
        update(br);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double secs = (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec);
    f = fopen(argv[2], "wb");
    if (!f) return 3;
    fwrite(x, 8, n, f);
    fwrite(tl, 8, n, f);
    fwrite(v, 8, n, f);
    fclose(f);
    printf("%ld %.6f\n", count, secs);
    return 0;
}
