/* Lifetimes of a scene under its integrators: an integrator steps only the layout it was made on
 * (adding a body, a ground plane, contact points or a coupling effect, or making another
 * integrator stops it with LAYOUT_CHANGED, on every path: fixed step whole-array and chunked,
 * CVODE), and a scene being stepped refuses re-entrant steps and layout changes with BUSY. Run
 * under ASan (the sanitizer builds of the test command), the refused calls also show that no
 * integrator reads or writes the state array that adding a body freed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/tumble.h"

#include <string.h>

static tb_body_def ball(void)
{
    tb_body_def def = tb_body_def_default();
    def.mass.mass = 1.0;
    for (int k = 0; k < 3; ++k) {
        def.mass.moments[k] = 0.004;
    }
    def.velocity[0] = 1.0;
    def.angular_velocity[2] = 3.0;
    return def;
}

/* One body in a scene with room for exactly one, so a second body moves the state array. */
static tb_scene *one_ball(bool coupled)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = 1;
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    tb_body_def body = ball();
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    if (coupled) { /* a spring to the world couples nothing but owns no states: whole-array path */
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = 0;
        spring.body_b = TB_WORLD;
        spring.stiffness = 1.0;
        spring.rest_length = 1.0;
        assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    }
    return scene;
}

static tb_integrator *make(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    return integrator;
}

static const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS,
                                    TB_METHOD_CVODE_BDF};

/* Adding a body moves the state array: every kind of integrator made before refuses its next
 * advance and step with LAYOUT_CHANGED naming the body, and changes nothing. */
static void test_adding_a_body_stops_every_integrator_made_before(void **state)
{
    (void)state;
    for (int coupled = 0; coupled < 2; ++coupled) {
        for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
            tb_scene *scene = one_ball(coupled);
            tb_integrator *integrator = make(scene, methods[m]);
            assert_int_equal(tb_integrator_advance(integrator, 0.1), TB_STATUS_OK);
            tb_body_def body = ball();
            assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
            double before[2 * TB_STATE_SIZE];
            memcpy(before, tb_scene_states(scene), sizeof before);
            assert_int_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_LAYOUT_CHANGED);
            assert_non_null(strstr(tb_integrator_detail(integrator), "body 1 added"));
            assert_int_equal(tb_integrator_step(integrator), TB_STATUS_LAYOUT_CHANGED);
            assert_memory_equal(before, tb_scene_states(scene), sizeof before);
            assert_near(tb_integrator_time(integrator), 0.1, 0.0);
            tb_integrator_destroy(integrator);
            integrator = make(scene, methods[m]); /* a new one steps both */
            assert_int_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_OK);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
        }
    }
}

static int add_a_body_at_frame_2(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    (void)t;
    (void)scene;
    if (frame == 2) {
        tb_body_def body = ball();
        assert_int_equal(tb_scene_add_body(ctx, &body, NULL), TB_STATUS_OK);
    }
    return 0;
}

/* A body added from a frame callback of tb_scene_run: the run stops with LAYOUT_CHANGED at
 * the next frame instead of stepping a freed array (CVODE wrote past it before). */
static void test_a_body_added_from_a_frame_callback_stops_the_run(void **state)
{
    (void)state;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        tb_scene *scene = one_ball(false);
        tb_run_def run = tb_run_def_default();
        run.integrator.method = methods[m];
        tb_error error;
        assert_int_equal(tb_scene_run(scene, &run, add_a_body_at_frame_2, scene, NULL, &error),
                         TB_STATUS_LAYOUT_CHANGED);
        assert_non_null(strstr(error.message, "body 1 added"));
        assert_int_equal(tb_scene_body_count(scene), 2);
        tb_scene_destroy(scene);
    }
}

/* Two integrators on one scene would each take the other's steps for changes from outside:
 * making the second stops the first. Effect-owned states (a ground plane) and coupling bodies
 * that were independent (a spring between them) stop it too. */
static void test_a_newer_integrator_a_ground_or_a_coupling_stops_the_older(void **state)
{
    (void)state;
    tb_scene *scene = one_ball(false);
    tb_body_def body = ball();
    body.position[0] = 2.0;
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    tb_integrator *first = make(scene, TB_METHOD_RK4);
    tb_integrator *second = make(scene, TB_METHOD_CVODE_ADAMS);
    assert_int_equal(tb_integrator_advance(first, 0.1), TB_STATUS_LAYOUT_CHANGED);
    assert_non_null(strstr(tb_integrator_detail(first), "newer integrator"));
    assert_int_equal(tb_integrator_advance(second, 0.1), TB_STATUS_OK);
    tb_spring_def spring = tb_spring_def_default();
    spring.body_a = 0;
    spring.body_b = 1;
    spring.stiffness = 1.0;
    spring.rest_length = 2.0;
    tb_integrator *chunked = make(scene, TB_METHOD_RK4);
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(chunked, 0.1), TB_STATUS_LAYOUT_CHANGED);
    assert_non_null(strstr(tb_integrator_detail(chunked), "coupling"));
    tb_integrator *bdf = make(scene, TB_METHOD_CVODE_BDF);
    tb_ground_def ground = tb_ground_def_default();
    ground.offset = -10.0;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(bdf, 0.2), TB_STATUS_LAYOUT_CHANGED);
    assert_non_null(strstr(tb_integrator_detail(bdf), "effect-owned states"));
    tb_integrator_destroy(first);
    tb_integrator_destroy(second);
    tb_integrator_destroy(chunked);
    tb_integrator_destroy(bdf);
    tb_scene_destroy(scene);
}

typedef struct reentry {
    tb_scene *scene;
    tb_integrator *other;
    tb_status advance_status, add_status;
    size_t calls;
} reentry;

/* A user effect that, from inside the derivative, advances an integrator of its own scene and
 * adds a body to it. */
static int reenter(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)scene;
    (void)y;
    (void)dydt;
    reentry *r = ctx;
    if (r->calls++ == 0) {
        r->advance_status = tb_integrator_advance(r->other, t + 1.0);
        tb_body_def body = ball();
        r->add_status = tb_scene_add_body(r->scene, &body, NULL);
    }
    return 0;
}

/* While an integrator steps the scene, another advance on it (here from inside a user effect:
 * it recursed until the stack overflowed) returns BUSY, and so does adding a body, which would
 * move the array the step reads. The outer step goes on and succeeds. */
static void test_calls_from_inside_a_step_are_refused_as_busy(void **state)
{
    (void)state;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        tb_scene *scene = one_ball(false);
        reentry r = {scene, NULL, TB_STATUS_OK, TB_STATUS_OK, 0};
        assert_int_equal(tb_scene_add_user_effect(scene, reenter, &r), TB_STATUS_OK);
        tb_integrator *integrator = make(scene, methods[m]);
        r.other = integrator; /* the same integrator, re-entered */
        assert_int_equal(tb_integrator_advance(integrator, 0.1), TB_STATUS_OK);
        assert_int_equal(r.advance_status, TB_STATUS_BUSY);
        assert_int_equal(r.add_status, TB_STATUS_BUSY);
        assert_int_equal(tb_scene_body_count(scene), 1);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_adding_a_body_stops_every_integrator_made_before),
        cmocka_unit_test(test_a_body_added_from_a_frame_callback_stops_the_run),
        cmocka_unit_test(test_a_newer_integrator_a_ground_or_a_coupling_stops_the_older),
        cmocka_unit_test(test_calls_from_inside_a_step_are_refused_as_busy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
