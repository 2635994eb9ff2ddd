/* Events and step limits of contact, so that no integrator steps a body through another.
 *
 * Adaptive methods: each body's gap (the smallest distance to what it can touch, negative in
 * contact, capped at TB__EVENT_LOOKAHEAD) is one of the scene's root functions, so CVODE ends a
 * step on every contact onset and separation and reports its time; and before every step the
 * step is limited so that no pair apart at its start can close its gap within it, unless the
 * step is at most half the shortest push (then the push holds a step's end, where CVODE's error
 * test sees the force). A body moves at most s h + a h^2 / 2 in a step h, with s = |v| +
 * |omega| R and a = |dP/dt| / M + (|dL/dt| / I_min + |omega|^2) R at the step's start (R the
 * reach of its shape from its centre of mass); a step covers at most half a gap at that bound.
 * Pairs farther apart than the look-ahead are bounded by the fastest body alone.
 *
 * Fixed-step methods: no pair may close by more than the thinner body's half-thickness in one
 * step (the pair's speeds as above), so the contact is seen before one body's centre is past
 * the other's middle, where the normal would turn and push it out of the far side. */
#include "effects/contact_events.h"

#include "contact/contact_pairs.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>

/* A step covers at most this fraction of a gap at the bodies' bounds. */
#define TB__GAP_SAFETY 0.5
/* Pairs handled per batch of a pass (a stack buffer). */
#define TB__EVENT_BATCH 16

tb_status tb__contact_events_create(tb_scene *scene, tb__contact_params *contact)
{
    return tb__contact_pairs_create(scene, contact->bodies, contact->body_count,
                                    TB__EVENT_LOOKAHEAD, &contact->lookahead, scene->detail);
}

void tb__contact_events_release(tb__contact_params *contact)
{
    tb__contact_pairs_destroy(contact->lookahead);
    contact->lookahead = NULL;
}

/* Minus the deepest point's depth: the pair's gap, m. */
static double pair_gap(const tb__pair_contact *pair)
{
    double deepest = -INFINITY;
    for (int j = 0; j < pair->manifold.count; ++j) {
        deepest = fmax(deepest, pair->manifold.points[j].depth);
    }
    return -deepest;
}

void tb__contact_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                            double *gap)
{
    tb__contact_pairs *pairs = effect->params.contact.lookahead;
    tb__pair_contact batch[TB__EVENT_BATCH];
    tb__contact_pairs_begin(pairs, scene, y);
    size_t count;
    while ((count = tb__contact_pairs_next(pairs, scene, y, batch, TB__EVENT_BATCH)) > 0) {
        for (size_t k = 0; k < count; ++k) {
            const double g = pair_gap(&batch[k]);
            gap[batch[k].body_a] = fmin(gap[batch[k].body_a], g);
            gap[batch[k].body_b] = fmin(gap[batch[k].body_b], g);
        }
    }
}

/* How far body id's shape reaches from its centre of mass at y (m). */
static double reach(const tb_scene *scene, const double *y, size_t id)
{
    double low[3], high[3];
    if (tb_scene_body_shape_bounds(scene, y, id, low, high) != TB_STATUS_OK) {
        return 0.0;
    }
    const double *x = y + TB_STATE_SIZE * id;
    double r[3];
    for (int k = 0; k < 3; ++k) {
        r[k] = fmax(fabs(low[k] - x[k]), fabs(high[k] - x[k]));
    }
    return tb__v3_norm(r);
}

/* Bounds on the speed and acceleration of every point of body id's shape at y (dydt NULL:
 * speed only). */
typedef struct bound {
    double speed, acceleration;
} bound;

static bound motion_bound(const tb_scene *scene, const double *y, const double *dydt, size_t id)
{
    const tb__body *body = &scene->bodies[id];
    tb__motion motion;
    tb__body_motion(body, y + TB_STATE_SIZE * id, &motion);
    const double r = reach(scene, y, id), spin = tb__v3_norm(motion.omega);
    bound out = {tb__v3_norm(motion.v) + spin * r, 0.0};
    if (dydt != NULL) {
        const double *d = dydt + TB_STATE_SIZE * id;
        const double *inverse = body->inv_moments;
        const double softest = fmax(inverse[0], fmax(inverse[1], inverse[2]));
        out.acceleration = tb__v3_norm(d + TB_STATE_P) * body->inv_mass +
                           (tb__v3_norm(d + TB_STATE_L) * softest + spin * spin) * r;
    }
    return out;
}

/* The longest time in which bodies closing at speed s with acceleration a (bounds) cover
 * distance d: the positive root of s h + a h^2 / 2 = d, INFINITY when nothing moves. */
static double travel_time(double s, double a, double d)
{
    const double denominator = s + sqrt(s * s + 2.0 * a * d);
    return denominator > 0.0 ? 2.0 * d / denominator : INFINITY;
}

/* The fastest body's bounds among the effect's bodies with shapes. */
static bound fastest(const tb__contact_params *contact, const tb_scene *scene, const double *y,
                     const double *dydt)
{
    bound worst = {0.0, 0.0};
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        if (id < scene->body_count && tb__scene_body_collision_shape(scene, id) != NULL) {
            const bound b = motion_bound(scene, y, dydt, id);
            worst.speed = fmax(worst.speed, b.speed);
            worst.acceleration = fmax(worst.acceleration, b.acceleration);
        }
    }
    return worst;
}

/* A pair's limit: the time to close half its gap, or (in contact) to move by half the law's
 * static sinking, gravity / omega^2; never below the floor. */
static double pair_limit(const tb__contact_params *contact, const tb_scene *scene, const double *y,
                         const double *dydt, const tb__pair_contact *pair, double floor)
{
    const bound a = motion_bound(scene, y, dydt, pair->body_a);
    const bound b = motion_bound(scene, y, dydt, pair->body_b);
    const double gap = pair_gap(pair);
    const double distance = gap > 0.0 ? gap : contact->gravity / (contact->omega * contact->omega);
    return fmax(floor, travel_time(a.speed + b.speed, a.acceleration + b.acceleration,
                                   TB__GAP_SAFETY * distance));
}

double tb__contact_step_limit(const tb__effect *effect, const tb_scene *scene, const double *y,
                              const double *dydt)
{
    const tb__contact_params *contact = &effect->params.contact;
    const double floor = 0.5 * contact->push_duration;
    if (dydt == NULL) {
        return floor; /* before the first step: CVODE's own first step is shorter anyway */
    }
    /* pairs not found are at least the look-ahead apart, closing at most twice the fastest */
    const bound worst = fastest(contact, scene, y, dydt);
    double limit = travel_time(2.0 * worst.speed, 2.0 * worst.acceleration,
                               TB__GAP_SAFETY * TB__EVENT_LOOKAHEAD);
    tb__pair_contact batch[TB__EVENT_BATCH];
    tb__contact_pairs_begin(contact->lookahead, scene, y);
    size_t count;
    while ((count = tb__contact_pairs_next(contact->lookahead, scene, y, batch, TB__EVENT_BATCH)) >
           0) {
        for (size_t k = 0; k < count; ++k) {
            limit = fmin(limit, pair_limit(contact, scene, y, dydt, &batch[k], floor));
        }
    }
    return fmax(limit, floor);
}

/* Half the thickness of body id's shape across its thinnest direction (m): what a body must
 * not pass in one step. Convex and points shapes: their shape-frame bounds'. */
static double half_thickness(const tb__collision_shape *shape)
{
    switch (shape->type) {
    case TB_SHAPE_SPHERE:
    case TB_SHAPE_CAPSULE:
        return shape->radius;
    case TB_SHAPE_CYLINDER:
        return fmin(shape->radius, shape->half_length);
    case TB_SHAPE_BOX:
    case TB_SHAPE_ELLIPSOID:
        return fmin(shape->half[0], fmin(shape->half[1], shape->half[2]));
    default: {
        double thinnest = INFINITY;
        for (int k = 0; k < 3; ++k) {
            thinnest = fmin(thinnest, 0.5 * (shape->local_max[k] - shape->local_min[k]));
        }
        return thinnest;
    }
    }
}

double tb__contact_tunnel_step(const tb__effect *effect, const tb_scene *scene, const double *y,
                               char *which, size_t size)
{
    const tb__contact_params *contact = &effect->params.contact;
    double speed[2] = {-1.0, -1.0},
           thinnest = INFINITY; /* below any speed: a body at rest counts */
    size_t fast[2] = {TB_ALL_BODIES, TB_ALL_BODIES}, thin = TB_ALL_BODIES;
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        const tb__collision_shape *shape =
            id < scene->body_count ? tb__scene_body_collision_shape(scene, id) : NULL;
        if (shape == NULL) {
            continue;
        }
        const double s = motion_bound(scene, y, NULL, id).speed, t = half_thickness(shape);
        const int slot = s > speed[0] ? 0 : s > speed[1] ? 1 : 2;
        if (slot == 0) {
            speed[1] = speed[0], fast[1] = fast[0];
        }
        if (slot < 2) {
            speed[slot] = s, fast[slot] = id;
        }
        if (t > 0.0 && t < thinnest) { /* points of radius 0 are passed by any step: no bound */
            thinnest = t, thin = id;
        }
    }
    /* the two fastest close at most at the sum of their speeds; every other pair slower */
    if (fast[1] == TB_ALL_BODIES || thin == TB_ALL_BODIES || !(speed[0] + speed[1] > 0.0)) {
        return INFINITY;
    }
    const int mover = thin != fast[0] ? 0 : 1;
    snprintf(which, size,
             "body %zu (\"%s\", %.3g m/s) could pass through body %zu (\"%s\", %.3g m thick) in "
             "one step",
             fast[mover], scene->names[fast[mover]], speed[mover], thin, scene->names[thin],
             2.0 * thinnest);
    return thinnest / (speed[0] + speed[1]);
}

void tb__ground_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                           double *gap)
{
    const tb__ground_params *ground = &effect->params.ground;
    tb__motion motion;
    size_t current = TB_ALL_BODIES;
    for (size_t j = 0; j < scene->contact_count; ++j) {
        const tb__contact *c = &scene->contacts[j];
        if (c->body != current) {
            current = c->body;
            tb__body_motion(&scene->bodies[current], y + TB_STATE_SIZE * current, &motion);
        }
        double arm[3];
        tb__point_arm(&motion, c->r, arm);
        const double height = tb__v3_dot(ground->normal, motion.x) +
                              tb__v3_dot(ground->normal, arm) - ground->offset - c->radius;
        gap[current] = fmin(gap[current], height);
    }
}
