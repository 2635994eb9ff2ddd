/* Waking is exact (src/scene/sleep.c, docs/effects.md "Sleeping islands"): a ball sent at a
 * sleeping box (or a sleeping stack of two) between two 24 fps outputs wakes it before the two
 * touch, under every method. Under CVODE the pair of an awake and an asleep body has a root
 * function (its gap less TB__WAKE_DISTANCE) and steps that close at most half its gap, so CVODE
 * stops before the touch and restarts with the island awake; a fixed step wakes the island one
 * step ahead, when the pair could close the margin within the step. The runs are compared with
 * the same runs without sleeping, and no derivative may ever push a ball into an asleep box. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

#define EDGE 0.1         /* m */
#define BOX_MASS 0.5     /* kg */
#define BALL_RADIUS 0.05 /* m */
#define BALL_MASS 0.3    /* kg */
#define FRAME (1.0 / 24.0)
#define SETTLED 1.0 /* s, 24 frames: the boxes ring out in 0.1 s, then TB_SLEEP_TIME still */
#define MAX_BOXES 2

static void add_box(tb_scene *scene, const double position[3])
{
    const double size[3] = {EDGE, EDGE, EDGE};
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = shape.size[1] = shape.size[2] = EDGE;
    tb_contact_point corners[8];
    size_t count = 0;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    tb_body_def body = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, BOX_MASS, size, &body.mass, NULL),
                     TB_STATUS_OK);
    memcpy(body.position, position, sizeof body.position);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, id, corners, count, 4), TB_STATUS_OK);
}

/* `boxes` boxes stacked at the origin (bodies 0 ..), and a ball resting on the floor 1 m away
 * (body `boxes`); a frictionless floor, so that no outside force acts along x. */
static tb_scene *scene_with(size_t boxes)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    for (size_t i = 0; i < boxes; ++i) {
        add_box(scene, (double[]){0.0, 0.0, EDGE * (0.5 + (double)i)});
    }
    tb_body_def ball = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, BALL_MASS, BALL_RADIUS, &ball.mass, NULL),
                     TB_STATUS_OK);
    ball.position[0] = -1.0;
    ball.position[2] = BALL_RADIUS;
    tb_shape sphere = tb_shape_default();
    sphere.type = TB_SHAPE_SPHERE;
    sphere.radius = BALL_RADIUS;
    assert_int_equal(tb_scene_add_body(scene, &ball, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, boxes, &sphere), TB_STATUS_OK);
    const tb_contact_point bottom = {{0, 0, 0}, BALL_RADIUS};
    assert_int_equal(tb_scene_set_contact_points(scene, boxes, &bottom, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = ground.kinetic_friction = 0.0;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

/* --- the derivative watched: an asleep box pushed by the ball is the error ------------------ */

static struct watch {
    tb_ode_derivative derivative; /* the scene's */
    tb_scene *scene;
    size_t boxes;
    long pushed_asleep; /* evaluations at which the ball overlapped an asleep box */
    long evaluations;
} watch;

/* Whether the ball overlaps box b at y: the distance from its centre to the box (axis-aligned
 * to within the micro-radians its rest tilts it) is below its radius. The ball is kept at least
 * TB__WAKE_DISTANCE / 2 = 0.25 mm from an asleep box, far beyond that tilt's 1e-7 m. */
static bool overlaps(const double *y, size_t b)
{
    const double *ball = y + 13 * watch.boxes, *box = y + 13 * b;
    double squared = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = fmax(fabs(ball[k] - box[k]) - 0.5 * EDGE, 0.0);
        squared += d * d;
    }
    return squared < BALL_RADIUS * BALL_RADIUS;
}

static int watched_derivative(double t, const double *y, double *dydt, void *ctx)
{
    const int rc = watch.derivative(t, y, dydt, ctx);
    watch.evaluations++;
    for (size_t b = 0; b < watch.boxes; ++b) {
        bool asleep = false;
        assert_int_equal(tb_scene_body_asleep(watch.scene, b, &asleep), TB_STATUS_OK);
        watch.pushed_asleep += asleep && overlaps(y, b);
    }
    return rc;
}

/* A CVODE integrator on the scene from t0 whose derivative is watched (what
 * tb_scene_integrator_create makes, with the scene's absolute tolerances). */
static tb_integrator *watched_cvode(tb_scene *scene, size_t boxes, tb_method method, double rtol,
                                    double t0)
{
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    watch = (struct watch){system.derivative, scene, boxes, 0, 0};
    system.derivative = watched_derivative;
    static double atol[13 * 8 + 4096];
    assert_true(system.n <= sizeof atol / sizeof atol[0]);
    assert_int_equal(tb_scene_absolute_tolerances(scene, 1e-2 * rtol, atol), TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    def.rtol = rtol;
    def.atol_vector = atol;
    def.max_steps = 10000000;
    tb_integrator *integrator = NULL;
    assert_int_equal(
        tb_integrator_create(&system, &def, t0, tb_scene_states(scene), &integrator, NULL),
        TB_STATUS_OK);
    return integrator;
}

static tb_integrator *scene_integrator(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = test_integrator_def(method, 0.0, 1e-6); /* dt 0: the default step */
    def.max_steps = 10000000;
    return test_integrator(scene, &def);
}

static void advance_frames(tb_integrator *integrator, double from, int frames)
{
    for (int k = 1; k <= frames; ++k) {
        assert_int_equal(tb_integrator_advance(integrator, from + k * FRAME), TB_STATUS_OK);
    }
}

static bool body_asleep(const tb_scene *scene, size_t id)
{
    bool asleep = false;
    assert_int_equal(tb_scene_body_asleep(scene, id, &asleep), TB_STATUS_OK);
    return asleep;
}

/* The scene settled for SETTLED under method with sleeping on (every body asleep), then with
 * sleeping as asked; the ball sent along x at speed v from `gap` before the first box. */
static tb_scene *settled_and_thrown(size_t boxes, tb_method method, bool sleeping, double v,
                                    double gap)
{
    tb_scene *scene = scene_with(boxes);
    tb_integrator *integrator = scene_integrator(scene, method);
    advance_frames(integrator, 0.0, 24);
    tb_integrator_destroy(integrator);
    size_t count = 0;
    assert_int_equal(tb_scene_asleep_count(scene, &count), TB_STATUS_OK);
    assert_int_equal(count, boxes + 1);
    assert_int_equal(tb_scene_set_sleeping(scene, sleeping), TB_STATUS_OK);
    tb_body_state s;
    assert_int_equal(tb_scene_get_state(scene, boxes, &s), TB_STATUS_OK);
    s.x[0] = -0.5 * EDGE - BALL_RADIUS - gap;
    s.P[0] = BALL_MASS * v;
    assert_int_equal(tb_scene_set_state(scene, boxes, &s), TB_STATUS_OK);
    for (size_t b = 0; b < boxes; ++b) {
        assert_true(body_asleep(scene, b) == sleeping);
    }
    return scene;
}

/* Every body's x and v (6 per body) into out; the largest box speed into *box_speed. */
static void motion_of(const tb_scene *scene, size_t bodies, double *out, double *box_speed)
{
    *box_speed = 0.0;
    for (size_t i = 0; i < bodies; ++i) {
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, i, &s), TB_STATUS_OK);
        const double mass = i + 1 < bodies ? BOX_MASS : BALL_MASS;
        for (int k = 0; k < 3; ++k) {
            out[6 * i + k] = s.x[k];
            out[6 * i + 3 + k] = s.P[k] / mass;
        }
        if (i + 1 < bodies) {
            *box_speed = fmax(*box_speed,
                              sqrt(s.P[0] * s.P[0] + s.P[1] * s.P[1] + s.P[2] * s.P[2]) / BOX_MASS);
        }
    }
}

static double momentum_x(const tb_scene *scene)
{
    double P[3];
    assert_int_equal(tb_scene_linear_momentum(scene, tb_scene_states_const(scene), P),
                     TB_STATUS_OK);
    return P[0];
}

/* The ball at 0.5 m/s from half a frame's travel away: it touches the first box half-way
 * between the outputs at SETTLED and SETTLED + FRAME. Six frames later every body's position
 * and velocity agree with the run without sleeping, from the same states, within
 *   position: 1e3 rtol m (the two runs take different steps through the hit, each held within
 *   rtol of the 1 m scale, over some 1e3 steps) plus the distance the boxes would have moved
 *   awake at their frozen speed until the wake (below 1e-4 m/s, TB_SLEEP_SPEED, measured),
 *   velocity: 1e3 rtol m/s times the hit's 3500 rad/s / 1e3 (a velocity error is a position
 *   error times the contact's rate).
 * The horizontal momentum, on which no outside force acts, is kept through the hit to the
 * round-off of 1e2 N forces over some 1e4 evaluations (1e-9 of it). */
static void check_throw(size_t boxes, tb_method method)
{
    const double rtol = 1e-8, v = 0.5, gap = 0.5 * v * FRAME;
    const size_t bodies = boxes + 1;
    double slept[6 * (MAX_BOXES + 1)], unslept[6 * (MAX_BOXES + 1)], frozen_speed, ignored;
    double P_before[2], P_after[2];
    long pushed[2], evaluations[2];
    for (int run = 0; run < 2; ++run) {
        const bool sleeping = run == 0;
        tb_scene *scene = settled_and_thrown(boxes, method, sleeping, v, gap);
        if (sleeping) {
            motion_of(scene, bodies, slept, &frozen_speed);
        }
        P_before[run] = momentum_x(scene);
        tb_integrator *integrator = watched_cvode(scene, boxes, method, rtol, SETTLED);
        advance_frames(integrator, SETTLED, 1);
        for (size_t b = 0; b < boxes; ++b) { /* woken between the outputs */
            assert_false(body_asleep(scene, b));
        }
        /* by a wake gap's root (functions bodies .. 2 bodies - 1), 0.5 mm before the touch at
         * SETTLED + FRAME / 2; without sleeping there is none (every body touches the floor,
         * so no contact gap changes sign) */
        tb_integrator_events events;
        assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
        assert_int_equal(events.count, sleeping ? 1 : 0);
        if (sleeping) {
            assert_true(events.last_root >= (long)bodies);
            assert_true(fabs(events.last_time - (SETTLED + 0.5 * FRAME - 5e-4 / v)) < 1e-6);
        }
        advance_frames(integrator, SETTLED + FRAME, 5);
        P_after[run] = momentum_x(scene);
        motion_of(scene, bodies, sleeping ? slept : unslept, &ignored);
        pushed[run] = watch.pushed_asleep;
        evaluations[run] = watch.evaluations;
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    double dx = 0.0, dv = 0.0;
    for (size_t i = 0; i < bodies; ++i) {
        for (int k = 0; k < 3; ++k) {
            dx = fmax(dx, fabs(slept[6 * i + k] - unslept[6 * i + k]));
            dv = fmax(dv, fabs(slept[6 * i + 3 + k] - unslept[6 * i + 3 + k]));
        }
    }
    const double x_bound = 1e3 * rtol + frozen_speed * FRAME, v_bound = 3.5e3 * rtol;
    print_message("%s, %zu box(es): slept and unslept runs differ by %.3g m (bound %.3g), %.3g m/s "
                  "(bound %.3g); P_x %.17g -> %.17g; %ld of %ld evaluations pushed an asleep box; "
                  "first box leaves at %.4g m/s\n",
                  tb_method_name(method), boxes, dx, x_bound, dv, v_bound, P_before[0], P_after[0],
                  pushed[0], evaluations[0], slept[3]);
    assert_int_equal(pushed[0], 0);
    assert_true(frozen_speed < 1e-4); /* TB_SLEEP_SPEED */
    assert_true(dx <= x_bound);
    assert_true(dv <= v_bound);
    for (int run = 0; run < 2; ++run) {
        assert_true(fabs(P_after[run] - P_before[run]) <= 1e-9 * BALL_MASS * v);
    }
    assert_true(slept[3] > 0.1 * v); /* the box was hit and moves */
}

static void test_a_ball_wakes_a_sleeping_box_between_outputs_under_cvode_adams(void **state)
{
    (void)state;
    check_throw(1, TB_METHOD_CVODE_ADAMS);
    check_throw(2, TB_METHOD_CVODE_ADAMS);
}

static void test_a_ball_wakes_a_sleeping_box_between_outputs_under_cvode_bdf(void **state)
{
    (void)state;
    check_throw(1, TB_METHOD_CVODE_BDF);
    check_throw(2, TB_METHOD_CVODE_BDF);
}

/* One CVODE step at a time (tb_integrator_step), every step is an output: the steps near the
 * asleep box close at most half the gap, so one ends within the 1 mm margin before the 0.5 mm
 * wake event, and the island wakes there. No evaluation pushes the asleep box, the box is awake
 * before the frame after the throw, and the x momentum is kept as in check_throw. */
static void test_one_cvode_step_at_a_time_wakes_the_box_before_the_touch(void **state)
{
    (void)state;
    const double v = 0.5, gap = 0.5 * v * FRAME;
    tb_scene *scene = settled_and_thrown(1, TB_METHOD_CVODE_BDF, true, v, gap);
    const double P0 = momentum_x(scene);
    tb_integrator *integrator = watched_cvode(scene, 1, TB_METHOD_CVODE_BDF, 1e-8, SETTLED);
    tb_integrator_events events;
    long steps = 0;
    for (; tb_integrator_time(integrator) < SETTLED + FRAME && steps < 1000000; ++steps) {
        assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
    }
    assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
    tb_body_state box;
    assert_int_equal(tb_scene_get_state(scene, 0, &box), TB_STATUS_OK);
    print_message("cvode-bdf one step at a time: %ld steps, %ld events, %ld of %ld evaluations "
                  "pushed an asleep box; P_x %.17g -> %.17g, box at %.4g m/s\n",
                  steps, events.count, watch.pushed_asleep, watch.evaluations, P0,
                  momentum_x(scene), box.P[0] / BOX_MASS);
    assert_int_equal(watch.pushed_asleep, 0);
    assert_false(body_asleep(scene, 0));
    assert_true(fabs(momentum_x(scene) - P0) <= 1e-9 * BALL_MASS * v);
    assert_true(box.P[0] / BOX_MASS > 0.1 * v);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* RK4 at the scene's default step h, the ball fast enough to close 2.5 mm (2.5 margins) in a
 * step, sent from 40.6 steps' travel away: at the last boundary before the touch the pair is
 * 1.5 mm apart, outside the margin, and the next step's stages would reach into the box. The
 * island wakes a step ahead: while the box is asleep at a step's start the ball's x momentum
 * comes through the step bit for bit (nothing along x acts on it but the box), and once awake
 * the hit keeps the total x momentum to round-off. */
static void test_a_fast_ball_wakes_a_sleeping_box_a_step_ahead_under_rk4(void **state)
{
    (void)state;
    tb_scene *probe = scene_with(1);
    double h = 0.0;
    assert_int_equal(tb_scene_default_step(probe, TB_METHOD_RK4, &h), TB_STATUS_OK);
    tb_scene_destroy(probe);
    const double v = 2.5e-3 / h, gap = 40.6 * v * h;
    tb_scene *scene = settled_and_thrown(1, TB_METHOD_RK4, true, v, gap);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_RK4), TB_STATUS_OK);
    def.dt = h;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, SETTLED, &integrator), TB_STATUS_OK);
    const double P0 = momentum_x(scene);
    long asleep_steps = 0, touched_asleep = 0;
    for (int k = 0; k < 100; ++k) {
        const bool asleep = body_asleep(scene, 0);
        tb_body_state before, after;
        assert_int_equal(tb_scene_get_state(scene, 1, &before), TB_STATUS_OK);
        assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
        assert_int_equal(tb_scene_get_state(scene, 1, &after), TB_STATUS_OK);
        asleep_steps += asleep;
        touched_asleep += asleep && after.P[0] != before.P[0];
    }
    tb_body_state box;
    assert_int_equal(tb_scene_get_state(scene, 0, &box), TB_STATUS_OK);
    print_message("rk4 h = %.3g s, ball at %.3g m/s: %ld steps with the box asleep, %ld of them "
                  "pushed the ball; P_x %.17g -> %.17g, box at %.4g m/s\n",
                  h, v, asleep_steps, touched_asleep, P0, momentum_x(scene), box.P[0] / BOX_MASS);
    assert_int_equal(touched_asleep, 0);
    assert_true(asleep_steps >= 30); /* it slept until the ball came near */
    assert_true(fabs(momentum_x(scene) - P0) <= 1e-9 * P0);
    assert_true(box.P[0] / BOX_MASS > 0.1 * v); /* the hit happened */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* F99: a box resting asleep on its 8 corner points (no shape) whose points were removed stayed
 * asleep where it was, held by nothing, through a new integrator and 0.5 s. Changing a body's
 * points now wakes it, as setting its state or shape does: it falls freely, z0 - g t^2 / 2,
 * which RK4 integrates exactly for a constant force (1e-9 m: rounding of 0.05 m positions). */
static void test_removing_an_asleep_bodys_points_wakes_it(void **state)
{
    (void)state;
    tb_scene_def def = tb_scene_def_default();
    def.sleeping = true;
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    add_box(scene, (double[]){0.0, 0.0, 0.5 * EDGE});
    assert_int_equal(tb_scene_set_body_shape(scene, 0, NULL), TB_STATUS_OK); /* points alone */
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, SETTLED), TB_STATUS_OK);
    bool asleep = false;
    assert_int_equal(tb_scene_body_asleep(scene, 0, &asleep), TB_STATUS_OK);
    assert_true(asleep);
    tb_integrator_destroy(integrator);
    tb_body_state rest;
    assert_int_equal(tb_scene_get_state(scene, 0, &rest), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, NULL, 0, 0), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_asleep(scene, 0, &asleep), TB_STATUS_OK);
    assert_false(asleep);
    tb_integrator_def step = test_integrator_def(TB_METHOD_RK4, 1e-3, 0.0);
    integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &step, SETTLED, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, SETTLED + 0.5), TB_STATUS_OK);
    tb_body_state fallen;
    assert_int_equal(tb_scene_get_state(scene, 0, &fallen), TB_STATUS_OK);
    const double v0 = rest.P[2] / BOX_MASS;
    assert_true(fabs(fallen.x[2] - (rest.x[2] + v0 * 0.5 - 0.5 * 9.81 * 0.25)) < 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A sleeping scene: a 1 x 1 x 0.1 m slab of `motion` centred at the origin (keys, when given,
 * set with linear interpolation), a box resting on its top, gravity and the default contact; run
 * by RK4 at its default step to 1.5 s, where the box is asleep. The slab's shape into
 * *out_shape, its id and the box's into out_ids. */
static tb_integrator *box_asleep_on_a_slab(tb_scene **out_scene, tb_body_motion motion,
                                           const tb_body_key *keys, size_t key_count,
                                           tb_shape *out_shape, size_t out_ids[2])
{
    tb_scene_def def = tb_scene_def_default();
    def.sleeping = true;
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    tb_body_def slab = tb_body_def_default();
    slab.motion = motion;
    assert_int_equal(tb_scene_add_body(scene, &slab, &out_ids[0]), TB_STATUS_OK);
    if (key_count > 0) {
        assert_int_equal(
            tb_scene_set_body_keys(scene, out_ids[0], keys, key_count, TB_INTERPOLATION_LINEAR),
            TB_STATUS_OK);
    }
    *out_shape = tb_shape_default();
    out_shape->type = TB_SHAPE_BOX;
    out_shape->size[0] = out_shape->size[1] = 1.0;
    out_shape->size[2] = 0.1;
    assert_int_equal(tb_scene_set_body_shape(scene, out_ids[0], out_shape), TB_STATUS_OK);
    out_ids[1] = test_add_box(scene, BOX_MASS, (double[]){EDGE, EDGE, EDGE},
                              (double[]){0.0, 0.0, 0.05 + 0.5 * EDGE});
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.5), TB_STATUS_OK);
    bool asleep = false;
    assert_int_equal(tb_scene_body_asleep(scene, out_ids[1], &asleep), TB_STATUS_OK);
    assert_true(asleep);
    *out_scene = scene;
    return integrator;
}

/* A box asleep on a slab that has no state (static, or keyframed at rest) wakes when the slab's
 * shape changes: the slab is in no island, so waking its island alone (the body whose shape was
 * set) left the box asleep, hovering 4.5 cm above the slab made 1 cm thin, through the
 * integrator made before and a new one. It now rests on the thin slab's top, z = 0.005 + 0.05 m
 * less the contact's static deflection (8e-7 m at the default penetration): within 1e-5 m. */
static void box_on_a_thinned_slab(tb_body_motion motion)
{
    tb_body_key keys[2] = {tb_body_key_default(), tb_body_key_default()}; /* at rest */
    keys[1].t = 10.0;
    tb_scene *scene = NULL;
    tb_shape shape;
    size_t ids[2];
    tb_integrator *integrator = box_asleep_on_a_slab(
        &scene, motion, keys, motion == TB_MOTION_KEYFRAMED ? 2 : 0, &shape, ids);
    shape.size[2] = 0.01; /* the slab's top drops from 0.05 m to 0.005 m */
    assert_int_equal(tb_scene_set_body_shape(scene, ids[0], &shape), TB_STATUS_OK);
    bool asleep = true;
    assert_int_equal(tb_scene_body_asleep(scene, ids[1], &asleep), TB_STATUS_OK);
    assert_false(asleep);
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
    tb_body_state fallen;
    assert_int_equal(tb_scene_get_state(scene, ids[1], &fallen), TB_STATUS_OK);
    assert_true(fabs(fallen.x[2] - (0.005 + 0.5 * EDGE)) < 1e-5);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_an_asleep_box_wakes_when_its_static_slab_thins(void **state)
{
    (void)state;
    box_on_a_thinned_slab(TB_MOTION_STATIC);
}

static void test_an_asleep_box_wakes_when_its_keyframed_slab_thins(void **state)
{
    (void)state;
    box_on_a_thinned_slab(TB_MOTION_KEYFRAMED);
}

/* A box asleep on a keyframed platform whose keys lower it by 0.5 m between 2 s and 3 s, the run
 * then continued from 5 s (a reset to a later time, or an integrator made there): no boundary saw
 * the platform move, and the box stayed asleep, hovering 0.5 m above it with status OK. It now
 * wakes and rests on the lowered platform by 6 s: its centre at -0.45 + 0.05 m less the static
 * deflection (8e-7 m), within 1e-5 m. */
static void box_on_a_platform_lowered_while_away(bool reset)
{
    tb_body_key keys[4] = {tb_body_key_default(), tb_body_key_default(), tb_body_key_default(),
                           tb_body_key_default()};
    keys[1].t = 2.0;
    keys[2].t = 3.0;
    keys[2].position[2] = -0.5;
    keys[3].t = 100.0;
    keys[3].position[2] = -0.5;
    tb_scene *scene = NULL;
    tb_shape shape;
    size_t ids[2];
    tb_integrator *integrator =
        box_asleep_on_a_slab(&scene, TB_MOTION_KEYFRAMED, keys, 4, &shape, ids);
    if (reset) {
        assert_int_equal(tb_integrator_reset(integrator, 5.0), TB_STATUS_OK);
    } else {
        tb_integrator_destroy(integrator);
        const tb_integrator_def step = test_integrator_def(TB_METHOD_RK4, 0.0, 0.0);
        integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &step, 5.0, &integrator), TB_STATUS_OK);
    }
    assert_int_equal(tb_integrator_advance(integrator, 6.0), TB_STATUS_OK);
    tb_body_state rest;
    assert_int_equal(tb_scene_get_state(scene, ids[1], &rest), TB_STATUS_OK);
    assert_true(fabs(rest.x[2] - (-0.45 + 0.5 * EDGE)) < 1e-5);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_a_reset_past_a_platform_lowered_wakes_the_box_on_it(void **state)
{
    (void)state;
    box_on_a_platform_lowered_while_away(true);
}

static void test_an_integrator_made_past_a_platform_lowered_wakes_the_box_on_it(void **state)
{
    (void)state;
    box_on_a_platform_lowered_while_away(false);
}

int main(int argc, char **argv)
{
    if (argc > 1) { /* a pattern of test names to run (cmocka's filter) */
        cmocka_set_test_filter(argv[1]);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_ball_wakes_a_sleeping_box_between_outputs_under_cvode_adams),
        cmocka_unit_test(test_a_ball_wakes_a_sleeping_box_between_outputs_under_cvode_bdf),
        cmocka_unit_test(test_one_cvode_step_at_a_time_wakes_the_box_before_the_touch),
        cmocka_unit_test(test_a_fast_ball_wakes_a_sleeping_box_a_step_ahead_under_rk4),
        cmocka_unit_test(test_removing_an_asleep_bodys_points_wakes_it),
        cmocka_unit_test(test_an_asleep_box_wakes_when_its_static_slab_thins),
        cmocka_unit_test(test_an_asleep_box_wakes_when_its_keyframed_slab_thins),
        cmocka_unit_test(test_a_reset_past_a_platform_lowered_wakes_the_box_on_it),
        cmocka_unit_test(test_an_integrator_made_past_a_platform_lowered_wakes_the_box_on_it),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
