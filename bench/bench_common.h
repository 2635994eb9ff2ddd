/* What every benchmark needs: CPU time and the median of repeated measurements. */
#ifndef TUMBLE_BENCH_COMMON_H
#define TUMBLE_BENCH_COMMON_H

#include <stdlib.h>
#include <time.h>

/* CPU seconds used by this process (not wall time: the machines are shared). */
static inline double bench_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Wall-clock seconds (what threads shorten; noisy on a shared machine). */
static inline double bench_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int bench_compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of count values (sorts them in place). */
static inline double bench_median(double *values, size_t count)
{
    qsort(values, count, sizeof values[0], bench_compare);
    return values[count / 2];
}

#endif
