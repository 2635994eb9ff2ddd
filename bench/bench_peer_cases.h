/* The cases of bench_peer_contact (see there): tumble's scene of each, and the world the peers
 * are built from (bench_peer_world.h). */
#ifndef TUMBLE_BENCH_PEER_CASES_H
#define TUMBLE_BENCH_PEER_CASES_H

#include "bench_peer_world.h"
#include "bench_scenes.h"
#include "tumble/tumble.h"

#include <string.h>

#ifndef BENCH_EXAMPLES
#define BENCH_EXAMPLES "examples/scenes"
#endif

#define CLOUD_SIDE 6
#define CLOUD_PITCH 0.12
#define PILE_DROP_GAP 0.02
#define COLUMN_BOXES 10
#define BALL_DROP 0.5
#define BALL_RESTITUTION 0.5

typedef enum { CASE_DICE, CASE_COLUMN, CASE_PILE, CASE_SPHERES, CASE_CLOUD, CASE_BALL, CASES } kind;
static const char *const case_names[] = {"dice", "column", "pile", "spheres", "cloud", "ball"};

/* How long each case runs (s), its bodies (0: the scene's own), and the sample interval (s). */
static inline double case_duration(kind k, int quick)
{
    static const double full[] = {5.0, 5.0, 0.75, 0.1, 0.03, 0.35};
    static const double brief[] = {0.02, 0.02, 0.02, 0.01, 0.002, 0.35};
    return quick ? brief[k] : full[k];
}

static inline size_t case_count(kind k, int quick)
{
    static const size_t full[] = {0, COLUMN_BOXES, 200, 1000, 200, 1};
    static const size_t brief[] = {0, COLUMN_BOXES, 16, 27, 16, 1};
    return quick ? brief[k] : full[k];
}

static inline double case_sample(kind k)
{
    return k == CASE_BALL ? 5e-4 : 0.01;
}

/* --- tumble's scenes ------------------------------------------------------------------------ */

static inline void add_shaped_box(tb_scene *scene, double mass, double edge, double height)
{
    tb_body_def def = tb_body_def_default();
    const double size[3] = {edge, edge, edge};
    tb_mass_from_box(TB_MASS_GIVEN, mass, size, &def.mass, NULL);
    def.position[2] = height;
    size_t id = 0;
    tb_scene_add_body(scene, &def, &id);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof size);
    tb_scene_set_body_shape(scene, id, &shape);
}

static inline tb_scene *empty_scene(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    return tb_scene_create(&def, &scene, NULL) == TB_STATUS_OK ? scene : NULL;
}

/* Gravity, the floor (restitution e) and, with `contact`, the default contact between bodies. */
static inline void add_floor(tb_scene *scene, double e, int contact)
{
    tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81});
    tb_ground_def ground = tb_ground_def_default();
    ground.restitution = e;
    tb_scene_add_ground(scene, &ground);
    if (contact) {
        tb_contact_def def = tb_contact_def_default();
        tb_scene_add_contact(scene, &def);
    }
}

static inline tb_scene *column(void)
{
    tb_scene *scene = empty_scene();
    for (int k = 0; scene != NULL && k < COLUMN_BOXES; ++k) {
        add_shaped_box(scene, 0.5, 0.1, 0.05 + 0.1 * k);
    }
    add_floor(scene, 0.3, 1);
    return scene;
}

static inline tb_scene *ball(void)
{
    tb_scene *scene = empty_scene();
    tb_body_def body = tb_body_def_default();
    const double r = BENCH_SPHERE_RADIUS;
    tb_mass_from_sphere(TB_MASS_DENSITY, BENCH_SPHERE_DENSITY, r, &body.mass, NULL);
    body.position[2] = BALL_DROP + r;
    tb_scene_add_body(scene, &body, NULL);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = r;
    tb_scene_set_body_shape(scene, 0, &shape);
    add_floor(scene, BALL_RESTITUTION, 0);
    return scene;
}

/* The pile of bench_scenes.h with each box lifted PILE_DROP_GAP per level above it. */
static inline tb_scene *dropped_pile(size_t count)
{
    tb_scene *scene = bench_box_pile(count, BENCH_ALL);
    for (size_t i = 0; scene != NULL && i < count; ++i) {
        tb_body_state s;
        tb_scene_get_state(scene, i, &s);
        s.x[2] += PILE_DROP_GAP * (double)(i % BENCH_PILE_HEIGHT + 1);
        tb_scene_set_state(scene, i, &s);
    }
    return scene;
}

/* 200 boxes in a 6 x 6 x 6 lattice 2 cm apart, each thrown (up to 1 m/s and 5 rad/s per
 * component, seeded), no gravity, no floor. */
static inline tb_scene *cloud(size_t count)
{
    tb_scene *scene = bench_box_pile(count, BENCH_CONTACT);
    for (size_t i = 0; scene != NULL && i < count; ++i) {
        tb_body_state s;
        tb_scene_get_state(scene, i, &s);
        s.x[0] = CLOUD_PITCH * (double)(i % CLOUD_SIDE);
        s.x[1] = CLOUD_PITCH * (double)(i / CLOUD_SIDE % CLOUD_SIDE);
        s.x[2] = CLOUD_PITCH * (double)(i / (CLOUD_SIDE * CLOUD_SIDE));
        tb_scene_set_state(scene, i, &s);
        unsigned long long rng = 1000 + i;
        double v[3], w[3];
        for (int k = 0; k < 3; ++k) {
            v[k] = bench_uniform(&rng, -1.0, 1.0);
            w[k] = bench_uniform(&rng, -5.0, 5.0);
        }
        tb_scene_set_velocity(scene, i, v, w);
    }
    return scene;
}

static inline tb_scene *tumble_case(kind k, int quick)
{
    const size_t count = case_count(k, quick);
    tb_scene *scene = NULL;
    tb_run_def run;
    switch (k) {
    case CASE_DICE:
        tb_scene_load_file(BENCH_EXAMPLES "/dice.json", &scene, &run, NULL);
        return scene;
    case CASE_COLUMN:
        return column();
    case CASE_PILE:
        return dropped_pile(count);
    case CASE_SPHERES:
        return bench_spheres_in_box(count, BENCH_ALL);
    case CASE_CLOUD:
        return cloud(count);
    default:
        return ball();
    }
}

/* The case's world for the peers: tumble's bodies, and the planes and material of the case. */
static inline int case_world(kind k, int quick, peer_world *w)
{
    tb_scene *scene = tumble_case(k, quick);
    memset(w, 0, sizeof *w);
    if (scene == NULL || peer_world_from_scene(scene, w) != 0) {
        tb_scene_destroy(scene);
        return 1;
    }
    tb_scene_destroy(scene);
    w->gravity = k == CASE_CLOUD ? 0.0 : -9.81;
    w->restitution = k == CASE_BALL ? BALL_RESTITUTION : 0.3;
    w->friction = 0.5;
    if (k == CASE_SPHERES) { /* bench_add_box_planes */
        static const double normals[5][3] = {
            {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
        const double width = 2.0 * BENCH_SPHERE_RADIUS * (double)bench_sphere_side(w->count);
        const double offsets[5] = {0.0, 0.0, -width, 0.0, -width};
        w->planes = 5;
        memcpy(w->normal, normals, sizeof normals);
        memcpy(w->offset, offsets, sizeof offsets);
    } else if (k != CASE_CLOUD) {
        w->planes = 1;
        w->normal[0][2] = 1.0;
    }
    return 0;
}

#endif
