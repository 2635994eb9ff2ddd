/* The contact effect's set-up checks: one pair in two contact effects, and pairs that start
 * deep inside each other. Both run outside the derivative. */
#include "effects/effect_contact_check.h"

#include "contact/collision_shape.h"
#include "contact/contact_pairs.h"
#include "contact/narrow_phase.h"
#include "core/detail.h"
#include "effects/contact_events.h"

#include "math/tb_math.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Pairs handled per batch of the start check (a stack buffer). */
#define START_BATCH 16

/* The first two of bodies[0 .. count) marked in `in` (first, second), false when fewer. */
static bool two_marked(const unsigned char *in, const size_t *bodies, size_t count, size_t *first,
                       size_t *second)
{
    int found = 0;
    for (size_t k = 0; k < count && found < 2; ++k) {
        if (in[bodies[k]]) {
            *(found++ == 0 ? first : second) = bodies[k];
        }
    }
    return found == 2;
}

/* A list with no pair that can touch: one body, or bodies none of which moves (a pair of static
 * and keyframed bodies is never tested). The scene file's loader took both, and the effect pushed
 * nothing, with no word. */
static tb_status check_movers(tb_scene *scene, const size_t *bodies, size_t count)
{
    size_t dynamic = 0;
    for (size_t k = 0; k < count; ++k) {
        dynamic += scene->slots[bodies[k]] != TB_NO_SLOT;
    }
    if (count < 2) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "bodies: only %zu listed: a contact pushes pairs of bodies, and one "
                              "body makes none",
                              count);
    }
    if (dynamic == 0) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "bodies: none of the %zu listed is dynamic: pairs of static and "
                              "keyframed bodies are never tested, so the effect would push nothing",
                              count);
    }
    return TB_STATUS_OK;
}

tb_status tb__contact_check_friction_rate(tb_scene *scene, double static_friction, double gravity,
                                          double presliding)
{
    const double s0 = static_friction / presliding; /* 1/m */
    if (!isfinite(s0) || !isfinite(gravity * s0) || !isfinite(s0 / gravity)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "presliding: %g m makes the friction spring's stiffness "
                              "static_friction / presliding (%g 1/m) or its rate under gravity "
                              "%g m/s^2 overflow",
                              presliding, s0, gravity);
    }
    const double rate = sqrt(gravity * s0), most = TB__CONTACT_RATE_MAX * TB__CONTACT_RATE_MAX;
    if (rate <= TB__CONTACT_RATE_MAX) {
        return TB_STATUS_OK;
    }
    if (fabs(log(static_friction / 0.6)) > fabs(log(presliding / 5e-7))) { /* the defaults */
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "static_friction: %g with presliding %g m and gravity %g m/s^2 "
                              "makes the friction spring's rate sqrt(gravity static_friction / "
                              "presliding) %g rad/s, above %g (the contact's bound): "
                              "static_friction must be in [kinetic_friction, %.3g] there",
                              static_friction, presliding, gravity, rate, TB__CONTACT_RATE_MAX,
                              most * presliding / gravity);
    }
    return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                          "presliding: %g m with static_friction %g and gravity %g m/s^2 makes "
                          "the friction spring's rate sqrt(gravity static_friction / presliding) "
                          "%g rad/s, above %g (the contact's bound): presliding must be at least "
                          "%.3g m there",
                          presliding, static_friction, gravity, rate, TB__CONTACT_RATE_MAX,
                          gravity * static_friction / most);
}

tb_status tb__contact_check_friction_points(tb_scene *scene, size_t friction_points,
                                            const size_t *bodies, size_t count)
{
    /* each piece of one body meets each piece of another through a manifold of its own: the
     * piece pairs are ((sum p)^2 - sum p^2) / 2, in doubles (no count wraps) */
    double pieces = 0.0, squares = 0.0;
    for (size_t k = 0; k < count; ++k) {
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, bodies[k]);
        const size_t p = shape != NULL ? tb__collision_shape_piece_count(shape) : 1;
        pieces += (double)p;
        squares += (double)p * (double)p;
    }
    const double n = count > 0 ? (double)count : 1.0, pairs = 0.5 * (pieces * pieces - squares);
    const double most = fmax(2.0 * TB__MANIFOLD_POINTS * pairs, 6.0 * n);
    if ((double)friction_points <= most) {
        return TB_STATUS_OK;
    }
    return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                          "friction_points: %zu slots for %zu bodies (%.0f pairs of their "
                          "pieces) is more than they can ever use: must be in [1, %.0f] (%d "
                          "touching points per pair of pieces, each with a slot relaxing beside "
                          "it, or 6 per body), or 0 for 6 per body",
                          friction_points, count, pairs, most, TB__MANIFOLD_POINTS);
}

tb_status tb__contact_check_shapes(tb_scene *scene, const size_t *bodies, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        const size_t id = bodies[k];
        if (tb__scene_body_collision_shape(scene, id) == NULL) {
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                  "bodies[%zu]: body %zu (\"%s\") has no collision shape "
                                  "(tb_scene_set_body_shape): it could touch nothing",
                                  k, id, scene->names[id]);
        }
    }
    return check_movers(scene, bodies, count);
}

/* How far body id's shape reaches from its centre of mass, m, by its bounds in the shape frame
 * (a corner of the box around it: at most sqrt(3) times the true reach). */
static double shape_reach(const tb_scene *scene, size_t id, const tb__collision_shape *shape)
{
    static const double identity[TB__POSE_SIZE] = {0, 0, 0, 1, 0, 0, 0};
    const double *center = scene->mass_props[id].center;
    double low[3], high[3], corner[3];
    tb__collision_shape_bounds(shape, identity, low, high);
    for (int k = 0; k < 3; ++k) {
        corner[k] = fmax(fabs(low[k] - center[k]), fabs(high[k] - center[k]));
    }
    return tb__v3_norm(corner);
}

tb_status tb__contact_check_shape_size(tb_scene *scene, size_t id, double penetration,
                                       size_t effect_index, const char *effect_kind)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    if (shape == NULL || tb__body_fixed(scene, id)) {
        return TB_STATUS_OK; /* a body that cannot move sinks into nothing */
    }
    const double reach = shape_reach(scene, id, shape);
    const double rounding = reach * DBL_EPSILON;
    if (!(rounding <= penetration)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "body %zu (\"%s\"): its shape reaches %.3g m from its centre of "
                              "mass, where a point's depth is known to %.3g m only, more than the "
                              "penetration %.3g m of effect %zu (%s): its contact force would be "
                              "rounding noise larger than its weight; give it a smaller shape or "
                              "the effect a larger penetration",
                              id, scene->names[id], reach, rounding, penetration, effect_index,
                              effect_kind);
    }
    const double arm[3] = {reach, 0.0, 0.0};
    const tb__body *body = tb__body_constants(scene, id);
    if (!isfinite(body->mass * tb__inverse_mass_at(body, arm))) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "body %zu (\"%s\"): its shape reaches %.3g m from its centre of "
                              "mass, so far for its moments of inertia that the contact rate of "
                              "effect %zu (%s) overflows",
                              id, scene->names[id], reach, effect_index, effect_kind);
    }
    return TB_STATUS_OK;
}

tb_status tb__contact_check_shape_sizes(tb_scene *scene, const size_t *bodies, size_t count,
                                        double penetration)
{
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = tb__contact_check_shape_size(scene, bodies[k], penetration, scene->effect_count,
                                              "a contact");
    }
    return status;
}

tb_status tb__contact_check_shape(const tb__effect *effect, tb_scene *scene, size_t id)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const size_t index = (size_t)(effect - scene->effects);
    for (size_t k = 0; k < contact->body_count; ++k) {
        if (contact->bodies[k] != id) {
            continue;
        }
        if (tb__scene_body_collision_shape(scene, id) != NULL) { /* seen at the next derivative */
            const double penetration = contact->gravity / (contact->omega * contact->omega);
            return tb__contact_check_shape_size(scene, id, penetration, index, "a contact");
        }
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "id: body %zu (\"%s\") is bodies[%zu] of effect %zu (a "
                              "contact): without a shape it would silently touch nothing "
                              "(a listed body keeps a shape; set another instead)",
                              id, scene->names[id], k, index);
    }
    return TB_STATUS_OK;
}

tb_status tb__contact_check_shared_pairs(tb_scene *scene, const tb__effect_ops *ops,
                                         const size_t *bodies, size_t count)
{
    unsigned char *in = NULL;
    for (size_t e = 0; e < scene->effect_count; ++e) {
        const tb__effect *other = &scene->effects[e];
        if (other->ops != ops) {
            continue;
        }
        if (in == NULL && (in = calloc(scene->body_count > 0 ? scene->body_count : 1, 1)) == NULL) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "contact pair check");
        }
        const tb__contact_params *contact = tb__contact_of(other);
        for (size_t k = 0; k < contact->body_count; ++k) {
            in[contact->bodies[k]] = 1;
        }
        size_t a = 0, b = 0;
        const bool shared = two_marked(in, bodies, count, &a, &b);
        for (size_t k = 0; k < contact->body_count; ++k) {
            in[contact->bodies[k]] = 0;
        }
        if (shared) {
            free(in);
            return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                                  "bodies: %zu (\"%s\") and %zu (\"%s\") are both in effect %zu "
                                  "(a contact) already: a pair in two contact effects is pushed "
                                  "by both (twice the stiffness, neither's restitution); give "
                                  "each pair to one contact effect",
                                  a, scene->names[a], b, scene->names[b], e);
        }
    }
    free(in);
    return TB_STATUS_OK;
}

/* The depth (m) at which pair's contact carries the heavier body's weight: its points together
 * push with M_min omega^2 depth (effect_contact.c). */
static double weight_depth(const tb__contact_params *contact, const tb__body *a, const tb__body *b)
{
    /* a body that cannot move carries the other's weight: the depth of that weight alone */
    const double light = fmin(a->mass, b->mass), heavier = fmax(a->mass, b->mass);
    const double heavy = isinf(heavier) ? light : heavier;
    return contact->gravity / (contact->omega * contact->omega) * (heavy / light);
}

static tb_status check_pair(const tb__contact_params *contact, const tb_scene *scene,
                            const tb__pair_contact *pair, char *detail)
{
    double depth = -INFINITY;
    for (int j = 0; j < pair->manifold.count; ++j) {
        depth = fmax(depth, pair->manifold.points[j].depth);
    }
    const tb__body *a = tb__body_constants(scene, pair->body_a);
    const tb__body *b = tb__body_constants(scene, pair->body_b);
    const double weights = TB__CONTACT_START_DEPTH_WEIGHTS * weight_depth(contact, a, b);
    /* and never past the middle of the thinner body, where its normal turns: the weight's depth
     * grows with the pair's mass ratio (the stiffness is the lighter's), so a 1 g marble let a
     * start 8 m deep in a 1 t crate pass, and was thrown out at 345 m/s */
    const double half = fmin(tb__contact_half_thickness(scene, pair->body_a),
                             tb__contact_half_thickness(scene, pair->body_b));
    const double limit = fmin(weights, half);
    if (!(depth > limit)) {
        return TB_STATUS_OK;
    }
    /* one point between free bodies rings at omega sqrt(M_min / m_reduced): the speed its
     * spring gives them back, released from that depth */
    const double light = fmin(a->mass, b->mass);
    const double reduced = tb__reduced_mass(a->mass, b->mass);
    const double speed = depth * contact->omega * sqrt(light / reduced);
    char why[96];
    if (weights <= half) {
        snprintf(why, sizeof why, "%g times the depth that carries the heavier's weight",
                 TB__CONTACT_START_DEPTH_WEIGHTS);
    } else {
        snprintf(why, sizeof why, "half the thinner body's thickness");
    }
    return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                          "bodies %zu (\"%s\") and %zu (\"%s\") start %.3g m inside each other, "
                          "deeper than %.3g m (%s): the contact would part them at about %.3g "
                          "m/s; start them apart",
                          pair->body_a, scene->names[pair->body_a], pair->body_b,
                          scene->names[pair->body_b], depth, limit, why, speed);
}

tb_status tb__contact_check_start(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  char *detail)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    tb__pair_contact batch[START_BATCH];
    tb__contact_pairs_begin(contact->pairs, scene, scene->time, y);
    size_t count;
    while ((count = tb__contact_pairs_next(contact->pairs, scene, y, batch, START_BATCH)) > 0) {
        for (size_t k = 0; k < count; ++k) {
            const tb_status status = check_pair(contact, scene, &batch[k], detail);
            if (status != TB_STATUS_OK) {
                return status;
            }
        }
    }
    return TB_STATUS_OK;
}
