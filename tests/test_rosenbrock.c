/* The linearly implicit method "rosenbrock" (ROS2, src/ode/rosenbrock.c): its order measured on
 * an exact solution, its stability far past RK4's limit, agreement between the system's own
 * Jacobian and difference quotients, and contact scenes at a user's step. */
#include "tumble/tumble.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>

/* y0' = y1, y1' = -w^2 y0 (ctx: w): the harmonic oscillator, exact y0 = cos(w t) from (1, 0). */
static int oscillator(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    const double w = *(const double *)ctx;
    dydt[0] = y[1];
    dydt[1] = -w * w * y[0];
    return 0;
}

static size_t oscillator_capacity(double t, const double *y, void *ctx)
{
    (void)t, (void)y, (void)ctx;
    return 4;
}

/* Its Jacobian [[0, 1], [-w^2, 0]] in CSR, the diagonal's zeros included. */
static int oscillator_jacobian(double t, const double *y, const double *fy, tb_ode_sparse *J,
                               void *ctx)
{
    (void)t, (void)y, (void)fy;
    const double w = *(const double *)ctx;
    static const size_t rows[3] = {0, 2, 4}, columns[4] = {0, 1, 0, 1};
    const double values[4] = {0.0, 1.0, -w * w, 0.0};
    for (size_t k = 0; k < 4; ++k) {
        J->columns[k] = columns[k];
        J->values[k] = values[k];
    }
    for (size_t k = 0; k < 3; ++k) {
        J->row_starts[k] = rows[k];
    }
    return 0;
}

/* y0 after advancing the oscillator (rate w) to t_end at step h, with the system's Jacobian or
 * without (difference quotients); y1 into *velocity. */
static double oscillate(double w, double h, double t_end, int own_jacobian, double *velocity)
{
    tb_ode_system system = {.n = 2, .derivative = oscillator, .ctx = &w};
    if (own_jacobian) {
        system.jacobian.capacity = oscillator_capacity;
        system.jacobian.evaluate = oscillator_jacobian;
    }
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_ROSENBROCK;
    def.dt = h;
    def.max_steps = 10000000;
    double y[2] = {1.0, 0.0};
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, t_end), TB_STATUS_OK);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    /* difference quotients: one Jacobian a step; the system's own: the factorisation is held
     * and reused while the steps pass (this J is constant), so one Jacobian in all unless a step
     * is halved */
    if (own_jacobian) {
        assert_true(stats.jacobian_evals >= 1 && stats.jacobian_evals < stats.steps);
    } else {
        assert_int_equal(stats.jacobian_evals, stats.steps);
    }
    tb_integrator_destroy(integrator);
    *velocity = y[1];
    return y[0];
}

/* ROS2 is of order 2: the error at t = 1 falls by 4 each time h halves. The measured order
 * log2(e(h) / e(h/2)) is within 0.05 of 2 at h = 0.1 .. 0.0125 (the next term of the error is
 * O(h^3), 5% of the leading one at h = 0.1), with either Jacobian. */
static void test_rosenbrock_is_of_order_two_on_the_oscillator(void **state)
{
    (void)state;
    for (int own = 0; own < 2; ++own) {
        double previous = 0.0, velocity = 0.0;
        for (int k = 0; k < 4; ++k) {
            const double h = 0.1 / (double)(1 << k);
            const double error = fabs(oscillate(1.0, h, 1.0, own, &velocity) - cos(1.0));
            if (k > 0) {
                const double order = log2(previous / error);
                print_message("own Jacobian %d: h = %g error %.3e order %.3f\n", own, h, error,
                              order);
                assert_true(fabs(order - 2.0) < 0.05);
            }
            previous = error;
        }
    }
}

/* x' = -k x at h k = 1e3, 2.8 / 360 times past RK4's limit on the real axis: one step multiplies
 * x by R(-1000) = (1 + 1000 (2 gamma - 1)) / (1 + 1000 gamma)^2 = 8.28e-4, the method's
 * stability function (rosenbrock.c); the step is measured against it to 1e-9 relative. A spring
 * at h w = 1e3 neither grows nor keeps ringing: after 100 steps its energy is below 1e-6 of the
 * start (L-stability damps what the step cannot resolve). */
static int decay(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    dydt[0] = -*(const double *)ctx * y[0];
    return 0;
}

static void test_rosenbrock_is_stable_far_past_rk4s_limit(void **state)
{
    (void)state;
    double rate = 1000.0, y = 1.0;
    tb_ode_system system = {.n = 1, .derivative = decay, .ctx = &rate};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_ROSENBROCK;
    def.dt = 1.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, &y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    const double gamma = 1.0 + 1.0 / sqrt(2.0), z = -1000.0;
    const double exact = (1.0 + (1.0 - 2.0 * gamma) * z) / ((1.0 - gamma * z) * (1.0 - gamma * z));
    print_message("R(-1000) measured %.6e, stated %.6e\n", y, exact);
    assert_true(fabs(y - exact) < 1e-9 * fabs(exact));
    for (int own = 0; own < 2; ++own) {
        double velocity = 0.0;
        const double x = oscillate(1000.0, 1.0, 100.0, own, &velocity);
        const double energy = x * x + velocity * velocity / (1000.0 * 1000.0);
        print_message("spring at h w = 1e3, 100 steps: energy %.3e of the start\n", energy);
        assert_true(energy < 1e-6);
    }
}

/* x' = v, v' = -w^2 x - 2 zeta w v + a (ctx: w, zeta, a): a damped oscillator under a constant
 * load; its Jacobian [[0, 1], [-w^2, -2 zeta w]] is constant. */
static int damped(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    const double *p = ctx;
    dydt[0] = y[1];
    dydt[1] = -p[0] * p[0] * y[0] - 2.0 * p[1] * p[0] * y[1] + p[2];
    return 0;
}

static int damped_jacobian(double t, const double *y, const double *fy, tb_ode_sparse *J, void *ctx)
{
    const double *p = ctx, w = p[0];
    oscillator_jacobian(t, y, fy, J, (void *)&w);
    J->values[3] = -2.0 * p[1] * w;
    return 0;
}

/* The range check (rosenbrock.c, docs/integrators.md "Halving") never halves a linear mode: ROS2
 * takes a component past h times the range of its end rates by at most (sqrt(2) - 1) / 2 = 0.207
 * of h (|f0| + |f1|), under the check's 1/4. Every step of 40, from each of 8 phases, at h w from
 * 0.5 to 1e4 and damping ratios 0 to 5, with and without a load, is then taken whole and the
 * factorisation of the first reused (one Jacobian in the run: a halved step would factorise
 * its halves afresh). */
static void test_a_linear_mode_is_never_halved(void **state)
{
    (void)state;
    static const double hw[] = {0.5, 2.0, 14.0, 1e2, 1e4}, zetas[] = {0.0, 0.1, 1.0, 5.0};
    for (size_t k = 0; k < 5 * 4 * 2 * 8; ++k) {
        const double phase = 0.785398163397448 * (double)(k % 8);
        double p[3] = {hw[k / 64], zetas[k / 16 % 4], k / 8 % 2 == 0 ? 0.0 : -10.0};
        tb_ode_system system = {.n = 2, .derivative = damped, .ctx = p};
        system.jacobian.capacity = oscillator_capacity;
        system.jacobian.evaluate = damped_jacobian;
        tb_integrator_def def = tb_integrator_def_default();
        def.method = TB_METHOD_ROSENBROCK;
        def.dt = 1.0;
        double y[2] = {cos(phase), p[0] * sin(phase)};
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 40.0), TB_STATUS_OK);
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        if (stats.jacobian_evals != 1) {
            print_error("h w %g zeta %g load %g phase %g: %ld Jacobians\n", p[0], p[1], p[2], phase,
                        stats.jacobian_evals);
        }
        assert_int_equal(stats.jacobian_evals, 1);
        tb_integrator_destroy(integrator);
    }
}

/* The example scene NAME with an integrator of the method at step dt made at t = 0; the caller
 * destroys both. */
static tb_scene *start_example(const char *name, double dt, tb_integrator **out)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", TUMBLE_SCENES_DIR, name);
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, &run, &error), TB_STATUS_OK);
    assert_int_equal(tb_integrator_def_set_method(&run.integrator, TB_METHOD_ROSENBROCK),
                     TB_STATUS_OK);
    run.integrator.dt = dt;
    assert_int_equal(tb_scene_integrator_create(scene, &run.integrator, 0.0, out), TB_STATUS_OK);
    return scene;
}

/* Advances to t_end, printing the integrator's detail where that fails. */
static void advance(tb_integrator *integrator, double t_end)
{
    const tb_status status = tb_integrator_advance(integrator, t_end);
    if (status != TB_STATUS_OK) {
        print_error("%s\n", tb_integrator_detail(integrator));
    }
    assert_int_equal(status, TB_STATUS_OK);
}

/* start_example advanced to t_end. */
static tb_scene *run_example(const char *name, double dt, double t_end, tb_integrator **out)
{
    tb_scene *scene = start_example(name, dt, out);
    advance(*out, t_end);
    return scene;
}

/* head_on_balls (1 kg at 2 m/s on 3 kg at rest, e = 0.8) at 1/1000 s. The contact's fastest
 * oscillation is 9.08e3 rad/s (tumble check), so an impact lasts pi / 9.08e3 = 0.35 ms, a third of
 * a step: the restitution cannot be resolved at this step (the 10% target is not met;
 * measured 0.11, and within 10% only from dt = 2.5e-5 s, docs/integrators.md). What holds and is
 * checked: momentum is kept to 1e-9 kg m/s (equal and opposite loads, round-off of the solve)
 * and the unresolved impact stores no energy: the kinetic energy after is not above the start's
 * 2 J (to 1e-9 J). */
static void test_head_on_at_a_millisecond_keeps_momentum_and_stores_no_energy(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = run_example("head_on_balls", 1e-3, 1.0, &integrator);
    const double *y = tb_scene_states(scene);
    double light[3], heavy[3];
    tb_scene_body_velocity(scene, y, 0, light);
    tb_scene_body_velocity(scene, y, 1, heavy);
    const double e = (heavy[0] - light[0]) / 2.0;
    const double kinetic = 0.5 * light[0] * light[0] + 1.5 * heavy[0] * heavy[0];
    print_message("restitution %.4f (stated 0.8), momentum %.3e off, energy %.4f J of 2\n", e,
                  light[0] + 3.0 * heavy[0] - 2.0, kinetic);
    assert_true(fabs(light[0] + 3.0 * heavy[0] - 2.0) < 1e-9);
    assert_true(kinetic < 2.0 + 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* box_on_slope (a box set on a 20 degree slope, static friction 0.6 > tan 20) at 1/240 s: after
 * 2 s static friction holds it inside the cone: its centre moves slower than 1e-6 m/s (the
 * issue's rest target; measured 9e-16 m/s). */
static void test_a_box_on_a_slope_rests_at_240_hz(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = run_example("box_on_slope", 1.0 / 240.0, 2.0, &integrator);
    double v[3];
    tb_scene_body_velocity(scene, tb_scene_states(scene), 0, v);
    const double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    print_message("speed after 2 s: %.3e m/s\n", speed);
    assert_true(speed < 1e-6);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* chain (ten 1 kg links on ball joints, falling and whipping) at 1/240 s: the scene gives no
 * sparse Jacobian for jointed bodies (the joints' solve couples a whole chain), so the method
 * takes dense difference quotients (130 unknowns) and runs 2 s without failing; before, the
 * contact pattern without the joints' couplings made the step blow up at 0.4 s. The energy
 * drift is not checked: the step damps the whip (L-stable; tumble run reports 14 J lost in 2 s). */
static void test_a_jointed_chain_runs_at_240_hz(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = run_example("chain", 1.0 / 240.0, 2.0, &integrator);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    print_message("steps %ld, derivatives %ld\n", stats.steps, stats.derivative_evals);
    assert_int_equal(stats.failed_steps, 0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* stack (five boxes stacked, each turned 3 degrees) at 1/240 s, where the step without halving
 * threw box2 off at t = 0.033 s: after 0.25 s the top box is where RK4 at its default step puts
 * it (z = 0.4499878 m: 12 micrometres of settling) to 1e-6 m, and moves slower than 1e-4 m/s
 * (measured 7.3e-8 m/s with the predictor's Jacobian taken at onsets only, 7e-6 m/s with it at
 * every step, 6.4e-7 m/s since the quotients are central at the start's touch,
 * scene_jacobian_values.c; RK4: 2e-6 m/s). The bound is not the rest target (1e-6 m/s): the
 * halved steps' jitter follows every change of a step (docs/integrators.md). */
static void test_a_stack_of_boxes_stands_at_240_hz(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = run_example("stack", 1.0 / 240.0, 0.25, &integrator);
    tb_body_state top;
    double v[3];
    assert_int_equal(tb_scene_get_state(scene, 4, &top), TB_STATUS_OK);
    tb_scene_body_velocity(scene, tb_scene_states(scene), 4, v);
    const double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    print_message("top box z %.7f m, speed %.3e m/s\n", top.x[2], speed);
    assert_true(fabs(top.x[2] - 0.4499878) < 1e-6);
    assert_true(speed < 1e-4);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* newtons_cradle (the first of five 263 g balls on strings released 40.2 mm above the others,
 * steel on steel e = 0.95) at 1/240 s: each impact lasts about pi / 4.95e3 rad/s (tumble
 * check), 0.63 ms, a seventh of a step, made at a stage point and gone by the step's end. No ball
 * may ever move faster than the whole initial potential energy allows, sqrt(2 g 0.0402) = 0.888 m/s
 * (the springs' stretch adds 2 mJ at most, under 1% of the speed; bound 1.01 x): an impact the
 * matrix did not see stores energy and throws a ball off (9.4 m/s at 1.09 s when the predictor's
 * Jacobian was left out; docs/integrators.md). */
static void test_an_impact_inside_a_step_stores_no_energy(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = start_example("newtons_cradle", 1.0 / 240.0, &integrator);
    const double limit = 1.01 * sqrt(2.0 * 9.81 * 0.040207349504);
    double fastest = 0.0;
    for (int frame = 1; frame <= 360; ++frame) { /* 1.5 s, a step a frame */
        advance(integrator, frame / 240.0);
        for (size_t body = 0; body < 5; ++body) {
            double v[3];
            tb_scene_body_velocity(scene, tb_scene_states(scene), body, v);
            fastest = fmax(fastest, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
        }
    }
    print_message("fastest ball over 1.5 s: %.4f m/s (bound %.4f)\n", fastest, limit);
    assert_true(fastest < limit);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* stack at 1/240 s: once every box is asleep the derivative is 0 at both stage times, and ROS2's
 * stages k1 = M^-1 f and k2 = M^-1 (f(t + h, y + h k1) - 2 k1) are 0 for any matrix M, so a step
 * leaves the state as it is, bit for bit, without a Jacobian or a factorisation (the column of ten
 * in bench_peer_contact: 14.7 CPU s per simulated s before, 0.19 after, the same states). */
static void test_a_sleeping_scene_steps_without_a_matrix(void **state)
{
    (void)state;
    tb_integrator *integrator = NULL;
    tb_scene *scene = run_example("stack", 1.0 / 240.0, 4.0, &integrator);
    size_t asleep = 0;
    assert_int_equal(tb_scene_asleep_count(scene, &asleep), TB_STATUS_OK);
    assert_int_equal(asleep, 5);
    const size_t n = tb_scene_state_size(scene);
    double *before = malloc(n * sizeof(double));
    assert_non_null(before);
    memcpy(before, tb_scene_states(scene), n * sizeof(double));
    tb_integrator_stats at_sleep, after;
    tb_integrator_get_stats(integrator, &at_sleep);
    advance(integrator, 5.0);
    tb_integrator_get_stats(integrator, &after);
    print_message("Jacobians %ld -> %ld over the last second, asleep %zu of 5\n",
                  at_sleep.jacobian_evals, after.jacobian_evals, asleep);
    assert_int_equal(after.jacobian_evals, at_sleep.jacobian_evals);
    assert_memory_equal(before, tb_scene_states(scene), n * sizeof(double));
    free(before);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* --- a standing column of ten boxes (bench_peer_contact's column case) ---------------------- */

#define COLUMN_BOXES 10
#define COLUMN_MASS 0.5
#define COLUMN_EDGE 0.1

/* Ten 10 cm, 0.5 kg boxes, each set exactly on the one below, the lowest exactly on the floor
 * (restitution 0.3), the default contact between them, gravity. */
static tb_scene *column_of_boxes(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    const double size[3] = {COLUMN_EDGE, COLUMN_EDGE, COLUMN_EDGE};
    for (int k = 0; k < COLUMN_BOXES; ++k) {
        tb_body_def def = tb_body_def_default();
        tb_mass_from_box(TB_MASS_GIVEN, COLUMN_MASS, size, &def.mass, NULL);
        def.position[2] = COLUMN_EDGE * (0.5 + k);
        size_t id = 0;
        assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_BOX;
        memcpy(shape.size, size, sizeof size);
        assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.restitution = 0.3;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

/* The boxes' heights, their depths into what carries them (depth[0] into the floor) and an
 * energy that cannot exceed the column's own: gravity's, the boxes' translation and the normal
 * springs' 1/2 k d^2 with k = M g / penetration (effects.h: k per point M g / (4 penetration),
 * four points a face). Rotation and friction springs left out make it a lower bound. */
static double column_energy(tb_scene *scene, double depth[COLUMN_BOXES], double *fastest)
{
    const double g = 9.81, p = tb_contact_def_default().penetration;
    const double p_ground = tb_ground_def_default().penetration;
    double energy = 0.0, below = 0.0;
    *fastest = 0.0;
    for (size_t k = 0; k < COLUMN_BOXES; ++k) {
        tb_body_state s;
        double v[3];
        assert_int_equal(tb_scene_get_state(scene, k, &s), TB_STATUS_OK);
        tb_scene_body_velocity(scene, tb_scene_states(scene), k, v);
        const double speed = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        *fastest = fmax(*fastest, speed);
        depth[k] = k == 0 ? 0.5 * COLUMN_EDGE - s.x[2] : COLUMN_EDGE - (s.x[2] - below);
        below = s.x[2];
        const double spring = COLUMN_MASS * g / (k == 0 ? p_ground : p);
        energy += 0.5 * COLUMN_MASS * speed * speed + COLUMN_MASS * g * s.x[2] +
                  (depth[k] > 0.0 ? 0.5 * spring * depth[k] * depth[k] : 0.0);
    }
    return energy;
}

/* The column of ten at 1/240 s, advanced to samples every 10 ms for 1 s (as bench_peer_contact
 * samples it: a short step ends at each sample). Started exactly touching, every contact's depth
 * is 0, where the law's force max(0, k d + ...) has its kink: forward difference quotients saw
 * the spring from one body only (the one deepening it), and the step threw the column apart
 * (boxes at 1.04 m/s at 0.06 s, a 11 mm gap under box9, depths to 0.28 mm). Checked against the
 * contact law alone:
 *   - no energy is stored: the lower bound column_energy never exceeds its start (exact touch:
 *     the heights' m g z) by more than 1e-6 J (a thousandth of the ~1e-3 J the settling
 *     releases; the throw above stored 0.3 J);
 *   - at rest after 1 s: every box slower than 1e-6 m/s (the rest target);
 *   - each box sinks into the one below by the penetration times the boxes it carries, its own
 *     included ((10 - k) 8e-7 m: k = M g / p per box carried, effects.h), the lowest into the
 *     floor by 10 ground penetrations, each within 1% (the law is linear at rest, where the
 *     dashpot is idle; 1% leaves room for a residual motion of 1e-8 m);
 *   - no depth beyond 2 mm at any sample (the bound). */
static void test_a_column_of_ten_boxes_stands_at_240_hz(void **state)
{
    (void)state;
    tb_scene *scene = column_of_boxes();
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_ROSENBROCK), TB_STATUS_OK);
    def.dt = 1.0 / 240.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    double depth[COLUMN_BOXES], fastest = 0.0, deepest = 0.0, surplus = -INFINITY;
    const double start = column_energy(scene, depth, &fastest);
    for (int sample = 1; sample <= 100; ++sample) {
        advance(integrator, 0.01 * sample);
        surplus = fmax(surplus, column_energy(scene, depth, &fastest) - start);
        for (size_t k = 0; k < COLUMN_BOXES; ++k) {
            deepest = fmax(deepest, depth[k]);
        }
    }
    print_message("energy over the start at most %.3e J, deepest %.4e m, fastest at 1 s %.3e m/s\n",
                  surplus, deepest, fastest);
    assert_true(surplus < 1e-6);
    assert_true(fastest < 1e-6);
    assert_true(deepest < 2e-3);
    for (size_t k = 0; k < COLUMN_BOXES; ++k) {
        const double expected =
            k == 0 ? COLUMN_BOXES * tb_ground_def_default().penetration
                   : (double)(COLUMN_BOXES - k) * tb_contact_def_default().penetration;
        print_message("box%zu sinks %.5e m, the law %.5e m\n", k, depth[k], expected);
        assert_true(fabs(depth[k] - expected) < 0.01 * expected);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A 2 cm, 100 g ball dropped from 0.5 m onto a 1 cm thick, 1 kg plate lying on the floor: it
 * meets the plate at sqrt(2 g 0.5) = 3.1 m/s, at which it could cross the plate's half-thickness
 * in 1.6 ms, under the step of 4.2 ms. The scene's tunnelling guard refused every fixed step here
 * (at t = 0.125 s); rosenbrock now takes such a step in halves no longer than the bound
 * (tb_ode_events.split_limit), and the guard refuses it only where 1/128 of the step is longer.
 * Checked at every frame: the ball never sinks 2 mm into the plate (it does not pass through);
 * the energy (translation and gravity, a lower bound) never exceeds the start's by 1e-6 J (the
 * drop's 0.49 J); after 1 s both rest (under 1e-6 m/s), the ball's centre lower than it would
 * sit on rigid bodies by the law's sinkings, 8e-7 m into the plate under its own weight and the
 * plate's 1.1 / 1 times 8e-7 m into the floor, within 1%. */
static void test_a_ball_dropped_on_a_thin_plate_at_240_hz(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    const double r = 0.02, thick = 0.01, drop = 0.5, g = 9.81, m_ball = 0.1, m_plate = 1.0;
    tb_body_def def = tb_body_def_default();
    const double size[3] = {0.3, 0.3, thick};
    tb_mass_from_box(TB_MASS_GIVEN, m_plate, size, &def.mass, NULL);
    def.position[2] = 0.5 * thick;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof size);
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_OK);
    def = tb_body_def_default();
    tb_mass_from_sphere(TB_MASS_GIVEN, m_ball, r, &def.mass, NULL);
    def.position[2] = thick + r + drop;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = r;
    assert_int_equal(tb_scene_set_body_shape(scene, 1, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -g}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator_def idef = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&idef, TB_METHOD_ROSENBROCK), TB_STATUS_OK);
    idef.dt = 1.0 / 240.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &idef, 0.0, &integrator), TB_STATUS_OK);
    const double masses[2] = {m_plate, m_ball};
    double start = 0.0, surplus = -INFINITY, deepest = 0.0, fastest = 0.0;
    for (int frame = 0; frame <= 240; ++frame) {
        if (frame > 0) {
            advance(integrator, frame / 240.0);
        }
        double energy = 0.0, z[2];
        fastest = 0.0;
        for (size_t k = 0; k < 2; ++k) {
            tb_body_state s;
            double v[3];
            assert_int_equal(tb_scene_get_state(scene, k, &s), TB_STATUS_OK);
            tb_scene_body_velocity(scene, tb_scene_states(scene), k, v);
            const double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            fastest = fmax(fastest, sqrt(v2));
            energy += 0.5 * masses[k] * v2 + masses[k] * g * s.x[2];
            z[k] = s.x[2];
        }
        start = frame == 0 ? energy : start;
        surplus = fmax(surplus, energy - start);
        deepest = fmax(deepest, z[0] + 0.5 * thick + r - z[1]);
    }
    tb_body_state ball;
    assert_int_equal(tb_scene_get_state(scene, 1, &ball), TB_STATUS_OK);
    const double sinking = thick + r - ball.x[2];
    const double law = contact.penetration + (m_plate + m_ball) / m_plate * ground.penetration;
    print_message("energy over the start at most %.3e J, deepest in the plate %.3e m, at 1 s "
                  "%.3e m/s, sunk %.5e m (the law %.5e m)\n",
                  surplus, deepest, fastest, sinking, law);
    assert_true(surplus < 1e-6);
    assert_true(deepest < 2e-3);
    assert_true(fastest < 1e-6);
    assert_true(fabs(sinking - law) < 0.01 * law);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rosenbrock_is_of_order_two_on_the_oscillator),
        cmocka_unit_test(test_rosenbrock_is_stable_far_past_rk4s_limit),
        cmocka_unit_test(test_a_linear_mode_is_never_halved),
        cmocka_unit_test(test_head_on_at_a_millisecond_keeps_momentum_and_stores_no_energy),
        cmocka_unit_test(test_a_box_on_a_slope_rests_at_240_hz),
        cmocka_unit_test(test_a_jointed_chain_runs_at_240_hz),
        cmocka_unit_test(test_a_stack_of_boxes_stands_at_240_hz),
        cmocka_unit_test(test_an_impact_inside_a_step_stores_no_energy),
        cmocka_unit_test(test_a_sleeping_scene_steps_without_a_matrix),
        cmocka_unit_test(test_a_column_of_ten_boxes_stands_at_240_hz),
        cmocka_unit_test(test_a_ball_dropped_on_a_thin_plate_at_240_hz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
