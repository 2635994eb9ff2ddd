/* The stability guard and the default step know the jointed bodies' modes (issue 21,
 * src/constraints/joint_rate.c): a 1000 kg weight on five 1 kg links sways at hundreds of
 * rad/s under its tension, which sets RK4's step; a soft joint adds its spring; a double
 * pendulum keeps its steps. Each checked against physics known without the code: the chain's
 * highest mode from its linearised equations, energy conservation, a spring's frequency. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <string.h>

#define LINKS 5
#define LINK 0.2    /* m, each 1 kg link's length (a 0.02 m square section) */
#define WEIGHT 1000 /* kg, a sphere of radius RADIUS hung by its top */
#define RADIUS 0.2

/* The chain hanging straight down from the origin, the weight moving at v (m/s, world). */
static tb_scene *heavy_chain(const double v[3])
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    size_t previous = TB_WORLD;
    for (size_t i = 0; i <= LINKS; ++i) {
        const double top = -(double)i * LINK;
        const size_t id =
            i < LINKS
                ? test_add_rod(scene, 1.0, LINK, 0.0, (double[]){0.0, 0.0, top - 0.5 * LINK})
                : test_add_ball(scene, NULL, WEIGHT, RADIUS, (double[]){0.0, 0.0, top - RADIUS}, v);
        tb_joint_def def = tb_joint_def_default();
        def.body_a = id;
        def.body_b = previous;
        def.anchor[2] = top;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        previous = id;
    }
    return scene;
}

/* x = A^-1 b for the n x n system (Gaussian elimination; A is positive definite). */
static void solve(int n, double A[LINKS][LINKS], const double b[LINKS], double x[LINKS])
{
    double M[LINKS][LINKS + 1];
    for (int i = 0; i < n; ++i) {
        memcpy(M[i], A[i], sizeof A[i]);
        M[i][n] = b[i];
    }
    for (int c = 0; c < n; ++c) {
        for (int r = c + 1; r < n; ++r) {
            const double f = M[r][c] / M[c][c];
            for (int k = c; k <= n; ++k) {
                M[r][k] -= f * M[c][k];
            }
        }
    }
    for (int r = n - 1; r >= 0; --r) {
        double s = M[r][n];
        for (int k = r + 1; k < n; ++k) {
            s -= M[r][k] * x[k];
        }
        x[r] = s / M[r][r];
    }
}

/* The chain's highest sideways mode at rest, from its linearised equations: the joints' sideways
 * displacements u_1..u_5 (u_0 = 0 at the pivot); a link of mass m between u_a and u_b has the
 * kinetic energy m/6 (u_a'^2 + u_a' u_b' + u_b'^2) and, under the tension T it carries, the
 * potential T / (2 l) (u_b - u_a)^2; the weight adds its mass at the last joint (an upper bound
 * on its effective mass there, which changes the highest mode little). Power iteration on
 * M^-1 K. */
static double chain_highest_mode(void)
{
    double M[LINKS][LINKS] = {{0}}, K[LINKS][LINKS] = {{0}};
    for (int k = 0; k < LINKS; ++k) { /* link k between joints k and k + 1 */
        const double m = 1.0, T = TEST_G * (WEIGHT + m * (LINKS - k - 0.5));
        const int ends[2] = {k - 1, k}; /* unknowns: joint j + 1 is u[j]; -1 the pivot */
        const double mass[2][2] = {{2 * m / 6, m / 6}, {m / 6, 2 * m / 6}};
        const double stiff[2][2] = {{T / LINK, -T / LINK}, {-T / LINK, T / LINK}};
        for (int a = 0; a < 2; ++a) {
            for (int b = 0; b < 2 && ends[a] >= 0; ++b) {
                if (ends[b] >= 0) {
                    M[ends[a]][ends[b]] += mass[a][b];
                    K[ends[a]][ends[b]] += stiff[a][b];
                }
            }
        }
    }
    M[LINKS - 1][LINKS - 1] += WEIGHT;
    double v[LINKS] = {1, -1, 1, -1, 1}, w[LINKS], Kv[LINKS], lambda = 0.0;
    for (int iteration = 0; iteration < 200; ++iteration) {
        for (int i = 0; i < LINKS; ++i) {
            Kv[i] = 0.0;
            for (int k = 0; k < LINKS; ++k) {
                Kv[i] += K[i][k] * v[k];
            }
        }
        solve(LINKS, M, Kv, w);
        double top = 0.0, vv = 0.0, ww = 0.0;
        for (int i = 0; i < LINKS; ++i) {
            top = fmax(top, fabs(w[i]));
            vv += v[i] * v[i];
            ww += w[i] * w[i];
        }
        lambda = sqrt(ww / vv);
        for (int i = 0; i < LINKS; ++i) {
            v[i] = w[i] / top;
        }
    }
    return sqrt(lambda);
}

static double rk4_limit(void)
{
    tb_method_info info;
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, &info), TB_STATUS_OK);
    return info.imaginary_limit;
}

/* At rest, the rate the guard sees (RK4's imaginary limit over its largest stable step) lies at
 * or above the chain's highest mode (669 rad/s: the estimate bounds each link alone, its
 * neighbours held, so it is an upper bound on a uniform chain) and within 1.25 of it (the
 * link's rotation about its centre, sqrt(12 T / (m l)), 767 rad/s, against the mode where the
 * neighbours move too). RK4 at 1/240 s is then refused (|h lambda| = 3.2 > 2.83), 1/480 s
 * accepted; the guard names the joints. */
static void test_guard_sees_the_light_links_sway_under_the_weight(void **state)
{
    (void)state;
    tb_scene *scene = heavy_chain((double[]){0.0, 0.0, 0.0});
    double dt = 0.0;
    char which[TB_DETAIL_SIZE];
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, which), TB_STATUS_OK);
    const double rate = rk4_limit() / dt, mode = chain_highest_mode();
    print_message("heavy chain: guard %.4g 1/s (%s), highest mode %.4g rad/s\n", rate, which, mode);
    assert_true(rate >= mode && rate <= 1.25 * mode);
    assert_non_null(strstr(which, "joints"));
    tb_integrator *integrator = NULL;
    tb_integrator_def def = test_integrator_def(TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_UNSTABLE_STEP);
    def.dt = 1.0 / 480.0;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* The largest |E - E0| over 2 s of the swinging chain under RK4 at dt (0: the default step). */
static double swing_drift(double dt, bool allow_unstable, double *out_dt)
{
    tb_scene *scene = heavy_chain((double[]){1.0, 0.5, 0.0});
    /* the links at rest under the moving weight: their velocities made to agree first */
    assert_int_equal(tb_scene_project_joints(scene, 0.0, NULL), TB_STATUS_OK);
    tb_scene_set_allow_unstable(scene, allow_unstable);
    if (dt == 0.0) {
        assert_int_equal(tb_scene_default_step(scene, TB_METHOD_RK4, &dt), TB_STATUS_OK);
    }
    *out_dt = dt;
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, dt, 0.0);
    const double e0 = test_total_energy(scene);
    double drift = 0.0;
    for (int frame = 1; frame <= 120; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        drift = fmax(drift, fabs(test_total_energy(scene) - e0));
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return drift;
}

/* Ball joints do no work: the energy is kept to RK4's error where its step resolves the links'
 * sway. At the default step, which the guard's rate sets (12 steps a period or more), the drift
 * stays within 1e-6 of M g L (the heavy-chain example's bound; measured 4.8e-8 at 1/2400 s);
 * at 1/240 s, forced past the guard, it does not (measured 2.7e-5: the step the guard refuses
 * is one where the energy drifts). The start is projected first (the links at rest under the
 * moving weight), so that the energy is measured from a start on the joints. */
static void test_default_step_keeps_the_heavy_chain_energy(void **state)
{
    (void)state;
    const double MgL = WEIGHT * TEST_G * (LINKS * LINK + RADIUS);
    double dt = 0.0, coarse = 0.0;
    const double kept = swing_drift(0.0, false, &dt);
    const double lost = swing_drift(1.0 / 240.0, true, &coarse);
    print_message("heavy chain rk4: default dt %.3g s drift %.3g M g L; 1/240 s drift %.3g M g L\n",
                  dt, kept / MgL, lost / MgL);
    assert_true(kept <= 1e-6 * MgL);
    assert_true(lost > 1e-6 * MgL);
}

/* A soft joint is a spring on its rows: a 1 kg ball on a 50 Hz soft ball joint to the world, at
 * its rest point, oscillates at w = 2 pi 50 rad/s (its rows' effective mass is the ball's mass:
 * the anchor at its centre); the guard's rate is that, to round-off. */
static void test_guard_sees_a_soft_joint_spring(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t ball = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, 0.0}, NULL);
    tb_joint_def def = tb_joint_def_default();
    def.body_a = ball;
    def.soft_frequency = 50.0;
    def.soft_damping_ratio = 0.1;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    double dt = 0.0;
    assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL), TB_STATUS_OK);
    const double w = 2.0 * TEST_PI * 50.0;
    assert_true(fabs(rk4_limit() / dt - w) <= 1e-12 * w);
    tb_scene_destroy(scene);
}

/* A motor is a velocity servo, d omega/dt = 20/s (speed - omega) while under its cap: a real
 * decay at 20/s, which the guard counts (RK4's largest stable step real_limit / 20 = 0.139 s, to
 * round-off) and names (the joints, decaying). The refusal is the servo's own: on this linear
 * equation each RK4 step multiplies the speed error by R(-20 h) = 1 - z + z^2/2 - z^3/6 + z^4/24
 * (z = 20 h) exactly, 1/3 at h = 0.1 s (accepted: the error after 10 steps is 3^-10 of the
 * start's to round-off) and 5 at h = 0.2 s (refused; forced, the error grows 5^10-fold). A
 * 1 kg m^2 wheel (a 6 kg 1 x 1 x 0.2 m box) toward 1 rad/s under a 1e12 N m cap, which RK4's
 * stages never reach (a capped stage would break the linear equation: 100 N m is passed by the
 * last stage at h = 0.2 s). */
static void test_guard_sees_a_motor_servo(void **state)
{
    (void)state;
    tb_method_info info;
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, &info), TB_STATUS_OK);
    const double steps[2] = {0.1, 0.2};
    for (int k = 0; k < 2; ++k) {
        tb_scene *scene = test_empty_scene();
        const size_t wheel =
            test_add_box(scene, 6.0, (double[]){1.0, 1.0, 0.2}, (double[]){0.0, 0.0, 0.0});
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_HINGE;
        def.body_a = wheel;
        def.motor = TB_MOTOR_VELOCITY;
        def.motor_speed = 1.0;
        def.motor_max_force = 1e12;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        double dt = 0.0;
        char which[TB_DETAIL_SIZE];
        assert_int_equal(tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, which), TB_STATUS_OK);
        assert_true(fabs(info.real_limit / dt - 20.0) <= 1e-12 * 20.0);
        assert_non_null(strstr(which, "joints"));
        tb_integrator *integrator = NULL;
        tb_integrator_def idef = test_integrator_def(TB_METHOD_RK4, steps[k], 0.0);
        assert_int_equal(tb_scene_integrator_create(scene, &idef, 0.0, &integrator),
                         k == 0 ? TB_STATUS_OK : TB_STATUS_UNSTABLE_STEP);
        tb_scene_set_allow_unstable(scene, true);
        if (k == 1) {
            assert_int_equal(tb_scene_integrator_create(scene, &idef, 0.0, &integrator),
                             TB_STATUS_OK);
        }
        assert_int_equal(tb_integrator_advance(integrator, 10.0 * steps[k]), TB_STATUS_OK);
        double omega[3];
        assert_int_equal(
            tb_scene_body_angular_velocity(scene, tb_scene_states(scene), wheel, omega),
            TB_STATUS_OK);
        const double z = 20.0 * steps[k];
        const double growth = 1.0 - z + z * z / 2.0 - z * z * z / 6.0 + z * z * z * z / 24.0;
        const double expected = pow(growth, 10.0); /* the error (omega - 1) / (0 - 1) */
        print_message("motor servo rk4 at %.2g s: guard step %.4g s (%s); error ratio %.17g, "
                      "R^10 %.17g\n",
                      steps[k], dt, which, 1.0 - omega[2], expected);
        assert_true(fabs((1.0 - omega[2]) - expected) <= 1e-12 * fmax(1.0, fabs(expected)));
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The double pendulum (1 m rods, hinges) keeps its steps: its links' sway under their own
 * weight is slow (sqrt(12 T / (m l)) ~ 15 rad/s at most), so the default step stays 1/240 s and
 * RK4 at 1/240 s is accepted. */
static void test_double_pendulum_keeps_its_steps(void **state)
{
    (void)state;
    tb_scene *scene = test_double_pendulum(1.0, 0.5, NULL);
    double dt = 0.0;
    assert_int_equal(tb_scene_default_step(scene, TB_METHOD_RK4, &dt), TB_STATUS_OK);
    assert_true(dt == 1.0 / 240.0);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A soft joint over-damped far past any use: damping ratio zeta = 1e300 at 1e-300 Hz decays at
 * the faster root of s^2 + 2 zeta w s + w^2, w (zeta + sqrt(zeta^2 - 1)) = 2 zeta w = 4 pi /s
 * (w = 2 pi 1e-300 rad/s), a slow joint; zeta^2 overflowed, the guard took the rate as infinite
 * and refused every step. RK4's largest stable step is now real_limit / (4 pi), to round-off. At
 * 1 Hz and zeta = 1e308 the rate, 4 pi 1e308, is infinite indeed: the integrator's creation at
 * the default step is refused naming that rate, not "def.dt: must be > 0, got 0" (the default
 * step it had taken as 0, a dt the caller never gave). */
static void test_a_soft_joint_overdamped_far_past_use_is_judged_by_its_rate(void **state)
{
    (void)state;
    tb_method_info info;
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, &info), TB_STATUS_OK);
    const double frequencies[2] = {1e-300, 1.0}, ratios[2] = {1e300, 1e308};
    for (int k = 0; k < 2; ++k) {
        tb_scene *scene = test_empty_scene();
        const size_t ball = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, 0.0}, NULL);
        tb_joint_def def = tb_joint_def_default();
        def.body_a = ball;
        def.soft_frequency = frequencies[k];
        def.soft_damping_ratio = ratios[k];
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        double dt = 0.0;
        const tb_status stable = tb_scene_max_stable_step(scene, TB_METHOD_RK4, &dt, NULL);
        tb_integrator_def step = test_integrator_def(TB_METHOD_RK4, 0.0, 0.0);
        tb_integrator *integrator = NULL;
        const tb_status made = tb_scene_integrator_create(scene, &step, 0.0, &integrator);
        if (k == 0) {
            assert_int_equal(stable, TB_STATUS_OK);
            assert_true(fabs(info.real_limit / dt - 4.0 * TEST_PI) <= 1e-12 * 4.0 * TEST_PI);
            assert_int_equal(made, TB_STATUS_OK);
        } else {
            assert_int_equal(stable, TB_STATUS_NOT_FINITE);
            assert_int_equal(made, TB_STATUS_NOT_FINITE);
            assert_non_null(strstr(tb_scene_detail(scene), "rate inf"));
            assert_null(strstr(tb_scene_detail(scene), "def.dt"));
            assert_null(integrator);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_guard_sees_the_light_links_sway_under_the_weight),
        cmocka_unit_test(test_default_step_keeps_the_heavy_chain_energy),
        cmocka_unit_test(test_guard_sees_a_soft_joint_spring),
        cmocka_unit_test(test_a_soft_joint_overdamped_far_past_use_is_judged_by_its_rate),
        cmocka_unit_test(test_guard_sees_a_motor_servo),
        cmocka_unit_test(test_double_pendulum_keeps_its_steps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
