/* The scene API: bodies in and states out, read-outs against hand-computed mechanics, and
 * bad input that is refused without changing anything. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "fixtures.h"
#include "near.h"
#include "math/tb_math.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static tb_scene *new_scene(size_t capacity)
{
    tb_scene_def def = tb_scene_def_default();
    def.body_capacity = capacity;
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    return scene;
}

/* Velocity and angular velocity set in the world frame come back unchanged; P = M v,
 * L = I_world omega with I_world = R_shape I_shape R_shape^T from the shape tensor, and the
 * kinetic energy is M v^2 / 2 + omega . I_world omega / 2 computed from that tensor. */
static void test_velocities_round_trip_through_momenta(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(4);
    tb_body_def def = tb_body_def_default();
    def.mass = test_tilted_mass();
    const double s = sqrt(0.5);
    const double orientation[4] = {s, s, 0.0, 0.0};
    memcpy(def.orientation, orientation, sizeof orientation);
    const double v[3] = {1.0, -2.0, 0.5}, w[3] = {0.3, 2.0, -1.0};
    memcpy(def.velocity, v, sizeof v);
    memcpy(def.angular_velocity, w, sizeof w);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);

    const double *y = tb_scene_states(scene);
    double v_out[3], w_out[3];
    tb_scene_body_velocity(scene, y, 0, v_out);
    tb_scene_body_angular_velocity(scene, y, 0, w_out);
    double I_shape[9], R[9], I_world[9], L_expected[3];
    tb_mass_tensor(&def.mass, I_shape);
    tb__q_to_matrix(R, orientation);
    double tmp[9], Rt[9];
    tb__m3_mul(tmp, R, I_shape);
    tb__m3_transpose(Rt, R);
    tb__m3_mul(I_world, tmp, Rt);
    tb__m3_mul_v(L_expected, I_world, w);
    for (int i = 0; i < 3; ++i) {
        assert_near(v_out[i], v[i], 1e-15);
        assert_near(w_out[i], w[i], 1e-14);
        assert_near(y[7 + i], 5.0 * v[i], 1e-14);
        assert_near(y[10 + i], L_expected[i], 1e-13);
    }
    double energy;
    tb_scene_kinetic_energy(scene, y, &energy);
    assert_near(energy, 0.5 * 5.0 * tb__v3_dot(v, v) + 0.5 * tb__v3_dot(w, L_expected), 1e-13);
    tb_scene_destroy(scene);
}

/* The shape frame's pose comes back as given: orientation as set, and the shape origin at
 * centre - R_shape c, where c is the centre of mass in the shape frame. */
static void test_shape_pose_round_trips(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = tb_body_def_default();
    def.mass = test_tilted_mass();
    const double orientation[4] = {0.5, 0.5, 0.5, 0.5}; /* 120 degrees about (1,1,1) */
    memcpy(def.orientation, orientation, sizeof orientation);
    tb__v3_set(def.position, 10.0, 20.0, 30.0);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    double position[3], q[4];
    assert_int_equal(tb_scene_body_shape_pose(scene, tb_scene_states(scene), 0, position, q),
                     TB_STATUS_OK);
    const double sign = q[0] * orientation[0] >= 0 ? 1.0 : -1.0;
    for (int k = 0; k < 4; ++k) {
        assert_near(sign * q[k], orientation[k], 1e-15);
    }
    /* R(120 deg about (1,1,1)) maps (x, y, z) to (z, x, y): c = (0.1, 0.2, 0.3) -> (0.3, 0.1, 0.2).
     */
    assert_near(position[0], 10.0 - 0.3, 1e-14);
    assert_near(position[1], 20.0 - 0.1, 1e-14);
    assert_near(position[2], 30.0 - 0.2, 1e-14);
    tb_scene_destroy(scene);
}

/* Total momenta of two bodies, and angular momentum about a point: sum (x - p) x P + L. */
static void test_total_momenta_add_orbital_and_spin_parts(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1); /* grows past its capacity */
    for (int k = 0; k < 2; ++k) {
        tb_body_def def = tb_body_def_default();
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 2.0, 0.5, &def.mass, NULL),
                         TB_STATUS_OK); /* I = 0.2 */
        tb__v3_set(def.position, k == 0 ? 1.0 : -1.0, 0.0, 0.0);
        tb__v3_set(def.velocity, 0.0, k == 0 ? 1.0 : 3.0, 0.0);
        tb__v3_set(def.angular_velocity, 0.0, 0.0, 10.0);
        assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_body_count(scene), 2);
    const double *y = tb_scene_states(scene);
    double P[3], L[3];
    tb_scene_linear_momentum(scene, y, P);
    assert_near(P[1], 2.0 * 1.0 + 2.0 * 3.0, 1e-15);
    /* about (0, 0, 0): (1,0,0) x (0,2,0) = (0,0,2); (-1,0,0) x (0,6,0) = (0,0,-6); spins 2 + 2 */
    tb_scene_angular_momentum(scene, y, (double[]){0, 0, 0}, L);
    assert_near(L[2], 2.0 - 6.0 + 2.0 + 2.0, 1e-14);
    /* about (0, 5, 0) the arms gain -5 y, which is parallel to P: no change */
    tb_scene_angular_momentum(scene, y, (double[]){0, 5, 0}, L);
    assert_near(L[2], 0.0, 1e-14);
    /* about (1, 0, 0): only the second body has an arm, (-2,0,0) x (0,6,0) = -12 */
    tb_scene_angular_momentum(scene, y, (double[]){1, 0, 0}, L);
    assert_near(L[2], -12.0 + 4.0, 1e-14);
    tb_scene_destroy(scene);
}

/* --- refused input leaves the scene exactly as it was: one row per case ------------------ */

typedef struct refusal {
    const char *label;
    tb_status (*attempt)(tb_scene *scene);
    tb_status expected;
    const char *named;
} refusal;

static tb_body_def sphere_def(void)
{
    tb_body_def def = tb_body_def_default();
    tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 1.0, &def.mass, NULL);
    return def;
}
static tb_status add_default_def(tb_scene *s)
{
    tb_body_def def = tb_body_def_default();
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_without_default(tb_scene *s)
{
    tb_body_def def;
    memset(&def, 0, sizeof def);
    def.mass.mass = 1;
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_zero_quaternion(tb_scene *s)
{
    tb_body_def def = sphere_def();
    def.orientation[0] = 0.0;
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_long_quaternion(tb_scene *s)
{
    tb_body_def def = sphere_def();
    def.orientation[0] = 2.0;
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_nan_velocity(tb_scene *s)
{
    tb_body_def def = sphere_def();
    def.velocity[1] = NAN;
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_infinite_position(tb_scene *s)
{
    tb_body_def def = sphere_def();
    def.position[2] = -INFINITY;
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status add_broken_moments(tb_scene *s)
{
    tb_body_def def = sphere_def();
    def.mass.moments[2] = 5.0; /* 0.4 + 0.4 < 5 */
    return tb_scene_add_body(s, &def, NULL);
}
static tb_status set_state_zero_q(tb_scene *s)
{
    tb_body_state state;
    tb_scene_get_state(s, 0, &state);
    memset(state.q, 0, sizeof state.q);
    return tb_scene_set_state(s, 0, &state);
}
static tb_status set_state_nan(tb_scene *s)
{
    tb_body_state state;
    tb_scene_get_state(s, 0, &state);
    state.P[0] = NAN;
    return tb_scene_set_state(s, 0, &state);
}
static tb_status set_state_out_of_range(tb_scene *s)
{
    tb_body_state state;
    tb_scene_get_state(s, 0, &state);
    return tb_scene_set_state(s, 7, &state);
}
static tb_status set_velocity_nan(tb_scene *s)
{
    return tb_scene_set_velocity(s, 0, (double[]){0, 0, 0}, (double[]){0, NAN, 0});
}
static tb_status force_out_of_range(tb_scene *s)
{
    return tb_scene_add_force(s, 3, (double[]){1, 0, 0}, (double[]){0, 0, 0}, TB_FRAME_WORLD);
}
static tb_status force_bad_frame(tb_scene *s)
{
    return tb_scene_add_force(s, 0, (double[]){1, 0, 0}, (double[]){0, 0, 0}, (tb_frame)9);
}
static tb_status torque_infinite(tb_scene *s)
{
    return tb_scene_add_torque(s, 0, (double[]){INFINITY, 0, 0}, TB_FRAME_WORLD);
}
static tb_status gravity_nan(tb_scene *s)
{
    return tb_scene_add_gravity(s, (double[]){0, 0, NAN});
}
static tb_status gravity_null(tb_scene *s)
{
    return tb_scene_add_gravity(s, NULL);
}

static void test_bad_input_is_refused_and_changes_nothing(void **state)
{
    (void)state;
    static const refusal cases[] = {
        {"def left at default", add_default_def, TB_STATUS_INVALID_ARGUMENT, "def.mass.mass"},
        {"def not from default", add_without_default, TB_STATUS_INVALID_ARGUMENT,
         "tb_body_def_default"},
        {"zero quaternion", add_zero_quaternion, TB_STATUS_INVALID_ARGUMENT, "def.orientation"},
        {"non-unit quaternion", add_long_quaternion, TB_STATUS_INVALID_ARGUMENT, "|q| = 2"},
        {"NaN velocity", add_nan_velocity, TB_STATUS_NOT_FINITE, "def.velocity"},
        {"infinite position", add_infinite_position, TB_STATUS_NOT_FINITE, "def.position"},
        {"moments break triangle", add_broken_moments, TB_STATUS_BAD_MASS_PROPERTIES, "triangle"},
        {"state with zero q", set_state_zero_q, TB_STATUS_INVALID_ARGUMENT, "body 0: q"},
        {"state with NaN", set_state_nan, TB_STATUS_NOT_FINITE, "body 0"},
        {"state of body 7", set_state_out_of_range, TB_STATUS_OUT_OF_RANGE, "body id 7"},
        {"NaN angular velocity", set_velocity_nan, TB_STATUS_NOT_FINITE, "angular_velocity"},
        {"force on body 3", force_out_of_range, TB_STATUS_OUT_OF_RANGE, "body id 3"},
        {"force in frame 9", force_bad_frame, TB_STATUS_INVALID_ARGUMENT, "frame"},
        {"infinite torque", torque_infinite, TB_STATUS_NOT_FINITE, "torque"},
        {"NaN gravity", gravity_nan, TB_STATUS_NOT_FINITE, "g"},
        {"NULL gravity", gravity_null, TB_STATUS_NULL_POINTER, "g is NULL"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tb_scene *scene = new_scene(1);
        tb_body_def def = sphere_def();
        tb__v3_set(def.velocity, 1, 2, 3);
        assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
        double before[TB_STATE_SIZE];
        memcpy(before, tb_scene_states(scene), sizeof before);
        const tb_status status = cases[i].attempt(scene);
        print_message("%-24s -> %-20s %s\n", cases[i].label, tb_status_name(status),
                      tb_scene_detail(scene));
        assert_int_equal(status, cases[i].expected);
        assert_non_null(strstr(tb_scene_detail(scene), cases[i].named));
        assert_int_equal(tb_scene_body_count(scene), 1);
        assert_int_equal(tb_scene_effect_count(scene), 0);
        assert_memory_equal(tb_scene_states(scene), before, sizeof before);
        tb_scene_destroy(scene);
    }
}

static void test_empty_scene_and_null_handles_are_errors_not_crashes(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(0);
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "no bodies"));
    double energy = -1.0;
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states(scene), &energy), TB_STATUS_OK);
    assert_near(energy, 0.0, 0.0);
    tb_scene_destroy(scene);
    tb_scene_destroy(NULL);
    tb_integrator_destroy(NULL);
    assert_int_equal(tb_scene_add_body(NULL, NULL, NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_body_count(NULL), 0);
    assert_int_equal(tb_integrator_advance(NULL, 1.0), TB_STATUS_NULL_POINTER);
    tb_error error;
    tb_scene_def def = tb_scene_def_default();
    def.internal_cookie = 0;
    tb_scene *none = (tb_scene *)&def;
    assert_int_equal(tb_scene_create(&def, &none, &error), TB_STATUS_INVALID_ARGUMENT);
    assert_null(none);
    assert_non_null(strstr(error.message, "tb_scene_def_default"));
}

static tb_body_def sphere_of_mass(double mass)
{
    tb_body_def def = tb_body_def_default();
    def.mass.mass = mass;
    for (int k = 0; k < 3; ++k) {
        def.mass.moments[k] = 0.4 * mass * 0.01; /* a sphere of radius 0.1 m */
    }
    return def;
}

/* What set-up would make non-finite is refused, naming the field, and nothing is added or
 * changed: 1/M of a subnormal mass (refused by the mass range), P = M v and L = I omega that
 * overflow, in tb_scene_add_body and tb_scene_set_velocity. */
static void test_set_up_that_overflows_is_refused_naming_the_field(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = sphere_of_mass(5e-324);
    assert_int_not_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    assert_non_null(strstr(tb_scene_detail(scene), "mass"));
    def = sphere_of_mass(1e100);
    def.velocity[0] = 1e300;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_scene_detail(scene), "def.velocity"));
    def = sphere_of_mass(1.0);
    def.angular_velocity[1] = 1.7976931348623157e308; /* I omega = 4e-3 * 1.8e308 is finite */
    def.angular_velocity[0] = 1e10;
    def.mass.moments[0] = def.mass.moments[1] = def.mass.moments[2] = 10.0;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_scene_detail(scene), "def.angular_velocity"));
    assert_int_equal(tb_scene_body_count(scene), 0);

    def = sphere_of_mass(1e100);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_body_state before, after;
    tb_scene_get_state(scene, 0, &before);
    assert_int_equal(tb_scene_set_velocity(scene, 0, (double[]){0, 0, 1e300}, (double[]){0, 0, 0}),
                     TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_scene_detail(scene), "velocity: (0, 0, 1e+300) m/s: the momentum"));
    tb_scene_get_state(scene, 0, &after);
    assert_memory_equal(&before, &after, sizeof before);
    tb_scene_destroy(scene);

    /* P = M v finite but dx/dt = P / M not: 0.9 kg at -1.797e308 m/s (P = -1.6e308) */
    scene = new_scene(1);
    def = sphere_of_mass(0.9);
    def.velocity[0] = -1.7976931348623157e308;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_scene_detail(scene), "def.velocity"));
    def = sphere_of_mass(0.5);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_scene_get_state(scene, 0, &before);
    after = before;
    after.P[1] = 1e308; /* P / M = 2e308 */
    assert_int_equal(tb_scene_set_state(scene, 0, &after), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_scene_detail(scene), "P / M"));
    tb_scene_get_state(scene, 0, &after);
    assert_memory_equal(&before, &after, sizeof before);
    tb_scene_destroy(scene);
}

/* A body moved deep into a ground plane after the plane was added (10 m: it was launched at
 * 366 m/s) is refused when an integrator is made, naming the effect and the body. */
static void test_a_start_deep_in_the_ground_is_refused_at_integrator_creation(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = sphere_of_mass(1.0);
    def.position[2] = 1.0;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_contact_point point = {{0, 0, 0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_body_state s;
    tb_scene_get_state(scene, 0, &s);
    s.x[2] = -10.0;
    assert_int_equal(tb_scene_set_state(scene, 0, &s), TB_STATUS_OK);
    tb_integrator_def idef = tb_integrator_def_default();
    idef.dt = 0.0; /* the default step: 1/240 s is beyond the stiff contact's stability limit */
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &idef, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    print_message("%s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "(a ground)"));
    assert_null(integrator);
    tb_scene_destroy(scene);
}

/* The derivative and the renormalisation hook refuse a NULL state with a fatal (< 0) return,
 * whatever the body count, instead of reading through it. */
static void test_derivative_and_hook_refuse_a_null_state(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = sphere_of_mass(1.0);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    double dydt[TB_STATE_SIZE];
    assert_true(tb_scene_derivative(0.0, NULL, dydt, scene) < 0);
    assert_true(tb_scene_derivative(0.0, tb_scene_states(scene), NULL, scene) < 0);
    assert_true(tb_scene_normalize_quaternions(0.0, NULL, scene) < 0);
    assert_int_equal(tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene), 0);
    tb_scene_destroy(scene);
}

/* Every scene function clears the last failure's detail before it checks, so a NULL argument
 * is reported as itself, not as the failure before it. */
static void test_a_null_argument_replaces_the_previous_detail(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = sphere_of_mass(1.0);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
#define TB_EXPECT_NULL(call, name)                                                                 \
    do {                                                                                           \
        tb_scene_add_gravity(scene, (double[]){NAN, 0, 0});                                        \
        assert_non_null(strstr(tb_scene_detail(scene), "NaN"));                                    \
        assert_int_equal((call), TB_STATUS_NULL_POINTER);                                          \
        assert_non_null(strstr(tb_scene_detail(scene), name " is NULL"));                          \
    } while (0)
    size_t id;
    double dt;
    tb_ode_system system;
    tb_integrator *integrator = NULL;
    tb_integrator_def idef = tb_integrator_def_default();
    TB_EXPECT_NULL(tb_scene_add_body(scene, NULL, NULL), "def");
    TB_EXPECT_NULL(tb_scene_set_state(scene, 0, NULL), "state");
    TB_EXPECT_NULL(tb_scene_get_state(scene, 0, NULL), "out_state");
    TB_EXPECT_NULL(tb_scene_set_velocity(scene, 0, NULL, (double[]){0, 0, 0}), "velocity");
    TB_EXPECT_NULL(tb_scene_set_velocity(scene, 0, (double[]){0, 0, 0}, NULL), "angular_velocity");
    TB_EXPECT_NULL(tb_scene_get_mass(scene, 0, NULL), "out_mass");
    TB_EXPECT_NULL(tb_scene_find_body(scene, NULL, &id), "name");
    TB_EXPECT_NULL(tb_scene_ode_system(scene, NULL), "out_system");
    TB_EXPECT_NULL(tb_scene_max_stable_step(scene, TB_METHOD_RK4, NULL, NULL), "out_dt");
    TB_EXPECT_NULL(tb_scene_absolute_tolerances(scene, 1.0, NULL), "out_atol");
    TB_EXPECT_NULL(tb_scene_integrator_create(scene, NULL, 0.0, &integrator), "def");
    TB_EXPECT_NULL(tb_scene_integrator_create(scene, &idef, 0.0, NULL), "out_integrator");
#undef TB_EXPECT_NULL
    (void)dt;
    (void)system;
    tb_scene_destroy(scene);
}

/* A failed tb_scene_integrator_create leaves *out_integrator NULL, whatever it held. */
static void test_a_refused_integrator_is_null(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = (tb_integrator *)&def;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT); /* no bodies */
    assert_null(integrator);
    tb_scene_destroy(scene);
}

/* A start time so large that doubles near it are coarser than the step (at 1e15 s they are
 * 0.125 s apart, 30 steps of 1/240 s) is refused naming t0, instead of taking 0 s steps. The
 * limit is a spacing of 1e-6 dt: 1e9 s (spacing 1.2e-7 s) is refused at 1/240 s, 1e6 s
 * (1.2e-10 s) is not. */
static void test_a_start_time_too_coarse_for_the_step_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def body = sphere_of_mass(1.0);
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    const double refused[2] = {1e15, 1e9};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(tb_scene_integrator_create(scene, &def, refused[k], &integrator),
                         TB_STATUS_INVALID_ARGUMENT);
        assert_non_null(strstr(tb_scene_detail(scene), "t0: "));
    }
    assert_int_equal(tb_scene_integrator_create(scene, &def, 1e6, &integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    /* near t0 = 0 it is dt that cannot be resolved (5e-324 s: the spacing of doubles there) */
    def.dt = 5e-324;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "def.dt: 4.94066e-324 s is too small"));
    tb_scene_destroy(scene);
}

/* Names by hash: 20000 bodies named "b<i>" (and 20000 named by default) are each found at
 * their id, a duplicate is refused naming the body that has it, and an unknown name is
 * OUT_OF_RANGE with a detail. */
static void test_every_name_is_found_and_duplicates_are_refused(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = sphere_of_mass(1.0);
    char name[32];
    for (size_t i = 0; i < 40000; ++i) {
        snprintf(name, sizeof name, "b%zu", i);
        def.name = i % 2 == 0 ? name : NULL;
        assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    }
    for (size_t i = 0; i < 40000; ++i) {
        size_t id = SIZE_MAX;
        snprintf(name, sizeof name, i % 2 == 0 ? "b%zu" : "body%zu", i);
        assert_int_equal(tb_scene_find_body(scene, name, &id), TB_STATUS_OK);
        assert_int_equal(id, i);
    }
    def.name = "b400";
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "already body 400's name"));
    size_t id;
    assert_int_equal(tb_scene_find_body(scene, "b401", &id), TB_STATUS_OUT_OF_RANGE);
    assert_non_null(strstr(tb_scene_detail(scene), "b401"));
    assert_int_equal(tb_scene_body_count(scene), 40000);
    tb_scene_destroy(scene);
}

/* Read-outs by hand: a body of test_tilted_mass (centre of mass at c = (0.1, 0.2, 0.3) in its shape
 * frame) with orientation identity at x = (1, 2, 3), v = (0.5, 0, 0), omega = (0, 0, 2). A
 * point p of the shape frame is at x + (p - c) and moves at v + omega x (p - c); the shape
 * origin is p = 0. Turned 90 degrees about z, the shape frame sees omega_world = (1, 0, 2) as
 * (0, -1, 2). Tolerance 1e-12: a few roundings of numbers of order 1. */
static void test_body_points_and_body_frame_omega_read_as_by_hand(void **state)
{
    (void)state;
    tb_scene *scene = new_scene(1);
    tb_body_def def = tb_body_def_default();
    def.mass = test_tilted_mass();
    def.position[0] = 1, def.position[1] = 2, def.position[2] = 3;
    def.velocity[0] = 0.5;
    def.angular_velocity[2] = 2.0;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    const double *y = tb_scene_states_const(scene);
    const double p[3] = {1.0, -1.0, 0.5};
    const double arm[3] = {p[0] - 0.1, p[1] - 0.2, p[2] - 0.3};
    double position[3], velocity[3];
    assert_int_equal(tb_scene_body_point(scene, y, 0, p, position, velocity), TB_STATUS_OK);
    const double expected_velocity[3] = {0.5 - 2.0 * arm[1], 2.0 * arm[0], 0.0};
    for (int k = 0; k < 3; ++k) {
        assert_near(position[k], def.position[k] + arm[k], 1e-12);
        assert_near(velocity[k], expected_velocity[k], 1e-12);
    }
    assert_int_equal(tb_scene_body_shape_velocity(scene, y, 0, velocity), TB_STATUS_OK);
    assert_near(velocity[0], 0.5 - 2.0 * -0.2, 1e-12);
    assert_near(velocity[1], 2.0 * -0.1, 1e-12);
    assert_near(velocity[2], 0.0, 1e-12);
    assert_int_equal(tb_scene_body_point(scene, y, 0, NULL, position, NULL),
                     TB_STATUS_NULL_POINTER);
    assert_non_null(strstr(tb_scene_detail(scene), "point is NULL"));

    const double half = sqrt(0.5);
    tb_body_def turned = tb_body_def_default();
    turned.mass = test_tilted_mass();
    turned.orientation[0] = half, turned.orientation[3] = half;
    turned.angular_velocity[0] = 1.0, turned.angular_velocity[2] = 2.0;
    assert_int_equal(tb_scene_add_body(scene, &turned, NULL), TB_STATUS_OK);
    double omega[3];
    assert_int_equal(
        tb_scene_body_frame_angular_velocity(scene, tb_scene_states_const(scene), 1, omega),
        TB_STATUS_OK);
    assert_near(omega[0], 0.0, 1e-12);
    assert_near(omega[1], -1.0, 1e-12);
    assert_near(omega[2], 2.0, 1e-12);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_velocities_round_trip_through_momenta),
        cmocka_unit_test(test_shape_pose_round_trips),
        cmocka_unit_test(test_total_momenta_add_orbital_and_spin_parts),
        cmocka_unit_test(test_bad_input_is_refused_and_changes_nothing),
        cmocka_unit_test(test_empty_scene_and_null_handles_are_errors_not_crashes),
        cmocka_unit_test(test_set_up_that_overflows_is_refused_naming_the_field),
        cmocka_unit_test(test_derivative_and_hook_refuse_a_null_state),
        cmocka_unit_test(test_a_null_argument_replaces_the_previous_detail),
        cmocka_unit_test(test_a_refused_integrator_is_null),
        cmocka_unit_test(test_a_start_time_too_coarse_for_the_step_is_refused),
        cmocka_unit_test(test_every_name_is_found_and_duplicates_are_refused),
        cmocka_unit_test(test_body_points_and_body_frame_omega_read_as_by_hand),
        cmocka_unit_test(test_a_start_deep_in_the_ground_is_refused_at_integrator_creation),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
