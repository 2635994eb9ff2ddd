/* A scene's root_signs (tb_ode_events.root_signs, src/scene/scene_events.c) against its roots,
 * where they can part: at the ulp on either side of each root's zero, in a scene of every kind of
 * body and shape the passes skip or keep (boxes with and without ground points, a compound, a
 * points shape, a sphere and a capsule; a static board and a keyframed block; sleeping and awake
 * bodies; the ground and a tilted second plane), and at states with a NaN, an infinity or a
 * zero quaternion. The fixed-step onset search reads only whether each function is above zero,
 * so one sign that differs would end a step elsewhere: no tolerance. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
/* What a root exactly 0 becomes (scene_events.c): a root equal to it was a gap of exactly 0. */
#define ZERO_GAP 1e-150
#define FLYERS 5

typedef struct probe {
    tb_ode_system system;
    size_t count;
    double *g, *signs, *again;
    unsigned long long checked, zeros, nonfinite;
} probe;

/* x in [low, high) from a linear congruential generator (deterministic, portable). */
static double uniform(unsigned long long *state, double low, double high)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return low + (high - low) * (double)(*state >> 11) / 9007199254740992.0;
}

/* roots and root_signs at y: every function above zero in one exactly where it is in the other,
 * and roots asked again after root_signs gives the same bits (no state of the skipping pass
 * leaks into the next). Returns the roots in p->g. */
static void check_at(probe *p, double t, const double *y)
{
    assert_int_equal(p->system.events.roots(t, y, p->g, p->system.ctx), 0);
    assert_int_equal(p->system.events.root_signs(t, y, p->signs, p->system.ctx), 0);
    assert_int_equal(p->system.events.roots(t, y, p->again, p->system.ctx), 0);
    for (size_t i = 0; i < p->count; ++i) {
        if ((p->g[i] > 0.0) != (p->signs[i] > 0.0)) {
            print_message("root %zu: roots %.17g, root_signs %.17g\n", i, p->g[i], p->signs[i]);
        }
        assert_int_equal(p->g[i] > 0.0, p->signs[i] > 0.0);
        p->zeros += p->g[i] == ZERO_GAP;
        p->nonfinite += !isfinite(p->g[i]);
    }
    assert_memory_equal(p->g, p->again, p->count * sizeof *p->g);
    p->checked++;
}

static double *body_x(tb_scene *scene, double *y, size_t id)
{
    size_t slot = 0;
    assert_int_equal(tb_scene_body_slot(scene, id, &slot), TB_STATUS_OK);
    return y + TB_STATE_SIZE * slot + TB_STATE_X;
}

/* Bisects coordinate c of body id's position between lo and hi (doubles, whose roots differ in
 * sign at `root`) down to adjacent doubles, then checks every ulp within 40 of the crossing. */
static void check_crossing(probe *p, tb_scene *scene, double *y, size_t id, int c, double lo,
                           double hi, size_t root)
{
    double *x = body_x(scene, y, id);
    x[c] = lo;
    check_at(p, 0.0, y);
    const bool above_lo = p->g[root] > 0.0;
    for (int k = 0; k < 200 && nextafter(lo, hi) != hi; ++k) {
        const double mid = lo + 0.5 * (hi - lo);
        if (mid == lo || mid == hi) {
            break;
        }
        x[c] = mid;
        check_at(p, 0.0, y);
        if ((p->g[root] > 0.0) == above_lo) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    const double toward = hi > lo ? INFINITY : -INFINITY;
    double s = lo;
    for (int k = 0; k < 40; ++k) {
        s = nextafter(s, -toward);
    }
    for (int k = 0; k < 81; ++k, s = nextafter(s, toward)) {
        x[c] = s;
        check_at(p, 0.0, y);
    }
}

static size_t add_body(tb_scene *scene, const double size[3], const double x[3], tb_body_motion m)
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 0.05, size, &def.mass, NULL), TB_STATUS_OK);
    memcpy(def.position, x, sizeof def.position);
    def.motion = m;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    return id;
}

static size_t add_box(tb_scene *scene, const double size[3], const double x[3], tb_body_motion m,
                      bool points)
{
    const size_t id = add_body(scene, size, x, m);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof shape.size);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    if (points) {
        tb_contact_point corners[8];
        size_t count = 0;
        assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, id, corners, count, 4), TB_STATUS_OK);
    }
    return id;
}

/* A block gliding along x at 0.1 m/s at height 0.1 m. */
static int glide(double t, void *ctx, tb_body_motion_sample *out)
{
    (void)ctx;
    *out = (tb_body_motion_sample){.position = {0.5 + 0.1 * t, 0.1, 0.1},
                                   .orientation = {1.0, 0.0, 0.0, 0.0},
                                   .velocity = {0.1, 0.0, 0.0}};
    return 0;
}

/* The scene: a row at rest on the ground that falls asleep (boxes with and without corner
 * points, a sphere, a capsule lying), a static board and a keyframed block beside it, a tilted
 * plane from x = 0.7, and five flyers in the air (a box with points, a two-box compound, a points
 * shape, a sphere, a sphere on a one-point stalk). Returns the flyers' ids in flyers. */
static tb_scene *mixed_scene(size_t flyers[FLYERS])
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    const double cube[3] = {0.04, 0.04, 0.04}, slab[3] = {0.05, 0.03, 0.02};
    for (int k = 0; k < 4; ++k) {
        add_box(scene, cube, (double[]){0.05 * k, 0.0, 0.02}, TB_MOTION_DYNAMIC, k % 2 == 0);
    }
    test_add_ball(scene, NULL, 0.05, 0.02, (double[]){0.2, 0.0, 0.02}, NULL);
    const size_t capsule = add_body(scene, cube, (double[]){0.27, 0.0, 0.015}, TB_MOTION_DYNAMIC);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_CAPSULE;
    shape.radius = 0.015;
    shape.length = 0.03;
    assert_int_equal(tb_scene_set_body_shape(scene, capsule, &shape), TB_STATUS_OK);
    tb_body_state s;
    assert_int_equal(tb_scene_get_state(scene, capsule, &s), TB_STATUS_OK);
    const double h = sqrt(0.5);
    memcpy(s.q, (double[]){h, 0.0, h, 0.0}, sizeof s.q); /* lying along x */
    assert_int_equal(tb_scene_set_state(scene, capsule, &s), TB_STATUS_OK);
    add_box(scene, (double[]){0.3, 0.1, 0.04}, (double[]){0.15, 0.12, 0.2}, TB_MOTION_STATIC,
            false);
    const size_t block =
        add_box(scene, cube, (double[]){0.5, 0.1, 0.1}, TB_MOTION_KEYFRAMED, false);
    assert_int_equal(tb_scene_set_body_motion_fn(scene, block, glide, NULL), TB_STATUS_OK);

    flyers[0] = add_box(scene, slab, (double[]){0.3, 0.6, 0.5}, TB_MOTION_DYNAMIC, true);
    flyers[1] = add_body(scene, cube, (double[]){0.3, 0.9, 0.5}, TB_MOTION_DYNAMIC);
    tb_shape_piece pieces[2] = {tb_shape_piece_default(), tb_shape_piece_default()};
    for (int k = 0; k < 2; ++k) {
        pieces[k].shape.type = TB_SHAPE_BOX;
        memcpy(pieces[k].shape.size, (double[]){0.03, 0.02, 0.02}, 3 * sizeof(double));
        pieces[k].position[0] = k == 0 ? -0.015 : 0.015;
        pieces[k].position[2] = k == 0 ? 0.0 : 0.01;
    }
    assert_int_equal(tb_scene_set_body_pieces(scene, flyers[1], pieces, 2), TB_STATUS_OK);
    flyers[2] = add_body(scene, cube, (double[]){0.3, 1.2, 0.5}, TB_MOTION_DYNAMIC);
    const double vertices[12] = {0.02, 0, 0, -0.02, 0, 0, 0, 0.02, 0.01, 0, -0.02, -0.01};
    const double radii[4] = {0.0, 0.005, 0.01, 0.002};
    shape = tb_shape_default();
    shape.type = TB_SHAPE_POINTS;
    shape.vertices = vertices;
    shape.vertex_count = 4;
    shape.radii = radii;
    assert_int_equal(tb_scene_set_body_shape(scene, flyers[2], &shape), TB_STATUS_OK);
    flyers[3] = test_add_ball(scene, NULL, 0.05, 0.015, (double[]){0.3, 1.5, 0.5}, NULL);
    /* a ball on a stalk: one ground point straight below the centre when upright, where the
     * ground's test for a body surely above the plane is tightest */
    flyers[4] = test_add_ball(scene, NULL, 0.05, 0.01, (double[]){0.3, 1.8, 0.5}, NULL);
    const tb_contact_point foot = {.position = {0.0, 0.0, -0.03}, .radius = 0.005};
    assert_int_equal(tb_scene_set_contact_points(scene, flyers[4], &foot, 1, 1), TB_STATUS_OK);
    for (int k = 0; k < FLYERS; ++k) {
        assert_int_equal(tb_scene_set_velocity(scene, flyers[k], (double[]){0, 0, 3.0},
                                               (double[]){1.0, 2.0, 0.0}),
                         TB_STATUS_OK);
    }
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-5;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    ground.normal[0] = -1.0, ground.normal[1] = 0.0, ground.normal[2] = 1.0;
    ground.offset = -0.7 * h; /* through x = 0.7 on the floor, rising beyond */
    const tb_status second = tb_scene_add_ground(scene, &ground);
    if (second != TB_STATUS_OK) {
        print_message("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(second, TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = 1e-5;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_sleeping(scene, true), TB_STATUS_OK);
    return scene;
}

/* Flyer id put at a random pose among the row, the board, the block and the tilted plane. */
static void place(tb_scene *scene, double *y, size_t id, unsigned long long *rng)
{
    double *x = body_x(scene, y, id);
    x[0] = uniform(rng, -0.06, 0.8);
    x[1] = uniform(rng, -0.06, 0.16);
    x[2] = uniform(rng, -0.01, 0.22);
    double q[4], norm = 0.0;
    for (int k = 0; k < 4; ++k) {
        q[k] = uniform(rng, -1.0, 1.0);
        norm += q[k] * q[k];
    }
    const bool square = uniform(rng, 0.0, 1.0) < 0.3; /* axis-aligned: exact touching */
    for (int k = 0; k < 4; ++k) {
        x[TB_STATE_Q - TB_STATE_X + k] = square ? (k == 0) : q[k] / sqrt(norm);
    }
}

/* Near every crossing of a root's sign as a flyer moves along an axis, and at random poses, the
 * two agree; both sides of zero and exact zeros are seen. */
static void test_root_signs_agree_at_every_crossing_to_the_ulp(void **unused)
{
    (void)unused;
    size_t flyers[FLYERS];
    tb_scene *scene = mixed_scene(flyers);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 0.65), TB_STATUS_OK);
    size_t asleep = 0;
    assert_int_equal(tb_scene_asleep_count(scene, &asleep), TB_STATUS_OK);
    print_message("asleep: %zu\n", asleep);
    assert_true(asleep >= 4); /* wake gaps to sleeping bodies are among the roots */
    probe p = {.checked = 0};
    assert_int_equal(tb_scene_ode_system(scene, &p.system), TB_STATUS_OK);
    assert_non_null(p.system.events.root_signs);
    p.count = p.system.events.root_count;
    const size_t n = p.system.n;
    double *y = malloc(n * sizeof *y), *lo_g = malloc(p.count * sizeof *lo_g);
    p.g = malloc(p.count * sizeof *p.g);
    p.signs = malloc(p.count * sizeof *p.signs);
    p.again = malloc(p.count * sizeof *p.again);
    assert_true(y != NULL && lo_g != NULL && p.g != NULL && p.signs != NULL && p.again != NULL);
    memcpy(y, tb_scene_states_const(scene), n * sizeof *y);
    unsigned long long rng = 41, crossings[2] = {0, 0}; /* gaps, wake gaps */
    const size_t bodies = tb_scene_body_count(scene);
    for (int trial = 0; trial < 3000; ++trial) {
        for (int k = 0; k < FLYERS; ++k) {
            place(scene, y, flyers[k], &rng);
        }
        const size_t id = flyers[trial % FLYERS];
        const int c = (int)(uniform(&rng, 0.0, 3.0));
        double *x = body_x(scene, y, id);
        const double lo = x[c], hi = lo + uniform(&rng, -0.05, 0.05);
        check_at(&p, 0.0, y);
        memcpy(lo_g, p.g, p.count * sizeof *lo_g);
        x[c] = hi;
        check_at(&p, 0.0, y);
        for (size_t root = 0; root < p.count; ++root) {
            if ((lo_g[root] > 0.0) != (p.g[root] > 0.0)) {
                check_crossing(&p, scene, y, id, c, lo, hi, root);
                crossings[root >= bodies]++;
            }
        }
        x[c] = lo;
    }
    /* states no integrator should reach, but which a probe between two states could */
    const double odd[4] = {NAN, INFINITY, -INFINITY, 1e301};
    for (int k = 0; k < 4; ++k) {
        for (int f = 0; f < FLYERS; ++f) {
            place(scene, y, flyers[f], &rng);
        }
        double *x = body_x(scene, y, flyers[k]);
        x[k % 3] = odd[k];
        check_at(&p, 0.0, y);
        x[k % 3] = 0.05;
        memset(x + TB_STATE_Q - TB_STATE_X, 0, 4 * sizeof(double)); /* no rotation at all */
        check_at(&p, 0.0, y);
    }
    print_message(
        "%llu states checked; crossings of gaps %llu, of wake gaps %llu; %llu exact zeros, "
        "%llu non-finite\n",
        p.checked, crossings[0], crossings[1], p.zeros, p.nonfinite);
    assert_true(crossings[0] >= 200 && crossings[1] >= 50 && p.zeros > 0);
    free(y), free(lo_g), free(p.g), free(p.signs), free(p.again);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_root_signs_agree_at_every_crossing_to_the_ulp),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
