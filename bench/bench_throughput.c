/* Throughput: N free boxes under gravity, N from 1 to 100000, for every integrator.
 * The last column is the median wall time per body-step, which threads shorten
 * (rk4-2-threads against rk4); the CPU time of the process counts every thread.
 * Prints CSV: method, bodies, nanoseconds per body per step, nanoseconds per body per
 * derivative evaluation, bytes of memory per body (scene + integrator, measured with glibc's
 * mallinfo2), steps per run. Median CPU time of 7 runs of about 2e6 body-steps each (--quick:
 * one run of 2e4, for a smoke test of the output). Targets (docs/performance.md): RK4 <= 100 ns per
 * body-step at N = 1000, flat within 30% from N = 100 to 100000, <= 2 KB per body for every
 * integrator.
 *
 * Rows named rk4-whole-array and rk4-8-forces[-whole-array] compare, in the same run, RK4 a
 * chunk of bodies at a time (the default for bodies that do not interact) with RK4 over the
 * whole array, with gravity alone and with 8 single-body forces; cvode-adams-order-5 caps
 * Adams' order (and history) at 5; cvode-bdf-band uses the banded preconditioner instead of the
 * block-diagonal one.
 *
 * --path NAME steps the scenes on one vector path (tb_vector_path_name: none, baseline, avx2,
 * avx512; default auto, the widest the processor has), --threads T on T threads (default 1),
 * --sizes N1,N2,... only those body counts.
 *
 * usage: bench_throughput [--quick] [--method PREFIX] [--path NAME] [--threads T] [--sizes LIST]
 * (PREFIX: rows whose name starts so) */
#define _GNU_SOURCE /* mallinfo2 */
#include "bench_common.h"
#include "bench_scenes.h"
#include "tumble/tumble.h"

#include <malloc.h>
#include <stdio.h>
#include <string.h>

static tb_vector_path vector_path = TB_VECTOR_PATH_AUTO;
static int threads = 1;

static tb_scene *make_scene(size_t bodies, size_t forces, int drag, tb_vector_path path)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = bodies;
    tb_scene *scene = NULL;
    tb_scene_create(&def, &scene, NULL);
    tb_scene_set_vector_path(scene, path);
    bench_add_free_boxes(scene, bodies);
    if (drag) { /* linear and quadratic, on the motion and the spin */
        tb_drag_def def_drag = tb_drag_def_default();
        def_drag.linear = 0.1;
        def_drag.quadratic = 0.01;
        def_drag.angular = 0.01;
        def_drag.angular_quadratic = 0.001;
        tb_scene_add_drag(scene, &def_drag);
    }
    /* single-body effects, which every chunk of bodies looks at */
    for (size_t k = 0; k < forces && k < bodies; ++k) {
        tb_scene_add_force(scene, k, (double[]){1.0, 0, 0}, (double[]){0, 0, 0.05}, TB_FRAME_BODY);
    }
    return scene;
}

/* Bytes in use from malloc: the heap's and those of blocks big enough for glibc to map them
 * separately (uordblks alone misses the latter, most of a large scene's). */
static size_t allocated_bytes(void)
{
    const struct mallinfo2 info = mallinfo2();
    return info.uordblks + info.hblkhd;
}

/* What to measure: a method; for fixed-step methods, whether the integrator may step a chunk
 * of bodies at a time (the default for scenes whose bodies do not interact) or must step the
 * whole array, and how many single-body forces the scene holds besides gravity. */
typedef struct variant {
    const char *name;
    tb_method method;
    int whole_array; /* BDF: the banded preconditioner instead of the block-diagonal one */
    size_t forces;
    int max_order; /* 0: the method's own */
    int path;      /* -1: --path's (default auto), else a tb_vector_path */
    int threads;   /* 0: --threads' (default 1) */
    int drag;      /* drag on every body */
    int advance;   /* the steps in one tb_integrator_advance instead of one call each */
} variant;

typedef struct measurement {
    double ns_per_body_step, wall_ns_per_body_step, bytes_per_body;
    long steps;
} measurement;

static tb_integrator *make_integrator(tb_scene *scene, const variant *v)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = v->method;
    def.rtol = 1e-6;
    def.max_order = v->max_order;
    def.max_steps = 100000000;
    def.threads = tb_method_is_adaptive(v->method) ? 1 : v->threads > 0 ? v->threads : threads;
    tb_integrator *integrator = NULL;
    if (!v->whole_array) {
        tb_scene_integrator_create(scene, &def, 0.0, &integrator);
        return integrator;
    }
    tb_ode_system system;
    tb_scene_ode_system(scene, &system);
    system.blocks.size = 0;
    def.preconditioner_half_bandwidth = TB_STATE_SIZE - 1; /* as the scene would set */
    tb_integrator_create(&system, &def, 0.0, tb_scene_states(scene), &integrator, NULL);
    return integrator;
}

/* body_steps: about how many body-steps a run takes (2e6; fewer for a smoke run) */
static measurement measure(const variant *v, size_t bodies, int repeats, double body_steps)
{
    measurement m = {0};
    double times[15], walls[15];
    for (int r = 0; r < repeats; ++r) {
        const size_t before = allocated_bytes();
        tb_scene *scene = make_scene(bodies, v->forces, v->drag,
                                     v->path < 0 ? vector_path : (tb_vector_path)v->path);
        tb_integrator *integrator = make_integrator(scene, v);
        tb_integrator_advance(integrator, 1e-3); /* CVODE finishes its set-up here */
        m.bytes_per_body = (double)(allocated_bytes() - before) / (double)bodies;
        const long steps = (long)(body_steps / (double)bodies) + 10;
        const double t0 = bench_cpu_seconds(), w0 = bench_wall_seconds();
        if (v->advance) {
            tb_integrator_advance(integrator, tb_integrator_time(integrator) + (double)steps / 240);
        }
        for (long k = 0; k < steps && !v->advance; ++k) {
            tb_integrator_step(integrator);
        }
        times[r] = bench_cpu_seconds() - t0;
        walls[r] = bench_wall_seconds() - w0;
        m.steps = steps;
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    m.ns_per_body_step =
        1e9 * bench_median(times, (size_t)repeats) / (double)m.steps / (double)bodies;
    m.wall_ns_per_body_step =
        1e9 * bench_median(walls, (size_t)repeats) / (double)m.steps / (double)bodies;
    return m;
}

static double derivative_ns(size_t bodies, int repeats, double body_steps)
{
    tb_scene *scene = make_scene(bodies, 0, 0, vector_path);
    static double dydt_buffer[13 * 100000];
    double times[15];
    const long evaluations = (long)(2 * body_steps / (double)bodies) + 10;
    for (int r = 0; r < repeats; ++r) {
        const double t0 = bench_cpu_seconds();
        for (long k = 0; k < evaluations; ++k) {
            tb_scene_derivative(0.0, tb_scene_states(scene), dydt_buffer, scene);
        }
        times[r] = bench_cpu_seconds() - t0;
    }
    tb_scene_destroy(scene);
    return 1e9 * bench_median(times, (size_t)repeats) / (double)evaluations / (double)bodies;
}

/* "100,1000" into sizes (at most 16); the count read. */
static size_t parse_sizes(const char *list, size_t *sizes)
{
    size_t count = 0;
    for (const char *p = list; *p != '\0' && count < 16;) {
        char *end;
        const unsigned long long value = strtoull(p, &end, 10);
        if (end == p) {
            break;
        }
        sizes[count++] = (size_t)value;
        p = *end == ',' ? end + 1 : end;
    }
    return count;
}

int main(int argc, char **argv)
{
    int quick = 0;
    const char *only = NULL; /* one method, or all */
    size_t sizes[16] = {1, 10, 100, 1000, 10000, 100000}, count = 6, sizes_given = 0;
    for (int a = 1; a < argc; ++a) {
        if (strcmp(argv[a], "--quick") == 0) {
            quick = 1;
        } else if (strcmp(argv[a], "--method") == 0 && a + 1 < argc) {
            only = argv[++a];
        } else if (strcmp(argv[a], "--path") == 0 && a + 1 < argc &&
                   tb_vector_path_parse(argv[a + 1], &vector_path) == TB_STATUS_OK &&
                   tb_vector_path_supported(vector_path)) {
            ++a;
        } else if (strcmp(argv[a], "--threads") == 0 && a + 1 < argc) {
            threads = atoi(argv[++a]);
        } else if (strcmp(argv[a], "--sizes") == 0 && a + 1 < argc) {
            sizes_given = parse_sizes(argv[++a], sizes);
        } else {
            fprintf(stderr, "usage: bench_throughput [--quick] [--method PREFIX] [--path "
                            "none|baseline|avx2|avx512] [--threads T] [--sizes N1,N2,...]\n");
            return 2;
        }
    }
    const int repeats = quick ? 1 : 7;
    const double body_steps = quick ? 2e4 : 2e6;
    count = sizes_given > 0 ? sizes_given : quick ? 2 : count;
    variant variants[TB_METHOD_COUNT + 5 + TB_VECTOR_PATH_COUNT + 6];
    size_t variant_count = 0;
    for (int method = 0; method < TB_METHOD_COUNT; ++method) {
        variants[variant_count++] =
            (variant){tb_method_name((tb_method)method), (tb_method)method, 0, 0, 0, -1, 0, 0, 0};
    }
    /* the price of chunking, measured in the same run: RK4 over the whole array, and both
     * paths with 8 single-body forces */
    variants[variant_count++] = (variant){"rk4-whole-array", TB_METHOD_RK4, 1, 0, 0, -1, 0, 0, 0};
    variants[variant_count++] = (variant){"rk4-8-forces", TB_METHOD_RK4, 0, 8, 0, -1, 0, 0, 0};
    variants[variant_count++] =
        (variant){"rk4-8-forces-whole-array", TB_METHOD_RK4, 1, 8, 0, -1, 0, 0, 0};
    /* what CVODE's memory is made of: Adams' history of 13 vectors at order 12 against 6 at
     * order 5; BDF's banded preconditioner against the block-diagonal one */
    variants[variant_count++] =
        (variant){"cvode-adams-order-5", TB_METHOD_CVODE_ADAMS, 0, 0, 5, -1, 0, 0, 0};
    variants[variant_count++] =
        (variant){"cvode-bdf-band", TB_METHOD_CVODE_BDF, 1, 0, 0, -1, 0, 0, 0};
    /* RK4 on each vector path the processor has (rk4-advance-path-none: body by body, all in
     * one advance), on two threads, and with drag on every body */
    static char path_names[TB_VECTOR_PATH_COUNT][32];
    for (int p = TB_VECTOR_PATH_NONE; p < TB_VECTOR_PATH_COUNT; ++p) {
        if (tb_vector_path_supported((tb_vector_path)p)) {
            snprintf(path_names[p], sizeof path_names[p], "rk4-advance-path-%s",
                     tb_vector_path_name((tb_vector_path)p));
            variants[variant_count++] =
                (variant){path_names[p], TB_METHOD_RK4, 0, 0, 0, p, 0, 0, 1};
        }
    }
    variants[variant_count++] = (variant){"rk4-2-threads", TB_METHOD_RK4, 0, 0, 0, -1, 2, 0, 0};
    variants[variant_count++] = (variant){"rk4-drag", TB_METHOD_RK4, 0, 0, 0, -1, 0, 1, 0};
    /* the same steps in one advance: without the stability guard's pass over the bodies that
     * every call makes (rk4 against rk4-advance) */
    variants[variant_count++] = (variant){"rk4-advance", TB_METHOD_RK4, 0, 0, 0, -1, 0, 0, 1};
    variants[variant_count++] =
        (variant){"rk4-advance-2-threads", TB_METHOD_RK4, 0, 0, 0, -1, 2, 0, 1};
    variants[variant_count++] = (variant){"rk4-advance-drag", TB_METHOD_RK4, 0, 0, 0, -1, 0, 1, 1};
    printf("method,bodies,ns_per_body_step,derivative_ns_per_body,bytes_per_body,steps,"
           "wall_ns_per_body_step\n");
    for (size_t s = 0; s < count; ++s) {
        const double derivative = derivative_ns(sizes[s], repeats, body_steps);
        for (size_t k = 0; k < variant_count; ++k) {
            const variant *v = &variants[k];
            if (only != NULL && strncmp(only, v->name, strlen(only)) != 0) {
                continue;
            }
            const measurement m = measure(v, sizes[s], repeats, body_steps);
            printf("%s,%zu,%.1f,%.1f,%.0f,%ld,%.1f\n", v->name, sizes[s], m.ns_per_body_step,
                   derivative, m.bytes_per_body, m.steps, m.wall_ns_per_body_step);
            fflush(stdout);
        }
    }
    return 0;
}
