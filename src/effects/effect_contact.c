/* Contact between bodies: at every point of every touching pair's manifold, the shared
 * compliant normal law (contact/contact_law.h) for the pair's effective mass along the normal
 * at that point, and regularised kinetic Coulomb friction in the tangent plane. Loads on the
 * two bodies are equal and opposite at the same world point, so they conserve linear and
 * angular momentum. The pairs come from the broad and narrow phase hook
 * (contact/contact_pairs.h), made when the effect is added. */
#include "scene/scene_internal.h"

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

#define TB__PAIR_COOKIE 0x7a1c
/* Touching pairs handled per batch of the hook (on the stack). */
#define TB__PAIR_BATCH 16
/* The regularised friction's slip speed (m/s): below it friction fades linearly to zero. */
#define TB__PAIR_SLIP_SPEED 0.01
/* The largest decay rate (1/s) friction may have: the slip speed of a point is raised so that
 * mu N w / v_eps stays below it, as the ground caps its bristles' rate (RK4 at 240 steps per
 * second: h * 400 = 1.7 < 2.785). */
#define TB__PAIR_FRICTION_MAX_RATE 400.0

/* One body at a contact point: its motion, its lever arm to the point and the point's velocity. */
typedef struct pair_end {
    const tb__body *body;
    tb__motion motion;
    double arm[3], velocity[3];
} pair_end;

/* n . ((I^-1 (r x n)) x r) = (r x n) . I^-1 (r x n): the inverse inertia the normal meets at arm
 * r, with I^-1 = R diag(inv_moments) R^T. */
static double rotational_inverse_mass(const pair_end *end, const double n[3])
{
    double rn[3], body_rn[3];
    tb__v3_cross(rn, end->arm, n);
    tb__q_rotate_inverse(body_rn, end->motion.q, rn);
    const double *inverse = end->body->inv_moments;
    return inverse[0] * body_rn[0] * body_rn[0] + inverse[1] * body_rn[1] * body_rn[1] +
           inverse[2] * body_rn[2] * body_rn[2];
}

static void end_at(pair_end *end, const double point[3])
{
    const double *x = end->motion.x;
    tb__v3_set(end->arm, point[0] - x[0], point[1] - x[1], point[2] - x[2]);
    tb__point_velocity(&end->motion, end->arm, end->velocity);
}

/* The friction force on b per unit normal force, against the tangential velocity of b
 * relative to a, v_t: -mu_k v_t / sqrt(|v_t|^2 + v_eps^2), with v_eps raised so that the
 * pair's friction decays no faster than TB__PAIR_FRICTION_MAX_RATE. */
static void friction(const tb__pair_params *pair, const double v_t[3], double pair_normal_force,
                     double w_tangent, double out[3])
{
    const double mu = pair->kinetic_friction;
    const double eps =
        fmax(TB__PAIR_SLIP_SPEED, mu * pair_normal_force * w_tangent / TB__PAIR_FRICTION_MAX_RATE);
    const double scale = -mu / sqrt(tb__v3_dot(v_t, v_t) + eps * eps);
    tb__v3_set(out, scale * v_t[0], scale * v_t[1], scale * v_t[2]);
}

/* The loads of one manifold point, shared among count points: on b at the point, -that on a. */
static void contact_point(const tb__pair_params *pair, pair_end *a, pair_end *b, const double n[3],
                          const tb__contact_point *p, int count, double *dydt, size_t ia, size_t ib)
{
    end_at(a, p->position);
    end_at(b, p->position);
    const double inverse_mass = a->body->inv_mass + b->body->inv_mass +
                                rotational_inverse_mass(a, n) + rotational_inverse_mass(b, n);
    const double relative[3] = {a->velocity[0] - b->velocity[0], a->velocity[1] - b->velocity[1],
                                a->velocity[2] - b->velocity[2]};
    const double closing = tb__v3_dot(relative, n); /* > 0: a moves into b, the depth grows */
    const double N = tb__contact_normal_force(1.0 / inverse_mass, pair->omega, pair->damping_ratio,
                                              p->depth, closing);
    if (!(N > 0.0)) {
        return;
    }
    double f[3] = {n[0], n[1], n[2]};
    if (pair->kinetic_friction > 0.0) {
        double v_t[3] = {-relative[0], -relative[1], -relative[2]}; /* b relative to a */
        tb__v3_axpy(v_t, closing, n);
        const double w_tangent =
            tb__inverse_mass_at(a->body, a->arm) + tb__inverse_mass_at(b->body, b->arm);
        double t[3];
        friction(pair, v_t, N, w_tangent, t);
        tb__v3_axpy(f, 1.0, t);
    }
    const double share = N / count;
    tb__v3_set(f, share * f[0], share * f[1], share * f[2]);
    tb__add_load(dydt, ib, b->arm, f);
    tb__v3_set(f, -f[0], -f[1], -f[2]);
    tb__add_load(dydt, ia, a->arm, f);
}

static void apply_pair(const tb__pair_params *pair, const tb_scene *scene, const double *y,
                       const tb__pair_contact *c, double *dydt)
{
    pair_end a = {.body = &scene->bodies[c->body_a]}, b = {.body = &scene->bodies[c->body_b]};
    tb__body_motion(a.body, y + TB_STATE_SIZE * c->body_a, &a.motion);
    tb__body_motion(b.body, y + TB_STATE_SIZE * c->body_b, &b.motion);
    const tb__contact_manifold *m = &c->manifold;
    for (int k = 0; k < m->count; ++k) {
        contact_point(pair, &a, &b, m->normal, &m->points[k], m->count, dydt, c->body_a, c->body_b);
    }
}

static int apply_contact(const tb__effect *effect, const tb_scene *scene, double t, const double *y,
                         double *dydt)
{
    (void)t;
    const tb__pair_params *pair = &effect->params.pair;
    tb__pair_contact batch[TB__PAIR_BATCH];
    tb__contact_pairs_begin(pair->pairs, scene, y);
    size_t n;
    while ((n = tb__contact_pairs_next(pair->pairs, scene, y, batch, TB__PAIR_BATCH)) > 0) {
        for (size_t k = 0; k < n; ++k) {
            apply_pair(pair, scene, y, &batch[k], dydt);
        }
    }
    return 0;
}

/* The points of a pair touching at y with depth > 0. */
static int touching_points(const tb__contact_manifold *m)
{
    int count = 0;
    for (int k = 0; k < m->count; ++k) {
        count += m->points[k].depth > 0.0;
    }
    return count;
}

/* a^2, the factor by which the pairs touching at y ring faster than one contact. Each point j
 * (of c_j in its pair) is a spring k_j = m_eff,j omega^2 / c_j along its Jacobian row g_j, so
 * the modes' omega^2 are the eigenvalues of the Gram matrix sqrt(k_j k_l) g_j M^-1 g_l, whose
 * entries are at most omega^2 / sqrt(c_j c_l) (Cauchy-Schwarz) between points sharing a body.
 * Gershgorin on a row of pair p (bodies a, b): 1 + sum over the other pairs P at a or b of
 * sqrt(c_P / c_p). Computed with weight[i] = sum of sqrt(c_P) over the pairs at body i. */
static double ringing_factor(const tb__pair_params *pair, const tb_scene *scene, const double *y)
{
    double *weight = pair->pair_weight;
    memset(weight, 0, pair->weight_count * sizeof *weight);
    tb__pair_contact batch[TB__PAIR_BATCH];
    for (int pass = 0; pass < 2; ++pass) {
        double a2 = 1.0;
        size_t n;
        tb__contact_pairs_begin(pair->pairs, scene, y);
        while ((n = tb__contact_pairs_next(pair->pairs, scene, y, batch, TB__PAIR_BATCH)) > 0) {
            for (size_t k = 0; k < n; ++k) {
                const int c = touching_points(&batch[k].manifold);
                const double root = sqrt((double)c);
                const size_t ia = batch[k].body_a, ib = batch[k].body_b;
                if (c == 0) {
                    continue;
                }
                if (pass == 0) {
                    weight[ia] += root;
                    weight[ib] += root;
                } else {
                    a2 = fmax(a2, 1.0 + (weight[ia] + weight[ib] - 2.0 * root) / root);
                }
            }
        }
        if (pass == 1) {
            return a2;
        }
    }
    return 1.0;
}

/* The contact rings at omega a with damping ratio zeta a (its damping is 2 zeta / omega times
 * its stiffness); a = 1 when nothing touches at y, for the contacts a step may start. Friction
 * decays at most TB__PAIR_FRICTION_MAX_RATE per pair, a^2 times that where pairs share bodies. */
static void contact_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                         tb__effect_rate *out)
{
    const tb__pair_params *pair = &effect->params.pair;
    *out = (tb__effect_rate){0.0, TB_ALL_BODIES, 0.0, TB_ALL_BODIES};
    const double a2 = ringing_factor(pair, scene, y), a = sqrt(a2);
    const double zeta = pair->damping_ratio * a, omega = pair->omega * a;
    if (zeta > 1.0) {
        out->decay = omega * (zeta + sqrt(zeta * zeta - 1.0));
    } else {
        out->oscillation = omega;
    }
    if (pair->kinetic_friction > 0.0) {
        out->decay = fmax(out->decay, TB__PAIR_FRICTION_MAX_RATE * a2);
    }
}

static void release_contact(tb__effect *effect)
{
    tb__contact_pairs_destroy(effect->params.pair.pairs);
    free(effect->params.pair.pair_weight);
    effect->params.pair.pairs = NULL;
    effect->params.pair.pair_weight = NULL;
}

static const tb__effect_ops contact_ops = {
    .name = "contact",
    .apply = apply_contact,
    .couples_bodies = true,
    .conserves_momentum = true, /* equal and opposite loads at one world point */
    .rate = contact_rate,
    .release = release_contact,
};

tb_contact_def tb_contact_def_default(void)
{
    tb_contact_def def;
    memset(&def, 0, sizeof def);
    def.gravity = 9.81;
    def.penetration = 1e-3;
    def.restitution = 0.3;
    def.static_friction = 0.6;
    def.kinetic_friction = 0.5;
    def.internal_cookie = TB__PAIR_COOKIE;
    return def;
}

static tb_status validate_contact(tb_scene *scene, const tb_contact_def *def)
{
    if (def->internal_cookie != TB__PAIR_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_contact_def_default()");
    }
    char *detail = scene->detail;
    if (def->bodies != NULL && def->body_count < 2) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "body_count: contact needs at least 2 bodies, got %zu",
                              def->body_count);
    }
    tb_status status = tb__validate_positive(detail, def->gravity, "gravity");
    if (status == TB_STATUS_OK) {
        status = tb__validate_positive(detail, def->penetration, "penetration");
    }
    if (status == TB_STATUS_OK) {
        status = tb__validate_nonnegative(detail, def->kinetic_friction, "kinetic_friction");
    }
    if (status == TB_STATUS_OK && !(def->restitution >= 0.0 && def->restitution <= 1.0)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "restitution: must be in [0, 1], got %g", def->restitution);
    }
    if (status == TB_STATUS_OK &&
        !(isfinite(def->static_friction) && def->static_friction >= def->kinetic_friction)) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "static_friction: must be finite and >= kinetic_friction (%g), "
                                "got %g",
                                def->kinetic_friction, def->static_friction);
    }
    if (status == TB_STATUS_OK && !isfinite(sqrt(def->gravity / def->penetration))) {
        status = tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                "penetration: %g m with gravity %g m/s^2 makes the contact's "
                                "rate overflow",
                                def->penetration, def->gravity);
    }
    return status;
}

/* Makes the pairs hook and the guard's scratch for the def's bodies. */
static tb_status make_contact(tb_scene *scene, const tb_contact_def *def, tb__pair_params *pair)
{
    const size_t count = def->bodies != NULL ? def->body_count : scene->body_count;
    tb_status status =
        tb__contact_pairs_create(scene, def->bodies, count, 0.0, &pair->pairs, scene->detail);
    if (status != TB_STATUS_OK) {
        return status;
    }
    pair->weight_count = scene->body_count;
    pair->pair_weight = malloc((scene->body_count > 0 ? scene->body_count : 1) * sizeof(double));
    if (pair->pair_weight == NULL) {
        tb__contact_pairs_destroy(pair->pairs);
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "contact for %zu bodies",
                              scene->body_count);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_add_contact(tb_scene *scene, const tb_contact_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (def == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "def is NULL");
    }
    tb_status status = tb__scene_check_idle(scene, "adding an effect");
    if (status == TB_STATUS_OK) {
        status = validate_contact(scene, def);
    }
    tb__effect effect = {.ops = &contact_ops, .body = TB_ALL_BODIES};
    tb__pair_params *pair = &effect.params.pair;
    if (status == TB_STATUS_OK) {
        status = make_contact(scene, def, pair);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    pair->omega = sqrt(def->gravity / def->penetration);
    pair->damping_ratio = tb__contact_damping_ratio(def->restitution);
    pair->kinetic_friction = def->kinetic_friction;
    pair->static_friction = def->static_friction;
    status = tb__scene_push_effect(scene, &effect);
    if (status != TB_STATUS_OK) {
        release_contact(&effect);
        return status;
    }
    return TB_STATUS_OK;
}
