/* What one contact derivative costs, and whether a change kept the results (issue 23 item 7).
 * Runs four contact scenes under RK4 at their default step (tb_scene_default_step) from their
 * initial states for a short span and prints, per scene, the CPU seconds of the stepping per
 * simulated second (median of the repeats) and a checksum of the final states' bits (FNV-1a over
 * every body's 13 doubles), so that a change meant to make the derivative cheaper without
 * changing its value can be timed and checked bit for bit against the code before it:
 *   dice      examples/scenes/dice.json (twelve dice thrown onto a board), first 1 s;
 *   dominoes  examples/scenes/dominoes.json (a row of dominoes toppling), first 1 s;
 *   pile      the 200 boxes of bench_peer_contact's pile, dropped, first 0.25 s;
 *   spheres   the 1000 spheres of bench_peer_contact's spheres, first 0.01 s.
 * --quick: a tenth of each span (the pile 16 boxes, the spheres 27), one repeat.
 *
 * usage: bench_contact_work [--quick] [--case NAME] [--repeats N]
 * Prints CSV: case, bodies, step (s), steps, simulated s, CPU s per simulated s (median), the
 * checksum (16 hex digits). The processor and the load average go to stderr. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "bench_peer_cases.h"
#include "tumble/tumble.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_REPEATS 9
#define WORK_CASES 4

static const char *const work_names[WORK_CASES] = {"dice", "dominoes", "pile", "spheres"};
static const double work_spans[WORK_CASES] = {1.0, 1.0, 0.25, 0.01};

static tb_scene *work_scene(int k, int quick)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    switch (k) {
    case 0:
        tb_scene_load_file(BENCH_EXAMPLES "/dice.json", &scene, &run, NULL);
        return scene;
    case 1:
        tb_scene_load_file(BENCH_EXAMPLES "/dominoes.json", &scene, &run, NULL);
        return scene;
    case 2:
        return dropped_pile(quick ? 16 : 200);
    default:
        return bench_spheres_in_box(quick ? 27 : 1000, BENCH_ALL);
    }
}

/* FNV-1a over the bytes of every body's state. */
static uint64_t state_checksum(const tb_scene *scene)
{
    uint64_t hash = 1469598103934665603ull;
    for (size_t i = 0; i < tb_scene_body_count(scene); ++i) {
        tb_body_state s;
        tb_scene_get_state(scene, i, &s);
        const unsigned char *bytes = (const unsigned char *)&s;
        for (size_t b = 0; b < sizeof s; ++b) {
            hash = (hash ^ bytes[b]) * 1099511628211ull;
        }
    }
    return hash;
}

typedef struct work_run {
    double dt, seconds;
    long steps;
    uint64_t checksum;
    size_t bodies;
} work_run;

/* One run of case k over span; seconds < 0 when it failed. */
static work_run run_once(int k, int quick, double span)
{
    work_run r = {0.0, -1.0, 0, 0, 0};
    tb_scene *scene = work_scene(k, quick);
    tb_integrator *integrator = NULL;
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator_def_set_method(&def, TB_METHOD_RK4);
    def.max_steps = 100000000;
    if (scene == NULL || tb_scene_default_step(scene, TB_METHOD_RK4, &def.dt) != TB_STATUS_OK ||
        tb_scene_integrator_create(scene, &def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "bench_contact_work: %s: could not be set up\n", work_names[k]);
        tb_scene_destroy(scene);
        return r;
    }
    const double start = bench_cpu_seconds();
    const tb_status status = tb_integrator_advance(integrator, span);
    const double seconds = bench_cpu_seconds() - start;
    if (status == TB_STATUS_OK) {
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        r = (work_run){def.dt, seconds, (long)stats.steps, state_checksum(scene),
                       tb_scene_body_count(scene)};
    } else {
        fprintf(stderr, "bench_contact_work: %s: %s\n", work_names[k],
                tb_integrator_detail(integrator));
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return r;
}

static void run_case(int k, int quick, int repeats)
{
    const double span = quick ? 0.1 * work_spans[k] : work_spans[k];
    double per_second[MAX_REPEATS];
    work_run r = {0.0, -1.0, 0, 0, 0};
    for (int j = 0; j < repeats; ++j) {
        r = run_once(k, quick, span);
        if (r.seconds < 0.0) {
            return;
        }
        per_second[j] = r.seconds / span;
    }
    printf("%s,%zu,%.6g,%ld,%g,%.4g,%016llx\n", work_names[k], r.bodies, r.dt, r.steps, span,
           bench_median(per_second, (size_t)repeats), (unsigned long long)r.checksum);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    int quick = 0, repeats = 0, only = -1;
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--quick") == 0) {
            quick = 1;
        } else if (strcmp(argv[a], "--repeats") == 0 && a + 1 < argc) {
            repeats = atoi(argv[++a]);
        } else if (strcmp(argv[a], "--case") == 0 && a + 1 < argc) {
            ++a;
            for (int k = 0; k < WORK_CASES; ++k) {
                only = strcmp(argv[a], work_names[k]) == 0 ? k : only;
            }
        } else {
            fprintf(stderr, "usage: bench_contact_work [--quick] [--case NAME] [--repeats N]\n");
            return 2;
        }
    }
    repeats = repeats > 0 ? (repeats < MAX_REPEATS ? repeats : MAX_REPEATS) : (quick ? 1 : 3);
    char model[256], extensions[256];
    bench_processor(model, extensions);
    fprintf(stderr, "bench_contact_work: processor %s; load average %.2f\n", model,
            bench_load_average());
    printf("case,bodies,step,steps,span,cpu_per_simulated_s,checksum\n");
    for (int k = 0; k < WORK_CASES; ++k) {
        if (only < 0 || only == k) {
            run_case(k, quick, repeats);
        }
    }
    return 0;
}
