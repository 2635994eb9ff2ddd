/* The rigid-body derivative and the quaternion-renormalisation hook: the hot loop. */
#include "scene/scene_internal.h"

#include "math/tb_math.h"
#include "scene/run_watch.h"
#include "scene/scene_jacobian.h"
#include "scene/sleep_frozen.h"

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

/* dx = P/M and dq = 1/2 (0, omega) (x) q for `count` slots, with dP and dL zeroed for the
 * effects to add into; y and dydt point at the first slot's state, bodies at its data. With
 * motions (by id, the slots' ids in ids) each body's tb__body_motion too, from the same omega
 * and v. */
static void kinematics(const tb__body *bodies, const double *y, double *dydt, size_t count,
                       tb__motion *motions, const size_t *ids)
{
    for (size_t i = 0; i < count; ++i) {
        const double *s = y + TB_STATE_SIZE * i;
        double *d = dydt + TB_STATE_SIZE * i;
        const tb__body *body = &bodies[i];
        /* dq uses q itself, for which 1/2 (0, omega) (x) q is tangent to the sphere
         * |q| = const. */
        tb__motion own;
        tb__motion *motion = motions != NULL ? &motions[ids[i]] : &own;
        double *omega = motion->omega;
        angular_velocity(body, s, omega);
        const double *qr = s + TB_STATE_Q;
        for (int k = 0; k < 3; ++k) {
            d[TB_STATE_X + k] = s[TB_STATE_P + k] * body->inv_mass;
        }
        if (motions != NULL) {
            tb__v3_copy(motion->x, s + TB_STATE_X);
            tb__unit_quaternion(s, 0, motion->q);
            tb__v3_copy(motion->v, d + TB_STATE_X);
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
        if (effects[order[middle]].slot < first) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    *begin = low;
    while (low < last && effects[order[low]].slot - first < count) {
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

/* The last stage: the constraint forces that keep the joints' rows, from the accelerations the
 * applied loads left in dydt (src/constraints/, through its row). */
static int constraint_forces(const tb_scene *scene, double t, const double *y, double *dydt)
{
    return scene->constraint_ops == NULL
               ? 0
               : scene->constraint_ops->apply(scene->constraints, scene, t, y, dydt);
}

/* kinematics() of the awake slots, run by run, and of the asleep bodies that are not frozen
 * at y (sleep_frozen.h) or whose frozen motion scene->motions no longer holds; a frozen body's
 * dydt is left for tb__scene_sleep_zero (zeroed first where the joints read the loads in it). */
static void kinematics_awake(const tb_scene *scene, const double *y, double *dydt)
{
    tb__sleep *sleep = scene->sleep;
    for (size_t r = 0; r < sleep->run_count; ++r) {
        const size_t first = sleep->runs[2 * r], count = sleep->runs[2 * r + 1] - first;
        kinematics(scene->bodies + first, y + TB_STATE_SIZE * first, dydt + TB_STATE_SIZE * first,
                   count, scene->motions, scene->slot_ids + first);
    }
    for (size_t k = 0; k < sleep->asleep_count; ++k) {
        const size_t s = sleep->asleep_slots[k], id = scene->slot_ids[s];
        const bool frozen = tb__body_frozen(scene, y, id);
        if (!frozen || !sleep->motion_kept[id]) {
            kinematics(scene->bodies + s, y + TB_STATE_SIZE * s, dydt + TB_STATE_SIZE * s, 1,
                       scene->motions, scene->slot_ids + s);
            sleep->motion_kept[id] = frozen;
        } else if (scene->constraint_ops != NULL) {
            memset(dydt + TB_STATE_SIZE * s, 0, TB_STATE_SIZE * sizeof(double));
        }
    }
}

/* The first stage: every body's motion (dynamic bodies' from y, into dydt's x and q rows too;
 * the others' from their kinds at t) for the loads to read. */
static int motions(const tb_scene *scene, double t, const double *y, double *dydt)
{
    const size_t n = scene->slot_count;
    const tb__sleep *sleep = scene->sleep;
    if (sleep != NULL && sleep->asleep_count > 0 && sleep->capacity == scene->body_count) {
        kinematics_awake(scene, y, dydt);
    } else {
        kinematics(scene->bodies, y, dydt, n, scene->motions, scene->slot_ids);
        if (sleep != NULL && sleep->asleep_count > 0) { /* bodies added: the kept motions went */
            memset(sleep->motion_kept, 0, sleep->capacity);
        }
    }
    int rc = 0;
    for (size_t k = 0; k < scene->body_count - n && rc == 0; ++k) { /* the bodies with no state */
        const size_t id = scene->fixed_ids[k];
        rc = tb__body_motion_at(scene, t, y, id, &scene->motions[id]) != 0 ? -1 : 0;
    }
    return rc;
}

int tb__scene_motions(const tb_scene *scene, double t, const double *y, double *scratch)
{
    return motions(scene, t, y, scratch);
}

int tb_scene_derivative(double t, const double *y, double *dydt, void *ctx)
{
    const tb_scene *scene = ctx;
    if (scene == NULL || y == NULL || dydt == NULL) {
        return -1;
    }
    tb__run_watch *watch = scene->watch;
    if (watch != NULL && --watch->countdown == 0) {
        watch->countdown = TB__RUN_WATCH_EVERY;
        if (watch->fn(t, watch->ctx) != 0) {
            return TB__RUN_WATCH_STOPPED;
        }
    }
    const size_t n = scene->slot_count;
    int rc = motions(scene, t, y, dydt);
    rc = rc != 0 ? rc : apply_per_body_effects(scene, t, y, dydt, 0, n);
    /* then the coupled effects, last in effect_order */
    const size_t first_coupled = scene->effect_count - scene->coupled_effect_count;
    for (size_t k = first_coupled; k < scene->effect_count && rc == 0; ++k) {
        const tb__effect *effect = &scene->effects[scene->effect_order[k]];
        rc = effect->ops->apply(effect, scene, t, y, dydt);
    }
    rc = rc != 0 ? rc : constraint_forces(scene, t, y, dydt);
    tb__scene_sleep_zero(scene, dydt);
    return rc;
}

/* An effect ark-imex takes explicitly: one with no mode of its own (no rate: constant loads, and
 * user callbacks, which cannot state one) that makes nothing touch and owns no states. The rest
 * (contact, ground, springs, drag), the kinematic rows and the joints' forces are the implicit
 * part: f_I = f - f_E costs a whole derivative whatever the split, so whatever has a mode that
 * may be stiff goes where its stiffness costs no stability. */
static bool explicit_effect(const tb__effect_ops *ops)
{
    return ops->rate == NULL && ops->stepping == NULL && !ops->owns_states && !ops->couples_bodies;
}

int tb__scene_explicit_part(double t, const double *y, double *dydt, void *ctx)
{
    const tb_scene *scene = ctx;
    if (scene == NULL || y == NULL || dydt == NULL) {
        return -1;
    }
    const size_t n = scene->slot_count;
    int rc = motions(scene, t, y, dydt);
    for (size_t i = 0; i < n; ++i) { /* kinematic rows: implicit */
        for (int k = 0; k < TB_STATE_P; ++k) {
            dydt[TB_STATE_SIZE * i + k] = 0.0;
        }
    }
    for (size_t k = TB_STATE_SIZE * n; k < TB_STATE_SIZE * n + scene->extra_count; ++k) {
        dydt[k] = 0.0; /* effects' own states: implicit */
    }
    for (size_t k = 0; k < scene->effect_count && rc == 0; ++k) {
        const tb__effect *effect = &scene->effects[scene->effect_order[k]];
        if (explicit_effect(effect->ops)) {
            rc = effect->ops->apply_bodies != NULL
                     ? effect->ops->apply_bodies(effect, scene, t, y, dydt, 0, n)
                     : effect->ops->apply(effect, scene, t, y, dydt);
        }
    }
    tb__scene_sleep_zero(scene, dydt);
    return rc;
}

bool tb__scene_rows_by_quotients(const tb_scene *scene, const tb__effect_ops *ops)
{
    /* The analytic rows hold a point and its normal fixed on the bodies. Between two bodies
     * that misses the normal's turn and the points' carry, and it cost: BDF took 50 times the
     * CPU on two boxes sliding on a box (test_run_again's short span: 10.9 s against 0.22), and
     * rosenbrock, whose stability rests on its matrix, threw a standing column of ten boxes
     * apart at 1/240 s (446 m/s within 0.05 s). So pairs of bodies take quotients, and under
     * rosenbrock every load row does (its steps those it took before the analytic rows, to the
     * bit); the ground's rows stay analytic for BDF and ark-imex. */
    return !ops->constant_loads && (ops->jacobian == NULL || ops->couples_bodies ||
                                    scene->guard_method == TB_METHOD_ROSENBROCK);
}

bool tb__scene_has_quotient_part(const tb_scene *scene)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        if (tb__scene_rows_by_quotients(scene, scene->effects[k].ops)) {
            return true;
        }
    }
    return false;
}

int tb__scene_quotient_part(double t, const double *y, double *dydt, void *ctx)
{
    const tb_scene *scene = ctx;
    const size_t n = scene->slot_count;
    int rc = motions(scene, t, y, dydt);
    for (size_t k = TB_STATE_SIZE * n; k < TB_STATE_SIZE * n + scene->extra_count; ++k) {
        dydt[k] = 0.0; /* effects' own states: analytic, or written below by their effect */
    }
    for (size_t k = 0; k < scene->effect_count && rc == 0; ++k) {
        const tb__effect *effect = &scene->effects[scene->effect_order[k]];
        if (tb__scene_rows_by_quotients(scene, effect->ops)) {
            rc = effect->ops->apply_bodies != NULL
                     ? effect->ops->apply_bodies(effect, scene, t, y, dydt, 0, n)
                     : effect->ops->apply(effect, scene, t, y, dydt);
        }
    }
    tb__scene_sleep_zero(scene, dydt);
    return rc;
}

bool tb__scene_separable(const tb_scene *scene)
{
    /* bodies without a state need the whole post-step hook, which keeps the scene's time */
    return scene->coupled_effect_count == 0 && scene->extra_count == 0 &&
           scene->slot_count == scene->body_count && scene->constraint_ops == NULL;
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
    kinematics(scene->bodies + first, y, dydt, count, NULL, NULL);
    return apply_per_body_effects(scene, t, y, dydt, first, count);
}

void tb__body_motion(const tb__body *body, const double *s, tb__motion *out)
{
    tb__v3_copy(out->x, s + TB_STATE_X);
    tb__unit_quaternion(s, 0, out->q);
    angular_velocity(body, s, out->omega);
    const double *P = s + TB_STATE_P;
    tb__v3_set(out->v, P[0] * body->inv_mass, P[1] * body->inv_mass, P[2] * body->inv_mass);
}

/* arm x u in the principal frame, where I^-1 is diagonal. */
static void principal_lever(const tb__motion *motion, const double arm[3], const double u[3],
                            double out[3])
{
    double lever[3];
    tb__v3_cross(lever, arm, u);
    tb__q_rotate_inverse(out, motion->q, lever);
}

static double inverse_inertia_product(const tb__body *body, const double a[3], const double b[3])
{
    const double *inverse = body->inv_moments;
    return inverse[0] * a[0] * b[0] + inverse[1] * a[1] * b[1] + inverse[2] * a[2] * b[2];
}

double tb__inverse_mass_along(const tb__body *body, const tb__motion *motion, const double arm[3],
                              const double u[3])
{
    double lever[3];
    principal_lever(motion, arm, u, lever);
    return body->inv_mass + inverse_inertia_product(body, lever, lever);
}

void tb__tangent_basis(const double n[3], double t1[3], double t2[3])
{
    const double axis[3] = {fabs(n[0]) < 0.9 ? 1.0 : 0.0, fabs(n[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    tb__v3_cross(t1, n, axis);
    const double length = tb__v3_norm(t1);
    tb__v3_set(t1, t1[0] / length, t1[1] / length, t1[2] / length);
    tb__v3_cross(t2, n, t1);
}

double tb__inverse_mass_across_basis(const tb__body *body, const tb__motion *motion,
                                     const double arm[3], const double t1[3], const double t2[3])
{
    /* the 2 x 2 form T_ab = (arm x t_a) . I^-1 (arm x t_b) has the largest eigenvalue
     * (T11 + T22) / 2 + sqrt(((T11 - T22) / 2)^2 + T12^2) */
    double a[3], b[3];
    principal_lever(motion, arm, t1, a);
    principal_lever(motion, arm, t2, b);
    const double T11 = inverse_inertia_product(body, a, a),
                 T22 = inverse_inertia_product(body, b, b);
    const double T12 = inverse_inertia_product(body, a, b), half = 0.5 * (T11 - T22);
    return body->inv_mass + 0.5 * (T11 + T22) + sqrt(half * half + T12 * T12);
}

double tb__inverse_mass_across(const tb__body *body, const tb__motion *motion, const double arm[3],
                               const double n[3])
{
    double t1[3], t2[3];
    tb__tangent_basis(n, t1, t2);
    return tb__inverse_mass_across_basis(body, motion, arm, t1, t2);
}

double tb__lightness_at(const tb__body *body, const double r[3])
{
    /* M (1/M + max over unit n of (r x n) . I^-1 (r x n)): the largest eigenvalue of
     * P = [r x]^T I^-1 [r x], closed form for a symmetric 3 x 3 (trigonometric) */
    const double *i = body->inv_moments;
    const double P00 = i[1] * r[2] * r[2] + i[2] * r[1] * r[1];
    const double P11 = i[0] * r[2] * r[2] + i[2] * r[0] * r[0];
    const double P22 = i[0] * r[1] * r[1] + i[1] * r[0] * r[0];
    const double P01 = -i[2] * r[0] * r[1], P02 = -i[1] * r[0] * r[2], P12 = -i[0] * r[1] * r[2];
    const double q = (P00 + P11 + P22) / 3.0, off = P01 * P01 + P02 * P02 + P12 * P12;
    const double d0 = P00 - q, d1 = P11 - q, d2 = P22 - q;
    const double p = sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0);
    if (!(p > 0.0)) {
        return 1.0 + body->mass * q;
    }
    const double det =
        d0 * (d1 * d2 - P12 * P12) - P01 * (P01 * d2 - P12 * P02) + P02 * (P01 * P12 - d1 * P02);
    const double half = fmax(-1.0, fmin(1.0, det / (2.0 * p * p * p)));
    return 1.0 + body->mass * (q + 2.0 * p * cos(acos(half) / 3.0));
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
        if (tb__body_asleep(scene, scene->slot_ids[first + i])) {
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
    return scene == NULL || y == NULL ? -1 : normalize(scene, y, 0, scene->slot_count);
}

int tb__scene_block_normalize(double t, double *y, size_t first, size_t count, void *ctx)
{
    (void)t;
    tb_scene *scene = ctx;
    return scene == NULL ? -1 : normalize(scene, y, first, count);
}
