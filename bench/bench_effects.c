/* What each effect costs in the derivative, and that an effect a scene lacks costs nothing.
 * 1000 boxes (8 contact points each); the derivative is timed as effects are added one by one,
 * plus a scene whose only extra effect acts on one body of the thousand. Prints CSV: the
 * scene, and the median nanoseconds per body per derivative evaluation over repeated runs.
 *
 * usage: bench_effects [--quick] */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "bench_common.h"
#include "tumble/tumble.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { GRAVITY = 1, DRAG = 2, SPRINGS = 4, FORCES = 8, GROUND = 16, USER = 32, DRAG_ONE = 64 };

static int user_push(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    const double up[3] = {0, 0, 1.0};
    for (size_t i = 0; i < tb_scene_body_count(scene); ++i) {
        tb_effect_add_force(scene, y, dydt, i, up, y + TB_STATE_SIZE * i);
    }
    return 0;
}

static void add_effects(tb_scene *scene, int bodies, int effects)
{
    if (effects & GRAVITY) {
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    }
    if (effects & (DRAG | DRAG_ONE)) {
        tb_drag_def drag = tb_drag_def_default();
        drag.linear = 0.1;
        drag.angular = 0.01;
        drag.body = effects & DRAG_ONE ? 0 : TB_ALL_BODIES;
        tb_scene_add_drag(scene, &drag);
    }
    for (int i = 1; (effects & SPRINGS) && i < bodies; ++i) {
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = (size_t)i;
        spring.body_b = (size_t)(i - 1);
        spring.stiffness = 100.0;
        spring.damping = 1.0;
        spring.rest_length = 1.0;
        tb_scene_add_spring(scene, &spring);
    }
    for (int i = 0; (effects & FORCES) && i < bodies; ++i) {
        tb_scene_add_force(scene, (size_t)i, (double[]){1, 0, 0}, (double[]){0, 0.1, 0},
                           TB_FRAME_BODY);
    }
    if (effects & GROUND) {
        tb_ground_def ground = tb_ground_def_default();
        if (tb_scene_add_ground(scene, &ground) != TB_STATUS_OK) {
            fprintf(stderr, "bench_effects: %s\n", tb_scene_detail(scene));
            exit(1);
        }
    }
    if (effects & USER) {
        tb_scene_add_user_effect(scene, user_push, NULL);
    }
}

static tb_scene *make_scene(int bodies, int effects)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = (size_t)bodies;
    tb_scene *scene = NULL;
    tb_scene_create(&def, &scene, NULL);
    const double size[3] = {0.2, 0.3, 0.4};
    tb_contact_point corners[8];
    size_t count;
    tb_contact_points_box(size, corners, 8, &count);
    for (int i = 0; i < bodies; ++i) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_box(TB_MASS_DENSITY, 500.0, size, &body.mass, NULL);
        body.position[0] = i;
        /* resting on the ground, sunk by its penetration: every corner below is in contact */
        body.position[2] = 0.2 - tb_ground_def_default().penetration;
        body.angular_velocity[2] = 0.5;
        tb_scene_add_body(scene, &body, NULL);
        tb_scene_set_contact_points(scene, (size_t)i, corners, count, 4);
    }
    add_effects(scene, bodies, effects);
    return scene;
}

/* Median ns per body per derivative evaluation. */
static double time_derivative(int bodies, int effects, int repeats, int evaluations)
{
    tb_scene *scene = make_scene(bodies, effects);
    const size_t n = tb_scene_state_size(scene);
    double *dydt = malloc(n * sizeof(double));
    double times[15];
    for (int r = 0; r < repeats; ++r) {
        const double start = bench_cpu_seconds();
        for (int k = 0; k < evaluations; ++k) {
            tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene);
        }
        times[r] = (bench_cpu_seconds() - start) / evaluations / bodies * 1e9;
    }
    free(dydt);
    tb_scene_destroy(scene);
    return bench_median(times, (size_t)repeats);
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && strcmp(argv[1], "--quick") == 0;
    const int bodies = quick ? 10 : 1000, repeats = quick ? 1 : 15;
    const int evaluations = quick ? 10 : 2000;
    static const struct {
        const char *name;
        int effects;
    } scenes[] = {
        {"no_effects", 0},
        {"gravity", GRAVITY},
        {"gravity+drag_on_one_body", GRAVITY | DRAG_ONE},
        {"gravity+drag", GRAVITY | DRAG},
        {"gravity+drag+springs", GRAVITY | DRAG | SPRINGS},
        {"gravity+drag+springs+forces", GRAVITY | DRAG | SPRINGS | FORCES},
        {"gravity+drag+springs+forces+ground", GRAVITY | DRAG | SPRINGS | FORCES | GROUND},
        {"gravity+user", GRAVITY | USER},
    };
    printf("scene,ns_per_body_per_derivative\n");
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; ++k) {
        printf("%s,%.2f\n", scenes[k].name,
               time_derivative(bodies, scenes[k].effects, repeats, evaluations));
        fflush(stdout);
    }
    return 0;
}
