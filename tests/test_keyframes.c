/* Keyframe curves (tumble/keys.h) against what calculus knows: the curve passes through its
 * keys, its velocities are the derivatives of its poses (central differences converge to them
 * at second order), a turn at a constant rate and a straight line at a constant speed are
 * reproduced exactly, a cubic curve is C1 at its keys and a linear one is not; plus the
 * refusals, each with its status, its detail and nothing made. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/keys.h"

#include <math.h>
#include <string.h>

static tb_body_motion_sample at(tb_keyframes *kf, double t)
{
    tb_body_motion_sample s;
    assert_int_equal(tb_keyframes_sample(t, kf, &s), 0);
    return s;
}

static tb_body_motion_sample left_of(tb_keyframes *kf, double t)
{
    tb_body_motion_sample s;
    assert_int_equal(tb_keyframes_sample_left(t, kf, &s), 0);
    return s;
}

static tb_keyframes *make(const tb_body_key *keys, size_t count, tb_interpolation how)
{
    tb_keyframes *kf = NULL;
    tb_error error;
    const tb_status status = tb_keyframes_create(keys, count, how, &kf, &error);
    if (status != TB_STATUS_OK) {
        print_error("%s\n", error.message);
    }
    assert_int_equal(status, TB_STATUS_OK);
    return kf;
}

/* (w, x, y, z) products and the rotation about the unit axis n by angle, written here from the
 * definitions (not the library's helpers). */
static void q_mul(double out[4], const double a[4], const double b[4])
{
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

static void axis_angle(double q[4], const double n[3], double angle)
{
    q[0] = cos(0.5 * angle);
    for (int i = 0; i < 3; ++i) {
        q[i + 1] = sin(0.5 * angle) * n[i];
    }
}

static double q_dot(const double a[4], const double b[4])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

/* The largest difference between two orientations, as rotations (q and -q are one). */
static double q_distance(const double a[4], const double b[4])
{
    const double sign = q_dot(a, b) < 0 ? -1.0 : 1.0;
    double d = 0.0;
    for (int i = 0; i < 4; ++i) {
        d = fmax(d, fabs(a[i] - sign * b[i]));
    }
    return d;
}

static double v_distance(const double a[3], const double b[3])
{
    return fmax(fabs(a[0] - b[0]), fmax(fabs(a[1] - b[1]), fabs(a[2] - b[2])));
}

/* A curve with uneven spacing, turns of up to 2.4 rad between keys about changing axes, one
 * quaternion given with the opposite sign and one not normalised; velocities given at some
 * keys only (cubic only). */
static size_t wild_keys(tb_body_key keys[5], bool with_velocities)
{
    static const double t[5] = {0.0, 0.4, 0.65, 1.3, 1.5};
    static const double x[5][3] = {
        {0, 0, 0}, {1, -0.5, 0.2}, {1.4, 0.3, 0.9}, {0.2, 1, 2}, {0, 0, 1}};
    static const double axes[5][3] = {
        {0, 0, 1}, {0.6, 0, 0.8}, {0, 1, 0}, {0.48, 0.6, 0.64}, {1, 0, 0}};
    static const double angles[5] = {0.0, 1.1, 2.4, 4.0, 5.5};
    static const double scale[5] = {1.0, -1.0, 3.0, 1.0, 1.0};
    for (size_t k = 0; k < 5; ++k) {
        keys[k] = tb_body_key_default();
        keys[k].t = t[k];
        memcpy(keys[k].position, x[k], sizeof x[k]);
        axis_angle(keys[k].orientation, axes[k], angles[k]);
        for (int i = 0; i < 4; ++i) {
            keys[k].orientation[i] *= scale[k];
        }
    }
    if (with_velocities) {
        keys[0].has_velocity = true;
        keys[0].velocity[0] = 2.0;
        keys[2].has_velocity = true;
        keys[2].velocity[1] = -3.0;
        keys[2].velocity[2] = 1.0;
        keys[1].has_angular_velocity = true;
        keys[1].angular_velocity[0] = 4.0;
        keys[1].angular_velocity[2] = -1.0;
        keys[4].has_angular_velocity = true; /* the end's: the left limit there */
        keys[4].angular_velocity[1] = 2.0;
    }
    return 5;
}

static const tb_interpolation every_interpolation[3] = {
    TB_INTERPOLATION_LINEAR, TB_INTERPOLATION_CUBIC, TB_INTERPOLATION_STEP};

/* At a key's time the curve is the key: the position to the bit, the orientation the key's
 * normalised (to a rounding of the normalisation, 4 ulp), from either side. */
static void test_the_curve_passes_through_its_keys(void **state)
{
    (void)state;
    for (int m = 0; m < 3; ++m) {
        tb_body_key keys[5];
        const size_t n = wild_keys(keys, every_interpolation[m] == TB_INTERPOLATION_CUBIC);
        tb_keyframes *kf = make(keys, n, every_interpolation[m]);
        for (size_t k = 0; k < n; ++k) {
            double unit[4];
            const double norm = sqrt(q_dot(keys[k].orientation, keys[k].orientation));
            for (int i = 0; i < 4; ++i) {
                unit[i] = keys[k].orientation[i] / norm;
            }
            const tb_body_motion_sample right = at(kf, keys[k].t);
            assert_memory_equal(right.position, keys[k].position, sizeof right.position);
            assert_true(q_distance(right.orientation, unit) <= 4e-16);
            if (m != 2 || k == 0) { /* a step's left limit is the key before */
                const tb_body_motion_sample left = left_of(kf, keys[k].t);
                assert_memory_equal(left.position, keys[k].position, sizeof left.position);
                assert_true(q_distance(left.orientation, unit) <= 4e-16);
            }
        }
        tb_keyframes_destroy(kf);
    }
}

/* A key's given velocity and angular velocity are the cubic curve's there, from the right and
 * (through the segment's end tangent J^-1 omega and back through J) from the left: 1e-14
 * covers the rounding of that round trip. */
static void test_a_given_velocity_is_the_curve_velocity(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const size_t n = wild_keys(keys, true);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_CUBIC);
    for (size_t k = 0; k < n; ++k) {
        const tb_body_motion_sample right = at(kf, keys[k].t), left = left_of(kf, keys[k].t);
        if (keys[k].has_velocity) {
            assert_memory_equal(right.velocity, keys[k].velocity, sizeof right.velocity);
            if (k > 0) {
                assert_true(v_distance(left.velocity, keys[k].velocity) <= 1e-14);
            }
        }
        if (keys[k].has_angular_velocity) {
            if (k + 1 < n) {
                assert_true(v_distance(right.angular_velocity, keys[k].angular_velocity) <= 1e-14);
            }
            assert_true(v_distance(left.angular_velocity, keys[k].angular_velocity) <= 1e-14);
        }
    }
    tb_keyframes_destroy(kf);
}

/* The errors of central differences of width 2h against the analytic derivatives: of position
 * and of orientation (omega = 2 q' (x) q*), and of the velocities for the accelerations. */
typedef struct errors {
    double velocity, angular_velocity, acceleration, angular_acceleration;
} errors;

static errors difference_errors(tb_keyframes *kf, double t, double h)
{
    const tb_body_motion_sample s = at(kf, t), after = at(kf, t + h), before = at(kf, t - h);
    errors e = {0, 0, 0, 0};
    double dq[4], omega[4];
    for (int i = 0; i < 4; ++i) {
        dq[i] = (after.orientation[i] - before.orientation[i]) / (2 * h);
    }
    const double conjugate[4] = {s.orientation[0], -s.orientation[1], -s.orientation[2],
                                 -s.orientation[3]};
    q_mul(omega, dq, conjugate);
    for (int i = 0; i < 3; ++i) {
        const double v = (after.position[i] - before.position[i]) / (2 * h);
        const double a = (after.velocity[i] - before.velocity[i]) / (2 * h);
        const double alpha = (after.angular_velocity[i] - before.angular_velocity[i]) / (2 * h);
        e.velocity = fmax(e.velocity, fabs(v - s.velocity[i]));
        e.angular_velocity =
            fmax(e.angular_velocity, fabs(2 * omega[i + 1] - s.angular_velocity[i]));
        e.acceleration = fmax(e.acceleration, fabs(a - s.acceleration[i]));
        e.angular_acceleration =
            fmax(e.angular_acceleration, fabs(alpha - s.angular_acceleration[i]));
    }
    return e;
}

/* A central difference's error is f''' h^2 / 6 + O(h^4): halving h divides it by 4. At
 * h = 1e-3 the error is about 1e-7 (f''' of order 1 to 100 here), far above the rounding
 * eps |f| / h ~ 1e-12, so the ratio is 4 to within the O(h^2) relative size of the next term;
 * 3.6 to 4.4 allows for it. */
static void check_ratio(double coarse, double fine, const char *what, double t)
{
    print_message("t = %-5g %-20s error %.3e -> %.3e, ratio %.3f\n", t, what, coarse, fine,
                  coarse / fine);
    assert_true(coarse < 1e-3);
    assert_true(coarse / fine > 3.6 && coarse / fine < 4.4);
}

/* Points inside segments, more than 2h from any key; 0.41 and 0.66 are 0.01 s after a key,
 * where |phi| < 0.5 and the Jacobian's coefficients come from their Taylor series. */
static void test_velocities_are_the_derivatives_of_the_pose(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const size_t n = wild_keys(keys, true);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_CUBIC);
    static const double times[] = {0.13, 0.41, 0.5, 0.61, 0.66, 0.9, 1.2, 1.41};
    for (size_t k = 0; k < sizeof times / sizeof times[0]; ++k) {
        const errors coarse = difference_errors(kf, times[k], 1e-3);
        const errors fine = difference_errors(kf, times[k], 5e-4);
        check_ratio(coarse.velocity, fine.velocity, "velocity", times[k]);
        check_ratio(coarse.angular_velocity, fine.angular_velocity, "angular velocity", times[k]);
        /* a cubic's acceleration is linear in t: its central difference is exact to rounding
         * (eps |a| / h, |a| < 1e3) */
        assert_true(coarse.acceleration <= 1e-9);
        check_ratio(coarse.angular_acceleration, fine.angular_acceleration, "angular acceleration",
                    times[k]);
    }
    tb_keyframes_destroy(kf);
}

/* Linear: velocity constant on a segment (the chord over the interval), angular velocity
 * constant (slerp turns about a fixed axis at a fixed rate), both accelerations zero. The
 * central difference of position at h = 1e-4 agrees to its rounding, eps |x| / h ~ 1e-11. */
static void test_linear_moves_at_constant_velocity_between_keys(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const size_t n = wild_keys(keys, false);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_LINEAR);
    for (size_t k = 0; k + 1 < n; ++k) {
        const double h = keys[k + 1].t - keys[k].t;
        const tb_body_motion_sample start = at(kf, keys[k].t);
        for (int j = 1; j < 4; ++j) {
            const double t = keys[k].t + 0.25 * j * h;
            const tb_body_motion_sample s = at(kf, t);
            const errors e = difference_errors(kf, t, 1e-4);
            assert_near(e.velocity, 0.0, 1e-10);
            /* q turns at a constant rate w: the difference gives w sin(w h/2) / (w h/2), short
             * by w^3 h^2 / 24 (to 1% here), plus rounding */
            const double w = sqrt(start.angular_velocity[0] * start.angular_velocity[0] +
                                  start.angular_velocity[1] * start.angular_velocity[1] +
                                  start.angular_velocity[2] * start.angular_velocity[2]);
            assert_near(e.angular_velocity, 0.0, 1.01 * w * w * w * 1e-8 / 24 + 1e-10);
            for (int i = 0; i < 3; ++i) {
                assert_near(s.velocity[i], (keys[k + 1].position[i] - keys[k].position[i]) / h,
                            1e-14);
                assert_near(s.angular_velocity[i], start.angular_velocity[i], 0.0);
                assert_near(s.acceleration[i], 0.0, 0.0);
                assert_near(s.angular_acceleration[i], 0.0, 0.0);
            }
        }
    }
    tb_keyframes_destroy(kf);
}

/* q(t) = exp(omega t n) q0 sampled at uneven times: cubic with each key's angular velocity
 * given, cubic with Catmull-Rom tangents (on the segments between interior keys: the ends'
 * tangents are 0), and linear (slerp) all give omega n and zero angular acceleration, and the
 * exact orientation, to rounding (1e-13 at 7 rad of turn). */
static void test_a_constant_rate_turn_is_reproduced_exactly(void **state)
{
    (void)state;
    const double omega = 5.0, n[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3};
    const double q0[4] = {0.5, 0.5, -0.5, 0.5}, times[5] = {0.0, 0.3, 0.7, 1.2, 1.4};
    tb_body_key keys[5];
    for (size_t k = 0; k < 5; ++k) {
        double turn[4];
        keys[k] = tb_body_key_default();
        keys[k].t = times[k];
        axis_angle(turn, n, omega * times[k]);
        q_mul(keys[k].orientation, turn, q0);
        for (int i = 0; i < 3; ++i) {
            keys[k].angular_velocity[i] = omega * n[i];
        }
    }
    for (int variant = 0; variant < 3; ++variant) {
        for (size_t k = 0; k < 5; ++k) {
            keys[k].has_angular_velocity = variant == 0;
        }
        tb_keyframes *kf =
            make(keys, 5, variant == 2 ? TB_INTERPOLATION_LINEAR : TB_INTERPOLATION_CUBIC);
        const double from = variant == 1 ? times[1] : times[0];
        const double to = variant == 1 ? times[3] : times[4];
        for (int j = 0; j < 100; ++j) {
            const double t = from + (to - from) * j / 100.0;
            const tb_body_motion_sample s = at(kf, t);
            double turn[4], exact[4];
            axis_angle(turn, n, omega * t);
            q_mul(exact, turn, q0);
            assert_true(q_distance(s.orientation, exact) <= 1e-13);
            for (int i = 0; i < 3; ++i) {
                assert_near(s.angular_velocity[i], omega * n[i], 1e-12);
                assert_near(s.angular_acceleration[i], 0.0, 1e-10);
            }
        }
        tb_keyframes_destroy(kf);
    }
}

/* |q| = 1 everywhere (to the rounding of a product of two unit quaternions, 1e-15), on a
 * dense grid through turns of up to 4 rad a segment. */
static void test_the_orientation_stays_a_unit_quaternion(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const size_t n = wild_keys(keys, true);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_CUBIC);
    for (int j = 0; j <= 2000; ++j) {
        const tb_body_motion_sample s = at(kf, -0.1 + 1.7 * j / 2000.0);
        assert_near(sqrt(q_dot(s.orientation, s.orientation)), 1.0, 1e-15);
    }
    tb_keyframes_destroy(kf);
}

/* At an interior key a cubic curve's velocities from the two sides agree (C1): sampled 1e-9 s
 * either side they differ by |a| 2e-9 < 1e-6. A linear curve's jump there from one chord's
 * slope to the next, as it must. */
static void test_cubic_is_c1_at_keys_and_linear_is_not(void **state)
{
    (void)state;
    tb_body_key keys[5];
    size_t n = wild_keys(keys, true);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_CUBIC);
    for (size_t k = 1; k + 1 < n; ++k) {
        const tb_body_motion_sample before = at(kf, keys[k].t - 1e-9);
        const tb_body_motion_sample after = at(kf, keys[k].t + 1e-9);
        assert_true(v_distance(before.velocity, after.velocity) <= 1e-6);
        assert_true(v_distance(before.angular_velocity, after.angular_velocity) <= 1e-6);
        assert_true(q_distance(before.orientation, after.orientation) <= 1e-7);
    }
    tb_keyframes_destroy(kf);
    n = wild_keys(keys, false);
    kf = make(keys, n, TB_INTERPOLATION_LINEAR);
    for (size_t k = 1; k + 1 < n; ++k) {
        const tb_body_motion_sample before = left_of(kf, keys[k].t), after = at(kf, keys[k].t);
        for (int i = 0; i < 3; ++i) {
            const double h0 = keys[k].t - keys[k - 1].t, h1 = keys[k + 1].t - keys[k].t;
            assert_near(before.velocity[i], (keys[k].position[i] - keys[k - 1].position[i]) / h0,
                        1e-14);
            assert_near(after.velocity[i], (keys[k + 1].position[i] - keys[k].position[i]) / h1,
                        1e-14);
        }
        assert_true(v_distance(before.velocity, after.velocity) > 1.0);
    }
    tb_keyframes_destroy(kf);
}

/* Before the first key and after the last the pose holds, at rest (all rates exactly 0), even
 * where the cubic curve's end tangent was given. */
static void test_the_pose_holds_before_and_after_the_keys(void **state)
{
    (void)state;
    for (int m = 0; m < 3; ++m) {
        tb_body_key keys[5];
        const size_t n = wild_keys(keys, every_interpolation[m] == TB_INTERPOLATION_CUBIC);
        tb_keyframes *kf = make(keys, n, every_interpolation[m]);
        static const double times[] = {-1e9, -1.0, -1e-12, 1.5, 1.5 + 1e-12, 3.0, 1e9};
        for (size_t j = 0; j < sizeof times / sizeof times[0]; ++j) {
            const tb_body_motion_sample s = at(kf, times[j]);
            const tb_body_motion_sample expected = at(kf, times[j] < 0 ? 0.0 : 1.5);
            assert_memory_equal(s.position, expected.position, sizeof s.position);
            assert_memory_equal(s.orientation, expected.orientation, sizeof s.orientation);
            const double zero[3] = {0, 0, 0};
            if (times[j] != 0.0) {
                assert_memory_equal(s.velocity, zero, sizeof zero);
                assert_memory_equal(s.angular_velocity, zero, sizeof zero);
                assert_memory_equal(s.acceleration, zero, sizeof zero);
                assert_memory_equal(s.angular_acceleration, zero, sizeof zero);
            }
        }
        tb_keyframes_destroy(kf);
    }
}

/* Step: the pose of the last key at or before t, at rest; before the first key, the first. */
static void test_step_holds_the_last_key(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const size_t n = wild_keys(keys, false);
    tb_keyframes *kf = make(keys, n, TB_INTERPOLATION_STEP);
    const double zero[3] = {0, 0, 0};
    for (size_t k = 0; k < n; ++k) {
        const double end = k + 1 < n ? keys[k + 1].t : keys[k].t + 1.0;
        for (int j = 0; j < 4; ++j) {
            const double t = keys[k].t + (end - keys[k].t) * j / 4.0;
            const tb_body_motion_sample s = at(kf, t);
            assert_memory_equal(s.position, keys[k].position, sizeof s.position);
            assert_memory_equal(s.velocity, zero, sizeof zero);
            assert_memory_equal(s.angular_velocity, zero, sizeof zero);
        }
    }
    assert_memory_equal(at(kf, -5.0).position, keys[0].position, sizeof keys[0].position);
    tb_keyframes_destroy(kf);
}

/* Catmull-Rom tangents: on a body moving uniformly (collinear positions at equal spacing, all
 * numbers exact in binary) the interior keys' velocity is exactly the body's, and between
 * interior keys the curve is the straight line at that speed (to rounding, 1e-14). With uneven
 * spacing the tangent is the derivative of the parabola through three keys, so x = t^2 gives
 * exactly 2 t_k (where the chord (x_(k+1) - x_(k-1)) / (t_(k+1) - t_(k-1)) would give
 * t_(k+1) + t_(k-1)). */
static void test_catmull_rom_tangents_follow_uniform_motion(void **state)
{
    (void)state;
    tb_body_key keys[5];
    const double v[3] = {2.0, -1.0, 3.0};
    for (size_t k = 0; k < 5; ++k) {
        keys[k] = tb_body_key_default();
        keys[k].t = 0.5 * (double)k;
        for (int i = 0; i < 3; ++i) {
            keys[k].position[i] = 0.5 * (i == 2) + v[i] * keys[k].t;
        }
    }
    tb_keyframes *kf = make(keys, 5, TB_INTERPOLATION_CUBIC);
    for (size_t k = 1; k < 4; ++k) {
        assert_memory_equal(at(kf, keys[k].t).velocity, v, sizeof v);
    }
    for (int j = 0; j <= 40; ++j) { /* [0.5, 1.5], 1.5 from the left */
        const double t = 0.5 + j / 40.0;
        const tb_body_motion_sample s = j < 40 ? at(kf, t) : left_of(kf, t);
        for (int i = 0; i < 3; ++i) {
            assert_near(s.position[i], 0.5 * (i == 2) + v[i] * t, 1e-14);
            assert_near(s.velocity[i], v[i], 1e-14);
            assert_near(s.acceleration[i], 0.0, 1e-13);
        }
    }
    tb_keyframes_destroy(kf);
    static const double uneven[5] = {0.0, 0.25, 1.0, 1.125, 2.0};
    for (size_t k = 0; k < 5; ++k) {
        keys[k].t = uneven[k];
        keys[k].position[0] = uneven[k] * uneven[k];
    }
    kf = make(keys, 5, TB_INTERPOLATION_CUBIC);
    for (size_t k = 1; k < 4; ++k) {
        assert_near(at(kf, uneven[k]).velocity[0], 2.0 * uneven[k], 1e-14);
    }
    tb_keyframes_destroy(kf);
}

/* One key: the pose everywhere, at rest. tb_keyframes_times gives the keys' times. */
static void test_one_key_holds_and_times_are_the_keys(void **state)
{
    (void)state;
    tb_body_key key = tb_body_key_default();
    key.t = 2.0;
    key.position[1] = 7.0;
    tb_keyframes *kf = make(&key, 1, TB_INTERPOLATION_CUBIC);
    assert_near(at(kf, -3.0).position[1], 7.0, 0.0);
    assert_near(at(kf, 2.0).position[1], 7.0, 0.0);
    assert_near(left_of(kf, 9.0).position[1], 7.0, 0.0);
    size_t count = 0;
    assert_non_null(tb_keyframes_times(kf, &count));
    assert_int_equal(count, 1);
    tb_keyframes_destroy(kf);
    tb_body_key keys[5];
    wild_keys(keys, false);
    kf = make(keys, 5, TB_INTERPOLATION_LINEAR);
    const double *times = tb_keyframes_times(kf, &count);
    assert_int_equal(count, 5);
    for (size_t k = 0; k < 5; ++k) {
        assert_near(times[k], keys[k].t, 0.0);
    }
    tb_keyframes_destroy(kf);
    assert_null(tb_keyframes_times(NULL, &count));
    assert_int_equal(count, 0);
    tb_keyframes_destroy(NULL);
}

/* --- refusals: each row a status, a detail naming the input, nothing made, keys unchanged -- */

typedef struct refusal {
    const char *name;
    size_t count;
    tb_interpolation interpolation;
    tb_status status;
    const char *detail;
} refusal;

/* Row r's keys: four good cubic keys, then the one change the row is about. */
static void spoil(tb_body_key keys[4], int r)
{
    for (size_t k = 0; k < 4; ++k) {
        keys[k] = tb_body_key_default();
        keys[k].t = (double)k;
        keys[k].position[0] = (double)k;
    }
    switch (r) {
    case 4:
        keys[2].t = 1.0;
        break;
    case 5:
        keys[3].t = 0.5;
        break;
    case 6:
        keys[1].t = NAN;
        break;
    case 7:
        keys[2].position[1] = INFINITY;
        break;
    case 8:
        keys[1].orientation[3] = NAN;
        break;
    case 9:
        memset(keys[3].orientation, 0, sizeof keys[3].orientation);
        break;
    case 10:
        keys[2].has_velocity = true, keys[2].velocity[0] = NAN;
        break;
    case 11:
        keys[1].has_angular_velocity = true;
        break; /* given to a linear curve */
    case 12:
        keys[0].t = -1.7e308, keys[1].t = 1.7e308;
        break;
    case 13:
        keys[0].position[2] = -1e308, keys[1].position[2] = 1e308;
        break;
    case 14:
        keys[1].t = 1e-300; /* 1 m in 1e-300 s: a velocity of 1e300, an acceleration past it */
        break;
    default:
        break;
    }
}

static const refusal refusals[] = {
    {"NULL keys", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NULL_POINTER, "keys is NULL"},
    {"NULL out", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NULL_POINTER, "out_keyframes is NULL"},
    {"no keys", 0, TB_INTERPOLATION_CUBIC, TB_STATUS_INVALID_ARGUMENT, "count: must be >= 1"},
    {"unknown interpolation", 4, (tb_interpolation)7, TB_STATUS_INVALID_ARGUMENT,
     "interpolation: unknown value 7"},
    {"repeated time", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_INVALID_ARGUMENT,
     "keys[2].t: must be > keys[1].t = 1, got 1"},
    {"decreasing time", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_INVALID_ARGUMENT, "keys[3].t"},
    {"NaN time", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NOT_FINITE, "keys[1].t: must be finite"},
    {"infinite position", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NOT_FINITE, "keys[2].position"},
    {"NaN orientation", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NOT_FINITE, "keys[1].orientation"},
    {"zero quaternion", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_INVALID_ARGUMENT,
     "keys[3].orientation: must be a nonzero quaternion"},
    {"NaN velocity", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_NOT_FINITE, "keys[2].velocity"},
    {"velocity given to linear", 4, TB_INTERPOLATION_LINEAR, TB_STATUS_INVALID_ARGUMENT,
     "keys[1].angular_velocity: only cubic interpolation reads it"},
    {"interval overflows", 4, TB_INTERPOLATION_LINEAR, TB_STATUS_INVALID_ARGUMENT,
     "keys[1].t: the interval"},
    {"chord overflows", 4, TB_INTERPOLATION_LINEAR, TB_STATUS_INVALID_ARGUMENT,
     "keys[0]: the curve overflows"},
    {"keys 1e-300 s apart", 4, TB_INTERPOLATION_CUBIC, TB_STATUS_INVALID_ARGUMENT,
     "keys[0]: the curve overflows"},
    {"count SIZE_MAX", SIZE_MAX, TB_INTERPOLATION_CUBIC, TB_STATUS_OUT_OF_MEMORY,
     "more than the address space"},
    {"count 2^60", (size_t)1 << 60, TB_INTERPOLATION_CUBIC, TB_STATUS_OUT_OF_MEMORY,
     "more than the address space"},
    {"count 2^56 (bytes fit size_t)", (size_t)1 << 56, TB_INTERPOLATION_CUBIC,
     TB_STATUS_OUT_OF_MEMORY, "more than the address space"},
};

/* The counts past memory are refused before a key is read (the array holds 4): valgrind and
 * the sanitizers would see a read past it. */
static void test_bad_keys_are_refused_by_name(void **state)
{
    (void)state;
    for (int r = 0; r < (int)(sizeof refusals / sizeof refusals[0]); ++r) {
        tb_body_key keys[4], copy[4];
        spoil(keys, r);
        memcpy(copy, keys, sizeof keys);
        tb_keyframes *kf = (tb_keyframes *)&copy; /* not NULL: must become NULL */
        tb_error error;
        const tb_status status =
            tb_keyframes_create(r == 0 ? NULL : keys, refusals[r].count, refusals[r].interpolation,
                                r == 1 ? NULL : &kf, &error);
        print_message("%-26s %s\n", refusals[r].name, error.message);
        assert_int_equal(status, refusals[r].status);
        assert_int_equal(error.status, refusals[r].status);
        assert_non_null(strstr(error.message, refusals[r].detail));
        if (r != 1) {
            assert_null(kf);
        }
        assert_memory_equal(keys, copy, sizeof keys);
    }
}

/* The rows spoil nothing else: the same keys without the change are accepted. */
static void test_the_refusal_rows_start_from_good_keys(void **state)
{
    (void)state;
    tb_body_key keys[4];
    spoil(keys, -1);
    tb_keyframes_destroy(make(keys, 4, TB_INTERPOLATION_CUBIC));
    tb_keyframes_destroy(make(keys, 4, TB_INTERPOLATION_LINEAR));
}

/* Sampling with no curve, no output or a NaN time: -1 and the output untouched. */
static void test_a_bad_sample_call_fails_and_writes_nothing(void **state)
{
    (void)state;
    tb_body_key key = tb_body_key_default();
    tb_keyframes *kf = make(&key, 1, TB_INTERPOLATION_LINEAR);
    tb_body_motion_sample s, before;
    memset(&s, 0x5a, sizeof s);
    before = s;
    assert_int_equal(tb_keyframes_sample(0.0, NULL, &s), -1);
    assert_int_equal(tb_keyframes_sample(NAN, kf, &s), -1);
    assert_int_equal(tb_keyframes_sample_left(NAN, kf, &s), -1);
    assert_int_equal(tb_keyframes_sample(0.0, kf, NULL), -1);
    assert_memory_equal(&s, &before, sizeof s);
    tb_keyframes_destroy(kf);
}

/* Names: parsed ignoring case, unknown ones refused with the list. */
static void test_interpolation_names_parse_back(void **state)
{
    (void)state;
    for (int m = 0; m < TB_INTERPOLATION_COUNT; ++m) {
        tb_interpolation parsed = (tb_interpolation)99;
        assert_int_equal(
            tb_interpolation_parse(tb_interpolation_name((tb_interpolation)m), &parsed, NULL),
            TB_STATUS_OK);
        assert_int_equal(parsed, m);
    }
    tb_interpolation parsed = TB_INTERPOLATION_STEP;
    assert_int_equal(tb_interpolation_parse("CUBIC", &parsed, NULL), TB_STATUS_OK);
    assert_int_equal(parsed, TB_INTERPOLATION_CUBIC);
    tb_error error;
    assert_int_equal(tb_interpolation_parse("spline", &parsed, &error), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "\"spline\"; interpolations: linear, cubic, step"));
    assert_int_equal(parsed, TB_INTERPOLATION_CUBIC);
    assert_int_equal(tb_interpolation_parse(NULL, &parsed, NULL), TB_STATUS_NULL_POINTER);
    assert_null(tb_interpolation_name((tb_interpolation)3));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_curve_passes_through_its_keys),
        cmocka_unit_test(test_a_given_velocity_is_the_curve_velocity),
        cmocka_unit_test(test_velocities_are_the_derivatives_of_the_pose),
        cmocka_unit_test(test_linear_moves_at_constant_velocity_between_keys),
        cmocka_unit_test(test_a_constant_rate_turn_is_reproduced_exactly),
        cmocka_unit_test(test_the_orientation_stays_a_unit_quaternion),
        cmocka_unit_test(test_cubic_is_c1_at_keys_and_linear_is_not),
        cmocka_unit_test(test_the_pose_holds_before_and_after_the_keys),
        cmocka_unit_test(test_step_holds_the_last_key),
        cmocka_unit_test(test_catmull_rom_tangents_follow_uniform_motion),
        cmocka_unit_test(test_one_key_holds_and_times_are_the_keys),
        cmocka_unit_test(test_bad_keys_are_refused_by_name),
        cmocka_unit_test(test_the_refusal_rows_start_from_good_keys),
        cmocka_unit_test(test_a_bad_sample_call_fails_and_writes_nothing),
        cmocka_unit_test(test_interpolation_names_parse_back),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
