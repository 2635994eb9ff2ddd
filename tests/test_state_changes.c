/* Changes to a scene's state between advances: a body moved deep into another body or into a
 * ground plane after the integrator exists is refused at the next advance, step or reset under
 * every method, as it is at the start (F26); and a second integrator on one scene takes the
 * state where the first left it (F30). So is a shape grown into another body after the start,
 * and a keyframed body's motion moved into one.
 * Each refusal names the bodies and changes nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const tb_method every_method[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                         TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
enum { METHOD_COUNT = sizeof every_method / sizeof every_method[0] };

/* A 1 kg ball of radius 0.1 m at (x, 0, z), named, with a sphere shape. */
static void add_ball(tb_scene *scene, const char *name, double x, double z)
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    def.name = name;
    def.position[0] = x;
    def.position[2] = z;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = 0.1;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
}

static tb_integrator *make_integrator(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (!tb_method_is_adaptive(method)) {
        def.dt = 0.0; /* the scene's default step */
    }
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    return integrator;
}

static void assert_detail_has(const char *detail, const char *words)
{
    if (strstr(detail, words) == NULL) {
        fail_msg("detail \"%s\" lacks \"%s\"", detail, words);
    }
}

/* Every call that steps (advance, step, reset) refuses with INVALID_ARGUMENT, its detail
 * naming `pair`; the scene's state and the integrator's time stay as they were, bit for bit. */
static void assert_every_call_refuses(tb_scene *scene, tb_integrator *integrator, const char *pair)
{
    enum { MAX_STATES = 64 };
    const size_t n = tb_scene_state_size(scene);
    assert_true(n <= MAX_STATES);
    double before[MAX_STATES];
    memcpy(before, tb_scene_states_const(scene), n * sizeof(double));
    const double t = tb_integrator_time(integrator);
    for (int call = 0; call < 3; ++call) {
        const tb_status status = call == 0   ? tb_integrator_advance(integrator, t + 0.01)
                                 : call == 1 ? tb_integrator_step(integrator)
                                             : tb_integrator_reset(integrator, t);
        assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
        assert_detail_has(tb_integrator_detail(integrator), pair);
        assert_detail_has(tb_integrator_detail(integrator), "inside");
        assert_memory_equal(tb_scene_states_const(scene), before, n * sizeof(double));
        assert_true(tb_integrator_time(integrator) == t);
    }
}

/* The largest speed of any body, m/s. */
static double fastest(const tb_scene *scene)
{
    double v = 0.0;
    for (size_t i = 0; i < tb_scene_body_count(scene); ++i) {
        double velocity[3];
        assert_int_equal(tb_scene_body_velocity(scene, tb_scene_states_const(scene), i, velocity),
                         TB_STATUS_OK);
        v = fmax(v, sqrt(velocity[0] * velocity[0] + velocity[1] * velocity[1] +
                         velocity[2] * velocity[2]));
    }
    return v;
}

/* F26: two balls at rest, 1 m apart, no gravity; after the first advance ball b is moved 0.15 m
 * into ball a (by tb_scene_set_state, then by a write through tb_scene_states). Before, every
 * method threw them apart at 220-240 m/s and said OK; the start check (F21: deeper than 10
 * times the depth that carries a weight, 8 micrometres here) now runs on the changed state.
 * Moved apart again, they stay at rest: no force acts, so the speed is exactly 0. */
static void test_a_body_moved_into_another_after_the_start_is_refused(void **state)
{
    (void)state;
    for (int m = 0; m < METHOD_COUNT; ++m) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "a", -0.5, 0.0);
        add_ball(scene, "b", 0.5, 0.0);
        tb_contact_def contact = tb_contact_def_default();
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator *integrator = make_integrator(scene, every_method[m]);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
        tb_body_state moved;
        assert_int_equal(tb_scene_get_state(scene, 1, &moved), TB_STATUS_OK);
        moved.x[0] = -0.45;
        assert_int_equal(tb_scene_set_state(scene, 1, &moved), TB_STATUS_OK);
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        moved.x[0] = 0.5; /* apart again: accepted */
        assert_int_equal(tb_scene_set_state(scene, 1, &moved), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 0.02), TB_STATUS_OK);
        assert_true(fastest(scene) == 0.0);
        tb_scene_states(scene)[13] = -0.45; /* x of body 1, written directly */
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        tb_scene_states(scene)[13] = 0.5;
        assert_int_equal(tb_integrator_advance(integrator, 0.03), TB_STATUS_OK);
        assert_true(fastest(scene) == 0.0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A red-team find beside F26: ball b's shape grown from 0.1 to 1.4 m after the first advance
 * (tb_scene_set_body_shape, no state changed) reaches 0.5 m into ball a. The state did not
 * change, so no check ran: CVODE Adams threw them apart at 580 m/s with OK (RK4 was stopped by
 * its stability guard, naming the step). Every call that steps now refuses as a start would,
 * under every method, the state and time unchanged; with the shape back (a piece list of one
 * sphere) they stay at rest: no force acts, so the speed is exactly 0. */
static void test_a_shape_grown_into_another_after_the_start_is_refused(void **state)
{
    (void)state;
    for (int m = 0; m < METHOD_COUNT; ++m) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "a", -0.5, 0.0);
        add_ball(scene, "b", 0.5, 0.0);
        tb_contact_def contact = tb_contact_def_default();
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator *integrator = make_integrator(scene, every_method[m]);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
        tb_shape_piece piece = tb_shape_piece_default();
        piece.shape.type = TB_SHAPE_SPHERE;
        piece.shape.radius = 1.4;
        assert_int_equal(tb_scene_set_body_shape(scene, 1, &piece.shape), TB_STATUS_OK);
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        assert_detail_has(tb_integrator_detail(integrator), "shapes were changed");
        piece.shape.radius = 0.1;
        assert_int_equal(tb_scene_set_body_pieces(scene, 1, &piece, 1), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 0.02), TB_STATUS_OK);
        assert_true(fastest(scene) == 0.0);
        piece.shape.radius = 1.4; /* and through the pieces */
        assert_int_equal(tb_scene_set_body_pieces(scene, 1, &piece, 1), TB_STATUS_OK);
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The same for a ground plane: a ball resting 1 m above z = 0, then moved 5 cm into it (more
 * than 10 penetrations, 8 micrometres), is refused at the next advance under every method. */
static void test_a_body_moved_into_the_ground_after_the_start_is_refused(void **state)
{
    (void)state;
    for (int m = 0; m < METHOD_COUNT; ++m) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "ball", 0.0, 1.0);
        tb_ground_def ground = tb_ground_def_default();
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        tb_contact_point point;
        size_t count = 0;
        assert_int_equal(tb_contact_points_sphere(0.1, &point, 1, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, count, 1), TB_STATUS_OK);
        tb_integrator *integrator = make_integrator(scene, every_method[m]);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
        tb_scene_states(scene)[2] = 0.05; /* the ball's lowest point 5 cm below the plane */
        assert_every_call_refuses(scene, integrator, "ball");
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A ball thrown under gravity, stepped by RK4 at 1/240 s. */
static tb_scene *thrown_ball(void)
{
    tb_scene *scene = test_empty_scene();
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    def.velocity[0] = 3.0;
    def.velocity[2] = 4.0;
    def.angular_velocity[1] = 2.0;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (const double[]){0, 0, -9.81}), TB_STATUS_OK);
    return scene;
}

static tb_integrator *rk4_at(tb_scene *scene, double t0)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 1.0 / 240.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, t0, &integrator), TB_STATUS_OK);
    return integrator;
}

/* F30: the contract of a second integrator on one scene. The scene holds one state; an
 * integrator made on it starts from that state as it is (where the first left it), at the t0
 * it is given, and the first then refuses to step (LAYOUT_CHANGED) instead of stepping the same
 * array behind the second's back. A fixed step has no memory beyond the state, so first to 0.5 s
 * and second from 0.5 s to 1 s is the single integrator's run, bit for bit. */
static void test_a_second_integrator_takes_the_state_where_the_first_left_it(void **state)
{
    (void)state;
    tb_scene *one = thrown_ball(), *two = thrown_ball();
    tb_integrator *single = rk4_at(one, 0.0);
    assert_int_equal(tb_integrator_advance(single, 0.5), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(single, 1.0), TB_STATUS_OK);
    tb_integrator *first = rk4_at(two, 0.0);
    assert_int_equal(tb_integrator_advance(first, 0.5), TB_STATUS_OK);
    tb_integrator *second = rk4_at(two, 0.5);
    assert_int_equal(tb_integrator_advance(second, 1.0), TB_STATUS_OK);
    const size_t n = tb_scene_state_size(one);
    assert_memory_equal(tb_scene_states_const(two), tb_scene_states_const(one), n * sizeof(double));
    double after[13];
    memcpy(after, tb_scene_states_const(two), sizeof after);
    assert_int_equal(tb_integrator_advance(first, 1.5), TB_STATUS_LAYOUT_CHANGED);
    assert_detail_has(tb_integrator_detail(first), "a newer integrator");
    assert_memory_equal(tb_scene_states_const(two), after, sizeof after);
    assert_true(tb_integrator_time(first) == 0.5);
    tb_integrator_destroy(single);
    tb_integrator_destroy(first);
    tb_integrator_destroy(second);
    tb_scene_destroy(one);
    tb_scene_destroy(two);
}

/* A state the run itself reached that the impact check refuses (a body closing on another
 * faster than the contact can stop it before the middle) is refused as before, INVALID_ARGUMENT
 * naming the pair, and its detail now says when and that the run reached it (it was the caller's
 * start before, in words: "use penetration <= ..."), so that a method that lost the motion is
 * told from a scene set up too fast. Ball b, 40 m from ball a, pushed towards it by 2.5e4 N
 * (1 kg): at t = 0.04 s it closes at 1000 m/s, past omega times the depth at which a ball's
 * tip passes the other's middle (3502 rad/s x (0.1 + 0.1) m = 700 m/s), 19.8 m away. The same
 * speed set by the caller is refused with the start's words alone. */
static void test_a_state_the_run_reached_too_fast_says_so(void **state)
{
    (void)state;
    for (int caller = 0; caller < 2; ++caller) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "a", -20.0, 0.0);
        add_ball(scene, "b", 20.0, 0.0);
        tb_contact_def contact = tb_contact_def_default();
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        const double push[3] = {caller ? 0.0 : -2.5e4, 0.0, 0.0}, centre[3] = {0.0, 0.0, 0.0};
        assert_int_equal(tb_scene_add_force(scene, 1, push, centre, TB_FRAME_WORLD), TB_STATUS_OK);
        tb_integrator *integrator = make_integrator(scene, TB_METHOD_CVODE_ADAMS);
        assert_int_equal(tb_integrator_advance(integrator, 0.04), TB_STATUS_OK);
        if (caller) {
            tb_body_state set;
            assert_int_equal(tb_scene_get_state(scene, 1, &set), TB_STATUS_OK);
            set.P[0] = -1000.0;
            assert_int_equal(tb_scene_set_state(scene, 1, &set), TB_STATUS_OK);
        }
        assert_true(fastest(scene) > 700.0);
        assert_int_equal(tb_integrator_advance(integrator, 0.041), TB_STATUS_INVALID_ARGUMENT);
        const char *detail = tb_integrator_detail(integrator);
        assert_detail_has(detail, "could pass through");
        if (caller) {
            assert_null(strstr(detail, "the run reached"));
        } else {
            assert_detail_has(detail, "at t = 0.04 s the run reached a state");
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* F113: the same for a keyframed body's motion: ball a at rest, a keyframed ball b held 1 m away
 * by one key; after the first advance b's keys (tb_scene_set_body_keys) put it 0.1 m from a's
 * centre, 0.1 m inside it. No state changed, so no check ran, and RK4 threw ball a out at 246
 * m/s with OK (a slab moved up through a ball). Every call that steps now refuses as a start
 * would, under every method, the state and time unchanged; with the key back the ball stays at
 * rest (no force acts: the speed is exactly 0), and a motion function
 * (tb_scene_set_body_motion_fn, here the curve sampled by tb_keyframes_sample) is checked
 * alike. */
static void test_a_keyframed_body_moved_into_another_after_the_start_is_refused(void **state)
{
    (void)state;
    for (int m = 0; m < METHOD_COUNT; ++m) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "a", -0.5, 0.0);
        tb_body_def def = tb_body_def_default();
        def.name = "b";
        def.motion = TB_MOTION_KEYFRAMED;
        size_t b = 0;
        assert_int_equal(tb_scene_add_body(scene, &def, &b), TB_STATUS_OK);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_SPHERE;
        shape.radius = 0.1;
        assert_int_equal(tb_scene_set_body_shape(scene, b, &shape), TB_STATUS_OK);
        tb_body_key key = tb_body_key_default();
        key.position[0] = 0.5;
        assert_int_equal(tb_scene_set_body_keys(scene, b, &key, 1, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        tb_contact_def contact = tb_contact_def_default();
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator *integrator = make_integrator(scene, every_method[m]);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
        key.position[0] = -0.4;
        assert_int_equal(tb_scene_set_body_keys(scene, b, &key, 1, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        assert_detail_has(tb_integrator_detail(integrator), "motions were changed");
        key.position[0] = 0.5;
        assert_int_equal(tb_scene_set_body_keys(scene, b, &key, 1, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 0.02), TB_STATUS_OK);
        assert_true(fastest(scene) == 0.0);
        key.position[0] = -0.4; /* and through a motion function */
        tb_keyframes *curve = NULL;
        assert_int_equal(tb_keyframes_create(&key, 1, TB_INTERPOLATION_LINEAR, &curve, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_scene_set_body_motion_fn(scene, b, tb_keyframes_sample, curve),
                         TB_STATUS_OK);
        assert_every_call_refuses(scene, integrator, "0 (\"a\") and 1 (\"b\")");
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
        tb_keyframes_destroy(curve);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_body_moved_into_another_after_the_start_is_refused),
        cmocka_unit_test(test_a_body_moved_into_the_ground_after_the_start_is_refused),
        cmocka_unit_test(test_a_shape_grown_into_another_after_the_start_is_refused),
        cmocka_unit_test(test_a_keyframed_body_moved_into_another_after_the_start_is_refused),
        cmocka_unit_test(test_a_second_integrator_takes_the_state_where_the_first_left_it),
        cmocka_unit_test(test_a_state_the_run_reached_too_fast_says_so),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
