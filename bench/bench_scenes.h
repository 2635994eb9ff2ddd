/* Scenes more than one benchmark runs, so that their figures are about the same work. */
#ifndef TUMBLE_BENCH_SCENES_H
#define TUMBLE_BENCH_SCENES_H

#include "tumble/tumble.h"

/* The free boxes of the throughput and peer benchmarks: 0.1 x 0.2 x 0.3 m of 500 kg/m^3, 1 m
 * apart along x, thrown up at 3 m/s spinning at (1, 2, 0) rad/s, under gravity (z down). */
static const double bench_box_size[3] = {0.1, 0.2, 0.3};

static inline void bench_add_free_boxes(tb_scene *scene, size_t bodies)
{
    for (size_t i = 0; i < bodies; ++i) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_box(TB_MASS_DENSITY, 500.0, bench_box_size, &body.mass, NULL);
        body.position[0] = (double)i;
        body.velocity[2] = 3.0;
        body.angular_velocity[0] = 1.0;
        body.angular_velocity[1] = 2.0;
        tb_scene_add_body(scene, &body, NULL);
    }
    tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
}

#endif
