/* What writing the frames costs on top of the integration: N boxes tumbling freely (no effect
 * couples them, so RK4 steps them a chunk at a time), run for T seconds at 60 fps with RK4 at
 * 1/240 s, with no output, then into each writer (.npz, .glb, .csv, and .npz to /dev/null). Median
 * of 3 runs each, CPU seconds of this process (the disk's own write-back is not in it) and wall
 * seconds. bench_export [--quick] [OUTPUT...]   default N = 1000, T = 20 s, every output;
 * --quick N = 10, T = 1 s, 1 run; OUTPUTs (labels below) pick some ("none" always runs).
 * CSV on standard output: output,bodies,frames,cpu_seconds,wall_seconds,extra_cpu_percent,bytes
 * (extra_cpu_percent: CPU time above the run without output, in percent of it). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"

#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

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
static int measure(size_t bodies, double duration, const char *path, tb_output_format format,
                   double *cpu, double *wall)
{
    tb_scene *scene = make_scene(bodies);
    tb_run_def run = tb_run_def_default(); /* RK4 at 1/240 s */
    run.fps = 60;
    run.duration = duration;
    tb_writer *writer = NULL;
    tb_writer_def def = tb_writer_def_default();
    const double cpu0 = bench_cpu_seconds(), wall0 = wall_seconds();
    int ok = 1;
    if (path != NULL) {
        def.format = format;
        size_t last = 0;
        tb_run_frame_count(run.duration, run.fps, &last, NULL);
        def.frame_count = last + 1; /* npz: streamed while the run goes on */
        ok = tb_writer_open(path, &def, scene, &writer, NULL) == TB_STATUS_OK;
    }
    ok = ok && tb_scene_run(scene, &run, writer ? tb_writer_on_frame : ignore, writer, NULL,
                            NULL) == TB_STATUS_OK;
    ok = ok && (writer == NULL || tb_writer_close(writer, NULL) == TB_STATUS_OK);
    *cpu = bench_cpu_seconds() - cpu0;
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

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const size_t bodies = quick ? 10 : 1000, repeats = quick ? 1 : 3;
    const double duration = quick ? 1.0 : 20.0;
    const char *directory = getenv("TMPDIR") != NULL ? getenv("TMPDIR") : "/tmp";
    /* npz to /dev/null: what the library does (read-outs, buffers, CRC) without the kernel's
     * copy of the bytes into the page cache */
    const struct {
        const char *label, *extension;
        tb_output_format format;
    } outputs[] = {{"none", NULL, TB_OUTPUT_CSV},
                   {"npz-to-dev-null", NULL, TB_OUTPUT_NPZ},
                   {"npz", "npz", TB_OUTPUT_NPZ},
                   {"glb", "glb", TB_OUTPUT_GLB},
                   {"csv", "csv", TB_OUTPUT_CSV}};
    double base = 0;
    printf("output,bodies,frames,cpu_seconds,wall_seconds,extra_cpu_percent,bytes\n");
    for (size_t o = 0; o < sizeof outputs / sizeof outputs[0]; ++o) {
        if (!wanted(outputs[o].label, argc, argv, quick ? 2 : 1)) {
            continue;
        }
        char path[512];
        if (outputs[o].extension != NULL) {
            snprintf(path, sizeof path, "%s/bench_export.%s", directory, outputs[o].extension);
        } else {
            snprintf(path, sizeof path, "/dev/null");
        }
        const char *target = o > 0 ? path : NULL;
        double cpu[3], wall[3];
        for (size_t r = 0; r < repeats; ++r) {
            if (!measure(bodies, duration, target, outputs[o].format, &cpu[r], &wall[r])) {
                fprintf(stderr, "bench_export: %s failed\n", path);
                return 1;
            }
        }
        struct stat info;
        const bool file = outputs[o].extension != NULL;
        const long long bytes = file && stat(path, &info) == 0 ? (long long)info.st_size : 0;
        if (file) {
            remove(path);
        }
        const double c = bench_median(cpu, repeats), w = bench_median(wall, repeats);
        base = o == 0 ? c : base;
        printf("%s,%zu,%.0f,%.4g,%.4g,%.3g,%lld\n", outputs[o].label, bodies, duration * 60 + 1, c,
               w, 100.0 * (c - base) / base, bytes);
    }
    return 0;
}
