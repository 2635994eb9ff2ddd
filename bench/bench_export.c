/* What writing the frames costs on top of the integration: N boxes tumbling freely (no effect
 * couples them, so RK4 steps them a chunk at a time), run for T seconds at 60 fps with RK4 at
 * 1/240 s, with no output, then into each writer (.npz, .glb, .csv, and .npz to /dev/null). Median
 * of 5 runs each (the outputs taking turns): CPU seconds of this process (the writer's thread
 * included; the disk's own write-back is not in it), CPU seconds of the calling thread alone
 * (what the integration waits for when a core is free for the writer), and wall seconds.
 * bench_export [--quick] [OUTPUT...]   default N = 1000, T = 20 s, every output;
 * --quick N = 10, T = 1 s, 1 run; OUTPUTs (labels below) pick some ("none" always runs).
 * CSV on standard output:
 * output,bodies,frames,cpu_seconds,caller_cpu_seconds,wall_seconds,extra_cpu_percent,
 *   extra_caller_cpu_percent,extra_wall_percent,bytes
 * (extra_*_percent: time above the run without output, in percent of it). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"

#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static tb_scene *make_scene(size_t bodies)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = bodies;
    tb_scene *scene = NULL;
    tb_scene_create(&def, &scene, NULL);
    for (size_t k = 0; k < bodies; ++k) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_box(TB_MASS_DENSITY, 700, (double[]){0.1, 0.2, 0.4}, &body.mass, NULL);
        body.position[0] = (double)(k % 32);
        body.position[1] = (double)(k / 32);
        /* a spin off every principal axis, different for each body */
        body.angular_velocity[0] = 0.5 + 0.01 * (double)(k % 7);
        body.angular_velocity[1] = 1.0 + 0.02 * (double)(k % 5);
        body.angular_velocity[2] = 8.0;
        tb_scene_add_body(scene, &body, NULL);
    }
    return scene;
}

static int ignore(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)frame, (void)t, (void)scene, (void)ctx;
    return 0;
}

/* One run into path (NULL: no output); CPU and wall seconds. */
/* CPU seconds of the calling thread alone (the one that integrates). */
static double thread_cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int measure(size_t bodies, double duration, const char *path, tb_output_format format,
                   bool announce, double *cpu, double *caller, double *wall)
{
    tb_scene *scene = make_scene(bodies);
    tb_run_def run = tb_run_def_default(); /* RK4 at 1/240 s */
    run.fps = 60;
    run.duration = duration;
    tb_writer *writer = NULL;
    tb_writer_def def = tb_writer_def_default();
    const double cpu0 = bench_cpu_seconds(), wall0 = wall_seconds(), caller0 = thread_cpu_seconds();
    tb_error error = {0};
    int ok = 1;
    if (path != NULL) {
        def.format = format;
        size_t last = 0;
        tb_run_frame_count(run.duration, run.fps, &last, NULL);
        def.frame_count = announce ? last + 1 : 0; /* npz: streamed while the run goes on */
        ok = tb_writer_open(path, &def, scene, &writer, &error) == TB_STATUS_OK;
    }
    ok = ok && tb_scene_run(scene, &run, writer ? tb_writer_on_frame : ignore, writer, NULL,
                            &error) == TB_STATUS_OK;
    if (!ok && writer != NULL) {
        fprintf(stderr, "bench_export: %s\n", tb_writer_detail(writer));
        tb_writer_destroy(writer);
        writer = NULL;
    }
    ok = ok && (writer == NULL || tb_writer_close(writer, &error) == TB_STATUS_OK);
    if (!ok) {
        fprintf(stderr, "bench_export: %s\n", error.message);
    }
    *cpu = bench_cpu_seconds() - cpu0;
    *caller = thread_cpu_seconds() - caller0;
    *wall = wall_seconds() - wall0;
    tb_scene_destroy(scene);
    return ok;
}

/* Whether the output labelled label is asked for: every one when no label is given. */
static bool wanted(const char *label, int argc, char **argv, int first)
{
    for (int k = first; k < argc; ++k) {
        if (strcmp(argv[k], label) == 0) {
            return true;
        }
    }
    return first >= argc || strcmp(label, "none") == 0;
}

typedef struct output {
    const char *label, *extension; /* extension NULL: /dev/null (or no output, for "none") */
    tb_output_format format;
    bool announce; /* the frame count (npz streams) */
    double cpu[5], caller[5], wall[5];
    long long bytes;
} output;

/* Repeat r of every output asked for, one after the other (so a change of the machine's load
 * touches them all alike); 0 if a run failed. */
static int measure_round(output *outputs, size_t count, size_t bodies, double duration, size_t r,
                         int argc, char **argv, int first)
{
    const char *directory = getenv("TMPDIR") != NULL ? getenv("TMPDIR") : "/tmp";
    for (size_t o = 0; o < count; ++o) {
        output *out = &outputs[o];
        if (!wanted(out->label, argc, argv, first)) {
            continue;
        }
        char path[512] = "/dev/null";
        if (out->extension != NULL) {
            /* the process id: another bench_export at the same time writes its own file */
            snprintf(path, sizeof path, "%s/bench_export-%ld.%s", directory, (long)getpid(),
                     out->extension);
        }
        if (!measure(bodies, duration, o > 0 ? path : NULL, out->format, out->announce,
                     &out->cpu[r], &out->caller[r], &out->wall[r])) {
            fprintf(stderr, "bench_export: %s failed\n", path);
            return 0;
        }
        struct stat info;
        if (out->extension != NULL && stat(path, &info) == 0) {
            out->bytes = (long long)info.st_size;
            remove(path);
        }
    }
    return 1;
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const size_t bodies = quick ? 10 : 1000, repeats = quick ? 1 : 5;
    const double duration = quick ? 1.0 : 20.0;
    /* npz to /dev/null: what the library does (read-outs, blocks, CRC) without the kernel's
     * copy of the bytes into the page cache; npz-kept: without announcing the frame count, so
     * the frames are kept in memory and written at close */
    output outputs[] = {
        {.label = "none", .extension = NULL, .format = TB_OUTPUT_CSV, .announce = true},
        {.label = "npz-to-dev-null", .extension = NULL, .format = TB_OUTPUT_NPZ, .announce = true},
        {.label = "npz", .extension = "npz", .format = TB_OUTPUT_NPZ, .announce = true},
        {.label = "npz-kept", .extension = "npz", .format = TB_OUTPUT_NPZ, .announce = false},
        {.label = "glb", .extension = "glb", .format = TB_OUTPUT_GLB, .announce = true},
        {.label = "csv", .extension = "csv", .format = TB_OUTPUT_CSV, .announce = true}};
    const size_t count = sizeof outputs / sizeof outputs[0];
    for (size_t r = 0; r < repeats; ++r) {
        if (!measure_round(outputs, count, bodies, duration, r, argc, argv, quick ? 2 : 1)) {
            return 1;
        }
    }
    const double base_cpu = bench_median(outputs[0].cpu, repeats);
    const double base_caller = bench_median(outputs[0].caller, repeats);
    const double base_wall = bench_median(outputs[0].wall, repeats);
    printf("output,bodies,frames,cpu_seconds,caller_cpu_seconds,wall_seconds,extra_cpu_percent,"
           "extra_caller_cpu_percent,extra_wall_percent,bytes\n");
    for (size_t o = 0; o < count; ++o) {
        if (wanted(outputs[o].label, argc, argv, quick ? 2 : 1)) {
            const double c = bench_median(outputs[o].cpu, repeats);
            const double w = bench_median(outputs[o].wall, repeats);
            const double t = bench_median(outputs[o].caller, repeats);
            printf("%s,%zu,%.0f,%.4g,%.4g,%.4g,%.3g,%.3g,%.3g,%lld\n", outputs[o].label, bodies,
                   duration * 60 + 1, c, t, w, 100.0 * (c - base_cpu) / base_cpu,
                   100.0 * (t - base_caller) / base_caller, 100.0 * (w - base_wall) / base_wall,
                   outputs[o].bytes);
        }
    }
    return 0;
}
