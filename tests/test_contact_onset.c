/* Fixed steps end at contact onsets (src/ode/fixed_onset.c): a step across the instant a
 * contact switches on integrates the kink in its force with an error of order one in the
 * step, which friction through an impact shows plainly; located on the step's cubic Hermite
 * interpolant, the onset ends a step, and the impact is integrated by smooth steps as CVODE's
 * roots give it. */
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
#define RADIUS 0.1
#define MASS 2.0

/* y = exp(-t), y' = -y */
static int decay(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = -y[0];
    return 0;
}

/* y - 1/2: zero at t = ln 2 on y = exp(-t) */
static int half(double t, const double *y, double *g, void *ctx)
{
    (void)t, (void)ctx;
    g[0] = y[0] - 0.5;
    return 0;
}

/* A root function falling through zero ends a fixed step there, located on the step's cubic
 * Hermite interpolant to 6e-8 of the step: RK4 at h = 0.1 has y within 1e-6 relative of
 * exp(-t) (its global error, about h^4 / 120), and |y' / y| = 1, so the event time is within
 * 1e-6 of ln 2 plus the interpolant's own error (h^4 / 384 |y''''| = 3e-7): 2e-6 allows both.
 * The grid after it is kept: the step after the onset ends on 0.7, the next on 0.8. */
static void test_an_onset_ends_a_fixed_step_at_ln2(void **unused)
{
    (void)unused;
    double y = 1.0;
    tb_ode_system system = {
        .n = 1, .derivative = decay, .events = {.root_count = 1, .roots = half}};
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.1;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, &y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.7), TB_STATUS_OK);
    tb_integrator_events events;
    assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
    print_message("rk4 h = 0.1: y = 1/2 at %.12f (ln 2 = %.12f)\n", events.last_time, log(2.0));
    assert_int_equal(events.count, 1);
    assert_int_equal(events.last_root, 0);
    assert_int_equal(events.last_direction, -1);
    assert_true(fabs(events.last_time - log(2.0)) < 2e-6);
    tb_integrator_stats stats;
    assert_int_equal(tb_integrator_get_stats(integrator, &stats), TB_STATUS_OK);
    assert_int_equal(stats.steps, 8); /* 0.1 .. 0.6, the onset, 0.7 */
    assert_true(fabs(stats.last_step - (0.7 - events.last_time)) < 1e-12);
    assert_true(fabs(y - exp(-0.7)) < 1e-6);
    tb_integrator_destroy(integrator);
}

/* The ball of the tests: a solid sphere of radius 0.1 m and 2 kg, with the ground's defaults
 * but for the friction (mu_s = mu_k = 0.5, so the law through the slide is mu_k N alone). */
static tb_scene *ball_scene(const double x[3], const double v[3], const double omega[3])
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, MASS, RADIUS, &def.mass, NULL),
                     TB_STATUS_OK);
    memcpy(def.position, x, sizeof def.position);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = RADIUS;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_velocity(scene, id, v, omega), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = 0.5;
    ground.kinetic_friction = 0.5;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    return scene;
}

typedef struct motion {
    double v[3], omega[3];
} motion;

static motion motion_of(const tb_scene *scene)
{
    motion m;
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_body_velocity(scene, y, 0, m.v), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_angular_velocity(scene, y, 0, m.omega), TB_STATUS_OK);
    return m;
}

/* The ball lands at 2 m/s moving forward at 1 m/s with 50 rad/s of backspin: its contact point
 * slips forward at v_x - R omega_y = 6 m/s. While it slips, friction is mu_k N against the slip,
 * so over the impact the tangential impulse is mu_k times the normal one, J_n = m (dv_z + g T)
 * over the span T run (gravity is the only other vertical force), and the slip falls by
 * (1 + m R^2 / I) mu_k J_n / m = 3.5 mu_k (1 + e) v_n = 4.55 m/s at e = 0.3: it slips
 * throughout. The law: dv_x = -mu_k J_n / m, d omega_y = R' mu_k J_n / I, R' the lever arm
 * (R less the sinking, at most v_n / omega_n, omega_n = sqrt(g / penetration)). */
typedef struct landing {
    double v_x, omega_y, v_z;        /* as it leaves */
    double law_v_x, law_omega_y;     /* the law with the ball's own J_n and the arm R */
    double change_v_x, change_omega; /* the law's changes through the impact */
} landing;

static const double v_n = 2.0, v_x0 = 1.0, omega_y0 = -50.0, span = 0.02, mu_k = 0.5;

static landing land_with_backspin(tb_method method)
{
    tb_scene *scene = ball_scene((double[]){0, 0, RADIUS + 0.01}, (double[]){v_x0, 0, -v_n},
                                 (double[]){0, omega_y0, 0});
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, 1e-10);
    assert_int_equal(tb_integrator_advance(integrator, span), TB_STATUS_OK);
    const motion after = motion_of(scene);
    const double impulse = after.v[2] + v_n + G * span; /* J_n / m */
    const double inertia = 0.4 * RADIUS * RADIUS;       /* I / m */
    landing out = {after.v[0],
                   after.omega[1],
                   after.v[2],
                   0,
                   0,
                   -mu_k * impulse,
                   RADIUS * mu_k * impulse / inertia};
    out.law_v_x = v_x0 + out.change_v_x;
    out.law_omega_y = omega_y0 + out.change_omega;
    double dt = 0.0;
    assert_int_equal(tb_scene_default_step(scene, method, &dt), TB_STATUS_OK);
    print_message("%-11s (dt %.3g s) leaves at v_x %.7f m/s (law %.7f), omega_y %.6f rad/s "
                  "(law %.6f), v_z %.6f m/s\n",
                  tb_method_name(method), dt, out.v_x, out.law_v_x, out.omega_y, out.law_omega_y,
                  out.v_z);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* Every method: the friction impulse is mu_k times the normal one to 1e-6 m/s (friction is
 * mu_k N at every stage of a step while the point slips; the stick anchor's deflection builds
 * over presliding = 5e-7 m, 1e-7 s at 6 m/s of slip, short of mu_k N for that long: 1e-9 m/s),
 * and the spin is the law's with the arm R to within the sinking's share of it, v_n / omega_n / R
 * of the change. Against CVODE Adams at rtol 1e-10 (the same law, its error 1e-9 of the
 * state), each fixed method at its default step h is within its own error over the contact's
 * duration pi / omega_n: its relative error per radian of the contact's ringing, C (omega_n h)^p
 * for order p with the leading local-error constants C = 1/2, 1/6, 1/120 (Euler, midpoint,
 * RK4), times the contact's pi radians, times the change. Before the onsets were located RK4
 * was 1.5e-3 m/s and 0.037 rad/s off CVODE (5.5 times its bound): its step straddled the onset's
 * kink, an error of order one in h. */
static void test_a_ball_landing_with_backspin_leaves_by_the_friction_law(void **unused)
{
    (void)unused;
    const double omega_n = sqrt(G / tb_ground_def_default().penetration);
    const landing exact = land_with_backspin(TB_METHOD_CVODE_ADAMS);
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4};
    const double constants[] = {0.5, 1.0 / 6.0, 1.0 / 120.0};
    for (size_t k = 0; k < 3; ++k) {
        const landing got = land_with_backspin(methods[k]);
        assert_true(fabs(got.v_x - got.law_v_x) < 1e-6);
        const double arm = v_n / omega_n / RADIUS;
        assert_true(fabs(got.omega_y - got.law_omega_y) <= arm * fabs(got.change_omega));
        double h = 0.0;
        tb_scene *probe = ball_scene((double[]){0, 0, 1}, (double[]){0, 0, 0}, (double[]){0, 0, 0});
        assert_int_equal(tb_scene_default_step(probe, methods[k], &h), TB_STATUS_OK);
        tb_scene_destroy(probe);
        const int order = tb_method_order(methods[k]);
        const double relative = pow(omega_n * h, order) * constants[k] * 3.14159265358979323846;
        print_message("  off CVODE: v_x %.3g m/s (bound %.3g), omega_y %.3g rad/s (bound %.3g)\n",
                      got.v_x - exact.v_x, relative * fabs(exact.change_v_x),
                      got.omega_y - exact.omega_y, relative * fabs(exact.change_omega));
        assert_true(fabs(got.v_x - exact.v_x) <= relative * fabs(exact.change_v_x));
        assert_true(fabs(got.omega_y - exact.omega_y) <= relative * fabs(exact.change_omega));
    }
}

/* The scene's own system (tb_scene_ode_system) under a fixed-step method at dt, with its root
 * functions or with none (the fixed steps of before). */
static tb_integrator *scene_stepper(tb_scene *scene, tb_method method, double dt, bool roots)
{
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    assert_true(system.events.root_count > 0);
    if (!roots) {
        system.events.root_count = 0;
        system.events.roots = NULL;
        system.events.at_event = NULL;
    }
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    def.dt = dt;
    tb_integrator *integrator = NULL;
    assert_int_equal(
        tb_integrator_create(&system, &def, 0.0, tb_scene_states(scene), &integrator, NULL),
        TB_STATUS_OK);
    return integrator;
}

/* Where no onset falls inside a step, the steps are those of before, bit for bit: a ball
 * falling 0.44 m towards the ground 0.9 m below (its gap never closes) and a ball resting on it
 * (its gap never opens), over 0.3 s at each fixed method's default step. */
static void test_steps_without_an_onset_are_those_of_before_bit_for_bit(void **unused)
{
    (void)unused;
    const double heights[2] = {1.0, RADIUS - tb_ground_def_default().penetration};
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4};
    for (int k = 0; k < 2; ++k) {
        for (size_t m = 0; m < 3; ++m) {
            tb_scene *scenes[2];
            tb_integrator *integrators[2];
            for (int roots = 0; roots < 2; ++roots) {
                scenes[roots] = ball_scene((double[]){0, 0, heights[k]}, (double[]){0, 0, 0},
                                           (double[]){0, 0, 0});
                double dt = 0.0;
                assert_int_equal(tb_scene_default_step(scenes[roots], methods[m], &dt),
                                 TB_STATUS_OK);
                integrators[roots] = scene_stepper(scenes[roots], methods[m], dt, roots == 1);
                assert_int_equal(tb_integrator_advance(integrators[roots], 0.3), TB_STATUS_OK);
            }
            tb_integrator_events events;
            assert_int_equal(tb_integrator_get_events(integrators[1], &events), TB_STATUS_OK);
            assert_int_equal(events.count, 0);
            assert_memory_equal(tb_scene_states(scenes[0]), tb_scene_states(scenes[1]),
                                TB_STATE_SIZE * sizeof(double));
            for (int roots = 0; roots < 2; ++roots) {
                tb_integrator_destroy(integrators[roots]);
                tb_scene_destroy(scenes[roots]);
            }
        }
    }
}

/* The restitution a ball dropped 5 cm onto a soft ground (penetration 1 mm: the contact rings at
 * omega_n = 99 rad/s and lasts about 32 ms, 7.6 steps of 1/240 s) leaves with: its rebound speed
 * at the touching height, sqrt(v_z^2 + 2 g (z - R)) in flight, over its landing speed
 * sqrt(2 g 0.05). */
static double rebound(tb_method method, bool roots, double e)
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, MASS, RADIUS, &def.mass, NULL),
                     TB_STATUS_OK);
    def.position[2] = RADIUS + 0.05;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = RADIUS;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-3;
    ground.restitution = e;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = method == TB_METHOD_CVODE_ADAMS
                                    ? test_integrator_for(scene, method, 0.0, 1e-10)
                                    : scene_stepper(scene, method, 1.0 / 240.0, roots);
    assert_int_equal(tb_integrator_advance(integrator, 0.16), TB_STATUS_OK);
    const double *y = tb_scene_states_const(scene);
    const double z = y[TB_STATE_X + 2], v_z = y[TB_STATE_P + 2] / MASS;
    assert_true(z > RADIUS && v_z > 0.0); /* in flight, rising */
    const double ratio = sqrt(v_z * v_z + 2.0 * G * (z - RADIUS)) / sqrt(2.0 * G * 0.05);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return ratio;
}

/* RK4 at 1/240 s with the onsets located keeps e better than without, by the measure above; the
 * reference is CVODE Adams at rtol 1e-10 (gravity through the 32 ms contact moves the measured
 * ratio off e a little, the same for every method). */
static void test_a_bounce_at_1_240_s_keeps_e_better_with_onsets(void **unused)
{
    (void)unused;
    const double restitutions[2] = {0.5, 0.8};
    for (int k = 0; k < 2; ++k) {
        const double e = restitutions[k];
        const double exact = rebound(TB_METHOD_CVODE_ADAMS, true, e);
        const double located = rebound(TB_METHOD_RK4, true, e);
        const double straddled = rebound(TB_METHOD_RK4, false, e);
        print_message("e = %.1f: cvode-adams %.6f, rk4 at 1/240 s with onsets %.6f, without "
                      "%.6f\n",
                      e, exact, located, straddled);
        assert_true(fabs(located - exact) < fabs(straddled - exact));
    }
}

/* A box of edge lengths size at x, with its eight corners as ground points where points. */
static size_t signs_box(tb_scene *scene, const double size[3], const double x[3], bool points)
{
    const size_t id = test_add_box(scene, 0.05, size, x);
    tb_contact_point corners[8];
    size_t count = 0;
    if (points) {
        assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, id, corners, count, 4), TB_STATUS_OK);
    }
    return id;
}

/* x in [low, high) from a linear congruential generator (deterministic, portable). */
static double signs_uniform(unsigned long long *state, double low, double high)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return low + (high - low) * (double)(*state >> 11) / 9007199254740992.0;
}

/* Body id put at a random pose in y among the resting row: overlapping it, touching,
 * within the look-ahead (5 cm) and beyond it, turned at random. */
static void place_flyer(tb_scene *scene, double *y, size_t id, unsigned long long *rng)
{
    tb_body_state s;
    assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
    const double x[3] = {signs_uniform(rng, -0.06, 0.36), signs_uniform(rng, -0.08, 0.08),
                         signs_uniform(rng, -0.01, 0.12)};
    double q[4], norm = 0.0;
    for (int k = 0; k < 4; ++k) {
        q[k] = signs_uniform(rng, -1.0, 1.0);
        norm += q[k] * q[k];
    }
    for (int k = 0; k < 3; ++k) {
        y[TB_STATE_SIZE * id + TB_STATE_X + k] = x[k];
    }
    for (int k = 0; k < 4; ++k) {
        y[TB_STATE_SIZE * id + TB_STATE_Q + k] = q[k] / sqrt(norm);
    }
}

/* The fixed-step onset search reads only the roots' signs, and a scene gives it root_signs,
 * which pass over the pairs that cannot change one (src/effects/effect_contact_events.c): each
 * must be above zero exactly where roots' is, with no tolerance (one sign changed would end a
 * step elsewhere). Seven 4 cm boxes rest asleep in a row on the ground (four with corner points,
 * three by their shapes), two boxes thrown up from far away are awake; the flyers are put at
 * 600 random poses among the row (into it, touching, within the look-ahead, beyond, into the
 * ground), where both kinds of root (gaps, and wake gaps to the asleep row) are seen on both
 * sides of zero. */
static void test_root_signs_are_the_roots_signs(void **unused)
{
    (void)unused;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    const double cube[3] = {0.04, 0.04, 0.04}, slab[3] = {0.05, 0.03, 0.02};
    for (int k = 0; k < 7; ++k) {
        signs_box(scene, cube, (double[]){0.05 * k, 0.0, 0.02}, k % 2 == 0);
    }
    const size_t flyers[2] = {signs_box(scene, slab, (double[]){1.0, 0.0, 0.5}, true),
                              signs_box(scene, cube, (double[]){1.3, 0.0, 0.5}, false)};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(tb_scene_set_velocity(scene, flyers[k], (double[]){0, 0, 3.0},
                                               (double[]){1.0, 2.0, 0.0}),
                         TB_STATUS_OK);
    }
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-5; /* a longer default step: the test is about signs, not depths */
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = 1e-5;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_sleeping(scene, true), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 0.65), TB_STATUS_OK);
    size_t asleep = 0;
    assert_int_equal(tb_scene_asleep_count(scene, &asleep), TB_STATUS_OK);
    assert_int_equal(asleep, 7); /* the row; the flyers are still in the air */
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    assert_non_null(system.events.root_signs);
    const size_t n = system.n, count = system.events.root_count, bodies = 9;
    assert_int_equal(count, 2 * bodies); /* gaps, then wake gaps */
    double *y = malloc(n * sizeof *y), *g = malloc(count * sizeof *g);
    double *signs = malloc(count * sizeof *signs);
    assert_true(y != NULL && g != NULL && signs != NULL);
    memcpy(y, tb_scene_states_const(scene), n * sizeof *y);
    unsigned long long rng = 23, seen[2][2] = {{0, 0}, {0, 0}}; /* [gap, wake][above, not] */
    for (int trial = 0; trial < 600; ++trial) {
        for (int k = 0; k < 2; ++k) {
            place_flyer(scene, y, flyers[k], &rng);
        }
        assert_int_equal(system.events.roots(0.65, y, g, system.ctx), 0);
        assert_int_equal(system.events.root_signs(0.65, y, signs, system.ctx), 0);
        for (size_t i = 0; i < count; ++i) {
            assert_int_equal(g[i] > 0.0, signs[i] > 0.0);
        }
        for (int k = 0; k < 2; ++k) {
            seen[0][!(g[flyers[k]] > 0.0)]++;
            seen[1][!(g[bodies + flyers[k]] > 0.0)]++;
        }
    }
    print_message("flyers' gaps above 0 / not: %llu / %llu; wake gaps %llu / %llu\n", seen[0][0],
                  seen[0][1], seen[1][0], seen[1][1]);
    for (int kind = 0; kind < 2; ++kind) {
        assert_true(seen[kind][0] >= 50 && seen[kind][1] >= 50);
    }
    free(y), free(g), free(signs);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A user's event added to a scene's system (its roots wrapped): the scene's root_signs answer
 * for the scene's roots only, so the onset search must call the user's roots. The event 0.3 - t
 * falls through zero once before 0.35 s, where the ball (1 m up) is still falling: exactly one
 * event, at 0.3 s, located on RK4's interpolant of a linear function (exact but for rounding:
 * 1e-9). Before root_signs_for the search read the scene's signs alone and never found it (the
 * user's slot unwritten). */
static tb_ode_system scene_system;

static int user_roots(double t, const double *y, double *g, void *ctx)
{
    const int rc = scene_system.events.roots(t, y, g, ctx);
    g[scene_system.events.root_count] = 0.3 - t;
    return rc;
}

static void test_a_users_event_added_to_a_scenes_roots_is_found(void **unused)
{
    (void)unused;
    tb_scene *scene = test_empty_scene();
    test_add_ball(scene, "ball", MASS, RADIUS, (double[]){0, 0, 1.0}, (double[]){0, 0, 0});
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_scene_ode_system(scene, &scene_system), TB_STATUS_OK);
    assert_non_null(scene_system.events.root_signs);
    tb_ode_system system = scene_system;
    system.events.root_count = scene_system.events.root_count + 1;
    system.events.roots = user_roots;
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_RK4), TB_STATUS_OK);
    def.dt = 0.007;
    tb_integrator *integrator = NULL;
    assert_int_equal(
        tb_integrator_create(&system, &def, 0.0, tb_scene_states(scene), &integrator, NULL),
        TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.35), TB_STATUS_OK);
    tb_integrator_events events;
    assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
    assert_int_equal(events.count, 1);
    assert_int_equal(events.last_root, (long)scene_system.events.root_count);
    assert_true(fabs(events.last_time - 0.3) < 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_an_onset_ends_a_fixed_step_at_ln2),
        cmocka_unit_test(test_a_ball_landing_with_backspin_leaves_by_the_friction_law),
        cmocka_unit_test(test_steps_without_an_onset_are_those_of_before_bit_for_bit),
        cmocka_unit_test(test_a_bounce_at_1_240_s_keeps_e_better_with_onsets),
        cmocka_unit_test(test_root_signs_are_the_roots_signs),
        cmocka_unit_test(test_a_users_event_added_to_a_scenes_roots_is_found),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
