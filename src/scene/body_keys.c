/* Keyframes: the object a keyframed body's motion comes from. Creation checks and copies the
 * keys, aligns the quaternions' signs, fills the tangents a cubic curve needs (given or
 * Catmull-Rom) and each segment's rotation; sampling finds the segment and holds the pose
 * outside the keys. The curves themselves are in body_keys_curves.c. */
#include "scene/body_keys_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *const interpolation_names[TB_INTERPOLATION_COUNT] = {
    [TB_INTERPOLATION_LINEAR] = "linear",
    [TB_INTERPOLATION_CUBIC] = "cubic",
    [TB_INTERPOLATION_STEP] = "step",
};

static bool is_interpolation(tb_interpolation interpolation)
{
    return (int)interpolation >= 0 && (int)interpolation < TB_INTERPOLATION_COUNT;
}

const char *tb_interpolation_name(tb_interpolation interpolation)
{
    return is_interpolation(interpolation) ? interpolation_names[interpolation] : NULL;
}

tb_status tb_interpolation_parse(const char *name, tb_interpolation *out_interpolation,
                                 tb_error *out_error)
{
    tb__clear_error(out_error);
    if (name == NULL || out_interpolation == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             name == NULL ? "name" : "out_interpolation");
    }
    for (int k = 0; k < TB_INTERPOLATION_COUNT; ++k) {
        if (tb__same_name(name, interpolation_names[k])) {
            *out_interpolation = (tb_interpolation)k;
            return TB_STATUS_OK;
        }
    }
    return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT,
                         "unknown interpolation \"%.64s\"; interpolations: linear, cubic, step",
                         name);
}

tb_body_key tb_body_key_default(void)
{
    tb_body_key key;
    memset(&key, 0, sizeof key);
    key.orientation[0] = 1.0;
    return key;
}

/* --- checks ------------------------------------------------------------------------------ */

/* q / |q| for a finite nonzero q, scaled by its largest component first so that |q|^2
 * neither underflows nor overflows; false for a zero q. */
static bool unit_quaternion(const double q[4], double out[4])
{
    double scale = 0.0;
    for (int i = 0; i < 4; ++i) {
        scale = fmax(scale, fabs(q[i]));
    }
    if (!(scale > 0.0)) {
        return false;
    }
    double s[4];
    for (int i = 0; i < 4; ++i) {
        s[i] = q[i] / scale;
    }
    const double norm = tb__q_norm(s);
    for (int i = 0; i < 4; ++i) {
        out[i] = s[i] / norm;
    }
    return true;
}

static tb_status check_time(const tb_body_key *keys, size_t k, tb_error *error)
{
    if (!isfinite(keys[k].t)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "keys[%zu].t: must be finite, got %g", k,
                             keys[k].t);
    }
    if (k > 0 && !(keys[k].t > keys[k - 1].t)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "keys[%zu].t: must be > keys[%zu].t = %.17g, got %.17g", k, k - 1,
                             keys[k - 1].t, keys[k].t);
    }
    if (k > 0 && !isfinite(keys[k].t - keys[k - 1].t)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "keys[%zu].t: the interval from keys[%zu].t (%g to %g) overflows", k,
                             k - 1, keys[k - 1].t, keys[k].t);
    }
    return TB_STATUS_OK;
}

static tb_status check_vector(const double *v, int n, size_t k, const char *field, tb_error *error)
{
    if (!tb__all_finite(v, n)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE,
                             "keys[%zu].%s: must be finite, got (%g, %g, %g%s)", k, field, v[0],
                             v[1], v[2], n == 4 ? ", ..." : "");
    }
    return TB_STATUS_OK;
}

/* A velocity only a cubic curve reads, given to another. */
static tb_status check_given(bool given, size_t k, const char *field, tb_interpolation how,
                             tb_error *error)
{
    if (given && how != TB_INTERPOLATION_CUBIC) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "keys[%zu].%s: only cubic interpolation reads it (this curve is %s)",
                             k, field, interpolation_names[how]);
    }
    return TB_STATUS_OK;
}

/* Key k into node k (orientation normalised, its sign aligned with node k - 1). */
static tb_status take_key(const tb_body_key *keys, size_t k, tb_keyframes *kf, tb_error *error)
{
    const tb_body_key *key = &keys[k];
    tb__key_node *node = &kf->nodes[k];
    tb_status status = check_time(keys, k, error);
    if (status == TB_STATUS_OK) {
        status = check_vector(key->position, 3, k, "position", error);
    }
    if (status == TB_STATUS_OK) {
        status = check_vector(key->orientation, 4, k, "orientation", error);
    }
    if (status == TB_STATUS_OK && key->has_velocity) {
        status = check_vector(key->velocity, 3, k, "velocity", error);
    }
    if (status == TB_STATUS_OK && key->has_angular_velocity) {
        status = check_vector(key->angular_velocity, 3, k, "angular_velocity", error);
    }
    if (status == TB_STATUS_OK) {
        status = check_given(key->has_velocity, k, "velocity", kf->interpolation, error);
    }
    if (status == TB_STATUS_OK) {
        status =
            check_given(key->has_angular_velocity, k, "angular_velocity", kf->interpolation, error);
    }
    if (status == TB_STATUS_OK && !unit_quaternion(key->orientation, node->orientation)) {
        status = tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                               "keys[%zu].orientation: must be a nonzero quaternion, got (0, 0, "
                               "0, 0)",
                               k);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double *previous = k > 0 ? kf->nodes[k - 1].orientation : NULL;
    const double dot = previous ? previous[0] * node->orientation[0] +
                                      tb__v3_dot(previous + 1, node->orientation + 1)
                                : 1.0;
    const double sign = dot < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        node->orientation[i] *= sign;
    }
    kf->times[k] = key->t;
    tb__v3_copy(node->position, key->position);
    tb__v3_copy(node->velocity, key->has_velocity ? key->velocity : (const double[3]){0, 0, 0});
    tb__v3_copy(node->angular_velocity,
                key->has_angular_velocity ? key->angular_velocity : (const double[3]){0, 0, 0});
    return TB_STATUS_OK;
}

/* --- tangents and segments --------------------------------------------------------------- */

/* The derivative at t_k of the parabola through the values at t_(k-1), t_k, t_(k+1): the
 * chords' slopes d0 = before / h0 and d1 = after / h1 weighted by the far interval,
 * m = (h1 d0 + h0 d1) / (h0 + h1). With even spacing it is Catmull-Rom's (x_(k+1) - x_(k-1)) /
 * 2h; with uneven spacing it stays exact for quadratics (a straight line at constant speed
 * included), where the plain chord (x_(k+1) - x_(k-1)) / (t_(k+1) - t_(k-1)) is not. */
static void catmull_rom(double out[3], const double before[3], const double after[3], double h0,
                        double h1)
{
    const double w0 = h1 / (h0 + h1), w1 = h0 / (h0 + h1);
    for (int i = 0; i < 3; ++i) {
        out[i] = w0 * (before[i] / h0) + w1 * (after[i] / h1);
    }
}

/* Each segment's rotation phi_1 = log(q_(k+1) (x) q_k*); the signs' alignment makes its w >= 0
 * (it is q_(k+1) . q_k), so |phi_1| <= pi, the shorter way. */
static void fill_rotations(tb_keyframes *kf)
{
    for (size_t k = 0; k + 1 < kf->count; ++k) {
        const double *q0 = kf->nodes[k].orientation;
        const double conjugate[4] = {q0[0], -q0[1], -q0[2], -q0[3]};
        double turn[4];
        tb__q_mul(turn, kf->nodes[k + 1].orientation, conjugate);
        tb__rotation_log(kf->segments[k].rotation, turn);
        tb__v3_set(kf->segments[k].end_rate, 0.0, 0.0, 0.0); /* cubic fills it */
    }
}

/* Cubic: the tangents not given, at the interior keys (the ends keep 0). For orientation the
 * chart is the rotation vector about q_k, where the rates are the angular velocity
 * (J_l(0) = I) and the neighbours sit at -phi_1 of segment k - 1 and phi_1 of segment k. */
static void fill_tangents(tb_keyframes *kf, const tb_body_key *keys)
{
    for (size_t k = 1; k + 1 < kf->count; ++k) {
        const double h0 = kf->times[k] - kf->times[k - 1], h1 = kf->times[k + 1] - kf->times[k];
        tb__key_node *node = &kf->nodes[k];
        if (!keys[k].has_velocity) {
            double before[3], after[3];
            for (int i = 0; i < 3; ++i) {
                before[i] = node->position[i] - kf->nodes[k - 1].position[i];
                after[i] = kf->nodes[k + 1].position[i] - node->position[i];
            }
            catmull_rom(node->velocity, before, after, h0, h1);
        }
        if (!keys[k].has_angular_velocity) {
            catmull_rom(node->angular_velocity, kf->segments[k - 1].rotation,
                        kf->segments[k].rotation, h0, h1);
        }
    }
    for (size_t k = 0; k + 1 < kf->count; ++k) {
        tb__rotation_rate_of(kf->segments[k].end_rate, kf->segments[k].rotation,
                             kf->nodes[k + 1].angular_velocity);
    }
}

static bool sample_finite(const tb_body_motion_sample *s)
{
    return tb__all_finite(s->position, 3) && tb__all_finite(s->orientation, 4) &&
           tb__all_finite(s->velocity, 3) && tb__all_finite(s->angular_velocity, 3) &&
           tb__all_finite(s->acceleration, 3) && tb__all_finite(s->angular_acceleration, 3);
}

/* Keys far apart for the time between them (or tangents that large) make a curve that
 * overflows: refused, naming the key. Each segment's ends are checked; the acceleration is
 * linear in t on a segment, so its largest magnitudes are there. */
static tb_status check_segments(const tb_keyframes *kf, tb_error *error)
{
    for (size_t k = 0; k + 1 < kf->count; ++k) {
        tb_body_motion_sample start, end;
        tb__keys_segment_sample(kf, k, kf->times[k], &start);
        tb__keys_segment_sample(kf, k, kf->times[k + 1], &end);
        const bool start_ok = sample_finite(&start);
        if (!start_ok || !sample_finite(&end)) {
            return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                 "keys[%zu]: the curve overflows there (keys too far apart for "
                                 "the time between them)",
                                 start_ok ? k + 1 : k);
        }
    }
    return TB_STATUS_OK;
}

/* --- the object -------------------------------------------------------------------------- */

void tb_keyframes_destroy(tb_keyframes *keyframes)
{
    if (keyframes == NULL) {
        return;
    }
    free(keyframes->times);
    free(keyframes->nodes);
    free(keyframes->segments);
    free(keyframes);
}

/* Room for count keys, every size checked (no key is read yet). */
static tb_status allocate(size_t count, tb_interpolation interpolation, tb_keyframes **out,
                          tb_error *error)
{
    const size_t per_key = sizeof(double) + sizeof(tb__key_node) + sizeof(tb__key_segment);
    size_t bytes = 0;
    if (!tb__size_product(count, per_key, &bytes) || bytes > PTRDIFF_MAX) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY,
                             "count: %zu keys of %zu bytes each are more than the address space",
                             count, per_key);
    }
    tb_keyframes *kf = calloc(1, sizeof *kf);
    if (kf != NULL) {
        kf->interpolation = interpolation;
        kf->count = count;
        kf->times = tb__malloc_array(count, sizeof *kf->times);
        kf->nodes = tb__malloc_array(count, sizeof *kf->nodes);
        kf->segments = tb__malloc_array(count > 1 ? count - 1 : 1, sizeof *kf->segments);
    }
    if (kf == NULL || kf->times == NULL || kf->nodes == NULL || kf->segments == NULL) {
        tb_keyframes_destroy(kf);
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY,
                             "count: no memory for %zu keys (%zu bytes each)", count, per_key);
    }
    *out = kf;
    return TB_STATUS_OK;
}

static tb_status check_arguments(const tb_body_key *keys, size_t count,
                                 tb_interpolation interpolation, tb_keyframes **out_keyframes,
                                 tb_error *error)
{
    if (out_keyframes == NULL || keys == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             keys == NULL ? "keys" : "out_keyframes");
    }
    if (count == 0) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "count: must be >= 1 (a curve needs a key), got 0");
    }
    if (!is_interpolation(interpolation)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "interpolation: unknown value %d; interpolations: linear, cubic, step",
                             (int)interpolation);
    }
    return TB_STATUS_OK;
}

tb_status tb_keyframes_create(const tb_body_key *keys, size_t count, tb_interpolation interpolation,
                              tb_keyframes **out_keyframes, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (out_keyframes != NULL) {
        *out_keyframes = NULL;
    }
    tb_keyframes *kf = NULL;
    tb_status status = check_arguments(keys, count, interpolation, out_keyframes, out_error);
    if (status == TB_STATUS_OK) {
        status = allocate(count, interpolation, &kf, out_error);
    }
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = take_key(keys, k, kf, out_error);
    }
    if (status == TB_STATUS_OK) {
        fill_rotations(kf);
        if (interpolation == TB_INTERPOLATION_CUBIC) {
            fill_tangents(kf, keys);
        }
        status = check_segments(kf, out_error);
    }
    if (status != TB_STATUS_OK) {
        tb_keyframes_destroy(kf);
        return status;
    }
    *out_keyframes = kf;
    return TB_STATUS_OK;
}

const double *tb_keyframes_times(const tb_keyframes *keyframes, size_t *out_count)
{
    if (out_count != NULL) {
        *out_count = keyframes != NULL ? keyframes->count : 0;
    }
    return keyframes != NULL ? keyframes->times : NULL;
}

/* --- sampling ---------------------------------------------------------------------------- */

/* Key k's pose, at rest. */
static void hold(const tb_keyframes *kf, size_t k, tb_body_motion_sample *out)
{
    memset(out, 0, sizeof *out);
    tb__v3_copy(out->position, kf->nodes[k].position);
    memcpy(out->orientation, kf->nodes[k].orientation, sizeof out->orientation);
}

/* The segment k with times[k] <= t < times[k + 1] (from the left: times[k] < t <=
 * times[k + 1]), for t inside the keys' span, by bisection. */
static size_t segment_at(const double *times, size_t count, double t, bool left)
{
    size_t low = 0, high = count - 1;
    while (high - low > 1) {
        const size_t middle = low + (high - low) / 2;
        if (left ? times[middle] < t : times[middle] <= t) {
            low = middle;
        } else {
            high = middle;
        }
    }
    return low;
}

static int sample(double t, const tb_keyframes *kf, bool left, tb_body_motion_sample *out)
{
    if (kf == NULL || out == NULL || isnan(t)) {
        return -1;
    }
    const size_t last = kf->count - 1;
    const bool before = left ? t <= kf->times[0] : t < kf->times[0];
    const bool after = left ? t > kf->times[last] : t >= kf->times[last];
    tb_body_motion_sample s;
    if (before || after) {
        hold(kf, before ? 0 : last, &s);
    } else {
        const size_t k = segment_at(kf->times, kf->count, t, left);
        if (kf->interpolation == TB_INTERPOLATION_STEP) {
            hold(kf, k, &s);
        } else {
            tb__keys_segment_sample(kf, k, t, &s);
        }
        if (kf->interpolation != TB_INTERPOLATION_STEP && t == kf->times[k + 1]) {
            /* the left end of a segment is its next key's pose, to the bit */
            tb__v3_copy(s.position, kf->nodes[k + 1].position);
            memcpy(s.orientation, kf->nodes[k + 1].orientation, sizeof s.orientation);
        }
    }
    if (!sample_finite(&s)) {
        return -1;
    }
    *out = s;
    return 0;
}

int tb_keyframes_sample(double t, void *ctx, tb_body_motion_sample *out)
{
    return sample(t, ctx, false, out);
}

int tb_keyframes_sample_left(double t, void *ctx, tb_body_motion_sample *out)
{
    return sample(t, ctx, true, out);
}
