/* Scenes more than one benchmark runs, so that their figures are about the same work. */
#ifndef TUMBLE_BENCH_SCENES_H
#define TUMBLE_BENCH_SCENES_H

#include "tumble/tumble.h"

#include <math.h>

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

/* --- contact scenes (bench_contact, bench_peer_contact) ------------------------------------
 * Which effects a contact scene gets: its bodies always (with shapes and contact points), then
 * gravity, the ground planes and contact between bodies as asked. Dropping the last ones gives
 * the twin scenes the benchmarks subtract to find each part's share of a derivative. */
enum { BENCH_GRAVITY = 1, BENCH_GROUND = 2, BENCH_CONTACT = 4, BENCH_ALL = 7 };

/* Spheres 5 cm across (radius 0.025 m) of 1000 kg/m^3 (65.4 g), packed touching in a simple
 * cubic lattice in a box of five ground planes (floor z = 0 and four walls, each touched by the
 * outer spheres), side x side columns, layer over layer until count, each given a velocity of up
 * to 0.2 m/s per component (seeded): a poured box still jostling. */
#define BENCH_SPHERE_RADIUS 0.025
#define BENCH_SPHERE_DENSITY 1000.0

static inline double bench_uniform(unsigned long long *state, double low, double high)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return low + (high - low) * (double)(*state >> 11) * 0x1.0p-53;
}

/* Columns per side: about the cube root of count (at least 1). */
static inline size_t bench_sphere_side(size_t count)
{
    size_t side = (size_t)ceil(cbrt((double)count) - 1e-9);
    return side > 0 ? side : 1;
}

/* The five planes around the lattice of bench_spheres_in_box: inward normals. */
static inline void bench_add_box_planes(tb_scene *scene, double width)
{
    static const double normals[5][3] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    const double offsets[5] = {0.0, 0.0, -width, 0.0, -width};
    for (int k = 0; k < 5; ++k) {
        tb_ground_def ground = tb_ground_def_default();
        for (int j = 0; j < 3; ++j) {
            ground.normal[j] = normals[k][j];
        }
        ground.offset = offsets[k];
        tb_scene_add_ground(scene, &ground);
    }
}

static inline tb_scene *bench_spheres_in_box(size_t count, int effects)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = count;
    tb_scene *scene = NULL;
    if (tb_scene_create(&def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    const double r = BENCH_SPHERE_RADIUS;
    const size_t side = bench_sphere_side(count);
    unsigned long long rng = 12;
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = r;
    tb_contact_point point;
    size_t points = 0;
    tb_contact_points_sphere(r, &point, 1, &points);
    for (size_t i = 0; i < count; ++i) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_sphere(TB_MASS_DENSITY, BENCH_SPHERE_DENSITY, r, &body.mass, NULL);
        body.position[0] = r + 2.0 * r * (double)(i % side);
        body.position[1] = r + 2.0 * r * (double)(i / side % side);
        body.position[2] = r + 2.0 * r * (double)(i / (side * side));
        for (int k = 0; k < 3; ++k) {
            body.velocity[k] = bench_uniform(&rng, -0.2, 0.2);
        }
        tb_scene_add_body(scene, &body, NULL);
        tb_scene_set_body_shape(scene, i, &shape);
        tb_scene_set_contact_points(scene, i, &point, points, 1);
    }
    if (effects & BENCH_GRAVITY) {
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    }
    if (effects & BENCH_GROUND) {
        bench_add_box_planes(scene, 2.0 * r * (double)side);
    }
    if (effects & BENCH_CONTACT) {
        tb_contact_def contact = tb_contact_def_default();
        tb_scene_add_contact(scene, &contact);
    }
    return scene;
}

/* Boxes piled: 10 cm cubes of 500 kg/m^3 (0.5 kg) in columns BENCH_PILE_HEIGHT high, each box
 * resting exactly on the one below (no gap, no overlap) and the lowest on the floor z = 0, the
 * columns on a square grid 1 cm apart, released at rest: the pile settles into its static
 * sinking. MuJoCo's pile (bench_peer_contact) is built from the same positions. */
#define BENCH_PILE_EDGE 0.1
#define BENCH_PILE_DENSITY 500.0
#define BENCH_PILE_HEIGHT 8
#define BENCH_PILE_GAP 0.01

static inline void bench_pile_position(size_t i, size_t count, double out[3])
{
    const size_t columns = (count + BENCH_PILE_HEIGHT - 1) / BENCH_PILE_HEIGHT;
    size_t side = (size_t)ceil(sqrt((double)columns) - 1e-9);
    side = side > 0 ? side : 1;
    const size_t column = i / BENCH_PILE_HEIGHT, level = i % BENCH_PILE_HEIGHT;
    const double pitch = BENCH_PILE_EDGE + BENCH_PILE_GAP;
    out[0] = pitch * (double)(column % side);
    out[1] = pitch * (double)(column / side);
    out[2] = BENCH_PILE_EDGE * (0.5 + (double)level);
}

/* Box i rests on box i - 1 (0 when it stands on the floor). */
static inline int bench_pile_on_box(size_t i)
{
    return i % BENCH_PILE_HEIGHT != 0;
}

static inline tb_scene *bench_box_pile(size_t count, int effects)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = count;
    tb_scene *scene = NULL;
    if (tb_scene_create(&def, &scene, NULL) != TB_STATUS_OK) {
        return NULL;
    }
    const double size[3] = {BENCH_PILE_EDGE, BENCH_PILE_EDGE, BENCH_PILE_EDGE};
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    for (int k = 0; k < 3; ++k) {
        shape.size[k] = size[k];
    }
    tb_contact_point corners[8];
    size_t points = 0;
    tb_contact_points_box(size, corners, 8, &points);
    for (size_t i = 0; i < count; ++i) {
        tb_body_def body = tb_body_def_default();
        tb_mass_from_box(TB_MASS_DENSITY, BENCH_PILE_DENSITY, size, &body.mass, NULL);
        bench_pile_position(i, count, body.position);
        tb_scene_add_body(scene, &body, NULL);
        tb_scene_set_body_shape(scene, i, &shape);
        tb_scene_set_contact_points(scene, i, corners, points, 4);
    }
    if (effects & BENCH_GRAVITY) {
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    }
    if (effects & BENCH_GROUND) {
        tb_ground_def ground = tb_ground_def_default();
        tb_scene_add_ground(scene, &ground);
    }
    if (effects & BENCH_CONTACT) {
        tb_contact_def contact = tb_contact_def_default();
        tb_scene_add_contact(scene, &contact);
    }
    return scene;
}

#endif
