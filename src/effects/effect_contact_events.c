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
 * Pairs farther apart than the look-ahead are bounded by the fastest body alone. The floor of
 * half a push is itself capped where bodies are thin or fast: no step is longer than the time
 * in which the pair (or, for pairs not found, twice the fastest body) could cover the thinner
 * body's half-thickness, so that no step starts before a thin body and ends beyond it with no
 * sign change of the gap in between (a 10 g ball at 100 m/s stepped over a 1 mm plate).
 *
 * Fixed-step methods: no pair may close by more than the thinner body's half-thickness in one
 * step (the pair's speeds as above), so the contact is seen before one body's centre is past
 * the other's middle, where the normal would turn and push it out of the far side.
 *
 * Every method: the law sinks a pair closing at speed s by at most s / omega (the undamped
 * oscillator's amplitude at the stiffness M_min omega^2 and a mass of at most M_min; the dashpot
 * only shortens it), so where the two fastest bodies could sink into each other past where one's
 * tip reaches the other's middle (the normal turns there and pushes it out of the far side)
 * before the law stops them, that happens whatever the step: such a state is refused, naming
 * the bodies (tb__contact_check_impacts). */
#include "effects/contact_events.h"

#include "contact/contact_pairs.h"
#include "core/detail.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static double half_thickness(const tb__collision_shape *shape);

/* A step covers at most this fraction of a gap at the bodies' bounds. */
#define TB__GAP_SAFETY 0.5
/* Pairs handled per batch of a pass (a stack buffer). */
#define TB__EVENT_BATCH 16

tb_status tb__contact_events_create(tb_scene *scene, tb__contact_params *contact)
{
    size_t ids = 0; /* after the pair finder, which checked the ids */
    for (size_t k = 0; k < contact->body_count; ++k) {
        ids = contact->bodies[k] >= ids ? contact->bodies[k] + 1 : ids;
    }
    contact->speeds = malloc((ids > 0 ? ids : 1) * sizeof *contact->speeds);
    if (contact->speeds == NULL) {
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "contact speed bounds: %zu", ids);
    }
    return tb__contact_pairs_create(scene, contact->bodies, contact->body_count,
                                    TB__EVENT_LOOKAHEAD, &contact->lookahead, scene->detail);
}

void tb__contact_events_release(tb__contact_params *contact)
{
    tb__contact_pairs_destroy(contact->lookahead);
    contact->lookahead = NULL;
    free(contact->speeds);
    contact->speeds = NULL;
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

/* Whether one body of the pair is asleep and the other awake: the asleep one would meet the
 * other as a fixed body, so the pair must not touch before its island wakes. */
static bool mixed(const tb_scene *scene, size_t a, size_t b)
{
    /* a static body has no island to wake */
    return tb__body_asleep(scene, a) != tb__body_asleep(scene, b) && !tb__body_static(scene, a) &&
           !tb__body_static(scene, b);
}

static bool any_asleep(const tb_scene *scene)
{
    return scene->sleep != NULL && scene->sleep->asleep_count > 0;
}

/* One pass over the look-ahead's pairs at y: lowers gap (when not NULL) to each body's least
 * pair gap and wake (when not NULL) to each body's least mixed pair gap beyond
 * TB__WAKE_DISTANCE. fmin is exact, so either array gets the same bits whether or not the other
 * is filled in the same pass. */
typedef struct gaps_target {
    const tb_scene *scene;
    const double *gap, *wake;
    bool signs; /* only whether each gap is below zero need be exact */
} gaps_target;

/* tb__pair_level for gaps_pass in signs: a pair is needed only where it could take a body's gap
 * below zero (a pair gap below 0), or a mixed pair's wake gap (below TB__WAKE_DISTANCE: g - W
 * is below zero exactly where g < W), for a body whose gap is not yet below; a pair above the
 * level leaves every sign as it is, and at -infinity the pass passes over the pair whatever
 * its shapes (tb__contact_pairs_filter). */
static double signs_level(const gaps_target *t, size_t a, size_t b)
{
    const bool gap_open = t->gap != NULL && !(t->gap[a] < 0.0 && t->gap[b] < 0.0);
    const bool wake_open =
        t->wake != NULL && mixed(t->scene, a, b) && !(t->wake[a] < 0.0 && t->wake[b] < 0.0);
    return wake_open ? TB__WAKE_DISTANCE : gap_open ? 0.0 : -INFINITY;
}

/* tb__pair_level for gaps_pass: a pair whose gap is above both bodies' gaps leaves each fmin
 * below as it is (a NaN gap: every pair). A mixed pair's wake gaps are the gap less
 * TB__WAKE_DISTANCE, rounded: +infinity, every mixed pair, when there are wake gaps. */
static double gaps_level(void *ctx, size_t a, size_t b)
{
    const gaps_target *t = ctx;
    if (t->signs) {
        return signs_level(t, a, b);
    }
    if (t->wake != NULL && mixed(t->scene, a, b)) {
        return INFINITY;
    }
    if (t->gap == NULL) {
        return -INFINITY;
    }
    const double ga = t->gap[a], gb = t->gap[b];
    return isnan(ga) || isnan(gb) ? INFINITY : fmax(ga, gb);
}

static void gaps_pass(const tb__effect *effect, const tb_scene *scene, const double *y, double *gap,
                      double *wake, bool signs)
{
    tb__contact_pairs *pairs = tb__contact_of(effect)->lookahead;
    tb__pair_contact batch[TB__EVENT_BATCH];
    gaps_target target = {scene, gap, wake, signs};
    tb__contact_pairs_filter(pairs, gaps_level, &target);
    tb__contact_pairs_begin(pairs, scene, scene->time, y);
    size_t count;
    while ((count = tb__contact_pairs_next(pairs, scene, y, batch, TB__EVENT_BATCH)) > 0) {
        for (size_t k = 0; k < count; ++k) {
            const size_t a = batch[k].body_a, b = batch[k].body_b;
            const double g = pair_gap(&batch[k]);
            if (gap != NULL) {
                gap[a] = fmin(gap[a], g);
                gap[b] = fmin(gap[b], g);
            }
            if (wake != NULL && mixed(scene, a, b)) {
                wake[a] = fmin(wake[a], g - TB__WAKE_DISTANCE);
                wake[b] = fmin(wake[b], g - TB__WAKE_DISTANCE);
            }
        }
    }
    tb__contact_pairs_filter(pairs, NULL, NULL);
}

void tb__contact_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                            double *gap, bool signs)
{
    gaps_pass(effect, scene, y, gap, NULL, signs);
}

void tb__contact_wake_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                           double *gap, double *wake, bool signs)
{
    if (any_asleep(scene)) {
        gaps_pass(effect, scene, y, gap, wake, signs);
    } else if (gap != NULL) { /* no mixed pair: every wake gap stays */
        gaps_pass(effect, scene, y, gap, NULL, signs);
    }
}

static double motion_speed(const tb_scene *scene, const double *y, size_t id);

typedef struct links_target {
    const tb_scene *scene;
    const double *y;
    double dt;
    double *speeds; /* by body id, NaN: not yet worked out in this pass */
} links_target;

/* Body id's speed bound at y, worked out once per pass (a body is in several pairs). */
static double link_speed(const links_target *t, size_t id)
{
    if (isnan(t->speeds[id])) {
        t->speeds[id] = motion_speed(t->scene, t->y, id);
    }
    return t->speeds[id];
}

/* The gap below which bodies a and b are linked: a step's stages reach dt ahead; twice the
 * pair's speed bound leaves room for the speeds' change over the step (the margin for the
 * rest). */
static double link_gap(const links_target *t, size_t a, size_t b)
{
    const double closing = link_speed(t, a) + link_speed(t, b);
    return TB__CONTACT_MARGIN + 2.0 * closing * t->dt;
}

/* tb__pair_level for the wake links: a pair whose gap floor is above its link gap is not
 * linked (a NaN link gap: every pair); a pair already in one island (linked by the step's
 * post_step passes, touching) needs no link. */
static double links_level(void *ctx, size_t a, size_t b)
{
    const links_target *t = ctx;
    if (tb__scene_sleep_linked(t->scene, a, b)) {
        return -INFINITY;
    }
    const double g = link_gap(t, a, b);
    return isnan(g) ? INFINITY : g;
}

void tb__contact_wake_links(const tb__effect *effect, const tb_scene *scene, const double *y,
                            double dt)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    tb__contact_pairs *pairs = contact->lookahead;
    tb__pair_contact batch[TB__EVENT_BATCH];
    links_target target = {scene, y, dt, contact->speeds};
    for (size_t k = 0; k < contact->body_count; ++k) {
        contact->speeds[contact->bodies[k]] = NAN;
    }
    tb__contact_pairs_filter(pairs, links_level, &target);
    tb__contact_pairs_begin(pairs, scene, scene->time, y);
    size_t count;
    while ((count = tb__contact_pairs_next(pairs, scene, y, batch, TB__EVENT_BATCH)) > 0) {
        for (size_t k = 0; k < count; ++k) {
            const tb__pair_contact *pair = &batch[k];
            if (pair_gap(pair) < link_gap(&target, pair->body_a, pair->body_b)) {
                tb__scene_sleep_link(scene, pair->body_a, pair->body_b);
            }
        }
    }
    tb__contact_pairs_filter(pairs, NULL, NULL);
}

/* How far body id's shape reaches from its centre of mass at y (m). */
static double reach(const tb_scene *scene, const double *y, size_t id)
{
    double low[3], high[3];
    if (tb_scene_body_shape_bounds(scene, y, id, low, high) != TB_STATUS_OK) {
        return 0.0;
    }
    double x[3], q[4];
    tb__body_pose_at(scene, scene->time, y, id, x, q);
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
    const tb__body *body = tb__body_constants(scene, id);
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    const double r = reach(scene, y, id), spin = tb__v3_norm(motion.omega);
    bound out = {tb__v3_norm(motion.v) + spin * r, 0.0};
    const double *d = dydt != NULL ? tb__body_state(scene, dydt, id) : NULL;
    if (dydt != NULL && d == NULL) { /* a body without a state: its own acceleration */
        double a[3], alpha[3];
        tb__fixed_body_acceleration_at(scene, scene->time, id, a, alpha);
        out.acceleration = tb__v3_norm(a) + (tb__v3_norm(alpha) + spin * spin) * r;
    }
    if (d != NULL) {
        const double *inverse = body->inv_moments;
        const double softest = fmax(inverse[0], fmax(inverse[1], inverse[2]));
        out.acceleration = tb__v3_norm(d + TB_STATE_P) * body->inv_mass +
                           (tb__v3_norm(d + TB_STATE_L) * softest + spin * spin) * r;
    }
    return out;
}

static double motion_speed(const tb_scene *scene, const double *y, size_t id)
{
    return motion_bound(scene, y, NULL, id).speed;
}

/* The longest time in which bodies closing at speed s with acceleration a (bounds) cover
 * distance d: the positive root of s h + a h^2 / 2 = d, INFINITY when nothing moves. */
static double travel_time(double s, double a, double d)
{
    if (!(d < INFINITY)) {
        return INFINITY; /* no thickness to pass (inf / inf would be NaN) */
    }
    const double denominator = s + sqrt(s * s + 2.0 * a * d);
    return denominator > 0.0 ? 2.0 * d / denominator : INFINITY;
}

/* Half the thickness of body id's shape (m), INFINITY for a body of no thickness (points of
 * radius 0, which any step passes: no bound) or without a shape. */
double tb__contact_half_thickness(const tb_scene *scene, size_t id)
{
    const tb__collision_shape *shape =
        id < scene->body_count ? tb__scene_body_collision_shape(scene, id) : NULL;
    const double half = shape != NULL ? half_thickness(shape) : 0.0;
    return half > 0.0 ? half : INFINITY;
}

/* The fastest body's bounds among the effect's bodies with shapes, and the thinnest body's
 * half-thickness (INFINITY: none has a thickness). */
static bound fastest(const tb__contact_params *contact, const tb_scene *scene, const double *y,
                     const double *dydt, double *thinnest)
{
    bound worst = {0.0, 0.0};
    *thinnest = INFINITY;
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        if (id < scene->body_count && tb__scene_body_collision_shape(scene, id) != NULL) {
            const bound b = motion_bound(scene, y, dydt, id);
            worst.speed = fmax(worst.speed, b.speed);
            worst.acceleration = fmax(worst.acceleration, b.acceleration);
            *thinnest = fmin(*thinnest, tb__contact_half_thickness(scene, id));
        }
    }
    return worst;
}

/* A pair's limit: the time to close half its gap, or (in contact) to move by half the law's
 * static sinking, gravity / omega^2; never below the floor, unless the floor would let the pair
 * close by the thinner body's half-thickness. */
static double pair_limit(const tb__contact_params *contact, const tb_scene *scene, const double *y,
                         const double *dydt, const tb__pair_contact *pair, double floor)
{
    const bound a = motion_bound(scene, y, dydt, pair->body_a);
    const bound b = motion_bound(scene, y, dydt, pair->body_b);
    /* before the first step (no dydt) each body is given the law's gravity */
    const double speed = a.speed + b.speed,
                 acceleration = a.acceleration + b.acceleration +
                                (dydt == NULL ? 2.0 * contact->gravity : 0.0);
    const double thinner = fmin(tb__contact_half_thickness(scene, pair->body_a),
                                tb__contact_half_thickness(scene, pair->body_b));
    floor = fmin(floor, travel_time(speed, acceleration, thinner));
    const double gap = pair_gap(pair);
    const double distance = gap > 0.0 ? gap : contact->gravity / (contact->omega * contact->omega);
    return fmax(floor, travel_time(speed, acceleration, TB__GAP_SAFETY * distance));
}

double tb__contact_step_limit(const tb__effect *effect, const tb_scene *scene, const double *y,
                              const double *dydt)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    double floor = 0.5 * contact->push_duration, thinnest;
    /* pairs not found are at least the look-ahead apart, closing at most twice the fastest; no
     * floor lets two bodies close by the thinnest half-thickness (before the first step, with
     * the speeds alone) */
    const bound worst = fastest(contact, scene, y, dydt, &thinnest);
    floor = fmin(floor, travel_time(2.0 * worst.speed, 2.0 * worst.acceleration, thinnest));
    if (dydt == NULL && !any_asleep(scene)) {
        return floor;
    }
    /* A pair of an awake and an asleep body gets no floor: no step closes more than half its
     * gap, so it never touches before its wake gap (TB__WAKE_DISTANCE, tb__contact_wake_gaps)
     * stops CVODE and the island wakes; pairs not found are farther than the look-ahead. */
    const double start = dydt == NULL ? 2.0 * contact->gravity : 0.0;
    double limit = dydt != NULL ? travel_time(2.0 * worst.speed, 2.0 * worst.acceleration,
                                              TB__GAP_SAFETY * TB__EVENT_LOOKAHEAD)
                                : INFINITY;
    double waking = any_asleep(scene)
                        ? travel_time(2.0 * worst.speed, 2.0 * worst.acceleration + start,
                                      TB__GAP_SAFETY * TB__EVENT_LOOKAHEAD)
                        : INFINITY;
    tb__pair_contact batch[TB__EVENT_BATCH];
    tb__contact_pairs_begin(contact->lookahead, scene, scene->time, y);
    size_t count;
    while ((count = tb__contact_pairs_next(contact->lookahead, scene, y, batch, TB__EVENT_BATCH)) >
           0) {
        for (size_t k = 0; k < count; ++k) {
            if (mixed(scene, batch[k].body_a, batch[k].body_b)) {
                waking = fmin(waking, pair_limit(contact, scene, y, dydt, &batch[k], 0.0));
            } else if (dydt != NULL) {
                limit = fmin(limit, pair_limit(contact, scene, y, dydt, &batch[k], floor));
            }
        }
    }
    return fmin(dydt != NULL ? fmax(limit, floor) : floor, waking);
}

/* Half the thickness of body id's shape across its thinnest direction (m): what a body must
 * not pass in one step. Convex and points shapes: their shape-frame bounds'; compound: the
 * thinnest piece's. */
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
    case TB_SHAPE_COMPOUND: { /* its thinnest piece's (a bowl's wall, not the bowl) */
        double thinnest = INFINITY;
        for (size_t k = 0; k < shape->piece_count; ++k) {
            thinnest = fmin(thinnest, half_thickness(shape->pieces[k].shape));
        }
        return thinnest;
    }
    default: {
        double thinnest = INFINITY;
        for (int k = 0; k < 3; ++k) {
            thinnest = fmin(thinnest, 0.5 * (shape->local_max[k] - shape->local_min[k]));
        }
        return thinnest;
    }
    }
}

/* The two fastest of the effect's bodies with shapes and the thinnest one with a thickness;
 * ahead: a keyframed body's speed is the fastest its keys take from the scene's time on (a bat
 * at rest that keys swing at 1000 m/s within an advance passed through a ball, F115). */
typedef struct extremes {
    double speed[2], thinnest, dynamic_speed; /* m/s (-1: none), half-thickness m (INFINITY) */
    size_t fast[2], thin, dynamic; /* TB_ALL_BODIES: none; dynamic: the fastest with a state */
} extremes;

static extremes find_extremes(const tb__contact_params *contact, const tb_scene *scene,
                              const double *y, bool ahead)
{
    /* speeds start below any speed: a body at rest counts */
    extremes e = {{-1.0, -1.0},  INFINITY,     -1.0, {TB_ALL_BODIES, TB_ALL_BODIES},
                  TB_ALL_BODIES, TB_ALL_BODIES};
    double thin_speed = INFINITY;
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        if (id >= scene->body_count || tb__scene_body_collision_shape(scene, id) == NULL) {
            continue;
        }
        const double s = ahead && tb__body_fixed(scene, id)
                             ? tb__body_fastest_from(scene, scene->time, y, id, reach(scene, y, id))
                             : motion_bound(scene, y, NULL, id).speed;
        const double t = tb__contact_half_thickness(scene, id);
        const int slot = s > e.speed[0] ? 0 : s > e.speed[1] ? 1 : 2;
        if (slot == 0) {
            e.speed[1] = e.speed[0], e.fast[1] = e.fast[0];
        }
        if (slot < 2) {
            e.speed[slot] = s, e.fast[slot] = id;
        }
        if (!tb__body_fixed(scene, id) && s > e.dynamic_speed) {
            e.dynamic_speed = s, e.dynamic = id;
        }
        /* of equally thin bodies the slowest, so that the mover named is another */
        if (t < e.thinnest || (t == e.thinnest && s < thin_speed)) {
            e.thinnest = t, e.thin = id, thin_speed = s;
        }
    }
    return e;
}

/* The faster of the two fastest that is not the thinnest body: the one that could pass it. */
static int mover(const extremes *e)
{
    return e->thin != e->fast[0] ? 0 : 1;
}

double tb__contact_tunnel_step(const tb__effect *effect, const tb_scene *scene, const double *y,
                               double dt, char *which, size_t size)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const extremes e = find_extremes(contact, scene, y, false);
    /* the two fastest close at most at the sum of their speeds; every other pair slower */
    const double closing = e.speed[0] + e.speed[1];
    if (e.fast[1] == TB_ALL_BODIES || e.thin == TB_ALL_BODIES || !(closing > 0.0)) {
        return INFINITY;
    }
    const double quick = e.thinnest / closing;
    if (dt > quick) { /* each pair by its distance and relative motion: at least quick */
        return tb__contact_tunnel_pairs(contact, scene, y, which, size);
    }
    const int m = mover(&e);
    snprintf(which, size,
             "body %zu (\"%s\", %.3g m/s) could pass through body %zu (\"%s\", %.3g m thick) in "
             "one step",
             e.fast[m], scene->names[e.fast[m]], e.speed[m], e.thin, scene->names[e.thin],
             2.0 * e.thinnest);
    return quick;
}

/* The radius of the round end a shape meets others with (m): a sphere's or capsule's; 0 for
 * shapes with corners or edges, which reach as deep as their tip. */
static double tip_radius(const tb_scene *scene, size_t id)
{
    const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
    return shape->type == TB_SHAPE_SPHERE || shape->type == TB_SHAPE_CAPSULE ? shape->radius : 0.0;
}

/* At least how deep two of the effect's bodies sink into each other before one's tip passes the
 * other's middle, where the normal turns (m): the least over pairs a != b, one of them with a
 * state (two static or keyframed bodies never touch), of a's tip radius plus
 * b's half-thickness (a box's corner passes a plate's middle at the plate's half-thickness, a
 * ball's centre at its radius more). Names a in tip and b in thin; INFINITY: no such pair. */
static double least_sinking_to_pass(const tb__contact_params *contact, const tb_scene *scene,
                                    size_t *tip, size_t *thin)
{
    double h[2] = {INFINITY, INFINITY}; /* the two thinnest, of ids thinnest[] */
    size_t thinnest[2] = {TB_ALL_BODIES, TB_ALL_BODIES}, thinnest_dynamic = TB_ALL_BODIES;
    double h_dynamic = INFINITY; /* the thinnest body with a state: what a fixed tip may pass */
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        const double t = tb__contact_half_thickness(scene, id);
        if (id < scene->body_count && !tb__body_fixed(scene, id) && t < h_dynamic) {
            h_dynamic = t, thinnest_dynamic = id;
        }
        const int slot = t < h[0] ? 0 : t < h[1] ? 1 : 2;
        if (slot == 0) {
            h[1] = h[0], thinnest[1] = thinnest[0];
        }
        if (slot < 2) {
            h[slot] = t, thinnest[slot] = id;
        }
    }
    double least = INFINITY;
    for (size_t k = 0; k < contact->body_count; ++k) {
        const size_t id = contact->bodies[k];
        if (id >= scene->body_count || tb__scene_body_collision_shape(scene, id) == NULL) {
            continue;
        }
        const int other = thinnest[0] != id ? 0 : 1;
        const bool fixed = tb__body_fixed(scene, id);
        const double depth = tip_radius(scene, id) + (fixed ? h_dynamic : h[other]);
        if (depth < least) {
            least = depth, *tip = id, *thin = fixed ? thinnest_dynamic : thinnest[other];
        }
    }
    return least;
}

tb_status tb__contact_check_impacts(const tb__effect *effect, const tb_scene *scene,
                                    const double *y, char *detail)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const extremes e = find_extremes(contact, scene, y, true);
    size_t tip = TB_ALL_BODIES, thin = TB_ALL_BODIES;
    const double depth = least_sinking_to_pass(contact, scene, &tip, &thin);
    /* the fastest pair that can meet: the two fastest, or, both without a state, the fastest
     * with one and the fastest (every pair a, b with a state has s_a + s_b at most that) */
    const bool fixed = e.dynamic != e.fast[0] && e.dynamic != e.fast[1];
    const double closing = e.speed[0] + (fixed ? e.dynamic_speed : e.speed[1]);
    if (e.fast[1] == TB_ALL_BODIES || e.dynamic == TB_ALL_BODIES ||
        !(closing > contact->omega * depth)) {
        return TB_STATUS_OK; /* NaN speeds are the stability guard's and the integrator's */
    }
    const double penetration = contact->gravity * (depth / closing) * (depth / closing);
    return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                          "body %zu (\"%s\") could pass through body %zu (\"%s\", %.3g m thick) at "
                          "up to %.3g m/s under every method: the contact stops it after %.3g m "
                          "(speed / omega), past %.3g m where the normal turns; use penetration "
                          "<= %.3g m, or slower or thicker bodies",
                          tip, scene->names[tip], thin, scene->names[thin],
                          2.0 * tb__contact_half_thickness(scene, thin), closing,
                          closing / contact->omega, depth, penetration);
}

void tb__ground_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                           double *gap, bool signs)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    tb__motion motion;
    for (size_t first = 0, end; first < scene->contact_count; first = end) {
        const size_t body = scene->contacts[first].body;
        end = tb__ground_run_end(scene, first);
        tb__body_motion_at(scene, scene->time, y, body, &motion);
        /* signs: a body surely above the plane has every point's gap above zero */
        if (signs && tb__ground_body_clear(ground, scene, first, end, &motion)) {
            continue;
        }
        /* signs: once a point is below zero, so is the body's gap */
        for (size_t j = first; j < end && !(signs && gap[body] < 0.0); ++j) {
            const tb__contact *c = &scene->contacts[j];
            double arm[3];
            tb__point_arm(&motion, c->r, arm);
            const double height = tb__v3_dot(ground->normal, motion.x) +
                                  tb__v3_dot(ground->normal, arm) - ground->offset - c->radius;
            gap[body] = fmin(gap[body], height);
        }
    }
}
