/* What every benchmark needs: CPU time and the median of repeated measurements. */
#ifndef TUMBLE_BENCH_COMMON_H
#define TUMBLE_BENCH_COMMON_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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

/* The processor's name and its vector extensions among sse2, avx, fma, avx2 and avx512f, as
 * Linux reads them ("unknown" and "" where /proc/cpuinfo says nothing). */
static inline void bench_processor(char model[256], char extensions[256])
{
    FILE *cpuinfo = fopen("/proc/cpuinfo", "r");
    char line[4096];
    snprintf(model, 256, "unknown");
    extensions[0] = '\0';
    while (cpuinfo != NULL && fgets(line, sizeof line, cpuinfo) != NULL) {
        if (strncmp(line, "model name", 10) == 0 && strchr(line, ':') != NULL) {
            snprintf(model, 256, "%s", strchr(line, ':') + 2);
            model[strcspn(model, "\n")] = '\0';
        } else if (strncmp(line, "flags", 5) == 0 && extensions[0] == '\0') {
            static const char *const wanted[] = {" sse2 ", " avx ", " fma ", " avx2 ", " avx512f "};
            for (size_t k = 0; k < sizeof wanted / sizeof wanted[0]; ++k) {
                if (strstr(line, wanted[k]) != NULL) {
                    strncat(extensions, wanted[k] + 1, strlen(wanted[k]) - 1);
                }
            }
        }
    }
    if (cpuinfo != NULL) {
        fclose(cpuinfo);
    }
}

/* The load average over the last minute (-1 where Linux does not say): the machines are
 * shared, and a figure measured at load 8 on 2 cores reads differently from one at load 1. */
static inline double bench_load_average(void)
{
    FILE *file = fopen("/proc/loadavg", "r");
    double load = -1.0;
    if (file != NULL && fscanf(file, "%lf", &load) != 1) {
        load = -1.0;
    }
    if (file != NULL) {
        fclose(file);
    }
    return load;
}

/* "NAME: processor MODEL; load average L" to stderr: what a figure was measured on. */
static inline void bench_print_machine(const char *name)
{
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "%s: processor %s; load average %.2f\n", name, model, bench_load_average());
}

#endif
