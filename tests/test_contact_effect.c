/* Contact between bodies against what mechanics says: two balls colliding keep their total
 * momentum and angular momentum, separate at e times their approach speed, never gain energy,
 * exchange velocities when equal and elastic; a ball resting on a box sinks as predicted; every
 * method agrees; bad definitions are refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "span.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

/* A ball of mass m and radius r at (x, y0, 0) moving along x at v; its shape a sphere. */
static void add_ball(tb_scene *scene, double m, double r, double x, double y0, double v)
{
    test_add_ball(scene, NULL, m, r, (double[]){x, y0, 0.0}, (double[]){v, 0.0, 0.0});
}

/* Ball 0 (mass ma, 0.1 m) from x = -0.15 at va towards ball 1 (mass mb, 0.1 m) at x = 0.15
 * moving at vb, offset sideways by `offset`; no gravity, no ground. */
static tb_scene *two_balls(double ma, double va, double mb, double vb, double offset,
                           const tb_contact_def *contact)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    add_ball(scene, ma, 0.1, -0.15, 0.0, va);
    add_ball(scene, mb, 0.1, 0.15, offset, vb);
    assert_int_equal(tb_scene_add_contact(scene, contact), TB_STATUS_OK);
    return scene;
}

/* dt > 0: that fixed step; dt = 0: the scene's default step (tb_scene_default_step); dt < 0: the
 * default step divided by -dt. */
static tb_integrator *integrator_for(tb_scene *scene, tb_method method, double dt)
{
    if (dt < 0.0 && !tb_method_is_adaptive(method)) {
        double step = 0.0;
        assert_int_equal(tb_scene_default_step(scene, method, &step), TB_STATUS_OK);
        dt = step / -dt;
    }
    tb_integrator_def def = test_integrator_def(method, dt, 1e-9);
    if (tb_method_is_adaptive(method)) {
        def.atol = 1e-12;
    }
    return test_integrator(scene, &def);
}

/* Advances to t frame by frame (1/60 s): an integrator's max_steps is a budget per advance, and
 * the stiff default contact takes the default step of 1e-5 s or less. */
static void advance_to(tb_integrator *integrator, double t)
{
    for (int frame = 1; frame <= (int)ceil(t * 60.0 - 1e-9); ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, fmin(frame / 60.0, t)), TB_STATUS_OK);
    }
}

/* Total linear momentum and angular momentum about the world origin, from the states. */
static void momenta(tb_scene *scene, double P[3], double L[3])
{
    const double *y = tb_scene_states(scene);
    memset(P, 0, 3 * sizeof *P);
    memset(L, 0, 3 * sizeof *L);
    for (size_t i = 0; i < tb_scene_body_count(scene); ++i) {
        const double *s = y + TB_STATE_SIZE * i, *x = s + TB_STATE_X, *p = s + TB_STATE_P;
        for (int k = 0; k < 3; ++k) {
            P[k] += p[k];
            L[k] += s[TB_STATE_L + k];
        }
        L[0] += x[1] * p[2] - x[2] * p[1];
        L[1] += x[2] * p[0] - x[0] * p[2];
        L[2] += x[0] * p[1] - x[1] * p[0];
    }
}

static double kinetic_energy(tb_scene *scene)
{
    double energy = 0.0;
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states(scene), &energy), TB_STATUS_OK);
    return energy;
}

/* x velocity of body i */
static double velocity_x(tb_scene *scene, size_t i, double mass)
{
    return tb_scene_states(scene)[TB_STATE_SIZE * i + TB_STATE_P] / mass;
}

/* An oblique hit with friction (offset 5 cm, so the balls spin up and slide): the loads are
 * equal and opposite at one world point, so total P is a linear invariant that every Runge-Kutta
 * and multistep method keeps to round-off: 1e-12 kg m/s (|P| ~ 1, ~100 steps of sums of forces
 * ~100 N times dt; measured 0). Angular momentum about the origin, sum x_i x P_i + L_i, has zero
 * derivative at every evaluation (the torques are p x (F_a + F_b) = 0 about the origin) but is
 * quadratic in the state, which these methods do not keep exactly: its change is the
 * integrator's error, so it must shrink with the step (by more than 2x for half the step; measured
 * 3.8x, not RK4's 16x, because the force has kinks at touchdown and in the friction) and with
 * CVODE's tolerance (below 1e-7 at rtol 1e-9; measured 9e-12), and stay below 1e-4 of |L| at RK4's
 * default step (measured 1.7e-6). */
static double collision_momentum_error(tb_method method, double dt, double *out_l_error)
{
    tb_contact_def contact = tb_contact_def_default();
    tb_scene *scene = two_balls(1.0, 1.0, 2.0, -0.5, 0.05, &contact);
    double P0[3], L0[3], P1[3], L1[3];
    momenta(scene, P0, L0);
    tb_integrator *integrator = integrator_for(scene, method, dt);
    advance_to(integrator, 0.15);
    momenta(scene, P1, L1);
    double p_error = 0.0, l_error = 0.0;
    for (int k = 0; k < 3; ++k) {
        p_error = fmax(p_error, fabs(P1[k] - P0[k]));
        l_error = fmax(l_error, fabs(L1[k] - L0[k]) / 0.05); /* |L| about the origin: 0.05 */
    }
    assert_true(fabs(L0[2] - 0.05) < 1e-15);
    assert_true(velocity_x(scene, 0, 1.0) < 0.5);                     /* they did collide */
    assert_true(fabs(tb_scene_states(scene)[TB_STATE_L + 2]) > 1e-4); /* friction spun ball 0 */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    *out_l_error = l_error;
    return p_error;
}

static void test_a_collision_keeps_linear_and_angular_momentum(void **state)
{
    (void)state;
    double l_coarse, l_fine;
    const double p_coarse = collision_momentum_error(TB_METHOD_RK4, 0.0, &l_coarse);
    const double p_fine = collision_momentum_error(TB_METHOD_RK4, -2.0, &l_fine);
    print_message("P error %.3g, %.3g; L relative error %.3g (default step), %.3g (half)\n",
                  p_coarse, p_fine, l_coarse, l_fine);
    double l_cvode;
    const double p_cvode = collision_momentum_error(TB_METHOD_CVODE_ADAMS, 0.0, &l_cvode);
    print_message("CVODE Adams at rtol 1e-9: P error %.3g, L relative error %.3g\n", p_cvode,
                  l_cvode);
    assert_true(p_coarse < 1e-12 && p_fine < 1e-12 && p_cvode < 1e-12);
    assert_true(l_coarse < 1e-4);
    assert_true(l_fine < l_coarse / 2.0);
    assert_true(l_cvode < 1e-7);
}

/* Separation speed over approach speed is e, for unequal masses (1 and 3 kg): the relative
 * motion along the normal is one oscillator of the reduced mass, the law's e(zeta) exactly.
 * RK4 at the default step (the guard's), within 5% (the target; the law's fade keeps a
 * fixed step's error near h omega squared). */
static double measured_restitution(double e, tb_method method, double dt)
{
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = e;
    contact.kinetic_friction = 0.0;
    contact.static_friction = 0.0;
    tb_scene *scene = two_balls(1.0, 1.0, 3.0, -0.5, 0.0, &contact);
    tb_integrator *integrator = integrator_for(scene, method, dt);
    advance_to(integrator, 0.15);
    const double separation = velocity_x(scene, 1, 3.0) - velocity_x(scene, 0, 1.0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return separation / 1.5;
}

static void test_balls_separate_at_e_times_their_approach_speed(void **state)
{
    (void)state;
    const double es[] = {0.2, 0.5, 0.8, 1.0};
    for (int k = 0; k < 4; ++k) {
        const double measured = measured_restitution(es[k], TB_METHOD_RK4, 0.0);
        print_message("e %.1f: measured %.5f\n", es[k], measured);
        assert_true(fabs(measured - es[k]) < 0.05 * es[k]);
    }
}

/* The kinetic energy after the collision is at most the energy before, beyond the integrator's
 * own error: the dashpot only takes energy and the clamp only removes force. With e = 1 and no
 * friction the law keeps energy exactly, so |after / before - 1| is RK4's error; it must shrink
 * with the step (more than 2x for half the step: the force's kink at touchdown, which a fixed
 * step straddles, makes the error fall as h^2 once h omega is small, and the default step, since
 * the guard no longer counts the arms' overdamped rates for balls, has h omega about 0.27, where
 * the fall is not yet 4x) and be below 1e-6 under CVODE at rtol 1e-9. For every e <= 1, with
 * friction, no gain beyond that measured error at the default step. */
static double energy_ratio(double e, tb_method method, double dt, double mu)
{
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = e;
    contact.kinetic_friction = mu;
    contact.static_friction = mu;
    tb_scene *scene = two_balls(1.0, 1.0, 3.0, -0.5, 0.02, &contact);
    const double before = kinetic_energy(scene);
    tb_integrator *integrator = integrator_for(scene, method, dt);
    advance_to(integrator, 0.15);
    const double after = kinetic_energy(scene);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return after / before;
}

static void test_energy_never_grows_through_a_collision(void **state)
{
    (void)state;
    const double coarse = energy_ratio(1.0, TB_METHOD_RK4, 0.0, 0.0);
    const double fine = energy_ratio(1.0, TB_METHOD_RK4, -2.0, 0.0);
    const double cvode = energy_ratio(1.0, TB_METHOD_CVODE_ADAMS, 0.0, 0.0);
    print_message("e 1: energy after / before - 1: %.3g (RK4, default step), %.3g (half), %.3g "
                  "(CVODE Adams)\n",
                  coarse - 1.0, fine - 1.0, cvode - 1.0);
    const double error = fabs(coarse - 1.0); /* RK4's, at the default step */
    assert_true(fabs(fine - 1.0) < error / 2.0);
    assert_true(fabs(cvode - 1.0) < 1e-6);
    const double es[] = {0.0, 0.2, 0.5, 0.8, 1.0};
    for (int k = 0; k < 5; ++k) {
        const double ratio = energy_ratio(es[k], TB_METHOD_RK4, 0.0, 0.5);
        print_message("e %.1f with friction: energy after / before %.6f\n", es[k], ratio);
        assert_true(ratio <= 1.0 + error);
    }
}

/* Equal masses, e = 1, head-on: the moving ball stops and the other leaves at its speed
 * (momentum and energy together leave no other outcome). 1% of the speed: the 5% restitution
 * tolerance gives up to 2.5% in each velocity; RK4 at the default step meets e far better. */
static void test_equal_elastic_balls_exchange_velocities(void **state)
{
    (void)state;
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = 1.0;
    tb_scene *scene = two_balls(1.0, 2.0, 1.0, 0.0, 0.0, &contact);
    tb_integrator *integrator = integrator_for(scene, TB_METHOD_RK4, 0.0);
    advance_to(integrator, 0.1);
    print_message("after: %.6f %.6f m/s\n", velocity_x(scene, 0, 1.0), velocity_x(scene, 1, 1.0));
    assert_true(fabs(velocity_x(scene, 0, 1.0)) < 0.01 * 2.0);
    assert_true(fabs(velocity_x(scene, 1, 1.0) - 2.0) < 0.01 * 2.0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* The same collision (e = 0.5, unequal masses) under every method: the fixed-step ones at their
 * default steps, CVODE at rtol 1e-9. RK4 and midpoint agree with CVODE BDF within 5% of e (the
 * issue's target), Adams within 1%; Euler, first order, within 15% (measured 13%: 0.566), and
 * BDF meets the law's e within 1%. rosenbrock's default step resolves the fastest oscillation at
 * h omega = 0.1 (scene/stability.c): measured 0.491, within 5% too. */
static void test_every_method_agrees_on_the_collision(void **state)
{
    (void)state;
    const double reference = measured_restitution(0.5, TB_METHOD_CVODE_BDF, 0.0);
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        const double e = measured_restitution(0.5, (tb_method)m, 0.0);
        print_message("%s: e %.5f (BDF %.5f)\n", tb_method_name((tb_method)m), e, reference);
        const double tolerance = m == TB_METHOD_EULER                  ? 0.15
                                 : tb_method_is_adaptive((tb_method)m) ? 0.01
                                                                       : 0.05;
        if (!(fabs(e - reference) < tolerance * 0.5)) {
            fail_msg("%s", tb_method_name((tb_method)m));
        }
    }
    assert_true(fabs(reference - 0.5) < 0.005); /* and CVODE meets the law's e */
}

/* A fixed step past the method's limit for the contact is refused at creation with the step
 * that would work, which is then accepted. */
static void test_the_guard_refuses_a_step_beyond_the_contacts_limit(void **state)
{
    (void)state;
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = 1e-5; /* omega = 990 rad/s */
    tb_scene *scene = two_balls(1.0, 1.0, 3.0, -0.5, 0.0, &contact);
    double limit = 0.0;
    char which[TB_DETAIL_SIZE];
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &limit, which), TB_STATUS_OK);
    print_message("RK4 limit %.4g s: %s\n", limit, which);
    assert_non_null(strstr(which, "contact"));
    /* RK4's imaginary limit ~2.8 over omega = 990 rad/s, or its real limit over friction's 400/s */
    assert_true(limit < 2.9 / 990.0); /* whatever else the guard counts (friction) */
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 1.2 * limit;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_UNSTABLE_STEP);
    assert_null(integrator);
    print_message("refused: %s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "use dt <="));
    def.dt = limit;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A ball (r 5 cm) resting on a 1 kg box (20 cm) resting on the ground, all at the default
 * settings. The ground sizes each corner for the box's own weight (k = M g / (4 p_g)), so it
 * carries box and ball by sinking (1 + m / M) p_g. The contact between bodies sizes its spring
 * for the lighter body's weight (include/tumble/effects.h: k = M_min g / (points p_c)), so the
 * ball sinks into the box by p_c m / min(m, M): p_c for a 0.5 kg ball, 2 p_c for a 2 kg one. An
 * equilibrium is a zero of the derivative, which no integrator moves: after 0.5 s (the contact
 * damps at zeta omega ~ 1000/s) within 2% of the sinking (8e-7 m) of the prediction. */
static void rest_ball_on_box(double m)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    const double size[3] = {0.2, 0.2, 0.2};
    tb_body_def box = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &box.mass, NULL), TB_STATUS_OK);
    box.position[2] = 0.1;
    assert_int_equal(tb_scene_add_body(scene, &box, NULL), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof size);
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_OK);
    tb_contact_point corners[8];
    size_t count = 0;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    tb_body_def ball = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, m, 0.05, &ball.mass, NULL), TB_STATUS_OK);
    ball.position[2] = 0.25;
    assert_int_equal(tb_scene_add_body(scene, &ball, NULL), TB_STATUS_OK);
    shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = 0.05;
    assert_int_equal(tb_scene_set_body_shape(scene, 1, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = integrator_for(scene, TB_METHOD_RK4, 0.0);
    for (int frame = 1; frame <= 30; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
    }
    const double *y = tb_scene_states(scene);
    const double ground_sink = (1.0 + m / 1.0) * ground.penetration;
    const double ball_sink = contact.penetration * m / fmin(m, 1.0);
    const double box_z = 0.1 - ground_sink, ball_z = box_z + 0.1 + 0.05 - ball_sink;
    print_message(
        "m %.1f: box %.4g m off (sinks %.3g), ball %.4g m off (sinks %.3g into the box)\n", m,
        y[2] - box_z, ground_sink, y[TB_STATE_SIZE + 2] - ball_z, ball_sink);
    assert_true(fabs(y[2] - box_z) < 0.02 * ground_sink);
    assert_true(fabs(y[TB_STATE_SIZE + 2] - ball_z) < 0.02 * ball_sink);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_a_ball_rests_on_a_box_at_the_predicted_sinking(void **state)
{
    (void)state;
    if (!tb_test_short()) { /* under memcheck the heavier ball alone: the same code paths */
        rest_ball_on_box(0.5);
    }
    rest_ball_on_box(2.0);
}

/* Each bad field is refused with a detail naming it, and the scene keeps its effects. */
static void expect_refused(tb_scene *scene, const tb_contact_def *def, const char *field)
{
    const size_t effects = tb_scene_effect_count(scene);
    assert_int_not_equal(tb_scene_add_contact(scene, def), TB_STATUS_OK);
    print_message("%s: %s\n", field, tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), field));
    assert_int_equal(tb_scene_effect_count(scene), effects);
}

static void test_bad_contact_definitions_are_refused(void **state)
{
    (void)state;
    tb_contact_def def = tb_contact_def_default();
    tb_scene *scene = two_balls(1.0, 1.0, 1.0, 0.0, 0.0, &def);
    const size_t ids[] = {0, 1, 0}, far[] = {0, 7};
    tb_contact_def bad;
    memset(&bad, 0, sizeof bad);
    expect_refused(scene, &bad, "tb_contact_def_default");
    struct {
        double *field;
        double value;
        const char *name;
    } numbers[] = {{&bad.restitution, 1.5, "restitution"},
                   {&bad.restitution, NAN, "restitution"},
                   {&bad.penetration, 0.0, "penetration"},
                   {&bad.penetration, INFINITY, "penetration"},
                   {&bad.gravity, -1.0, "gravity"},
                   {&bad.gravity, NAN, "gravity"},
                   {&bad.kinetic_friction, -0.1, "kinetic_friction"},
                   {&bad.static_friction, 0.1, "static_friction"},
                   {&bad.penetration, 1e-320, "penetration"}};
    for (size_t k = 0; k < sizeof numbers / sizeof numbers[0]; ++k) {
        bad = tb_contact_def_default();
        *numbers[k].field = numbers[k].value;
        expect_refused(scene, &bad, numbers[k].name);
    }
    bad = tb_contact_def_default();
    bad.bodies = ids;
    bad.body_count = 3;
    expect_refused(scene, &bad, "bodies[2]");
    bad.bodies = far;
    bad.body_count = 2;
    expect_refused(scene, &bad, "bodies[1]");
    assert_int_equal(tb_scene_add_contact(scene, NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_add_contact(NULL, &def), TB_STATUS_NULL_POINTER);
    tb_scene_destroy(scene);
}

/* Contact limited to a list: a third ball not in it passes through ball 1 untouched. */
static void test_only_the_listed_bodies_touch(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    add_ball(scene, 1.0, 0.1, -0.15, 0.0, 1.0);
    add_ball(scene, 1.0, 0.1, 0.15, 0.0, 0.0);
    add_ball(scene, 1.0, 0.1, 0.15, 1.0, 0.0); /* far to the side: never meets */
    add_ball(scene, 1.0, 0.1, -0.15, 0.05, 1.0);
    tb_contact_def def = tb_contact_def_default();
    const size_t ids[] = {0, 1, 2};
    def.bodies = ids;
    def.body_count = 3;
    assert_int_equal(tb_scene_add_contact(scene, &def), TB_STATUS_OK);
    tb_integrator *integrator = integrator_for(scene, TB_METHOD_RK4, 0.0);
    advance_to(integrator, 0.2);
    assert_true(fabs(velocity_x(scene, 3, 1.0) - 1.0) < 1e-14); /* body 3: not listed */
    assert_true(velocity_x(scene, 1, 1.0) > 0.3);               /* body 1 was hit by body 0 */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* CVODE at its default tolerances (rtol 1e-6, the scene's automatic atol) must not step over a
 * collision: in free flight its error estimate is zero and its steps grow without bound, so two
 * balls 0.1 m apart at 2 m/s met nothing but a step that jumped them through each other (the
 * light ball ended at x = 1.7 m still at 2 m/s). A scene with contact between bodies caps the
 * adaptive step at half the shortest push, so a step's end lands in every collision. Then the
 * outcome is the law's: 1 kg at 2 m/s on 3 kg at rest with e = 0.8 leaves at (1 - 3 e) v / 4 =
 * -0.7 and (1 + e) v / 4 = 0.9 m/s; the tolerance is 1% of the approach speed, far above what
 * rtol 1e-6 leaves and far below the pass-through's error (the balls keep 2 and 0 m/s). The
 * balls first spend 1.5 s apart, so the steps have grown long before they meet. */
static void test_cvode_at_its_defaults_does_not_step_over_a_collision(void **unused)
{
    (void)unused;
    const tb_method methods[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (int m = 0; m < 2; ++m) {
        tb_contact_def contact = tb_contact_def_default();
        contact.restitution = 0.8;
        tb_scene_def scene_def = tb_scene_def_default();
        tb_scene *scene = NULL;
        assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
        add_ball(scene, 1.0, 0.1, -3.2, 0.0, 2.0);
        add_ball(scene, 3.0, 0.1, 0.0, 0.0, 0.0);
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator_def def = tb_integrator_def_default();
        assert_int_equal(tb_integrator_def_set_method(&def, methods[m]), TB_STATUS_OK);
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        advance_to(integrator, 2.0);
        const double light = velocity_x(scene, 0, 1.0), heavy = velocity_x(scene, 1, 3.0);
        print_message("%s at its defaults: light %.6f m/s (-0.7), heavy %.6f m/s (0.9)\n",
                      tb_method_name(methods[m]), light, heavy);
        assert_true(fabs(light + 0.7) < 0.02 && fabs(heavy - 0.9) < 0.02);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_collision_keeps_linear_and_angular_momentum),
        cmocka_unit_test(test_balls_separate_at_e_times_their_approach_speed),
        cmocka_unit_test(test_energy_never_grows_through_a_collision),
        cmocka_unit_test(test_equal_elastic_balls_exchange_velocities),
        cmocka_unit_test(test_every_method_agrees_on_the_collision),
        cmocka_unit_test(test_cvode_at_its_defaults_does_not_step_over_a_collision),
        cmocka_unit_test(test_the_guard_refuses_a_step_beyond_the_contacts_limit),
        cmocka_unit_test(test_a_ball_rests_on_a_box_at_the_predicted_sinking),
        cmocka_unit_test(test_bad_contact_definitions_are_refused),
        cmocka_unit_test(test_only_the_listed_bodies_touch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
