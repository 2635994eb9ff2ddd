/* Body kinds: static and keyframed bodies (no state, infinite mass) touch dynamic ones through
 * the contact pipeline, and every call that would change a body with no state is refused with
 * nothing changed. The physics: a ball at rest on a finite static table sinks by the contact's
 * static deflection, and a ball sliding off its edge follows the ballistic arc from the edge. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "scene/scene_internal.h" /* tb__scene_set_body_motion_source */
#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
/* A soft contact (omega = sqrt(g / penetration) = 99 rad/s) so that fixed steps of 1 ms
 * resolve it cheaply; the static deflection M g / k of one point is this penetration. */
#define PENETRATION 1e-3
#define BALL_RADIUS 0.05
#define TABLE_SIZE_X 1.2
#define TABLE_SIZE_Y 0.8
#define TABLE_HEIGHT 0.75

/* A static box-shaped table (1.2 x 0.8 x 0.75 m) standing on z = 0, its top at z = 0.75. */
static size_t add_table(tb_scene *scene)
{
    tb_body_def def = tb_body_def_default();
    def.name = "table";
    def.motion = TB_MOTION_STATIC;
    def.position[2] = 0.5 * TABLE_HEIGHT;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = TABLE_SIZE_X;
    shape.size[1] = TABLE_SIZE_Y;
    shape.size[2] = TABLE_HEIGHT;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

/* Gravity, the table (body 0) and a 1 kg ball (body 1) at x moving at v, with a contact
 * effect over every body (restitution 0.3, the given friction). */
static tb_scene *table_and_ball(const double x[3], const double v[3], double friction)
{
    tb_scene *scene = test_empty_scene();
    add_table(scene);
    test_add_ball(scene, "ball", 1.0, BALL_RADIUS, x, v);
    const double g[3] = {0, 0, -G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = PENETRATION;
    contact.static_friction = friction;
    contact.kinetic_friction = friction;
    contact.presliding = 1e-4; /* a friction spring as soft as the normal one */
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

static void ball_position(const tb_scene *scene, double out[3])
{
    tb_body_state state;
    assert_int_equal(tb_scene_get_state(scene, 1, &state), TB_STATUS_OK);
    memcpy(out, state.x, sizeof state.x);
}

/* The methods each physics test runs under: fixed ones at the scene's default step (dt 0),
 * which the stability guard sizes with the table counted infinitely heavy; adaptive ones at
 * rtol 1e-7 (their atol from the bodies, scaled by rtol: 1e-7 of the ball's 2 cm radius of
 * gyration, far below the millimetre bounds below). */
typedef struct method_case {
    tb_method method;
    double dt, rtol;
} method_case;

static const method_case methods[] = {
    {TB_METHOD_EULER, 0.0, 0.0},        {TB_METHOD_MIDPOINT, 0.0, 0.0},   {TB_METHOD_RK4, 0.0, 0.0},
    {TB_METHOD_CVODE_ADAMS, 0.0, 1e-7}, {TB_METHOD_CVODE_BDF, 0.0, 1e-7},
};

static void test_static_body_has_no_state_and_reads_as_its_pose(void **state)
{
    (void)state;
    const double x[3] = {0.0, 0.0, 1.0};
    tb_scene *scene = table_and_ball(x, NULL, 0.5);
    /* the state array holds the one dynamic body: the ball, in slot 0 */
    size_t slot = 0;
    assert_int_equal(tb_scene_body_slot(scene, 0, &slot), TB_STATUS_OK);
    assert_true(slot == TB_NO_SLOT);
    assert_int_equal(tb_scene_body_slot(scene, 1, &slot), TB_STATUS_OK);
    assert_int_equal(slot, 0);
    tb_body_motion kind = TB_MOTION_DYNAMIC;
    assert_int_equal(tb_scene_body_motion_kind(scene, 0, &kind), TB_STATUS_OK);
    assert_int_equal(kind, TB_MOTION_STATIC);
    /* its pose and zero momenta; a frame row like any body's */
    tb_body_state table;
    assert_int_equal(tb_scene_get_state(scene, 0, &table), TB_STATUS_OK);
    assert_true(table.x[2] == 0.5 * TABLE_HEIGHT && table.q[0] == 1.0);
    assert_true(table.P[0] == 0.0 && table.P[1] == 0.0 && table.P[2] == 0.0);
    double values[2 * TB_FRAME_VALUES];
    assert_int_equal(tb_scene_frame_values(scene, tb_scene_states(scene), values), TB_STATUS_OK);
    assert_true(values[2] == 0.5 * TABLE_HEIGHT && values[3] == 1.0);
    for (int k = 7; k < 13; ++k) {
        assert_true(values[k] == 0.0); /* at rest */
    }
    assert_true(values[TB_FRAME_VALUES + 2] == 1.0); /* the ball's row after it */
    tb_scene_destroy(scene);
}

/* Released 0.1 mm above the table top, the ball settles where its weight is carried: its
 * centre at top + radius - M g / k, k = M g / penetration (one manifold point), so sunk by the
 * penetration. Tolerance 2 % of it: what is left of the bounce after 1.5 s (the damped mode
 * decays as exp(-zeta omega t), far below) plus the step's error on the spring's equilibrium
 * (none: the equilibrium is a fixed point of every method); the ball also falls asleep, at
 * rest on a body that never sleeps. */
static void test_ball_rests_on_static_table_at_its_static_deflection(void **state)
{
    (void)state;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        const double x[3] = {0.1, 0.05, TABLE_HEIGHT + BALL_RADIUS + 1e-4};
        tb_scene *scene = table_and_ball(x, NULL, 0.5);
        tb_integrator *integrator =
            test_integrator_for(scene, methods[m].method, methods[m].dt, methods[m].rtol);
        for (int frame = 1; frame <= 30; ++frame) { /* outputs: the sleep boundaries */
            assert_int_equal(tb_integrator_advance(integrator, 0.05 * frame), TB_STATUS_OK);
        }
        double p[3];
        ball_position(scene, p);
        const double expected = TABLE_HEIGHT + BALL_RADIUS - PENETRATION;
        if (fabs(p[2] - expected) > 0.02 * PENETRATION) {
            fail_msg("%s: the ball rests at z = %.9g m, expected %.9g m",
                     tb_method_name(methods[m].method), p[2], expected);
        }
        /* asleep on a body that never sleeps (an adaptive method applies the decision of an
         * output at its next advance) */
        assert_int_equal(tb_integrator_advance(integrator, 1.6), TB_STATUS_OK);
        bool asleep = false;
        assert_int_equal(tb_scene_body_asleep(scene, 1, &asleep), TB_STATUS_OK);
        assert_true(asleep);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* Sliding without friction at 2 m/s along x on the table top, the ball leaves the edge
 * (x = 0.6 m) when its centre passes it: the edge would have to pull to keep it on a circle
 * of radius r (v^2 / r = 80 m/s^2 > g). From there it falls freely: at t_e + s it is at
 * x = 0.6 + v s, z = z0 - g s^2 / 2. Checked at s = 0.3 s (a fall of 0.44 m): within 3 mm,
 * the penetration-sized push of the edge's corner while the ball leaves it (a few ms of a
 * force below M g) and the start's settling, each under 1 mm; under Euler plus its own
 * error g s h / 2 on the fall. */
static void test_ball_slides_off_static_table_on_the_ballistic_arc(void **state)
{
    (void)state;
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        const double speed = 2.0, start = 0.2;
        const double z0 = TABLE_HEIGHT + BALL_RADIUS - PENETRATION;
        const double x[3] = {start, 0.0, z0}, v[3] = {speed, 0.0, 0.0};
        tb_scene *scene = table_and_ball(x, v, 0.0);
        double h = 0.0; /* the step a fixed method takes: the default, at the start */
        assert_int_equal(tb_scene_default_step(scene, methods[m].method, &h), TB_STATUS_OK);
        tb_integrator *integrator =
            test_integrator_for(scene, methods[m].method, methods[m].dt, methods[m].rtol);
        const double edge_time = (0.5 * TABLE_SIZE_X - start) / speed, s = 0.3;
        assert_int_equal(tb_integrator_advance(integrator, edge_time + s), TB_STATUS_OK);
        double p[3];
        ball_position(scene, p);
        const double expected_x = 0.5 * TABLE_SIZE_X + speed * s;
        const double expected_z = z0 - 0.5 * G * s * s;
        /* Euler's own error on a constant acceleration, exactly g t h / 2 after t */
        const double euler = methods[m].method == TB_METHOD_EULER ? 0.5 * G * s * h : 0.0;
        if (fabs(p[0] - expected_x) > 3e-3 || fabs(p[2] - expected_z) > 3e-3 + euler) {
            fail_msg("%s: the ball is at (%.6g, %.6g) m, the arc says (%.6g, %.6g) m",
                     tb_method_name(methods[m].method), p[0], p[2], expected_x, expected_z);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The scene's observable contents, to compare byte for byte around a refused call. */
typedef struct snapshot {
    size_t bodies, size, effects;
    double states[64];
} snapshot;

static snapshot take(tb_scene *scene)
{
    snapshot s;
    memset(&s, 0, sizeof s);
    s.bodies = tb_scene_body_count(scene);
    s.size = tb_scene_state_size(scene);
    s.effects = tb_scene_effect_count(scene);
    assert_true(s.size <= 64);
    memcpy(s.states, tb_scene_states(scene), s.size * sizeof(double));
    return s;
}

/* Each refusal: TB_STATUS_INVALID_ARGUMENT, a detail naming the body (or the field), and the
 * scene as it was, byte for byte. */
static void test_changes_to_bodies_without_state_are_refused(void **state)
{
    (void)state;
    const double x[3] = {0.0, 0.0, 1.0};
    tb_scene *scene = table_and_ball(x, NULL, 0.5);
    const snapshot before = take(scene);
    tb_body_def bad_kind = tb_body_def_default();
    bad_kind.motion = (tb_body_motion)7;
    tb_body_def moving_static = tb_body_def_default();
    moving_static.motion = TB_MOTION_STATIC;
    moving_static.velocity[1] = 0.5;
    tb_body_def spinning_static = moving_static;
    spinning_static.velocity[1] = 0.0;
    spinning_static.angular_velocity[2] = 1.0;
    tb_body_state table_state;
    assert_int_equal(tb_scene_get_state(scene, 0, &table_state), TB_STATUS_OK);
    const double v[3] = {1, 0, 0}, zero[3] = {0, 0, 0};
    const struct {
        const char *what, *detail;
        tb_status status;
    } refusals[] = {
        {"bad kind", "def.motion", tb_scene_add_body(scene, &bad_kind, NULL)},
        {"static with a velocity", "def.velocity", tb_scene_add_body(scene, &moving_static, NULL)},
        {"static spinning", "def.angular_velocity",
         tb_scene_add_body(scene, &spinning_static, NULL)},
        {"set_state", "table", tb_scene_set_state(scene, 0, &table_state)},
        {"set_velocity", "table", tb_scene_set_velocity(scene, 0, v, zero)},
        {"force", "table", tb_scene_add_force(scene, 0, v, zero, TB_FRAME_WORLD)},
        {"torque", "table", tb_scene_add_torque(scene, 0, v, TB_FRAME_WORLD)},
    };
    for (size_t k = 0; k < sizeof refusals / sizeof refusals[0]; ++k) {
        if (refusals[k].status != TB_STATUS_INVALID_ARGUMENT) {
            fail_msg("%s: status %d", refusals[k].what, (int)refusals[k].status);
        }
        const snapshot after = take(scene);
        if (memcmp(&before, &after, sizeof before) != 0) {
            fail_msg("%s: the scene changed", refusals[k].what);
        }
    }
    /* the detail of the last one names the body and its kind */
    assert_non_null(strstr(tb_scene_detail(scene), "static"));
    assert_int_equal(tb_scene_add_torque(scene, 0, v, TB_FRAME_WORLD), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "\"table\""));
    tb_scene_destroy(scene);
}

/* A scene of static bodies alone has nothing to integrate. */
static void test_scene_of_static_bodies_alone_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_table(scene);
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "dynamic"));
    tb_scene_destroy(scene);
}

/* --- keyframed bodies driven by a C callback ------------------------------------------------ */

/* A motion along z (or y) of piecewise constant acceleration: C1 (velocity continuous). */
typedef struct segment {
    double t0, t1, a; /* s, s, m/s^2 */
} segment;

typedef struct profile {
    const segment *segments;
    size_t count;
    double start[3]; /* position at t = 0 */
    double v0;       /* velocity at t = 0 along axis */
    int axis;        /* 1: y, 2: z */
} profile;

/* The platform: at rest, rises at 1 m/s, stops, descends at 1 m/s, stops; each change of speed
 * at 5 m/s^2 (less than g, so that the box is never left behind when it slows down). */
static const segment platform_segments[] = {
    {0.2, 0.4, 5.0}, {0.8, 1.0, -5.0}, {1.1, 1.3, -5.0}, {1.6, 1.8, 5.0}};

static int profile_motion(double t, void *ctx, tb_body_motion_sample *out)
{
    const profile *p = ctx;
    double x = 0.0, v = p->v0, a = 0.0, last = 0.0;
    for (size_t k = 0; k < p->count; ++k) {
        const segment *s = &p->segments[k];
        const double coast = fmin(t, s->t0) - last; /* at constant speed up to the segment */
        if (coast > 0.0) {
            x += v * coast;
            last += coast;
        }
        if (t <= s->t0) {
            break;
        }
        const double dt = fmin(t, s->t1) - s->t0;
        x += v * dt + 0.5 * s->a * dt * dt;
        v += s->a * dt;
        last = s->t0 + dt;
        a = t < s->t1 ? s->a : 0.0;
    }
    if (t > last) {
        x += v * (t - last);
    }
    memset(out, 0, sizeof *out);
    memcpy(out->position, p->start, sizeof p->start);
    out->position[p->axis] += x;
    out->orientation[0] = 1.0;
    out->velocity[p->axis] = v;
    out->acceleration[p->axis] = a;
    return 0;
}

/* Adds a keyframed box of size (m) driven by p (NULL: set its motion later); returns its id. */
static size_t add_keyframed_box(tb_scene *scene, const char *name, const double size[3], profile *p)
{
    tb_body_def def = tb_body_def_default();
    def.name = name;
    def.motion = TB_MOTION_KEYFRAMED;
    if (p != NULL) {
        memcpy(def.position, p->start, sizeof def.position);
    }
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof shape.size);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    if (p != NULL) {
        assert_int_equal(tb_scene_set_body_motion_fn(scene, id, profile_motion, p), TB_STATUS_OK);
    }
    return id;
}

/* A 1 kg box (0.2 x 0.2 x 0.1 m) on the platform (1 x 1 x 0.1 m, its top at z = 0.05 at
 * rest). The box never loses contact: the force it puts on the platform (the platform's
 * reaction read-out) points down at every output. While the platform rises at constant speed
 * (0.55 s to 0.8 s, after the ramp's ringing has died: zeta omega = 36 1/s) the box sinks into it
 * by M g / k = penetration (the four manifold points share k = M g / penetration), within 10 %;
 * at rest again (1.05 s) it has risen with it, 0.6 m. Steps: the fixed ones at the default step,
 * CVODE at rtol 1e-7 (atol 1e-7 of the box's 8 cm radius of gyration: far below the 0.1 mm
 * asked); outputs every 5 ms. */
static void check_box_rides_platform(tb_method method, double rtol)
{
    profile p = {platform_segments, 4, {0.0, 0.0, 0.0}, 0.0, 2};
    tb_scene *scene = test_empty_scene();
    const double platform_size[3] = {1.0, 1.0, 0.1};
    const size_t platform = add_keyframed_box(scene, "platform", platform_size, &p);
    tb_body_def def = tb_body_def_default();
    def.name = "box";
    const double box_size[3] = {0.2, 0.2, 0.1};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, box_size, &def.mass, NULL), TB_STATUS_OK);
    def.position[2] = 0.1 - PENETRATION;
    size_t box = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &box), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, box_size, sizeof shape.size);
    assert_int_equal(tb_scene_set_body_shape(scene, box, &shape), TB_STATUS_OK);
    const double g[3] = {0, 0, -G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = PENETRATION;
    contact.presliding = 1e-4;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, rtol);
    double worst = 0.0;
    for (int frame = 1; frame <= 210; ++frame) {
        const double t = 0.005 * frame;
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        assert_true(fabs(tb_scene_time(scene) - t) < 1e-12);
        double force[3], torque[3];
        assert_int_equal(
            tb_scene_body_reaction(scene, tb_scene_states(scene), platform, force, torque),
            TB_STATUS_OK);
        if (!(force[2] < 0.0)) {
            fail_msg("%s: t = %g s: the box pushes the platform with %g N", tb_method_name(method),
                     t, -force[2]);
        }
        tb_body_state b, q;
        assert_int_equal(tb_scene_get_state(scene, box, &b), TB_STATUS_OK);
        assert_int_equal(tb_scene_get_state(scene, platform, &q), TB_STATUS_OK);
        const double sinking = q.x[2] + 0.1 - b.x[2];
        if (t >= 0.55 && t <= 0.8) {
            worst = fmax(worst, fabs(sinking / PENETRATION - 1.0));
        }
        if (frame == 210) { /* at rest, 0.6 m up */
            assert_true(fabs(q.x[2] - 0.6) < 1e-12);
            assert_true(fabs(sinking - PENETRATION) < 0.1 * PENETRATION);
        }
    }
    print_message("%s: sinking within %.2f %% of the static deflection\n", tb_method_name(method),
                  100.0 * worst);
    assert_true(worst < 0.1);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_box_rides_a_keyframed_platform_at_its_static_deflection(void **state)
{
    (void)state;
    check_box_rides_platform(TB_METHOD_RK4, 0.0);
    check_box_rides_platform(TB_METHOD_MIDPOINT, 0.0);
    check_box_rides_platform(TB_METHOD_CVODE_BDF, 1e-7);
}

/* A keyframed paddle (0.4 x 0.05 x 0.3 m) sweeping along y at 10 m/s meets a 2 cm ball (10 g)
 * at rest, restitution 0.5, no gravity. The paddle is infinitely heavy: in its frame the ball
 * comes in at 10 m/s and leaves at e times that, so in the world at (1 + e) 10 m/s = 15 m/s,
 * within the law's 5 % of e (test_balls_separate_at_e_times_their_approach_speed: 0.25 m/s),
 * and it never passes through (it ends ahead of the paddle). */
static void check_paddle_hits_ball(tb_method method, double rtol)
{
    profile p = {NULL, 0, {0.0, -0.2, 0.0}, 10.0, 1};
    tb_scene *scene = test_empty_scene();
    const double paddle_size[3] = {0.4, 0.05, 0.3};
    const size_t paddle = add_keyframed_box(scene, "paddle", paddle_size, &p);
    const double x[3] = {0, 0, 0};
    const size_t ball = test_add_ball(scene, "ball", 0.01, 0.01, x, NULL);
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = 0.5;
    contact.static_friction = contact.kinetic_friction = 0.0;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, rtol);
    assert_int_equal(tb_integrator_advance(integrator, 0.06), TB_STATUS_OK);
    double v[3];
    assert_int_equal(tb_scene_body_velocity(scene, tb_scene_states(scene), ball, v), TB_STATUS_OK);
    tb_body_state b, q;
    assert_int_equal(tb_scene_get_state(scene, ball, &b), TB_STATUS_OK);
    assert_int_equal(tb_scene_get_state(scene, paddle, &q), TB_STATUS_OK);
    print_message("%s: the ball leaves at %.4f m/s\n", tb_method_name(method), v[1]);
    assert_true(b.x[1] > q.x[1] + 0.025); /* ahead of the paddle's face */
    assert_true(fabs(v[1] - 15.0) < 0.25);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_keyframed_paddle_sends_ball_off_at_one_plus_e_its_speed(void **state)
{
    (void)state;
    check_paddle_hits_ball(TB_METHOD_RK4, 0.0);
    check_paddle_hits_ball(TB_METHOD_CVODE_BDF, 1e-7);
}

/* A motion function on a body that is not keyframed is refused, naming it; nothing changes. */
static void test_motion_fn_needs_a_keyframed_body(void **state)
{
    (void)state;
    const double x[3] = {0.0, 0.0, 1.0};
    tb_scene *scene = table_and_ball(x, NULL, 0.5);
    const snapshot before = take(scene);
    profile p = {NULL, 0, {0, 0, 0}, 0.0, 2};
    assert_int_equal(tb_scene_set_body_motion_fn(scene, 0, profile_motion, &p),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "\"table\") is static"));
    assert_int_equal(tb_scene_set_body_motion_fn(scene, 1, profile_motion, &p),
                     TB_STATUS_INVALID_ARGUMENT);
    const snapshot after = take(scene);
    assert_memory_equal(&before, &after, sizeof before);
    tb_scene_destroy(scene);
}

/* A motion source that notes whether it was asked at the break time exactly. */
typedef struct break_probe {
    double at;
    int hits;
} break_probe;

static int probe_motion(double t, void *ctx, tb_body_motion_sample *out)
{
    break_probe *probe = ctx;
    probe->hits += t == probe->at;
    memset(out, 0, sizeof *out);
    out->orientation[0] = 1.0;
    out->position[2] = t < probe->at ? 0.0 : t - probe->at; /* C0 there: a kink */
    out->velocity[2] = t < probe->at ? 0.0 : 1.0;
    return 0;
}

static void release_probe(void *ctx)
{
    ((break_probe *)ctx)->hits = -1000; /* seen by the test after destroy */
}

/* A break time (a key time, where the motion is only C1) ends a fixed step and is where CVODE
 * stops and restarts: each method evaluates the derivative at the break time itself (a step
 * starts there), though 0.1234 s is on no step grid. The scene owns the source's ctx: it is
 * released at destroy. */
static void test_steps_end_on_break_times(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_EULER, TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS,
                                          TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 4; ++m) {
        break_probe probe = {0.1234, 0};
        tb_scene *scene = test_empty_scene();
        tb_body_def def = tb_body_def_default();
        def.motion = TB_MOTION_KEYFRAMED;
        size_t id = 0;
        assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
        const double x[3] = {0, 0, 5};
        test_add_ball(scene, "ball", 1.0, 0.1, x, NULL);
        const double g[3] = {0, 0, -G};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        tb_spring_def spring = tb_spring_def_default(); /* of no stiffness: it only couples */
        spring.body_a = 1;
        spring.body_b = id;
        assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
        const double breaks[1] = {probe.at};
        assert_int_equal(tb__scene_set_body_motion_source(scene, id, probe_motion, &probe, breaks,
                                                          1, release_probe),
                         TB_STATUS_OK);
        const bool fixed = !tb_method_is_adaptive(methods_to_check[m]);
        tb_integrator *integrator =
            test_integrator_for(scene, methods_to_check[m], fixed ? 0.01 : 0.0, 1e-8);
        assert_int_equal(tb_integrator_advance(integrator, 0.3), TB_STATUS_OK);
        if (probe.hits < 1) {
            fail_msg("%s: no derivative at the break", tb_method_name(methods_to_check[m]));
        }
        /* the ball falls freely all the same: z = 5 - g t^2 / 2 */
        tb_body_state b;
        assert_int_equal(tb_scene_get_state(scene, 1, &b), TB_STATUS_OK);
        assert_true(fabs(b.x[2] - (5.0 - 0.5 * G * 0.09)) < (fixed ? 0.5 * G * 0.3 * 0.01 : 1e-6));
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
        assert_int_equal(probe.hits, -1000);
    }
}

/* Two balls resting far apart on the static table sleep each on its own island: the table joins
 * none (else every body on it would be one island), so waking one (a new velocity) leaves the
 * other asleep. */
static void test_balls_on_a_static_table_sleep_on_their_own_islands(void **state)
{
    (void)state;
    const double a[3] = {-0.4, 0.0, TABLE_HEIGHT + BALL_RADIUS - PENETRATION};
    const double b[3] = {0.4, 0.0, a[2]};
    tb_scene *scene = test_empty_scene();
    add_table(scene);
    test_add_ball(scene, "ball", 1.0, BALL_RADIUS, a, NULL);
    const size_t other = test_add_ball(scene, "other", 1.0, BALL_RADIUS, b, NULL);
    const double g[3] = {0, 0, -G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = PENETRATION;
    contact.presliding = 1e-4;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    for (int frame = 1; frame <= 20; ++frame) { /* outputs: the sleep boundaries */
        assert_int_equal(tb_integrator_advance(integrator, 0.05 * frame), TB_STATUS_OK);
    }
    bool asleep[2] = {false, false};
    assert_int_equal(tb_scene_body_asleep(scene, 1, &asleep[0]), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_asleep(scene, other, &asleep[1]), TB_STATUS_OK);
    assert_true(asleep[0] && asleep[1]);
    const double v[3] = {0.1, 0, 0}, zero[3] = {0, 0, 0};
    assert_int_equal(tb_scene_set_velocity(scene, 1, v, zero), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_asleep(scene, 1, &asleep[0]), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_asleep(scene, other, &asleep[1]), TB_STATUS_OK);
    assert_false(asleep[0]);
    assert_true(asleep[1]);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A ball asleep on the static table, and a keyframed paddle that stands still until 0.7 s and
 * then sweeps toward it at 0.5 m/s: every dynamic body asleep, yet the run must keep stepping
 * (a fixed-step method jumps over time only where nothing moves by time, tb__scene_rest_until),
 * so the paddle meets the ball, wakes it and pushes it ahead. The hit at v = 0.5 m/s goes at
 * most v / omega deep, omega = sqrt(g / penetration) the law's undamped oscillation (its
 * dashpot only shortens it): 5.05 mm at every 10 ms output to 1.5 s; a ball left asleep would
 * let the paddle through. */
static void test_a_keyframed_paddle_wakes_a_ball_asleep_on_the_table(void **state)
{
    (void)state;
    static const segment start[] = {{0.7, 0.8, 5.0}}; /* to 0.5 m/s along y */
    profile p = {start, 1, {0.0, -0.2, TABLE_HEIGHT + 0.1}, 0.0, 1};
    tb_scene *scene = test_empty_scene();
    add_table(scene);
    const double size[3] = {0.3, 0.05, 0.2};
    const size_t paddle = add_keyframed_box(scene, "paddle", size, &p);
    const double x[3] = {0.0, 0.0, TABLE_HEIGHT + BALL_RADIUS - PENETRATION};
    const size_t ball = test_add_ball(scene, "ball", 1.0, BALL_RADIUS, x, NULL);
    const double g[3] = {0, 0, -G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = PENETRATION;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    double closest = INFINITY; /* the ball's centre ahead of the paddle's face, m */
    for (int frame = 1; frame <= 150; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, 0.01 * frame), TB_STATUS_OK);
        if (frame == 70) { /* 0.7 s: the paddle about to move */
            bool asleep = false;
            assert_int_equal(tb_scene_body_asleep(scene, ball, &asleep), TB_STATUS_OK);
            assert_true(asleep);
        }
        tb_body_state b, k;
        assert_int_equal(tb_scene_get_state(scene, ball, &b), TB_STATUS_OK);
        assert_int_equal(tb_scene_get_state(scene, paddle, &k), TB_STATUS_OK);
        closest = fmin(closest, b.x[1] - (k.x[1] + 0.5 * size[1]));
    }
    print_message("the ball's centre came within %.4f m of the paddle's face\n", closest);
    assert_true(closest >= BALL_RADIUS - 0.5 * sqrt(PENETRATION / G));
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Integrators keep the scene's time at their last output, so read-outs give a keyframed body
 * where its source puts it then, whether the bodies interact (RK4 of a contact scene) or not
 * (each body alone, gravity only: the chunked path), and under CVODE. */
static void test_read_outs_follow_the_scene_time(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 2; ++m) {
        profile p = {NULL, 0, {0.0, -0.2, 0.0}, 10.0, 1};
        tb_scene *scene = test_empty_scene();
        const double size[3] = {0.4, 0.05, 0.3};
        const size_t paddle = add_keyframed_box(scene, "paddle", size, &p);
        const double x[3] = {0, 0, 5};
        test_add_ball(scene, "ball", 1.0, 0.1, x, NULL);
        const double g[3] = {0, 0, -G};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        assert_true(tb_scene_time(scene) == 0.0);
        tb_integrator *integrator =
            test_integrator_for(scene, methods_to_check[m], m == 0 ? 0.01 : 0.0, 1e-8);
        assert_int_equal(tb_integrator_advance(integrator, 0.25), TB_STATUS_OK);
        assert_true(fabs(tb_scene_time(scene) - 0.25) < 1e-12);
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, paddle, &s), TB_STATUS_OK);
        assert_true(fabs(s.x[1] - (-0.2 + 10.0 * 0.25)) < 1e-9);
        double values[2 * TB_FRAME_VALUES];
        assert_int_equal(tb_scene_frame_values(scene, tb_scene_states(scene), values),
                         TB_STATUS_OK);
        assert_true(fabs(values[1] - s.x[1]) < 1e-12 && values[8] == 10.0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A keyframed wall (a 2 m cube) at x = -5 at t = 0 that has slid to x = 0 by t = 1, and a ball
 * at x = 0.5, inside where the wall ends: the integrator's start check reads the wall at the
 * integrator's t0, not at the scene's older time. From t0 = 5 the start is refused naming both
 * (the scene's time unchanged); from t0 = 0 it is accepted although the scene's time was 5. */
static void test_the_start_check_reads_keyframed_bodies_at_t0(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 2; ++m) {
        tb_scene *scene = test_empty_scene();
        const size_t wall = add_keyframed_box(scene, "wall", (double[]){2.0, 2.0, 2.0}, NULL);
        tb_body_key keys[2] = {tb_body_key_default(), tb_body_key_default()};
        keys[0].position[0] = -5.0;
        keys[1].t = 1.0;
        assert_int_equal(tb_scene_set_body_keys(scene, wall, keys, 2, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        test_add_ball(scene, "ball", 1.0, 0.1, (double[]){0.5, 0, 0}, NULL);
        tb_contact_def contact = tb_contact_def_default();
        contact.penetration = PENETRATION;
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator_def def_m = test_integrator_def(methods_to_check[m], 0.0, 1e-6);
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def_m, 5.0, &integrator),
                         TB_STATUS_INVALID_ARGUMENT);
        assert_null(integrator);
        assert_non_null(strstr(tb_scene_detail(scene), "\"wall\""));
        assert_non_null(strstr(tb_scene_detail(scene), "\"ball\""));
        assert_true(tb_scene_time(scene) == 0.0);
        assert_int_equal(tb_scene_set_time(scene, 5.0), TB_STATUS_OK);
        assert_int_equal(tb_scene_integrator_create(scene, &def_m, 0.0, &integrator), TB_STATUS_OK);
        assert_true(tb_scene_time(scene) == 0.0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The same wall and ball, the integrator made at t0 = 0 (the wall 5 m away): a reset to t = 5,
 * where the keys put the wall around the ball, is refused as a start there would be (naming
 * both), and changes nothing: the integrator's and the scene's times and the states, byte for
 * byte. A reset to t = 0.5 (the wall at x = -2.5, its face 1.5 m from the ball) is accepted and
 * the scene's time follows it. */
static void test_a_reset_to_where_keys_put_a_body_inside_another_is_refused(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_EULER, TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS,
                                          TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 4; ++m) {
        tb_scene *scene = test_empty_scene();
        const size_t wall = add_keyframed_box(scene, "wall", (double[]){2.0, 2.0, 2.0}, NULL);
        tb_body_key keys[2] = {tb_body_key_default(), tb_body_key_default()};
        keys[0].position[0] = -5.0;
        keys[1].t = 1.0;
        assert_int_equal(tb_scene_set_body_keys(scene, wall, keys, 2, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        test_add_ball(scene, "ball", 1.0, 0.1, (double[]){0.5, 0, 0}, NULL);
        tb_contact_def contact = tb_contact_def_default();
        contact.penetration = PENETRATION;
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, methods_to_check[m], 0.0, 1e-6);
        const size_t n = tb_scene_state_size(scene);
        double before[4 * TB_STATE_SIZE]; /* the ball, and the contact's friction slots */
        assert_true(n <= 4 * TB_STATE_SIZE);
        memcpy(before, tb_scene_states(scene), n * sizeof(double));
        assert_int_equal(tb_integrator_reset(integrator, 5.0), TB_STATUS_INVALID_ARGUMENT);
        assert_non_null(strstr(tb_integrator_detail(integrator), "\"wall\""));
        assert_non_null(strstr(tb_integrator_detail(integrator), "\"ball\""));
        assert_true(tb_integrator_time(integrator) == 0.0 && tb_scene_time(scene) == 0.0);
        assert_memory_equal(before, tb_scene_states(scene), n * sizeof(double));
        assert_int_equal(tb_integrator_reset(integrator, 0.5), TB_STATUS_OK);
        assert_true(tb_integrator_time(integrator) == 0.5 && tb_scene_time(scene) == 0.5);
        assert_int_equal(tb_integrator_advance(integrator, 0.6), TB_STATUS_OK);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A user effect that pushes the body in *ctx along x by the keyframed body 0's x (N per m), as
 * the read-out gives it inside the callback. */
static int push_by_wall_x(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)t;
    double x[3], q[4], f[3] = {0, 0, 0};
    if (tb_scene_body_shape_pose(scene, y, 0, x, q) != TB_STATUS_OK) {
        return -1;
    }
    f[0] = x[0];
    return tb_effect_add_force(scene, y, dydt, *(const size_t *)ctx, f, x) == TB_STATUS_OK ? 0 : -1;
}

/* The derivative is a function of (t, y) alone and changes nothing (DESIGN.md): the wall (linear
 * keys, x = -5 m at t = 0 to 0 at t = 1, a 2 m cube) and two balls (r = 0.1 m): A 0.5 mm inside
 * the wall's face where the wall is at t = 0.5 (face at x = -1.5), B far off, pushed by a user
 * effect with the wall's x as its read-out sees it inside the callback. With the scene's time
 * at 0, the derivative at t = 0.5 gives B dP_x = -2.5 N exactly (the wall at 0.5) and A a push
 * out of the wall (+x), at t = 0 B -5 N and A nothing (the wall 2.5 m off); the scene's time
 * stays 0, and the derivative at 0.5 is the same, bit for bit, when the scene's time is 0.5. */
static void test_the_derivative_reads_keyframed_bodies_at_its_own_t(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t wall = add_keyframed_box(scene, "wall", (double[]){2.0, 2.0, 2.0}, NULL);
    tb_body_key keys[2] = {tb_body_key_default(), tb_body_key_default()};
    keys[0].position[0] = -5.0;
    keys[1].t = 1.0;
    assert_int_equal(tb_scene_set_body_keys(scene, wall, keys, 2, TB_INTERPOLATION_LINEAR),
                     TB_STATUS_OK);
    const size_t a = test_add_ball(scene, "a", 1.0, 0.1, (double[]){-1.4005, 0, 0}, NULL);
    static size_t b;
    b = test_add_ball(scene, "b", 1.0, 0.1, (double[]){0, 10, 0}, NULL);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = PENETRATION;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_user_effect(scene, push_by_wall_x, &b), TB_STATUS_OK);
    const size_t n = tb_scene_state_size(scene);
    double y[8 * TB_STATE_SIZE], at_half[8 * TB_STATE_SIZE], at_zero[8 * TB_STATE_SIZE];
    double again[8 * TB_STATE_SIZE];
    assert_true(n <= 8 * TB_STATE_SIZE);
    memcpy(y, tb_scene_states(scene), n * sizeof(double));
    assert_int_equal(tb_scene_derivative(0.5, y, at_half, scene), 0);
    assert_true(tb_scene_time(scene) == 0.0);
    assert_int_equal(tb_scene_derivative(0.0, y, at_zero, scene), 0);
    /* the balls hold slots 0 and 1 (the wall has none): their dP_x */
    const size_t pa = TB_STATE_SIZE * (a - 1) + TB_STATE_P,
                 pb = TB_STATE_SIZE * (b - 1) + TB_STATE_P;
    assert_true(at_half[pb] == -2.5 && at_zero[pb] == -5.0);
    assert_true(at_half[pa] > 0.0 && at_zero[pa] == 0.0);
    assert_int_equal(tb_scene_set_time(scene, 0.5), TB_STATUS_OK);
    assert_int_equal(tb_scene_derivative(0.5, y, again, scene), 0);
    assert_memory_equal(at_half, again, n * sizeof(double));
    assert_true(tb_scene_time(scene) == 0.5);
    tb_scene_destroy(scene);
}

/* A user effect that pushes the body in *ctx along x by C_DRIVE times the x velocity of the
 * keyframed body 0 as the read-out gives it at the callback's t: F = c v_key(t). */
#define C_DRIVE 2.0
static int drive_by_key_velocity(double t, const tb_scene *scene, const double *y, double *dydt,
                                 void *ctx)
{
    (void)t;
    double v[3], x[3], q[4], f[3] = {0, 0, 0};
    if (tb_scene_body_velocity(scene, y, 0, v) != TB_STATUS_OK ||
        tb_scene_body_shape_pose(scene, y, *(const size_t *)ctx, x, q) != TB_STATUS_OK) {
        return -1;
    }
    f[0] = C_DRIVE * v[0];
    return tb_effect_add_force(scene, y, dydt, *(const size_t *)ctx, f, x) == TB_STATUS_OK ? 0 : -1;
}

/* The keyframed body's x for the linear keys below (m): 0, 1, 0.4, 0.4 at t = 0, 0.1, 0.25,
 * 0.3, held after. Its integral from 0 to t (m s), exact. */
static const double drive_times[4] = {0.0, 0.1, 0.25, 0.3}, drive_x[4] = {0.0, 1.0, 0.4, 0.4};
static double drive_position(double t, double *out_integral)
{
    double integral = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double t0 = drive_times[k], t1 = drive_times[k + 1];
        const double v = (drive_x[k + 1] - drive_x[k]) / (t1 - t0);
        if (t <= t1) {
            const double x = drive_x[k] + v * (t - t0);
            *out_integral = integral + 0.5 * (drive_x[k] + x) * (t - t0);
            return x;
        }
        integral += 0.5 * (drive_x[k] + drive_x[k + 1]) * (t1 - t0);
    }
    *out_integral = integral + drive_x[3] * (t - drive_times[3]);
    return drive_x[3];
}

/* A 1 kg ball pushed by F = c v_key(t) (c = 2 N s/m), v_key the velocity of a body on linear
 * keys (10, -4 and 0 m/s on [0, 0.1], [0.1, 0.25], [0.25, 0.3]): its momentum is exactly
 * P(t) = c (x_key(t) - x_key(0)) and its x, from 0, c / M times the integral of that. The
 * force is constant inside each piece and the steps end on the key times, so a step whose
 * stages see the piece it lies in integrates it exactly: Euler P (x' = P / M is linear in t
 * there, which Euler does not integrate exactly), midpoint and RK4 both P and x. RK4's last
 * stage lies at the step's end: on a key time it must see the piece before it (the curve's left
 * derivative), or the step gets (h / 6) c (v_after - v_before): 0.019 N s after the two jumps
 * at dt = 1/240 s. CVODE (rtol 1e-10) stops at each key time and restarts there: P exact as
 * well (a constant P' is integrated exactly at every order), x within 1e-8 m (100 rtol).
 * Checked at every frame (1/60 s) and at the key times, to 1e-12 (rounding over about 100
 * steps). */
static void test_a_step_ending_on_a_linear_key_sees_the_segment_before_it(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                          TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 5; ++m) {
        const bool adaptive = tb_method_is_adaptive(methods_to_check[m]);
        tb_scene *scene = test_empty_scene();
        const size_t key = add_keyframed_box(scene, "key", (double[]){0.1, 0.1, 0.1}, NULL);
        tb_body_key keys[4];
        for (int k = 0; k < 4; ++k) {
            keys[k] = tb_body_key_default();
            keys[k].t = drive_times[k];
            keys[k].position[0] = drive_x[k];
            keys[k].position[1] = 5.0; /* away from the ball */
        }
        assert_int_equal(tb_scene_set_body_keys(scene, key, keys, 4, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        static size_t ball;
        ball = test_add_ball(scene, "ball", 1.0, 0.1, (double[]){0, 0, 0}, NULL);
        assert_int_equal(tb_scene_add_user_effect(scene, drive_by_key_velocity, &ball),
                         TB_STATUS_OK);
        tb_integrator *integrator =
            test_integrator_for(scene, methods_to_check[m], adaptive ? 0.0 : 1.0 / 240, 1e-10);
        double worst_p = 0.0, worst_x = 0.0;
        const double times[] = {1.0 / 60, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35};
        for (size_t i = 0; i < sizeof times / sizeof times[0]; ++i) {
            assert_int_equal(tb_integrator_advance(integrator, times[i]), TB_STATUS_OK);
            double integral;
            const double x_key = drive_position(times[i], &integral);
            tb_body_state s;
            assert_int_equal(tb_scene_get_state(scene, ball, &s), TB_STATUS_OK);
            worst_p = fmax(worst_p, fabs(s.P[0] - C_DRIVE * x_key));
            worst_x = fmax(worst_x, fabs(s.x[0] - C_DRIVE * integral));
        }
        print_message("%s: worst |P - c x_key| %.3g N s, |x - exact| %.3g m\n",
                      tb_method_name(methods_to_check[m]), worst_p, worst_x);
        assert_true(worst_p < 1e-12);
        assert_true(methods_to_check[m] == TB_METHOD_EULER || worst_x < (adaptive ? 1e-8 : 1e-12));
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A ball asleep on a keyframed platform (a 4 x 4 x 1 m box, top at z = 0) that holds still
 * until t = 2 s and then rises 1 m in 1 s: the moving platform wakes the ball and carries it,
 * so at t = 3.5 s the ball is above the platform's final top (z = 1 m; it rests on it at
 * 1 + radius less its 1 mm deflection). Asleep, it would stay at z = 0.1 inside the box. */
static void test_a_platform_that_starts_moving_wakes_the_ball_asleep_on_it(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 2; ++m) {
        tb_scene *scene = test_empty_scene();
        const size_t platform =
            add_keyframed_box(scene, "platform", (double[]){4.0, 4.0, 1.0}, NULL);
        tb_body_key keys[3] = {tb_body_key_default(), tb_body_key_default(), tb_body_key_default()};
        keys[0].position[2] = keys[1].position[2] = -0.5;
        keys[1].t = 2.0;
        keys[2].t = 3.0;
        keys[2].position[2] = 0.5;
        assert_int_equal(tb_scene_set_body_keys(scene, platform, keys, 3, TB_INTERPOLATION_LINEAR),
                         TB_STATUS_OK);
        const size_t ball = test_add_ball(scene, "ball", 1.0, 0.1, (double[]){0, 0, 0.1}, NULL);
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
        tb_contact_def contact = tb_contact_def_default();
        contact.penetration = PENETRATION;
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_sleeping(scene, true), TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, methods_to_check[m], 0.0, 1e-6);
        bool asleep = false;
        for (int k = 1; k <= 19 && !asleep; ++k) { /* it falls asleep before the platform moves */
            assert_int_equal(tb_integrator_advance(integrator, 0.1 * k), TB_STATUS_OK);
            assert_int_equal(tb_scene_body_asleep(scene, ball, &asleep), TB_STATUS_OK);
        }
        assert_true(asleep);
        assert_int_equal(tb_integrator_advance(integrator, 3.5), TB_STATUS_OK);
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, ball, &s), TB_STATUS_OK);
        assert_true(s.x[2] > 1.0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A motion that says 0 but gives NaN (position, velocity) or a zero quaternion from t = 0.05 s
 * on. */
static int broken_motion(double t, void *ctx, tb_body_motion_sample *out)
{
    const int *mode = ctx;
    memset(out, 0, sizeof *out);
    out->orientation[0] = 1.0;
    out->position[2] = -0.5;
    if (t > 0.05) {
        if (*mode == 0) {
            out->position[2] = NAN;
        } else if (*mode == 1) {
            out->velocity[0] = INFINITY;
        } else {
            out->orientation[0] = 0.0;
        }
    }
    return 0;
}

/* A ball resting on a keyframed platform whose motion function turns to garbage: the advance
 * past 0.05 s fails (not OK) and the ball stays at its last good state, finite and on the
 * platform (its 0.1 m radius above the top at z = 0, less the deflection). */
static void test_a_motion_giving_nan_fails_the_step(void **state)
{
    (void)state;
    const tb_method methods_to_check[] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (int mode = 0; mode < 3; ++mode) {
        for (size_t m = 0; m < 2; ++m) {
            tb_scene *scene = test_empty_scene();
            tb_body_def def = tb_body_def_default();
            def.motion = TB_MOTION_KEYFRAMED;
            size_t platform = 0;
            assert_int_equal(tb_scene_add_body(scene, &def, &platform), TB_STATUS_OK);
            tb_shape shape = tb_shape_default();
            shape.type = TB_SHAPE_BOX;
            shape.size[0] = shape.size[1] = 4.0;
            shape.size[2] = 1.0;
            assert_int_equal(tb_scene_set_body_shape(scene, platform, &shape), TB_STATUS_OK);
            assert_int_equal(tb_scene_set_body_motion_fn(scene, platform, broken_motion, &mode),
                             TB_STATUS_OK);
            const size_t ball = test_add_ball(scene, "ball", 1.0, 0.1, (double[]){0, 0, 0.1}, NULL);
            assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
            tb_contact_def contact = tb_contact_def_default();
            contact.penetration = PENETRATION;
            assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
            tb_integrator *integrator = test_integrator_for(scene, methods_to_check[m], 0.0, 1e-6);
            assert_int_not_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_OK);
            tb_body_state s;
            assert_int_equal(tb_scene_get_state(scene, ball, &s), TB_STATUS_OK);
            assert_true(isfinite(s.x[2]) && fabs(s.x[2] - 0.1) < 2.0 * PENETRATION);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_body_has_no_state_and_reads_as_its_pose),
        cmocka_unit_test(test_ball_rests_on_static_table_at_its_static_deflection),
        cmocka_unit_test(test_ball_slides_off_static_table_on_the_ballistic_arc),
        cmocka_unit_test(test_changes_to_bodies_without_state_are_refused),
        cmocka_unit_test(test_scene_of_static_bodies_alone_is_refused),
        cmocka_unit_test(test_box_rides_a_keyframed_platform_at_its_static_deflection),
        cmocka_unit_test(test_keyframed_paddle_sends_ball_off_at_one_plus_e_its_speed),
        cmocka_unit_test(test_motion_fn_needs_a_keyframed_body),
        cmocka_unit_test(test_steps_end_on_break_times),
        cmocka_unit_test(test_balls_on_a_static_table_sleep_on_their_own_islands),
        cmocka_unit_test(test_a_keyframed_paddle_wakes_a_ball_asleep_on_the_table),
        cmocka_unit_test(test_read_outs_follow_the_scene_time),
        cmocka_unit_test(test_the_start_check_reads_keyframed_bodies_at_t0),
        cmocka_unit_test(test_a_reset_to_where_keys_put_a_body_inside_another_is_refused),
        cmocka_unit_test(test_the_derivative_reads_keyframed_bodies_at_its_own_t),
        cmocka_unit_test(test_a_step_ending_on_a_linear_key_sees_the_segment_before_it),
        cmocka_unit_test(test_a_platform_that_starts_moving_wakes_the_ball_asleep_on_it),
        cmocka_unit_test(test_a_motion_giving_nan_fails_the_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
