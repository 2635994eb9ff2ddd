/* The C side of bindings/python/bench/bench_frames.py: a scene file loaded and run with every
 * frame kept in memory as the Python package keeps it (tb_scene_frame_values into one block
 * allocated for the run, plus the totals: energies, momenta, centre of mass), so that the
 * two times compare the same work. Prints CSV: api,bodies,frames,median_ms (CPU time, the median
 * of the repeats; each repeat loads the scene from its text, runs it and frees it). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"

#include "tumble/tumble.h"

#include <stdio.h>
#include <string.h>

typedef struct memory {
    size_t bodies;
    double *t, *values, *totals; /* per frame: 1, 13 per body, 11 */
    const double *mass_fraction;
} memory;

static int keep_frame(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    memory *m = ctx;
    const double *y = tb_scene_states_const(scene);
    double *totals = m->totals + 11 * frame, origin[3] = {0, 0, 0};
    m->t[frame] = t;
    tb_scene_frame_values(scene, y, m->values + frame * m->bodies * TB_FRAME_VALUES);
    tb_scene_kinetic_energy(scene, y, &totals[0]);
    tb_scene_potential_energy(scene, y, &totals[1]);
    tb_scene_linear_momentum(scene, y, totals + 2);
    tb_scene_angular_momentum(scene, y, origin, totals + 5);
    totals[8] = totals[9] = totals[10] = 0.0;
    for (size_t i = 0; i < m->bodies; ++i) {
        for (int k = 0; k < 3; ++k) {
            totals[8 + k] += m->mass_fraction[i] * y[TB_STATE_SIZE * i + k];
        }
    }
    return 0;
}

static char *read_text(const char *path)
{
    FILE *file = fopen(path, "rb");
    if (file == NULL) {
        return NULL;
    }
    fseek(file, 0, SEEK_END);
    const long size = ftell(file);
    fseek(file, 0, SEEK_SET);
    char *text = malloc((size_t)size + 1);
    if (text != NULL && fread(text, 1, (size_t)size, file) == (size_t)size) {
        text[size] = '\0';
    }
    fclose(file);
    return text;
}

/* One repeat: CPU seconds for load, the frames' memory, run and free, or -1 on failure. The
 * frames are allocated for each run, as Scene.run allocates them: a reused buffer would spare
 * C the first touch of every page that Python pays. */
static double timed_run(const char *text, memory *m, size_t *out_frames)
{
    const double start = bench_cpu_seconds();
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_string(text, "bench", NULL, &scene, &run, &error) != TB_STATUS_OK) {
        fprintf(stderr, "bench_frames_in_memory: %s\n", error.message);
        return -1.0;
    }
    tb_run_frame_count(run.duration, run.fps, out_frames, NULL);
    *out_frames += 1;
    m->bodies = tb_scene_body_count(scene);
    m->t = malloc(*out_frames * sizeof(double));
    m->values = malloc(*out_frames * m->bodies * TB_FRAME_VALUES * sizeof(double));
    m->totals = malloc(*out_frames * 11 * sizeof(double));
    tb_status status = TB_STATUS_OUT_OF_MEMORY;
    if (m->t != NULL && m->values != NULL && m->totals != NULL) {
        status = tb_scene_run(scene, &run, keep_frame, m, NULL, &error);
    }
    tb_scene_destroy(scene);
    free(m->t), free(m->values), free(m->totals);
    if (status != TB_STATUS_OK) {
        fprintf(stderr, "bench_frames_in_memory: %s\n", tb_status_string(status));
        return -1.0;
    }
    return bench_cpu_seconds() - start;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_frames_in_memory SCENE.json [REPEATS]\n");
        return 2;
    }
    const int repeats = argc > 2 ? atoi(argv[2]) : 7;
    char *text = read_text(argv[1]);
    tb_scene *scene = NULL;
    tb_run_def run;
    if (text == NULL || repeats < 1 || repeats > 1000 ||
        tb_scene_load_string(text, "bench", NULL, &scene, &run, NULL) != TB_STATUS_OK) {
        fprintf(stderr, "bench_frames_in_memory: cannot load %s\n", argv[1]);
        return 2;
    }
    size_t frames = 0;
    tb_run_frame_count(run.duration, run.fps, &frames, NULL);
    frames += 1;
    const size_t bodies = tb_scene_body_count(scene);
    double *fraction = malloc(bodies * sizeof(double)), total = 0.0;
    for (size_t i = 0; i < bodies; ++i) {
        tb_mass_properties mass;
        tb_scene_get_mass(scene, i, &mass);
        fraction[i] = mass.mass;
        total += mass.mass;
    }
    for (size_t i = 0; i < bodies; ++i) {
        fraction[i] /= total;
    }
    tb_scene_destroy(scene);
    memory m = {bodies, NULL, NULL, NULL, fraction};
    double *seconds = malloc((size_t)repeats * sizeof(double));
    for (int r = 0; r < repeats; ++r) {
        seconds[r] = timed_run(text, &m, &frames);
        if (seconds[r] < 0) {
            return 1;
        }
    }
    printf("api,bodies,frames,median_ms\nc,%zu,%zu,%.3f\n", bodies, frames,
           1e3 * bench_median(seconds, (size_t)repeats));
    free(seconds), free(fraction), free(text);
    return 0;
}
