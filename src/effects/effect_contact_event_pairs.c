/* The pairs contact events watch (tb__effect_ops.event_pairs, scene/contact_event_watch.c): of
 * contact between bodies, the pairs within TB__EVENT_LOOKAHEAD (the events' pair finder) at
 * their deepest manifold point; of a ground plane, each body with contact points at its lowest
 * point, body_b TB_WORLD and the normal into the ground. Called at step boundaries only. */
#include "effects/contact_events.h"
#include "effects/ground_shapes.h"

#include "contact/contact_pairs.h"
#include "math/tb_math.h"

#include <math.h>

/* Pairs handled per batch of a pass (a stack buffer). */
#define TB__EVENT_PAIR_BATCH 16

double tb__manifold_landing_share(const tb__contact_manifold *m)
{
    const tb__contact_point *deepest = tb__manifold_deepest(m);
    int landing = 0;
    for (int j = 0; j < m->count; ++j) {
        landing += m->points[j].depth > deepest->depth - TB__CONTACT_MARGIN;
    }
    return 1.0 / landing;
}

/* The pair's deepest point, its gap and the relative normal speed and inverse mass there. */
static tb__event_pair event_pair(const tb_scene *scene, const double *y,
                                 const tb__pair_contact *pair)
{
    const tb__contact_point *deepest = tb__manifold_deepest(&pair->manifold);
    tb__event_pair out = {.body_a = pair->body_a,
                          .body_b = pair->body_b,
                          .gap = -deepest->depth,
                          .share = tb__manifold_landing_share(&pair->manifold)};
    tb__v3_copy(out.point, deepest->position);
    tb__v3_copy(out.normal, pair->manifold.normal);
    const size_t ids[2] = {pair->body_a, pair->body_b};
    for (int k = 0; k < 2; ++k) {
        tb__motion motion;
        tb__body_motion_at(scene, scene->time, y, ids[k], &motion);
        double arm[3], velocity[3];
        for (int i = 0; i < 3; ++i) {
            arm[i] = deepest->position[i] - motion.x[i];
        }
        tb__point_velocity(&motion, arm, velocity);
        out.gap_rate += (k == 0 ? -1.0 : 1.0) * tb__v3_dot(velocity, out.normal);
        out.inverse_mass +=
            tb__inverse_mass_along(tb__body_constants(scene, ids[k]), &motion, arm, out.normal);
    }
    return out;
}

size_t tb__contact_event_pairs(const tb__effect *effect, const tb_scene *scene, const double *y,
                               tb__event_pair *out, size_t capacity)
{
    tb__contact_pairs *pairs = tb__contact_of(effect)->lookahead;
    tb__pair_contact batch[TB__EVENT_PAIR_BATCH];
    /* a pair resting in a sleeping island (or on a static body) still touches: test it here too,
     * else its falling asleep would read as an end */
    tb__contact_pairs_skip_asleep(pairs, false);
    tb__contact_pairs_begin(pairs, scene, scene->time, y);
    size_t count, total = 0;
    while ((count = tb__contact_pairs_next(pairs, scene, y, batch, TB__EVENT_PAIR_BATCH)) > 0) {
        for (size_t k = 0; k < count; ++k, ++total) {
            if (total < capacity) {
                out[total] = event_pair(scene, y, &batch[k]);
            }
        }
    }
    tb__contact_pairs_skip_asleep(pairs, true);
    return total;
}

/* Body `body`'s points [first, end) against the plane: the lowest one's pair. */
static tb__event_pair ground_pair(const tb__ground_params *ground, const tb_scene *scene,
                                  const double *y, size_t first, size_t end)
{
    const size_t body = scene->contacts[first].body;
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, body, &motion);
    tb__event_pair out = {
        .body_a = body, .body_b = TB_WORLD, .gap = INFINITY, .gravity = ground->gravity};
    double lowest[3] = {0.0, 0.0, 0.0};
    for (size_t j = first; j < end; ++j) {
        const tb__contact *c = &scene->contacts[j];
        double arm[3];
        tb__point_arm(&motion, c->r, arm);
        tb__v3_axpy(arm, -c->radius, ground->normal); /* the sphere's lowest point */
        const double height =
            tb__v3_dot(ground->normal, motion.x) + tb__v3_dot(ground->normal, arm) - ground->offset;
        if (height < out.gap) {
            out.gap = height;
            out.share = c->share;
            tb__v3_copy(lowest, arm);
        }
    }
    double velocity[3];
    tb__point_velocity(&motion, lowest, velocity);
    out.gap_rate = tb__v3_dot(velocity, ground->normal);
    for (int k = 0; k < 3; ++k) {
        out.point[k] = motion.x[k] + lowest[k];
        out.normal[k] = -ground->normal[k];
    }
    out.inverse_mass =
        tb__inverse_mass_along(tb__body_constants(scene, body), &motion, lowest, ground->normal);
    return out;
}

size_t tb__ground_event_pairs(const tb__effect *effect, const tb_scene *scene, const double *y,
                              tb__event_pair *out, size_t capacity)
{
    size_t total = 0, first = 0;
    while (first < scene->contact_count) {
        size_t end = first + 1;
        while (end < scene->contact_count &&
               scene->contacts[end].body == scene->contacts[first].body) {
            ++end;
        }
        const tb__event_pair pair = ground_pair(tb__ground_of(effect), scene, y, first, end);
        if (pair.gap < TB__EVENT_LOOKAHEAD) {
            if (total < capacity) {
                out[total] = pair;
            }
            ++total;
        }
        first = end;
    }
    return tb__ground_shapes_event_pairs(effect, scene, y, out, capacity, total);
}

/* The pair's law at its landing point, of stiffness k = M_light omega^2 share (the law splits k
 * among the manifold's points: share 1 for spheres, 1/4 for a box landing flat) pushing the
 * effective mass 1 / inverse_mass: rate omega sqrt(M_light share inverse_mass), omega sqrt(4/3)
 * for head_on_balls' 1 and 3 kg, omega for a box landing flat on a static one (4 / M at a
 * corner). The push lasts push_units / rate, push_units recovered from the
 * effect's floor push_duration = push_units / (sqrt(2) omega). */
void tb__contact_impact_law(const tb__effect *effect, const tb_scene *scene,
                            const tb__event_pair *pair, struct tb__impact_law *out)
{
    const tb__contact_params *contact = tb__contact_of(effect);
    const double light = fmin(tb__body_constants(scene, pair->body_a)->mass,
                              tb__body_constants(scene, pair->body_b)->mass);
    out->rate = contact->omega * sqrt(light * pair->share * pair->inverse_mass);
    out->duration = contact->push_duration * sqrt(2.0) * contact->omega / out->rate;
    out->gravity = contact->gravity;
}

/* A body landing on the plane on its lowest point: that point's spring, k = M share omega0^2
 * (share = 1 / support of its contact points; for a shape 1 / its manifold's points landing
 * together, as its law splits k among them),
 * pushing the effective mass 1 / inverse_mass there. A sphere (share 1, 1 / M) rings at omega0;
 * a cube landing flat, its corner's share 1/4 against an inverse mass of 4 / M there, at omega0
 * too; a cube landing on one corner, 1/4 against at most 4 / M, more slowly (it took the whole
 * law before, as if all its points pushed at once, and counted corner landings the step
 * resolved). */
void tb__ground_impact_law(const tb__effect *effect, const tb_scene *scene,
                           const tb__event_pair *pair, struct tb__impact_law *out)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const double mass = tb__body_constants(scene, pair->body_a)->mass;
    out->rate = ground->omega * sqrt(mass * pair->share * pair->inverse_mass);
    out->duration = ground->push_units / out->rate;
    out->gravity = ground->gravity;
}
