/* The limit tumble's RK4 is measured against (docs/performance.md): a plain-C probe of the same
 * work with none of the library around it, and the memory bound.
 *   probe   N free boxes under gravity: the state kept component by component (structure of
 *           arrays) for good, the derivative of derivative.c (rotation of q/|q| without a square
 *           root, omega = R I^-1 R^T L, dq = 1/2 (0, omega) q, dx = P/M, dP = M g), RK4 in 32-body
 *           chunks that stay in L1, and the renormalisation: ns per body-step, compiled for the
 *           build machine (-march=native);
 *   memory  the bandwidth of copying 13 N doubles (a read and a write a byte), and what a step
 *           that reads the state and writes it, and the copy kept aside to undo a failed step,
 *           must move: 3 x 104 bytes a body, over that bandwidth.
 * Prints CSV: what, bodies, ns per body-step (the probe's, or the memory bound's), GB/s.
 *
 * usage: bench_limit [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LANES 32
#define COMPONENTS 13

/* A chunk of LANES bodies: component c of body j at [c][j]. */
typedef struct chunk {
    double s[COMPONENTS][LANES];
} chunk;

static void derivative(const chunk *y, chunk *d, const double *inv_mass, const double *mass,
                       double inv_moments[3][LANES])
{
    for (int j = 0; j < LANES; ++j) {
        const double w = y->s[3][j], x = y->s[4][j], yy = y->s[5][j], z = y->s[6][j];
        const double s = 2.0 / (w * w + x * x + yy * yy + z * z);
        const double R0 = 1 - s * (yy * yy + z * z), R1 = s * (x * yy - w * z),
                     R2 = s * (x * z + w * yy), R3 = s * (x * yy + w * z),
                     R4 = 1 - s * (x * x + z * z), R5 = s * (yy * z - w * x),
                     R6 = s * (x * z - w * yy), R7 = s * (yy * z + w * x),
                     R8 = 1 - s * (x * x + yy * yy);
        const double L0 = y->s[10][j], L1 = y->s[11][j], L2 = y->s[12][j];
        const double b0 = (R0 * L0 + R3 * L1 + R6 * L2) * inv_moments[0][j];
        const double b1 = (R1 * L0 + R4 * L1 + R7 * L2) * inv_moments[1][j];
        const double b2 = (R2 * L0 + R5 * L1 + R8 * L2) * inv_moments[2][j];
        const double o0 = R0 * b0 + R1 * b1 + R2 * b2, o1 = R3 * b0 + R4 * b1 + R5 * b2,
                     o2 = R6 * b0 + R7 * b1 + R8 * b2;
        for (int k = 0; k < 3; ++k) {
            d->s[k][j] = y->s[7 + k][j] * inv_mass[j];
        }
        d->s[3][j] = 0.5 * (-o0 * x - o1 * yy - o2 * z);
        d->s[4][j] = 0.5 * (o0 * w + o1 * z - o2 * yy);
        d->s[5][j] = 0.5 * (-o0 * z + o1 * w + o2 * x);
        d->s[6][j] = 0.5 * (o0 * yy - o1 * x + o2 * w);
        d->s[7][j] = 0.0;
        d->s[8][j] = 0.0;
        d->s[9][j] = mass[j] * -9.81;
        d->s[10][j] = d->s[11][j] = d->s[12][j] = 0.0;
    }
}

static void rk4_chunk(chunk *y, double h, const double *inv_mass, const double *mass,
                      double inv_moments[3][LANES])
{
    static const double next[4] = {0.5, 0.5, 1.0, 0.0},
                        weight[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
    chunk k, stage, sum;
    const chunk *input = y;
    for (int s = 0; s < 4; ++s) {
        derivative(input, &k, inv_mass, mass, inv_moments);
        const double b = weight[s] * h, a = next[s] * h;
        for (int c = 0; c < COMPONENTS; ++c) {
            for (int j = 0; j < LANES; ++j) {
                sum.s[c][j] = (s == 0 ? y->s[c][j] : sum.s[c][j]) + b * k.s[c][j];
                stage.s[c][j] = y->s[c][j] + a * k.s[c][j];
            }
        }
        input = &stage;
    }
    for (int j = 0; j < LANES; ++j) {
        const double n = sqrt(sum.s[3][j] * sum.s[3][j] + sum.s[4][j] * sum.s[4][j] +
                              sum.s[5][j] * sum.s[5][j] + sum.s[6][j] * sum.s[6][j]);
        for (int c = 3; c < 7; ++c) {
            sum.s[c][j] /= n;
        }
    }
    *y = sum;
}

/* ns per body-step of the probe on `bodies` boxes (a multiple of LANES). */
static double probe(size_t bodies, double body_steps)
{
    const size_t chunks = bodies / LANES;
    chunk *y = malloc(chunks * sizeof *y);
    double inv_mass[LANES], mass[LANES], inv_moments[3][LANES];
    for (int j = 0; j < LANES; ++j) {
        mass[j] = 500.0 * 0.1 * 0.2 * 0.3;
        inv_mass[j] = 1.0 / mass[j];
        inv_moments[0][j] = 12.0 / (mass[j] * (0.04 + 0.09));
        inv_moments[1][j] = 12.0 / (mass[j] * (0.01 + 0.09));
        inv_moments[2][j] = 12.0 / (mass[j] * (0.01 + 0.04));
    }
    for (size_t g = 0; g < chunks; ++g) {
        memset(&y[g], 0, sizeof y[g]);
        for (int j = 0; j < LANES; ++j) {
            y[g].s[0][j] = (double)(g * LANES + (size_t)j);
            y[g].s[3][j] = 1.0;
            y[g].s[9][j] = 3.0 * mass[j];
            y[g].s[10][j] = 1.0 / inv_moments[0][j];
            y[g].s[11][j] = 2.0 / inv_moments[1][j];
        }
    }
    const long steps = (long)(body_steps / (double)bodies) + 1;
    const double start = bench_cpu_seconds();
    for (long k = 0; k < steps; ++k) {
        for (size_t g = 0; g < chunks; ++g) {
            rk4_chunk(&y[g], 1.0 / 240, inv_mass, mass, inv_moments);
        }
    }
    const double seconds = bench_cpu_seconds() - start;
    volatile double keep = y[chunks - 1].s[0][0];
    (void)keep;
    free(y);
    return 1e9 * seconds / (double)steps / (double)bodies;
}

/* GB/s of copying 13 bodies' doubles (bytes read plus bytes written, over the time). */
static double copy_bandwidth(size_t bodies, int repeats)
{
    const size_t n = COMPONENTS * bodies;
    double *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    for (size_t i = 0; i < n; ++i) {
        a[i] = (double)i;
    }
    double times[16];
    for (int r = 0; r < repeats; ++r) {
        const double start = bench_cpu_seconds();
        memcpy(b, a, n * sizeof *a);
        memcpy(a, b, n * sizeof *a);
        times[r] = bench_cpu_seconds() - start;
    }
    free(a);
    free(b);
    return 4.0 * (double)(n * sizeof(double)) / bench_median(times, (size_t)repeats) / 1e9;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    printf("what,bodies,ns_per_body_step,gigabytes_per_second\n");
    static const size_t sizes[] = {128, 1024, 10240, 102400};
    for (size_t s = 0; s < (quick ? 1 : sizeof sizes / sizeof sizes[0]); ++s) {
        double times[7];
        for (int r = 0; r < (quick ? 1 : 7); ++r) {
            times[r] = probe(sizes[s], quick ? 2e4 : 2e6);
        }
        printf("probe,%zu,%.1f,nan\n", sizes[s], bench_median(times, quick ? 1 : 7));
        const double bandwidth = copy_bandwidth(sizes[s], quick ? 3 : 15);
        /* a step reads the state, writes it, and writes the copy kept aside */
        printf("memory-bound,%zu,%.1f,%.1f\n", sizes[s],
               3.0 * COMPONENTS * sizeof(double) / bandwidth, bandwidth);
    }
    return 0;
}
