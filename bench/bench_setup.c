/* What setting up a scene costs: n boxes added after a ground plane, then given 10 contact
 * points each, body by body (a program that builds its scene in that order; the scene file adds
 * its effects last). Prints CSV: the bodies, the points per body, and the median CPU seconds of
 * the whole set-up over 3 runs. Linear set-up doubles the seconds with the bodies; a cost per
 * body that grows with the points already held quadruples them.
 *
 * usage: bench_setup [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "tumble/tumble.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { POINTS = 10, RUNS = 3 };

static void check(tb_status status, const tb_scene *scene)
{
    if (status != TB_STATUS_OK) {
        fprintf(stderr, "bench_setup: %s\n", tb_scene_detail(scene));
        exit(1);
    }
}

/* CPU seconds to build the scene of n boxes 1 m apart, the ground first. */
static double set_up(size_t n)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    if (tb_scene_create(&def, &scene, NULL) != TB_STATUS_OK) {
        exit(1);
    }
    const double start = bench_cpu_seconds();
    tb_ground_def ground = tb_ground_def_default();
    check(tb_scene_add_ground(scene, &ground), scene);
    tb_contact_point points[POINTS];
    for (int k = 0; k < POINTS; ++k) { /* a 0.2 m box's corners and two face centres */
        for (int i = 0; i < 3; ++i) {
            points[k].position[i] = k < 8 ? ((k >> i) & 1 ? 0.1 : -0.1) : 0.0;
        }
        points[k].position[2] = k < 8 ? points[k].position[2] : (k == 8 ? 0.1 : -0.1);
        points[k].radius = 0.0;
    }
    for (size_t b = 0; b < n; ++b) {
        tb_body_def body = tb_body_def_default();
        check(
            tb_mass_from_box(TB_MASS_GIVEN, 1.0, (const double[]){0.2, 0.2, 0.2}, &body.mass, NULL),
            scene);
        body.position[0] = (double)b;
        body.position[2] = 0.5;
        size_t id;
        check(tb_scene_add_body(scene, &body, &id), scene);
        check(tb_scene_set_contact_points(scene, id, points, POINTS, 4), scene);
    }
    const double seconds = bench_cpu_seconds() - start;
    tb_scene_destroy(scene);
    return seconds;
}

int main(int argc, char **argv)
{
    const bool quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const size_t full[] = {1000, 2000, 4000, 8000}, brief[] = {100};
    const size_t *counts = quick ? brief : full;
    const size_t count = quick ? 1 : sizeof full / sizeof full[0];
    printf("bodies,points_per_body,seconds\n");
    for (size_t c = 0; c < count; ++c) {
        double seconds[RUNS];
        for (int r = 0; r < RUNS; ++r) {
            seconds[r] = set_up(counts[c]);
        }
        printf("%zu,%d,%.4g\n", counts[c], POINTS, bench_median(seconds, RUNS));
    }
    return 0;
}
