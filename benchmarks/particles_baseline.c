/* Sequential baseline loops for benchmarks/particles_ulam_lattice.py (not part of the package).
 *
 *   particles_baseline ulam    N COUNT SEED R   -> COUNT random-pair collisions (Ulam model)
 *   particles_baseline lattice N COUNT SEED R   -> COUNT random-bond attempts with the kinematic
 *                                                  constraint v_i > v_{i+1} (lattice model)
 *
 * Collision rule: d = (v_a - v_b) * p; v_a -= d; v_b += d; p = (1 + r) / 2.
 * Random numbers: xoshiro256** (one 64-bit draw per index, mapped to [0, m) by a 128-bit
 * multiply), or with -DUSE_DRAND48 the C library's drand48() scaled to [0, m).
 * Prints "seconds energy" for the timed loop only (initialisation excluded).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static uint64_t s[4];

static inline uint64_t rotl(const uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t next(void) {
    const uint64_t result = rotl(s[1] * 5, 7) * 9;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

#ifdef USE_DRAND48
static inline uint64_t below(uint64_t m) { return (uint64_t)(drand48() * (double)m); }
#else
static inline uint64_t below(uint64_t m) { return (uint64_t)(((__uint128_t)next() * m) >> 64); }
#endif

static double uniform(void) { return (next() >> 11) * 0x1.0p-53; }

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char **argv) {
    if (argc != 6) {
        fprintf(stderr, "usage: %s ulam|lattice N COUNT SEED R\n", argv[0]);
        return 2;
    }
    const int lattice = strcmp(argv[1], "lattice") == 0;
    const uint64_t n = strtoull(argv[2], NULL, 10);
    const uint64_t count = strtoull(argv[3], NULL, 10);
    uint64_t seed = strtoull(argv[4], NULL, 10);
    const double p = 0.5 * (1.0 + atof(argv[5]));
    for (int i = 0; i < 4; i++) { /* splitmix64 seeding */
        uint64_t z = (seed += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        s[i] = z ^ (z >> 31);
    }
#ifdef USE_DRAND48
    srand48((long)s[0]);
#endif
    double *v = malloc(n * sizeof(double));
    for (uint64_t i = 0; i < n; i++) { /* Box-Muller, not timed */
        double u1 = uniform(), u2 = uniform();
        v[i] = sqrt(-2.0 * log(1.0 - u1)) * cos(6.283185307179586 * u2);
    }
    const double t0 = now();
    if (lattice) {
        for (uint64_t c = 0; c < count; c++) {
            const uint64_t a = below(n);
            const uint64_t b = (a + 1 == n) ? 0 : a + 1;
            if (v[a] > v[b]) {
                const double d = (v[a] - v[b]) * p;
                v[a] -= d;
                v[b] += d;
            }
        }
    } else {
        for (uint64_t c = 0; c < count; c++) {
            const uint64_t a = below(n);
            uint64_t b = below(n - 1);
            b += (b >= a);
            const double d = (v[a] - v[b]) * p;
            v[a] -= d;
            v[b] += d;
        }
    }
    const double t1 = now();
    double e = 0.0;
    for (uint64_t i = 0; i < n; i++) e += v[i] * v[i];
    printf("%.6f %.10e\n", t1 - t0, e / n);
    free(v);
    return 0;
}
