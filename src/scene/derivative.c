/* The rigid-body derivative and the quaternion-renormalisation hook: the hot loop. */
#include "scene/scene_internal.h"

#include "math/tb_math.h"

void tb__unit_quaternion(const double *y, size_t i, double q[4])
{
    const double *raw = y + TB_STATE_SIZE * i + TB_STATE_Q;
    const double inv_norm = 1.0 / tb__q_norm(raw);
    for (int k = 0; k < 4; ++k) {
        q[k] = raw[k] * inv_norm;
    }
}

/* omega = R I_body^-1 R^T L for the body whose state starts at s, with R the rotation of q/|q|
 * built without a square root, so a quaternion that drifted off the unit sphere still means a
 * rotation. */
static inline void angular_velocity(const tb__body *body, const double *s, double omega[3])
{
    double R[9], w_body[3];
    tb__q_to_matrix_any(R, s + TB_STATE_Q);
    const double *L = s + TB_STATE_L;
    for (int k = 0; k < 3; ++k) {
        w_body[k] = (R[k] * L[0] + R[3 + k] * L[1] + R[6 + k] * L[2]) * body->inv_moments[k];
    }
    for (int k = 0; k < 3; ++k) {
        omega[k] = R[3 * k] * w_body[0] + R[3 * k + 1] * w_body[1] + R[3 * k + 2] * w_body[2];
    }
}

void tb__angular_velocity(const tb__body *body, const double *s, double omega[3])
{
    angular_velocity(body, s, omega);
}

/* dx = P/M and dq = 1/2 (0, omega) (x) q for `count` bodies, with dP and dL zeroed for the
 * effects to add into; y and dydt point at the first body's state, bodies at its data. */
static void kinematics(const tb__body *bodies, const double *y, double *dydt, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        const double *s = y + TB_STATE_SIZE * i;
        double *d = dydt + TB_STATE_SIZE * i;
        const tb__body *body = &bodies[i];
        /* dq uses q itself, for which 1/2 (0, omega) (x) q is tangent to the sphere
         * |q| = const. */
        double omega[3];
        angular_velocity(body, s, omega);
        const double *qr = s + TB_STATE_Q;
        for (int k = 0; k < 3; ++k) {
            d[TB_STATE_X + k] = s[TB_STATE_P + k] * body->inv_mass;
        }
        d[3] = 0.5 * (-omega[0] * qr[1] - omega[1] * qr[2] - omega[2] * qr[3]);
        d[4] = 0.5 * (omega[0] * qr[0] + omega[1] * qr[3] - omega[2] * qr[2]);
        d[5] = 0.5 * (-omega[0] * qr[3] + omega[1] * qr[0] + omega[2] * qr[1]);
        d[6] = 0.5 * (omega[0] * qr[2] - omega[1] * qr[1] + omega[2] * qr[0]);
        for (int k = TB_STATE_P; k < TB_STATE_SIZE; ++k) { /* P and L */
            d[k] = 0.0;
        }
    }
}

void tb__scene_single_body_effects(const tb_scene *scene, size_t first, size_t count, size_t *begin,
                                   size_t *end)
{
    const tb__effect *effects = scene->effects;
    const size_t *order = scene->effect_order;
    const size_t all = scene->all_body_effect_count;
    const size_t last = all + scene->single_body_effect_count;
    size_t low = all, high = last;
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        if (effects[order[middle]].body < first) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    *begin = low;
    while (low < last && effects[order[low]].body - first < count) {
        ++low;
    }
    *end = low;
}

/* The per-body effects on the bodies [first, first + count), y and dydt pointing at body
 * first: those on every body, then those on one body of the range, found by bisection. */
static int apply_per_body_effects(const tb_scene *scene, double t, const double *y, double *dydt,
                                  size_t first, size_t count)
{
    const tb__effect *effects = scene->effects;
    const size_t *order = scene->effect_order;
    for (size_t k = 0; k < scene->all_body_effect_count; ++k) {
        const tb__effect *effect = &effects[order[k]];
        const int rc = effect->ops->apply_bodies(effect, scene, t, y, dydt, first, count);
        if (rc != 0) {
            return rc;
        }
    }
    size_t begin, end;
    tb__scene_single_body_effects(scene, first, count, &begin, &end);
    for (size_t k = begin; k < end; ++k) {
        const tb__effect *effect = &effects[order[k]];
        const int rc = effect->ops->apply_bodies(effect, scene, t, y, dydt, first, count);
        if (rc != 0) {
            return rc;
        }
    }
    return 0;
}

int tb_scene_derivative(double t, const double *y, double *dydt, void *ctx)
{
    const tb_scene *scene = ctx;
    if (scene == NULL || y == NULL || dydt == NULL) {
        return -1;
    }
    const size_t n = scene->body_count;
    kinematics(scene->bodies, y, dydt, n);
    int rc = apply_per_body_effects(scene, t, y, dydt, 0, n);
    /* then the coupled effects, last in effect_order */
    const size_t first_coupled = scene->effect_count - scene->coupled_effect_count;
    for (size_t k = first_coupled; k < scene->effect_count && rc == 0; ++k) {
        const tb__effect *effect = &scene->effects[scene->effect_order[k]];
        rc = effect->ops->apply(effect, scene, t, y, dydt);
    }
    tb__scene_sleep_zero(scene, dydt);
    return rc;
}

bool tb__scene_separable(const tb_scene *scene)
{
    return scene->coupled_effect_count == 0 && scene->extra_count == 0;
}

int tb__scene_block_derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                               void *ctx)
{
    const tb_scene *scene = ctx;
    /* an effect coupling bodies added after the system was made: the blocks are no longer
     * independent */
    if (scene == NULL || !tb__scene_separable(scene)) {
        return -1;
    }
    kinematics(scene->bodies + first, y, dydt, count);
    return apply_per_body_effects(scene, t, y, dydt, first, count);
}

void tb__body_motion(const tb__body *body, const double *s, tb__motion *out)
{
    out->x = s;
    tb__unit_quaternion(s, 0, out->q);
    angular_velocity(body, s, out->omega);
    const double *P = s + TB_STATE_P;
    tb__v3_set(out->v, P[0] * body->inv_mass, P[1] * body->inv_mass, P[2] * body->inv_mass);
}

void tb__point_arm(const tb__motion *motion, const double r[3], double arm[3])
{
    tb__q_rotate(arm, motion->q, r);
}

void tb__point_velocity(const tb__motion *motion, const double arm[3], double velocity[3])
{
    tb__v3_cross(velocity, motion->omega, arm);
    tb__v3_axpy(velocity, 1.0, motion->v);
}

void tb__add_load(double *dydt, size_t i, const double arm[3], const double f[3])
{
    double torque[3];
    tb__v3_cross(torque, arm, f);
    tb__v3_axpy(dydt + TB_STATE_SIZE * i + TB_STATE_P, 1.0, f);
    tb__v3_axpy(dydt + TB_STATE_SIZE * i + TB_STATE_L, 1.0, torque);
}

void tb__scene_note_drift(tb_scene *scene, double drift)
{
#if defined(__GNUC__) || defined(__clang__)
    /* a chunk's hook may run on any thread (fixed-step threads) */
    double seen;
    __atomic_load(&scene->quaternion_drift, &seen, __ATOMIC_RELAXED);
    while (drift > seen && !__atomic_compare_exchange(&scene->quaternion_drift, &seen, &drift,
                                                      false, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
    }
#else
    scene->quaternion_drift = fmax(scene->quaternion_drift, drift);
#endif
}

/* q <- q / |q| for the bodies [first, first + count), y at body first, asleep ones left as
 * they are (their state stays the one they fell asleep with, bit for bit); the largest
 * | |q| - 1 | found (up to a failure) goes into the scene's drift. */
static int normalize(tb_scene *scene, double *y, size_t first, size_t count)
{
    double drift = 0.0;
    int rc = 0;
    for (size_t i = 0; i < count && rc == 0; ++i) {
        if (tb__body_asleep(scene, first + i)) {
            continue;
        }
        double *q = y + TB_STATE_SIZE * i + TB_STATE_Q;
        const double norm = tb__q_norm(q);
        if (!(norm > 0) || !isfinite(norm)) {
            rc = 1;
            break;
        }
        drift = fmax(drift, fabs(norm - 1.0));
        const double inverse = 1.0 / norm;
        for (int k = 0; k < 4; ++k) {
            q[k] *= inverse;
        }
    }
    tb__scene_note_drift(scene, drift);
    return rc;
}

int tb_scene_normalize_quaternions(double t, double *y, void *ctx)
{
    (void)t;
    tb_scene *scene = ctx;
    return scene == NULL || y == NULL ? -1 : normalize(scene, y, 0, scene->body_count);
}

int tb__scene_block_normalize(double t, double *y, size_t first, size_t count, void *ctx)
{
    (void)t;
    tb_scene *scene = ctx;
    return scene == NULL ? -1 : normalize(scene, y, first, count);
}
