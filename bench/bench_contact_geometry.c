/* What finding contacts costs as bodies are added: N bodies (spheres, capsules, boxes, in
 * turn; 5 cm across) scattered in a layer 0.3 m deep at a fixed density (a pile's, each body a
 * few neighbours), from 100 to 10 000. One pass is what a contact effect does each derivative:
 * bounds and sort (begin), then the sweep with the narrow phase on each candidate. Also the
 * brute-force check of every pair's bounds (N (N - 1) / 2) up to 3000 bodies, for the scaling
 * it avoids. Prints CSV: bodies, candidate pairs, touching pairs, and the median nanoseconds
 * per body of: begin (bounds + sort), the sweep alone (the broad phase's pairs without the
 * narrow phase), the whole pass (begin + sweep + narrow), the brute-force bounds check (0 where
 * not run). A second pass after every body moved slightly is what a step
 * sees: the sort starts nearly sorted.
 *
 * With --hull: what a convex hull costs (every mesh body gets one at load), for 1e4, 1e5 and
 * 1e6 points on a sphere (all of them vertices: the worst case) and in a ball (few vertices).
 * Prints CSV: the point set, points, hull vertices, CPU seconds (the median of 3; 1 for 1e6).
 *
 * usage: bench_contact_geometry [--hull] [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "contact/contact_pairs.h"
#include "contact/convex_hull.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double uniform(unsigned long long *state, double low, double high)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return low + (high - low) * (double)(*state >> 11) * 0x1.0p-53;
}

static tb_scene *scattered(size_t count)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = count;
    tb_scene *scene = NULL;
    if (tb_scene_create(&def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    /* 0.3 m deep, one body per 10 cm x 10 cm x 10 cm on average */
    const double side = sqrt((double)count * 1e-3 / 0.3);
    unsigned long long rng = 7;
    for (size_t i = 0; i < count; ++i) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_sphere(TB_MASS_GIVEN, 0.1, 0.025, &body.mass, NULL);
        body.position[0] = uniform(&rng, 0, side);
        body.position[1] = uniform(&rng, 0, side);
        body.position[2] = uniform(&rng, 0, 0.3);
        const double q[4] = {uniform(&rng, -1, 1), uniform(&rng, -1, 1), uniform(&rng, -1, 1),
                             uniform(&rng, -1, 1)};
        const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int k = 0; k < 4; ++k) {
            body.orientation[k] = q[k] / n;
        }
        tb_scene_add_body(scene, &body, NULL);
        tb_shape s = tb_shape_default();
        s.type = i % 3 == 0 ? TB_SHAPE_SPHERE : i % 3 == 1 ? TB_SHAPE_CAPSULE : TB_SHAPE_BOX;
        s.radius = 0.025;
        s.length = 0.03;
        s.size[0] = s.size[1] = s.size[2] = 0.05;
        tb_scene_set_body_shape(scene, i, &s);
    }
    return scene;
}

typedef struct pass_result {
    size_t candidates, touching;
    double begin_seconds, pass_seconds;
} pass_result;

static pass_result one_pass(tb__contact_pairs *pairs, const tb_scene *scene, const double *y)
{
    pass_result r = {0};
    tb__pair_contact out[64];
    const double t0 = bench_cpu_seconds();
    tb__contact_pairs_begin(pairs, scene, tb_scene_time(scene), y);
    const double t1 = bench_cpu_seconds();
    size_t n;
    while ((n = tb__contact_pairs_next(pairs, scene, y, out, 64)) > 0) {
        r.touching += n;
    }
    r.pass_seconds = bench_cpu_seconds() - t0;
    r.begin_seconds = t1 - t0;
    return r;
}

/* Candidates: the broad phase alone (sort and sweep, without the narrow phase), and the
 * sweep's time in *sweep_seconds (the sort starts from the order of the last call). */
static size_t candidates(tb__broad_phase *bp_in, const tb_scene *scene, const double *y,
                         size_t count, double *sweep_seconds)
{
    tb__broad_phase bp = *bp_in;
    size_t boxes = 0;
    for (size_t i = 0; i < count; ++i) {
        double low[3], high[3];
        tb_scene_body_shape_bounds(scene, y, i, low, high);
        for (int k = 0; k < 3; ++k) {
            bp.boxes[boxes].min[k] = low[k] - 0.005;
            bp.boxes[boxes].max[k] = high[k] + 0.005;
        }
        ++boxes;
    }
    tb__broad_phase_sort(&bp, boxes);
    tb__index_pair batch[256];
    size_t total = 0, n;
    const double t0 = bench_cpu_seconds();
    while ((n = tb__broad_phase_next(&bp, batch, 256)) > 0) {
        total += n;
    }
    *sweep_seconds = bench_cpu_seconds() - t0;
    *bp_in = bp;
    return total;
}

static double brute_force_seconds(const tb_scene *scene, const double *y, size_t count)
{
    double(*bounds)[6] = malloc(count * sizeof *bounds);
    if (bounds == NULL) {
        return 0.0;
    }
    for (size_t i = 0; i < count; ++i) {
        tb_scene_body_shape_bounds(scene, y, i, bounds[i], bounds[i] + 3);
    }
    const double t0 = bench_cpu_seconds();
    volatile size_t found = 0;
    for (size_t i = 0; i < count; ++i) {
        for (size_t j = i + 1; j < count; ++j) {
            int overlap = 1;
            for (int k = 0; k < 3; ++k) {
                overlap &= bounds[i][3 + k] >= bounds[j][k] && bounds[j][3 + k] >= bounds[i][k];
            }
            found += (size_t)overlap;
        }
    }
    const double seconds = bench_cpu_seconds() - t0;
    (void)found; /* volatile: the loop cannot be optimised away */
    free(bounds);
    return seconds;
}

static void measure(size_t count, int repeats)
{
    tb_scene *scene = scattered(count);
    tb__contact_pairs *pairs = NULL;
    if (scene == NULL ||
        tb__contact_pairs_create(scene, NULL, 0, 0.01, &pairs, NULL) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return;
    }
    double *y = tb_scene_states(scene);
    double begin[64], pass[64], brute[64], sweep[64];
    size_t c = 0;
    tb__broad_phase bp;
    if (tb__broad_phase_init(&bp, count) != TB_STATUS_OK) {
        tb__contact_pairs_destroy(pairs);
        tb_scene_destroy(scene);
        return;
    }
    pass_result r = one_pass(pairs, scene, y); /* the first sort starts from any order */
    unsigned long long rng = 11;
    for (int k = 0; k < repeats; ++k) {
        for (size_t i = 0; i < count; ++i) { /* every body moves up to 1 mm, as in a step */
            y[TB_STATE_SIZE * i] += uniform(&rng, -1e-3, 1e-3);
        }
        r = one_pass(pairs, scene, y);
        begin[k] = r.begin_seconds;
        pass[k] = r.pass_seconds;
        brute[k] = count <= 3000 && k < 5 ? brute_force_seconds(scene, y, count) : 0.0;
        c = candidates(&bp, scene, y, count, &sweep[k]);
    }
    tb__broad_phase_free(&bp);
    const double per_body = 1e9 / (double)count;
    printf("%zu,%zu,%zu,%.4g,%.4g,%.4g,%.4g\n", count, c, r.touching,
           per_body * bench_median(begin, (size_t)repeats),
           per_body * bench_median(sweep, (size_t)repeats),
           per_body * bench_median(pass, (size_t)repeats),
           per_body * bench_median(brute, (size_t)(repeats < 5 ? repeats : 5)));
    tb__contact_pairs_destroy(pairs);
    tb_scene_destroy(scene);
}

/* n points on the unit sphere (the Fibonacci lattice) or uniform in the unit ball. */
static void hull_points(bool on_sphere, size_t n, double *points)
{
    unsigned long long rng = 11;
    for (size_t i = 0; i < n; ++i) {
        double *x = points + 3 * i;
        if (on_sphere) {
            const double z = 1.0 - (2.0 * (double)i + 1.0) / (double)n, r = sqrt(1.0 - z * z);
            x[0] = r * cos(2.399963229728653 * (double)i);
            x[1] = r * sin(2.399963229728653 * (double)i);
            x[2] = z;
            continue;
        }
        do {
            for (int k = 0; k < 3; ++k) {
                x[k] = uniform(&rng, -1, 1);
            }
        } while (x[0] * x[0] + x[1] * x[1] + x[2] * x[2] > 1.0);
    }
}

static void measure_hull(bool on_sphere, size_t n, int repeats)
{
    double *points = malloc(3 * n * sizeof *points);
    unsigned char *on_hull = malloc(n);
    double seconds[3];
    size_t vertices = 0;
    char detail[TB_DETAIL_SIZE];
    if (points == NULL || on_hull == NULL) {
        fprintf(stderr, "bench_contact_geometry: out of memory for %zu points\n", n);
        exit(1);
    }
    hull_points(on_sphere, n, points);
    for (int r = 0; r < repeats; ++r) {
        const double start = bench_cpu_seconds();
        if (tb__convex_hull(points, n, on_hull, detail) != TB_STATUS_OK) {
            fprintf(stderr, "bench_contact_geometry: %s\n", detail);
            exit(1);
        }
        seconds[r] = bench_cpu_seconds() - start;
    }
    for (size_t i = 0; i < n; ++i) {
        vertices += on_hull[i];
    }
    printf("%s,%zu,%zu,%.4g\n", on_sphere ? "sphere" : "ball", n, vertices,
           bench_median(seconds, (size_t)repeats));
    free(points);
    free(on_hull);
}

static int hull_table(bool quick)
{
    printf("points_on,points,hull_vertices,cpu_seconds\n");
    static const size_t sizes[] = {10000, 100000, 1000000};
    for (int shape = 0; shape < 2; ++shape) {
        for (size_t k = 0; k < (quick ? 1 : 3); ++k) {
            measure_hull(shape == 0, sizes[k], sizes[k] < 1000000 ? 3 : 1);
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    int quick = 0, hull = 0;
    for (int k = 1; k < argc; ++k) {
        quick |= strcmp(argv[k], "--quick") == 0;
        hull |= strcmp(argv[k], "--hull") == 0;
    }
    if (hull) {
        return hull_table(quick);
    }
    printf("bodies,candidates,touching,begin_ns_per_body,sweep_ns_per_body,pass_ns_per_body,"
           "brute_force_ns_per_body\n");
    static const size_t full[] = {100, 300, 1000, 3000, 10000};
    static const size_t brief[] = {100, 1000};
    const size_t *sizes = quick ? brief : full;
    const size_t n = quick ? 2 : 5;
    for (size_t k = 0; k < n; ++k) {
        measure(sizes[k], quick ? 3 : 21);
    }
    return 0;
}
