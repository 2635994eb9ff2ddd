/* Effects' contracts beyond their physics: what the add functions and the user-effect load
 * helpers refuse (status, the argument named, nothing changed), sizes that would overflow, and
 * what the stability guard learns from each effect's row (drag's rates, a light body rocking on
 * wide contact points), each checked against the mechanics it stands for. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

static size_t add_sphere(tb_scene *scene, double mass, double radius, const double position[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, mass, radius, &def.mass, NULL),
                     TB_STATUS_OK);
    memcpy(def.position, position, 3 * sizeof(double));
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    return id;
}

static tb_status make_integrator(tb_scene *scene, tb_method method, double dt, tb_integrator **out)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    if (tb_method_is_adaptive(method)) {
        def.rtol = 1e-10;
    } else {
        def.dt = dt;
    }
    return tb_scene_integrator_create(scene, &def, 0.0, out);
}

static double rk4_real_limit(void)
{
    tb_method_info info;
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, &info), TB_STATUS_OK);
    return info.real_limit;
}

/* dt is RK4's real-axis limit (the method table's 2.7853) over rate, to 0.1%: the guard may
 * round the limit down by that much as a margin. */
static bool near_limit(double dt, double rate)
{
    const double expected = rk4_real_limit() / rate;
    return dt <= expected * (1 + 1e-12) && dt >= 0.999 * expected; /* 1e-12: rounding of 1/I */
}

/* --- the user-effect load helpers ---------------------------------------------------------- */

static const double finite3[3] = {1.0, 2.0, 3.0};
static const double nan3[3] = {0.0, NAN, 0.0};
static const double inf3[3] = {INFINITY, 0.0, 0.0};

/* One refused call each: the status, the argument the detail must name, and dydt untouched. */
static void test_user_loads_refuse_bad_arguments_and_add_nothing(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0});
    const double *y = tb_scene_states_const(scene);
    double dydt[TB_STATE_SIZE] = {0}, before[TB_STATE_SIZE];
    memcpy(before, dydt, sizeof dydt);
    const struct {
        const char *label;
        tb_status status, expected;
        const char *named;
    } cases[] = {
        {"force, NULL y", tb_effect_add_force(scene, NULL, dydt, 0, finite3, finite3),
         TB_STATUS_NULL_POINTER, "y is NULL"},
        {"force, NULL dydt", tb_effect_add_force(scene, y, NULL, 0, finite3, finite3),
         TB_STATUS_NULL_POINTER, "dydt is NULL"},
        {"force, id 1 of 1", tb_effect_add_force(scene, y, dydt, 1, finite3, finite3),
         TB_STATUS_OUT_OF_RANGE, "id"},
        {"force, NULL force", tb_effect_add_force(scene, y, dydt, 0, NULL, finite3),
         TB_STATUS_NULL_POINTER, "force is NULL"},
        {"force, NaN force", tb_effect_add_force(scene, y, dydt, 0, nan3, finite3),
         TB_STATUS_NOT_FINITE, "force"},
        {"force, NULL point", tb_effect_add_force(scene, y, dydt, 0, finite3, NULL),
         TB_STATUS_NULL_POINTER, "point is NULL"},
        {"force, infinite point", tb_effect_add_force(scene, y, dydt, 0, finite3, inf3),
         TB_STATUS_NOT_FINITE, "point"},
        {"torque, NULL dydt", tb_effect_add_torque(scene, NULL, 0, finite3), TB_STATUS_NULL_POINTER,
         "dydt is NULL"},
        {"torque, id past the count", tb_effect_add_torque(scene, dydt, SIZE_MAX, finite3),
         TB_STATUS_OUT_OF_RANGE, "id"},
        {"torque, NULL torque", tb_effect_add_torque(scene, dydt, 0, NULL), TB_STATUS_NULL_POINTER,
         "torque is NULL"},
        {"torque, NaN torque", tb_effect_add_torque(scene, dydt, 0, nan3), TB_STATUS_NOT_FINITE,
         "torque"},
    };
    /* The calls ran as the table was built (in no set order), so the detail is one of theirs:
     * the details are checked below, one call at a time. */
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        print_message("%-26s -> %s\n", cases[i].label, tb_status_name(cases[i].status));
        assert_int_equal(cases[i].status, cases[i].expected);
    }
    assert_memory_equal(dydt, before, sizeof dydt);
    assert_int_equal(tb_effect_add_force(NULL, y, dydt, 0, finite3, finite3),
                     TB_STATUS_NULL_POINTER);
    tb_effect_add_force(scene, y, dydt, 0, finite3, NULL);
    assert_non_null(strstr(tb_scene_detail(scene), "point is NULL"));
    tb_effect_add_torque(scene, dydt, 4, finite3);
    assert_non_null(strstr(tb_scene_detail(scene), "id: id 4 out of range (1 bodies)"));
    tb_effect_add_force(scene, y, dydt, 0, nan3, finite3);
    assert_non_null(strstr(tb_scene_detail(scene), "force: contains NaN"));
    /* and a good call after them adds exactly its load: F = f, tau = (p - x) x f */
    assert_int_equal(
        tb_effect_add_force(scene, y, dydt, 0, (double[]){0, 0, 2}, (double[]){1, 0, 0}),
        TB_STATUS_OK);
    assert_string_equal(tb_scene_detail(scene), "");
    assert_true(dydt[TB_STATE_P + 2] == 2.0 && dydt[TB_STATE_L + 1] == -2.0);
    tb_scene_destroy(scene);
}

/* A callback that pushes a body that does not exist and ignores the refusal. */
static int push_missing_body(double t, const tb_scene *scene, const double *y, double *dydt,
                             void *ctx)
{
    (void)t;
    (void)ctx;
    tb_effect_add_force(scene, y, dydt, 7, finite3, finite3);
    return 0;
}

/* The missing force must not pass silently: the derivative fails (fatal), naming the id. */
static void test_a_refused_load_fails_the_derivative(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0});
    assert_int_equal(tb_scene_add_user_effect(scene, push_missing_body, NULL), TB_STATUS_OK);
    double dydt[TB_STATE_SIZE];
    assert_true(tb_scene_derivative(0.0, tb_scene_states_const(scene), dydt, scene) < 0);
    assert_non_null(strstr(tb_scene_detail(scene), "id 7 out of range"));
    tb_integrator *integrator = NULL;
    assert_int_equal(make_integrator(scene, TB_METHOD_RK4, 1e-2, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_DERIVATIVE_FAILED);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* --- sizes and refused calls --------------------------------------------------------------- */

/* 2^61 effects of any size overflow a 64-bit byte count: refused before allocating (it used
 * to wrap to a small block that the first effect overran). */
static void test_an_effect_capacity_past_the_address_space_is_refused(void **state)
{
    (void)state;
    const size_t capacities[] = {(size_t)1 << 61, SIZE_MAX / 8 + 1, SIZE_MAX};
    for (size_t i = 0; i < sizeof capacities / sizeof capacities[0]; ++i) {
        tb_scene_def def = tb_scene_def_default();
        def.effect_capacity = capacities[i];
        tb_scene *scene = (tb_scene *)&def; /* must become NULL */
        tb_error error;
        assert_int_equal(tb_scene_create(&def, &scene, &error), TB_STATUS_OUT_OF_MEMORY);
        assert_null(scene);
        assert_non_null(strstr(error.message, "effects"));
    }
}

static tb_status null_gravity(tb_scene *s)
{
    return tb_scene_add_gravity(s, NULL);
}
static tb_status null_force(tb_scene *s)
{
    return tb_scene_add_force(s, 0, NULL, finite3, TB_FRAME_WORLD);
}
static tb_status null_torque(tb_scene *s)
{
    return tb_scene_add_torque(s, 0, NULL, TB_FRAME_BODY);
}
static tb_status null_drag(tb_scene *s)
{
    return tb_scene_add_drag(s, NULL);
}
static tb_status null_spring(tb_scene *s)
{
    return tb_scene_add_spring(s, NULL);
}
static tb_status null_ground(tb_scene *s)
{
    return tb_scene_add_ground(s, NULL);
}
static tb_status null_points(tb_scene *s)
{
    return tb_scene_set_contact_points(s, 0, NULL, 2, 1);
}
static tb_status null_callback(tb_scene *s)
{
    return tb_scene_add_user_effect(s, NULL, NULL);
}
static tb_status null_conserved(tb_scene *s)
{
    return tb_scene_conserved(s, NULL);
}
static tb_status null_contact_info(tb_scene *s)
{
    return tb_scene_get_contact(s, 0, NULL);
}
static tb_status null_touching_count(tb_scene *s)
{
    return tb_scene_contact_touching(s, tb_scene_states_const(s), NULL, 0, NULL);
}
static tb_status null_point_count(tb_scene *s)
{
    return tb_scene_body_contact_point_count(s, 0, NULL);
}
static tb_status null_touching_out(tb_scene *s)
{
    size_t count = 0;
    return tb_scene_contact_touching(s, tb_scene_states_const(s), NULL, 4, &count);
}

/* After an earlier failure left its detail, a NULL argument gets its own: each function clears
 * the detail first and names the argument (issue 11, class 5). */
static void test_a_null_argument_is_named_not_the_previous_failure(void **state)
{
    (void)state;
    static const struct {
        tb_status (*attempt)(tb_scene *);
        const char *named;
    } cases[] = {
        {null_gravity, "g is NULL"},
        {null_force, "force is NULL"},
        {null_torque, "torque is NULL"},
        {null_drag, "def is NULL"},
        {null_spring, "def is NULL"},
        {null_ground, "def is NULL"},
        {null_points, "points is NULL"},
        {null_callback, "fn is NULL"},
        /* issue 19: these returned the status and left the earlier failure's detail */
        {null_conserved, "out_conserved is NULL"},
        {null_contact_info, "out is NULL"},
        {null_touching_count, "out_count is NULL"},
        {null_touching_out, "out is NULL"},
        {null_point_count, "out_count is NULL"}, /* the red team's: as issue 19's */
    };
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0});
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        assert_int_equal(tb_scene_add_gravity(scene, nan3), TB_STATUS_NOT_FINITE);
        assert_int_equal(cases[i].attempt(scene), TB_STATUS_NULL_POINTER);
        assert_non_null(strstr(tb_scene_detail(scene), cases[i].named));
        assert_int_equal(tb_scene_effect_count(scene), 0);
    }
    tb_scene_destroy(scene);
}

/* --- what the stability guard learns from the effects' rows ------------------------------ */

/* The largest RK4 step the guard allows for a 1 kg ball moving at v (m/s) and spinning at
 * omega (rad/s) under drag alone. */
static double drag_limit(const tb_drag_def *drag, double v, double omega, tb_scene **out)
{
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0}); /* I = 0.004 kg m^2 */
    assert_int_equal(
        tb_scene_set_velocity(scene, ball, (double[]){v, 0, 0}, (double[]){0, 0, omega}),
        TB_STATUS_OK);
    assert_int_equal(tb_scene_add_drag(scene, drag), TB_STATUS_OK);
    double dt;
    char which[TB_DETAIL_SIZE];
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, which), TB_STATUS_OK);
    print_message("RK4 limit %.6g s: %s\n", dt, which);
    assert_non_null(strstr(which, "drag"));
    *out = scene;
    return dt;
}

/* Linear drag b on mass m: dv/dt = -(b/m) v, one real eigenvalue -b/m, so RK4 is stable exactly
 * while h b/m <= its real-axis limit (2.785). The guard's step is that; 10% beyond it the speed
 * grows step by step (|R(-h b/m)| > 1), 10% inside it decays: the limit is where the numerics
 * says, not only where the guard says. (Before the rows carried drag's rate, the guard saw none
 * and a run at h b/m past the limit reached 1e70 m/s with status OK.) */
static void test_the_guard_holds_linear_drag_at_rk4s_real_limit(void **state)
{
    (void)state;
    tb_drag_def drag = tb_drag_def_default();
    drag.linear = 100.0; /* b/m = 100 1/s */
    tb_scene *scene;
    const double limit = drag_limit(&drag, 1.0, 0.0, &scene);
    assert_true(near_limit(limit, 100.0));
    tb_integrator *integrator = NULL;
    assert_int_equal(make_integrator(scene, TB_METHOD_RK4, 1.1 * limit, &integrator),
                     TB_STATUS_UNSTABLE_STEP);
    assert_non_null(strstr(tb_scene_detail(scene), "drag"));
    const double factors[2] = {0.9, 1.1};
    double speeds[2];
    tb_scene_set_allow_unstable(scene, true);
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(tb_scene_set_velocity(scene, 0, (double[]){1, 0, 0}, (double[]){0, 0, 0}),
                         TB_STATUS_OK);
        assert_int_equal(make_integrator(scene, TB_METHOD_RK4, factors[k] * limit, &integrator),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 100 * factors[k] * limit), TB_STATUS_OK);
        speeds[k] = fabs(tb_scene_states(scene)[TB_STATE_P]);
        tb_integrator_destroy(integrator);
    }
    print_message("|v| after 100 steps: %.3g m/s at 0.9 x the limit, %.3g at 1.1 x\n", speeds[0],
                  speeds[1]);
    assert_true(speeds[0] < 1.0 && speeds[1] > 1.0);
    tb_scene_destroy(scene);
}

/* Quadratic drag F = -c |v| v linearised about v: dF/dv = -2 c |v| along v, so the rate is
 * 2 c |v| / m at the current speed (200 1/s at c = 1, 100 m/s, 1 kg); angular drag's rate is
 * b_w / I (0.4 / 0.004 = 100 1/s) and its quadratic twin 2 c_w |omega| / I. */
static void test_the_guard_reads_quadratic_and_angular_drag_at_the_state(void **state)
{
    (void)state;
    tb_scene *scene;
    tb_drag_def drag = tb_drag_def_default();
    drag.quadratic = 1.0;
    assert_true(near_limit(drag_limit(&drag, 100.0, 0.0, &scene), 200.0));
    tb_scene_destroy(scene);
    drag = tb_drag_def_default();
    drag.angular = 0.4;
    assert_true(near_limit(drag_limit(&drag, 0.0, 0.0, &scene), 100.0));
    tb_scene_destroy(scene);
    drag = tb_drag_def_default();
    drag.angular_quadratic = 0.004; /* 2 c_w |omega| / I = 2 (0.004) (50) / 0.004 = 100 1/s */
    /* (the spin itself is a mode of 50 rad/s on the imaginary axis, limit ~2.8 / 50: larger) */
    assert_true(near_limit(drag_limit(&drag, 0.0, 50.0, &scene), 100.0));
    tb_scene_destroy(scene);
}

/* A 10 g ball (radius 1 cm, I = 4e-7 kg m^2) on four contact points 0.5 m out, resting on the
 * ground: the contact springs at the arms act on its rotation through I, not only its mass, and
 * it rocks ~100 times faster than it bounces (a^2 ~ M r^2 / I ~ 1e4). At the 240 steps per second
 * that suit a box, RK4 spun it up to 3e6 rad/s with status OK; the guard now refuses that step,
 * and at the step it allows the ball stays at rest. */
static void test_a_light_body_on_wide_contact_points_sets_a_short_step(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 0.01, 0.01, (double[]){0, 0, 0.01});
    const tb_contact_point points[4] = {{{0.5, 0.5, -0.01}, 0.0},
                                        {{-0.5, 0.5, -0.01}, 0.0},
                                        {{0.5, -0.5, -0.01}, 0.0},
                                        {{-0.5, -0.5, -0.01}, 0.0}};
    assert_int_equal(tb_scene_set_contact_points(scene, ball, points, 4, 4), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = NULL;
    assert_int_equal(make_integrator(scene, TB_METHOD_RK4, 1.0 / 240.0, &integrator),
                     TB_STATUS_UNSTABLE_STEP);
    assert_non_null(strstr(tb_scene_detail(scene), "ground"));
    double limit;
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &limit, NULL), TB_STATUS_OK);
    print_message("RK4 limit on wide points: %.3g s\n", limit);
    assert_true(limit < 1e-5); /* a box's is 2e-4 s */
    assert_int_equal(make_integrator(scene, TB_METHOD_RK4, 0.9 * limit, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 2e-3), TB_STATUS_OK); /* 6e4 steps */
    double omega[3];
    assert_int_equal(
        tb_scene_body_angular_velocity(scene, tb_scene_states_const(scene), ball, omega),
        TB_STATUS_OK);
    assert_true(sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]) < 1e-3);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* --- a body starting inside the ground ----------------------------------------------------- */

/* A ball (radius 0.1 m) whose centre is 10 m under the plane z = 0 is 10.1 m deep: the contact
 * would push it with 10^4 times its weight and launch it (366 m/s before this was refused).
 * Refused whichever comes last, the plane or the contact points, or at integrator creation
 * when the body was moved there after both, naming the body and depth; nothing changes. 5
 * penetrations deep (a placement off by a little) is accepted. */
static void test_a_body_starting_deep_in_the_ground_is_refused(void **state)
{
    (void)state;
    const tb_contact_point point = {{0, 0, 0}, 0.1};
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 1.0, 0.1, (double[]){0, 0, -10.0});
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1), TB_STATUS_OK);
    size_t size = tb_scene_state_size(scene);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    print_message("%s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "body 0 (\"body0\"): starts 10.1 m inside"));
    assert_int_equal(tb_scene_effect_count(scene), 0);
    assert_int_equal(tb_scene_state_size(scene), size);
    tb_scene_destroy(scene);

    scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, -10.0});
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    size = tb_scene_state_size(scene);
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "starts 10.1 m inside"));
    assert_int_equal(tb_scene_state_size(scene), size); /* no bristle states were added */
    tb_scene_destroy(scene);

    /* moved there after both: the integrator is refused, naming the body */
    scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0.1});
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_body_state moved;
    assert_int_equal(tb_scene_get_state(scene, ball, &moved), TB_STATUS_OK);
    moved.x[2] = -10.0;
    assert_int_equal(tb_scene_set_state(scene, ball, &moved), TB_STATUS_OK);
    tb_integrator *integrator = (tb_integrator *)scene;
    assert_int_equal(make_integrator(scene, TB_METHOD_CVODE_BDF, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_null(integrator);
    assert_non_null(strstr(tb_scene_detail(scene), "body 0 (\"body0\"): starts 10.1 m inside"));
    tb_scene_destroy(scene);

    scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0.1 - 5.0 * ground.penetration});
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_scene_destroy(scene);
}

/* --- effects added while an integrator exists --------------------------------------------- */

/* A ball touching the plane z = 0 at its contact point (no gravity: it stays there), and an
 * integrator of `method` made on it. */
static tb_scene *ball_with_integrator(tb_method method, tb_integrator **out)
{
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0.1});
    const tb_contact_point point = {{0, 0, 0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1), TB_STATUS_OK);
    assert_int_equal(make_integrator(scene, method, 1.0 / 240.0, out), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(*out, 0.1), TB_STATUS_OK);
    return scene;
}

static tb_status add_default_ground(tb_scene *scene)
{
    tb_ground_def ground = tb_ground_def_default();
    return tb_scene_add_ground(scene, &ground);
}

static tb_status add_wider_points(tb_scene *scene)
{
    const tb_contact_point points[2] = {{{0, 0, 0}, 0.1}, {{0, 0, 0.05}, 0.1}};
    return tb_scene_set_contact_points(scene, 0, points, 2, 1);
}

/* A ground plane (2 bristle states per contact point) or more contact points make the state
 * longer than the integrator's: it refuses to advance (LAYOUT_CHANGED) instead of writing past
 * its array (the sanitizer and valgrind builds run this), and the bodies' states stay as they
 * were. Under RK4 and both CVODE methods. */
static void test_a_layout_change_after_the_integrator_is_refused_by_it(void **state)
{
    (void)state;
    const tb_method methods[3] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    tb_status (*changes[2])(tb_scene *) = {add_default_ground, add_wider_points};
    for (int m = 0; m < 3; ++m) {
        for (int c = 0; c < 2; ++c) {
            tb_integrator *integrator = NULL;
            tb_scene *scene = ball_with_integrator(methods[m], &integrator);
            if (c == 1) {
                assert_int_equal(add_default_ground(scene), TB_STATUS_OK);
                tb_integrator_destroy(integrator);
                assert_int_equal(make_integrator(scene, methods[m], 0.0, &integrator),
                                 TB_STATUS_OK); /* dt 0: the default step the contact needs */
            }
            assert_int_equal(changes[c](scene), TB_STATUS_OK);
            double before[TB_STATE_SIZE];
            memcpy(before, tb_scene_states_const(scene), sizeof before);
            assert_int_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_LAYOUT_CHANGED);
            print_message("%s: %s\n", tb_method_name(methods[m]), tb_integrator_detail(integrator));
            assert_memory_equal(tb_scene_states_const(scene), before, sizeof before);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
        }
    }
}

/* F17 (fuzz): no points for a body on a scene without any (NULL storage) did arithmetic on a
 * NULL pointer (undefined; the sanitizer builds stop on it). Each contact point of a scene with
 * a ground owns 2 states (the bristle's deflection), so the state size counts the points: none,
 * one, none again. */
static void test_contact_points_come_and_go_with_their_states(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 1});
    assert_int_equal(tb_scene_set_contact_points(scene, 0, NULL, 0, 0), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_scene_state_size(scene), 13);
    const tb_contact_point centre = {{0, 0, 0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &centre, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_state_size(scene), 13 + 2);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, NULL, 0, 0), TB_STATUS_OK);
    assert_int_equal(tb_scene_state_size(scene), 13);
    tb_scene_destroy(scene);
}

/* F9 (fuzz): a spring point 6e246 m from its body's centre of mass made the inverse mass at the
 * arm, |r|^2 / I, overflow, and the guard answered a largest stable step of 0 s with status OK.
 * Such a spring is refused, naming the point; the guard never answers 0 for what it accepted. */
static void test_a_spring_whose_rate_overflows_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0});
    tb_spring_def spring = tb_spring_def_default();
    spring.point_a[1] = 6.3498042097568784e246;
    spring.stiffness = 2.8;
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_INVALID_ARGUMENT);
    print_message("%s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "point_a"));
    assert_int_equal(tb_scene_effect_count(scene), 0);
    const tb_contact_point far = {{0, 1e200, 0}, 0.0}; /* the same for a contact point */
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &far, 1, 1), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "points[0]"));
    spring.point_a[1] = 1e100; /* far, but its rate (1e100 / sqrt(0.004) 1/s) is a number */
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    double dt;
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL), TB_STATUS_OK);
    assert_true(dt > 0.0);
    tb_scene_destroy(scene);
}

/* The guard's rates are numbers for every state the scene accepts: a 1 kg sphere of radius 0.5 m
 * (I = 0.1 kg m^2) spinning at 1e300 rad/s, or moving at 1e200 m/s under quadratic drag
 * c = 1 kg/m, has the rotation rate |omega| = 1e300 1/s and the drag rate 2 c |v| / m = 2e200 1/s,
 * so the largest stable RK4 step is the method's limit over them (2.8e-300 s, 1.4e-200 s), not
 * the 0 s that |omega|^2 = 1e600 overflowing to infinity gave. */
static void test_the_guard_answers_a_step_for_fast_states_it_accepted(void **state)
{
    (void)state;
    tb_method_info info;
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, &info), TB_STATUS_OK);
    tb_scene *scene = test_empty_scene();
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.5, &def.mass, NULL), TB_STATUS_OK);
    def.angular_velocity[2] = 1e300;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    double dt = -1.0;
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL), TB_STATUS_OK);
    print_message("spinning at 1e300 rad/s: dt %g s\n", dt);
    const double spin_limit = info.imaginary_limit / 1e300; /* the margin: at most 0.1% below */
    assert_true(dt <= spin_limit * (1 + 1e-12) && dt >= 0.999 * spin_limit);
    tb_scene_destroy(scene);

    scene = test_empty_scene();
    def.angular_velocity[2] = 0.0;
    def.velocity[0] = 1e200;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_drag_def drag = tb_drag_def_default();
    drag.quadratic = 1.0;
    assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL), TB_STATUS_OK);
    print_message("1e200 m/s under quadratic drag: dt %g s\n", dt);
    assert_true(near_limit(dt, 2e200));
    tb_scene_destroy(scene);
}

/* F18 (fuzz): a ground with presliding 1e-310 m (bristle stiffness mu_s / presliding = inf) was
 * accepted, and the guard then answered a largest stable step of 0 s with OK. Such a ground is
 * refused naming the field; a rate that still is not a number (linear drag 1e300 N s/m on a
 * 1e-100 kg body: b / m = 1e400 1/s) makes the guard answer NOT_FINITE naming it, and a
 * fixed step is refused. */
static void test_rates_that_are_not_numbers_are_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 1});
    tb_ground_def ground = tb_ground_def_default();
    ground.presliding = 1e-310;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "presliding: 1e-310 m"));
    ground = tb_ground_def_default();
    ground.penetration = 1e-310;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "penetration: 1e-310 m"));
    assert_int_equal(tb_scene_effect_count(scene), 0);
    tb_scene_destroy(scene);

    scene = test_empty_scene();
    add_sphere(scene, 1e-100, 1e-30, (double[]){0, 0, 1});
    tb_drag_def drag = tb_drag_def_default();
    drag.linear = 1e300;
    assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
    double dt = -1.0;
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL),
                     TB_STATUS_NOT_FINITE);
    print_message("%s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "a drag"));
    assert_true(dt == -1.0); /* the output untouched */
    tb_integrator *integrator = NULL;
    assert_int_equal(make_integrator(scene, TB_METHOD_RK4, 1e-3, &integrator),
                     TB_STATUS_UNSTABLE_STEP);
    assert_null(integrator);
    tb_scene_destroy(scene);
}

/* A free 2 kg body at rest; at t = 1 s a force of 4 N along x is added: x(t) = (t - 1)^2 for
 * t > 1 (a = 2 m/s^2). RK4 is exact on a quadratic (to rounding); CVODE at rtol 1e-10 must see the
 * force too (it kept integrating the old right-hand side from its history before), to 1e-6 m. */
static void test_a_force_added_mid_run_acts_under_every_method(void **state)
{
    (void)state;
    const tb_method methods[3] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (int m = 0; m < 3; ++m) {
        tb_scene *scene = test_empty_scene();
        const size_t body = add_sphere(scene, 2.0, 0.1, (double[]){0, 0, 0});
        tb_integrator *integrator = NULL;
        assert_int_equal(make_integrator(scene, methods[m], 1e-2, &integrator), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
        assert_int_equal(tb_scene_add_force(scene, body, (double[]){4, 0, 0}, (double[]){0, 0, 0},
                                            TB_FRAME_WORLD),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_OK);
        const double x = tb_scene_states_const(scene)[TB_STATE_X];
        print_message("%-12s x(3) = %.12f (exact 4)\n", tb_method_name(methods[m]), x);
        assert_true(fabs(x - 4.0) < 1e-6);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_user_loads_refuse_bad_arguments_and_add_nothing),
        cmocka_unit_test(test_a_refused_load_fails_the_derivative),
        cmocka_unit_test(test_an_effect_capacity_past_the_address_space_is_refused),
        cmocka_unit_test(test_a_null_argument_is_named_not_the_previous_failure),
        cmocka_unit_test(test_the_guard_holds_linear_drag_at_rk4s_real_limit),
        cmocka_unit_test(test_the_guard_reads_quadratic_and_angular_drag_at_the_state),
        cmocka_unit_test(test_a_light_body_on_wide_contact_points_sets_a_short_step),
        cmocka_unit_test(test_a_body_starting_deep_in_the_ground_is_refused),
        cmocka_unit_test(test_contact_points_come_and_go_with_their_states),
        cmocka_unit_test(test_a_spring_whose_rate_overflows_is_refused),
        cmocka_unit_test(test_the_guard_answers_a_step_for_fast_states_it_accepted),
        cmocka_unit_test(test_rates_that_are_not_numbers_are_refused),
        cmocka_unit_test(test_a_layout_change_after_the_integrator_is_refused_by_it),
        cmocka_unit_test(test_a_force_added_mid_run_acts_under_every_method),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
