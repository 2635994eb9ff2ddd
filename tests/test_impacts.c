/* Unresolved impacts (tb_scene_unresolved_impacts, include/tumble/contact_events.h): a fixed step
 * too long for an impact's push counts the impacts that happened, with the first and the fastest;
 * a step that resolves them counts none and watches nothing. The impacts expected are known from
 * the scenes' geometry, not from the watch. Links the counting malloc
 * (tests/support/counting_malloc.c). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#ifdef TB_TEST_COUNTING_MALLOC
#include "counting_malloc.h"
#endif
#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The example scene NAME with an integrator of method at step dt (0: the scene's default step)
 * made at t = 0; the caller destroys both. */
static tb_scene *start_example(const char *name, tb_method method, double dt, tb_integrator **out)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", TUMBLE_SCENES_DIR, name);
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, &run, &error), TB_STATUS_OK);
    assert_int_equal(tb_integrator_def_set_method(&run.integrator, method), TB_STATUS_OK);
    if (!tb_method_is_adaptive(method)) {
        run.integrator.dt = dt;
    }
    const tb_status made = tb_scene_integrator_create(scene, &run.integrator, 0.0, out);
    if (made != TB_STATUS_OK) {
        print_error("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(made, TB_STATUS_OK);
    return scene;
}

static tb_unresolved_impacts run_and_count(const char *name, tb_method method, double dt,
                                           double t_end)
{
    tb_integrator *integrator = NULL;
    tb_scene *scene = start_example(name, method, dt, &integrator);
    assert_int_equal(tb_integrator_advance(integrator, t_end), TB_STATUS_OK);
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    print_message("%s, %s at dt %g s: watched %d, %zu impacts; fastest %zu-%zu at t = %.17g s, "
                  "%.17g m/s, %.3g s (%.3g steps)\n",
                  name, tb_method_name(method), found.dt, found.watched, found.count,
                  found.fastest.body_a, found.fastest.body_b, found.fastest.t, found.fastest.speed,
                  found.fastest.duration, found.fastest.steps);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return found;
}

/* head_on_balls: spheres of radius 0.1 m at x = -0.3 and 0.3 m, the 1 kg one at 2 m/s, no
 * gravity: the gap 0.4 m closes at 2 m/s, so they touch once, at t = 0.2 s at 2 m/s, and part
 * (momentum kept, any e >= 0), nothing else in the scene: one impact in 1 s. Its push lasts
 * 0.78 ms (omega = sqrt(9.81 / 8e-7) = 3 502 rad/s, the pair's rate omega sqrt(4/3)), a fifth of
 * rosenbrock's 1/240 s step. The begin is located on the free motion's cubic, exact for a
 * uniform motion: t and speed asserted to 1e-9 (rounding of positions near 0.1 m). */
static void test_head_on_balls_at_240_hz_count_their_one_impact(void **unused)
{
    (void)unused;
    const double dt = 1.0 / 240.0;
    const tb_unresolved_impacts found =
        run_and_count("head_on_balls", TB_METHOD_ROSENBROCK, dt, 1.0);
    assert_true(found.watched);
    assert_true(found.dt == dt);
    assert_true(found.resolution == 0.1); /* rosenbrock's default step's */
    assert_int_equal(found.count, 1);
    const tb_impact *impacts[2] = {&found.first, &found.fastest};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(impacts[k]->body_a, 0);
        assert_int_equal(impacts[k]->body_b, 1);
        assert_int_equal(impacts[k]->effect, 0);
        assert_true(fabs(impacts[k]->t - 0.2) < 1e-9);
        assert_true(fabs(impacts[k]->speed - 2.0) < 1e-9);
        assert_true(impacts[k]->steps < 1.0 && impacts[k]->steps > 0.0);
        assert_true(fabs(impacts[k]->steps - impacts[k]->duration / dt) < 1e-12);
    }
}

/* head_on_pairs: four such pairs 1 m apart in y, each with its own contact (e = 0.2, 0.5, 0.8, 1),
 * each meeting once at t = 0.2 s at 2 m/s and never another pair: four impacts. The first onset
 * ends a step; the other pairs, touching a rounding later, begin inside the step taken whole
 * after it (fixed_onset.c), whose cubic the law's force already bends: t to 1e-9 s and the speed
 * to 1e-6 m/s (measured 1.7e-12 s and 1.3e-9 m/s). Pair k is bodies 2k and 2k + 1 of effect k. */
static void test_head_on_pairs_at_240_hz_count_four_impacts(void **unused)
{
    (void)unused;
    const tb_unresolved_impacts found =
        run_and_count("head_on_pairs", TB_METHOD_ROSENBROCK, 1.0 / 240.0, 1.0);
    assert_true(found.watched);
    assert_int_equal(found.count, 4);
    const tb_impact *impacts[2] = {&found.first, &found.fastest};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(impacts[k]->body_a, 2 * impacts[k]->effect);
        assert_int_equal(impacts[k]->body_b, 2 * impacts[k]->effect + 1);
        assert_true(fabs(impacts[k]->t - 0.2) < 1e-9);
        assert_true(fabs(impacts[k]->speed - 2.0) < 1e-6);
    }
}

typedef struct hits {
    size_t count;
    double faster_than; /* m/s */
} hits;

static void count_hits(const tb_contact_event *event, void *ctx)
{
    hits *h = ctx;
    h->count += event->kind == TB_CONTACT_HIT && event->speed > h->faster_than;
}

/* newtons_cradle (five equal 263 g balls 1 mm apart, the first at 0.89 m/s) at rosenbrock's
 * 1/1000 s: every pair is of equal balls under one law (rate omega sqrt(2), a push of 0.64 ms,
 * under a step), so every hit the user's contact events see closing faster than g dt = 9.81e-3
 * m/s is counted (16 in one advance over the 1.5 s). The count also holds the touches made and
 * gone inside one step, which no boundary sees touching and so no contact event reports: a pair
 * apart at both ends of a step, closing at the first and opening at the second, whose approach
 * reached zero inside it (18 in all): between balls only a contact turns the pair's rate, since
 * each ball is pushed only by its two neighbours, the one behind forward and the one ahead back. */
static void test_the_cradle_counts_its_hits_faster_than_g_dt(void **unused)
{
    (void)unused;
    char path[512];
    snprintf(path, sizeof path, "%s/newtons_cradle.json", TUMBLE_SCENES_DIR);
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, &run, &error), TB_STATUS_OK);
    assert_int_equal(tb_integrator_def_set_method(&run.integrator, TB_METHOD_ROSENBROCK),
                     TB_STATUS_OK);
    run.integrator.dt = 1e-3;
    hits h = {0, 9.81 * run.integrator.dt};
    tb_contact_events_def events = tb_contact_events_def_default();
    events.fn = count_hits;
    events.ctx = &h;
    assert_int_equal(tb_scene_set_contact_events(scene, &events), TB_STATUS_OK);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &run.integrator, 0.0, &integrator),
                     TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, run.duration), TB_STATUS_OK);
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    print_message("%zu impacts counted, %zu hits faster than %g m/s; fastest %zu-%zu at %.3f m/s "
                  "(%.3g steps)\n",
                  found.count, h.count, h.faster_than, found.fastest.body_a, found.fastest.body_b,
                  found.fastest.speed, found.fastest.steps);
    assert_true(h.count > 0);
    assert_true(found.count >= h.count);
    assert_true(found.fastest.steps < 1.0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* At a resolving step nothing is watched and nothing counted: RK4 at the scene's default step
 * (h omega <= 0.5 on the guard's bound, inside its stability limit), rosenbrock at its own
 * default step (h omega <= 0.1), and rosenbrock at 2e-5 s (the pair's h omega 0.081 < 0.1, though
 * above the guard's bound: watched, none counted). */
static void test_resolving_steps_count_none(void **unused)
{
    (void)unused;
    tb_unresolved_impacts found = run_and_count("head_on_balls", TB_METHOD_RK4, 0.0, 0.4);
    assert_false(found.watched);
    assert_int_equal(found.count, 0);
    assert_true(found.dt == 0.0);
    found = run_and_count("head_on_balls", TB_METHOD_ROSENBROCK, 0.0, 0.4);
    assert_false(found.watched);
    assert_int_equal(found.count, 0);
    found = run_and_count("head_on_balls", TB_METHOD_ROSENBROCK, 2e-5, 0.4);
    assert_true(found.watched);
    assert_int_equal(found.count, 0);
    found = run_and_count("head_on_balls", TB_METHOD_CVODE_ADAMS, 0.0, 0.4);
    assert_false(found.watched);
    assert_int_equal(found.count, 0);
}

/* The count reads the states at step boundaries into a list made with the integrator, so a run
 * counting impacts allocates nothing per step: Euler (no matrix to grow, unlike rosenbrock's
 * Jacobian pattern) at 1e-4 s on head_on_balls, beyond its stability limit on the impact's rate
 * (h omega 0.40; allow_unstable, the only way an explicit method counts), from 0.1 s, before the
 * impact, to 1 s. */
static void test_counting_allocates_nothing_per_step(void **unused)
{
    (void)unused;
#ifndef TB_TEST_COUNTING_MALLOC
    skip(); /* the sanitizers' runtime owns malloc */
#else
    char path[512];
    snprintf(path, sizeof path, "%s/head_on_balls.json", TUMBLE_SCENES_DIR);
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, &run, &error), TB_STATUS_OK);
    assert_int_equal(tb_integrator_def_set_method(&run.integrator, TB_METHOD_EULER), TB_STATUS_OK);
    run.integrator.dt = 1e-4;
    tb_scene_set_allow_unstable(scene, true);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &run.integrator, 0.0, &integrator),
                     TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.1), TB_STATUS_OK);
    const long allocations = counted_allocations;
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const long made = counted_allocations - allocations;
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    print_message("%zu impacts (%.3g steps), %ld allocations\n", found.count, found.first.steps,
                  made);
    assert_true(found.watched);
    assert_int_equal(found.count, 1);
    assert_int_equal(made, 0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
#endif
}

/* A 1 kg cube of side 0.2 m with its 8 corners as contact points (support 4), closing at 0.5 m/s
 * on a plane of penetration 1e-4 m (omega0 = sqrt(9.81 / 1e-4) = 313 rad/s), no gravity, at
 * rosenbrock's dt = dt_omega0 / omega0; q its orientation; shaped: a box shape instead of the
 * points. The count after 0.3 s. */
static tb_unresolved_impacts cube_landing_at(const double q[4], bool shaped, double dt_omega0)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {0.2, 0.2, 0.2};
    tb_body_def body = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &body.mass, NULL), TB_STATUS_OK);
    body.position[2] = 0.2;
    for (int k = 0; k < 4; ++k) {
        body.orientation[k] = q[k];
    }
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_velocity(scene, id, (double[]){0, 0, -0.5}, (double[]){0, 0, 0}),
                     TB_STATUS_OK);
    if (shaped) {
        tb_shape box = tb_shape_default();
        box.type = TB_SHAPE_BOX;
        box.size[0] = box.size[1] = box.size[2] = size[0];
        assert_int_equal(tb_scene_set_body_shape(scene, id, &box), TB_STATUS_OK);
    } else {
        tb_contact_point corners[8];
        size_t count = 0;
        assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, id, corners, count, 4), TB_STATUS_OK);
    }
    /* a 1 kg ball of radius 0.1 m far off, held 5 m up by nothing (no gravity), on one point
     * 1 m from its centre: lightness 1 + 1 / 0.004 = 251, so the guard's bound is 16 omega0 and
     * the count is watched down to dt omega0 = 0.0063 */
    tb_body_def far = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &far.mass, NULL), TB_STATUS_OK);
    far.position[0] = 10.0;
    far.position[2] = 5.0;
    size_t far_id = 0;
    assert_int_equal(tb_scene_add_body(scene, &far, &far_id), TB_STATUS_OK);
    const tb_contact_point reach = {{1.0, 0.0, 0.0}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, far_id, &reach, 1, 1), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-4;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    const double omega0 = sqrt(ground.gravity / ground.penetration);
    tb_integrator *integrator =
        test_integrator_for(scene, TB_METHOD_ROSENBROCK, dt_omega0 / omega0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 0.3), TB_STATUS_OK);
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return found;
}

static tb_unresolved_impacts cube_landing(const double q[4])
{
    return cube_landing_at(q, false, 0.15);
}

/* F97: a body on a plane was taken as its whole law, k = M omega0^2, as if every point pushed at
 * once. A cube landing flat does ring at omega0 (4 corners of k / 4 against M); landing on one
 * corner with its diagonal vertical, one corner's spring k / 4 pushes the whole mass (the arm is
 * along the normal: the effective mass is M), at omega0 / 2. At dt omega0 = 0.15 the flat landing
 * is beyond rosenbrock's resolution of 0.1 and the corner landing (0.075) inside it: one impact
 * counted, then none (the whole law counted both). The rates are exact; 0.15 and 0.075 lie a
 * factor 1.5 and 1.33 from 0.1. */
static void test_a_corner_landing_is_counted_at_its_own_rate(void **unused)
{
    (void)unused;
    const tb_unresolved_impacts flat = cube_landing((double[]){1, 0, 0, 0});
    assert_true(flat.watched);
    assert_int_equal(flat.count, 1);
    assert_true(fabs(flat.first.speed - 0.5) < 1e-6);
    /* a turn of acos(1 / sqrt 3) about (1, -1, 0) / sqrt 2 takes the diagonal (1, 1, 1) to z */
    const double angle = acos(1.0 / sqrt(3.0)), s = sin(0.5 * angle) / sqrt(2.0);
    const tb_unresolved_impacts corner = cube_landing((double[]){cos(0.5 * angle), s, -s, 0.0});
    assert_true(corner.watched);
    assert_int_equal(corner.count, 0);
}

/* F97 for a shape: the plane splits its law among the manifold's points (k / count each), so a
 * box shape landing flat, four corners at once, rings at omega0, as the points do; it was taken
 * as one point of the whole law at a corner's inverse mass 4 / M, at 2 omega0. At dt omega0 =
 * 0.075 the flat landing is resolved (none counted; it counted one before), at 0.15 it is not
 * (one). */
static void test_a_shape_landing_flat_is_counted_at_its_own_rate(void **unused)
{
    (void)unused;
    const double level[4] = {1, 0, 0, 0};
    const tb_unresolved_impacts resolved = cube_landing_at(level, true, 0.075);
    assert_true(resolved.watched);
    assert_int_equal(resolved.count, 0);
    const tb_unresolved_impacts counted = cube_landing_at(level, true, 0.15);
    assert_int_equal(counted.count, 1);
}

/* F101: between bodies the contact splits its law among the manifold's points too (k / count):
 * a 1 kg cube of side 0.2 m landing flat at 0.5 m/s on a static slab (contact of penetration
 * 1e-4 m, omega = 313 rad/s) rings at omega (4 corners of k / 4 against M), but was counted as
 * one point of the whole law at a corner's inverse mass 4 / M, at 2 omega. At dt omega = 0.075
 * none is counted (one before), at 0.15 one. A far ball on a point 1 m from its centre over a
 * plane 100 m below keeps the count watched (the guard's bound). */
static size_t cube_on_slab_count(double dt_omega)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {0.2, 0.2, 0.2};
    tb_body_def slab = tb_body_def_default();
    slab.motion = TB_MOTION_STATIC;
    slab.position[2] = -0.1;
    size_t slab_id = 0, cube_id = 0, far_id = 0;
    assert_int_equal(tb_scene_add_body(scene, &slab, &slab_id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = shape.size[1] = 2.0;
    shape.size[2] = 0.2;
    assert_int_equal(tb_scene_set_body_shape(scene, slab_id, &shape), TB_STATUS_OK);
    tb_body_def cube = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &cube.mass, NULL), TB_STATUS_OK);
    cube.position[2] = 0.2;
    cube.velocity[2] = -0.5;
    assert_int_equal(tb_scene_add_body(scene, &cube, &cube_id), TB_STATUS_OK);
    shape.size[0] = shape.size[1] = shape.size[2] = 0.2;
    assert_int_equal(tb_scene_set_body_shape(scene, cube_id, &shape), TB_STATUS_OK);
    tb_body_def far = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &far.mass, NULL), TB_STATUS_OK);
    far.position[0] = 10.0;
    assert_int_equal(tb_scene_add_body(scene, &far, &far_id), TB_STATUS_OK);
    const tb_contact_point reach = {{1.0, 0.0, 0.0}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, far_id, &reach, 1, 1), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.offset = -100.0;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = 1e-4;
    contact.bodies = (const size_t[]){slab_id, cube_id};
    contact.body_count = 2;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const double omega = sqrt(contact.gravity / contact.penetration);
    tb_integrator *integrator =
        test_integrator_for(scene, TB_METHOD_ROSENBROCK, dt_omega / omega, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 0.3), TB_STATUS_OK);
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    assert_true(found.watched);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return found.count;
}

static void test_a_box_landing_flat_on_a_box_is_counted_at_its_own_rate(void **unused)
{
    (void)unused;
    assert_int_equal(cube_on_slab_count(0.075), 0);
    assert_int_equal(cube_on_slab_count(0.15), 1);
}

/* F97: tb_integrator_reset to a time before a counted impact kept the count, so the run again
 * counted the same impact twice: head_on_balls (one impact at t = 0.2 s) run to 1 s, set back to
 * its start and reset to t = 0, then run to 1 s again, counts 1, at 0.2 s. A reset after the
 * impact (to t = 1 s, states as they are) keeps it. */
static void test_a_reset_before_an_impact_counts_it_once(void **unused)
{
    (void)unused;
    tb_integrator *integrator = NULL;
    tb_scene *scene =
        start_example("head_on_balls", TB_METHOD_ROSENBROCK, 1.0 / 240.0, &integrator);
    tb_body_state start[2];
    for (size_t id = 0; id < 2; ++id) {
        assert_int_equal(tb_scene_get_state(scene, id, &start[id]), TB_STATUS_OK);
    }
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    tb_unresolved_impacts found;
    assert_int_equal(tb_integrator_reset(integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    assert_int_equal(found.count, 1);
    for (size_t id = 0; id < 2; ++id) {
        assert_int_equal(tb_scene_set_state(scene, id, &start[id]), TB_STATUS_OK);
    }
    assert_int_equal(tb_integrator_reset(integrator, 0.0), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    assert_int_equal(found.count, 0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    assert_int_equal(found.count, 1);
    assert_true(fabs(found.first.t - 0.2) < 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* F110: a tb_integrator_reset to a time between two counted impacts forgot both (the count kept
 * three figures, not the impacts): the cradle at rosenbrock's 1/1000 s, run to 0.6 s (its count
 * then holds the impacts before 0.6 s), on to 1.5 s, and set back to its state at 0.6 s by a
 * reset there, counted 0 where it had counted those before 0.6 s. A reset to t now keeps exactly
 * the impacts at or before t (the same count, first and fastest as the run stopped at t), and the
 * run on to 1.5 s again counts the later ones on top of them, its first impact still the first
 * run's (the run after a reset need not repeat the first bit for bit: its onset search starts
 * afresh, so the count past t may differ by an impact near the threshold). */
static void test_a_reset_between_impacts_keeps_those_before_it(void **unused)
{
    (void)unused;
    tb_integrator *integrator = NULL;
    tb_scene *scene = start_example("newtons_cradle", TB_METHOD_ROSENBROCK, 1e-3, &integrator);
    const double middle = 0.6;
    assert_int_equal(tb_integrator_advance(integrator, middle), TB_STATUS_OK);
    tb_unresolved_impacts before, after, again;
    assert_int_equal(tb_scene_unresolved_impacts(scene, &before), TB_STATUS_OK);
    const size_t n = tb_scene_state_size(scene);
    double *y = malloc(n * sizeof *y);
    assert_non_null(y);
    memcpy(y, tb_scene_states(scene), n * sizeof *y);
    assert_int_equal(tb_integrator_advance(integrator, 1.5), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &after), TB_STATUS_OK);
    print_message("%zu impacts by %.1f s, %zu by 1.5 s\n", before.count, middle, after.count);
    assert_true(before.count > 0 && after.count > before.count); /* impacts on both sides */
    memcpy(tb_scene_states(scene), y, n * sizeof *y);
    assert_int_equal(tb_integrator_reset(integrator, middle), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &again), TB_STATUS_OK);
    assert_int_equal(again.count, before.count);
    assert_memory_equal(&again.first, &before.first, sizeof before.first);
    assert_memory_equal(&again.fastest, &before.fastest, sizeof before.fastest);
    assert_int_equal(tb_integrator_advance(integrator, 1.5), TB_STATUS_OK);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &again), TB_STATUS_OK);
    print_message("%zu by 1.5 s again\n", again.count);
    assert_true(again.count > before.count); /* the later ones counted anew, on top */
    assert_memory_equal(&again.first, &before.first, sizeof before.first);
    free(y);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_null_pointers_are_refused(void **unused)
{
    (void)unused;
    tb_unresolved_impacts found;
    assert_int_equal(tb_scene_unresolved_impacts(NULL, &found), TB_STATUS_NULL_POINTER);
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_unresolved_impacts(scene, NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_unresolved_impacts(scene, &found), TB_STATUS_OK);
    assert_false(found.watched);
    assert_int_equal(found.count, 0);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_head_on_balls_at_240_hz_count_their_one_impact),
        cmocka_unit_test(test_head_on_pairs_at_240_hz_count_four_impacts),
        cmocka_unit_test(test_the_cradle_counts_its_hits_faster_than_g_dt),
        cmocka_unit_test(test_resolving_steps_count_none),
        cmocka_unit_test(test_counting_allocates_nothing_per_step),
        cmocka_unit_test(test_a_corner_landing_is_counted_at_its_own_rate),
        cmocka_unit_test(test_a_shape_landing_flat_is_counted_at_its_own_rate),
        cmocka_unit_test(test_a_box_landing_flat_on_a_box_is_counted_at_its_own_rate),
        cmocka_unit_test(test_a_reset_before_an_impact_counts_it_once),
        cmocka_unit_test(test_a_reset_between_impacts_keeps_those_before_it),
        cmocka_unit_test(test_null_pointers_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
