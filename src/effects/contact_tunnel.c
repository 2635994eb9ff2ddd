/* The contact's tunnelling step pair by pair (tb__contact_tunnel_pairs): what a fixed step is
 * checked against where the quick bound over all bodies (the two fastest closing on the
 * thinnest, effect_contact_events.c) refuses it. Bodies parting, or passing each other at a
 * distance, cannot pass through each other however fast they move, and two slow ones close
 * slower than the two fastest: door_ball's ball falling away from the door at 4.95 m/s (t = 0.5
 * s) and bat_sweep's boxes falling to the floor at 3.6 m/s (1.43 s) were refused at 1/240 s by
 * the quick bound, which sums the two fastest speeds in the scene and sets them against its
 * thinnest body. O(n^2) in the effect's bodies, only where the quick bound refused a step (at an
 * advance or a frame). */
#include "effects/contact_events.h"

#include "contact/contact_pairs.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>

/* One body's part in the pairwise tunnelling bound: its centre of mass, velocity, spin, reach
 * (m: a radius about x that holds its shape at any orientation) and half-thickness. */
typedef struct mover_state {
    double x[3], v[3], omega[3], reach, half;
} mover_state;

static mover_state mover_at(const tb_scene *scene, const double *y, size_t id)
{
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, id, &motion);
    mover_state m;
    tb__v3_copy(m.x, motion.x);
    tb__v3_copy(m.v, motion.v);
    tb__v3_copy(m.omega, motion.omega);
    double low[3], high[3], r[3]; /* the corners of its world bounds hold every point */
    if (tb_scene_body_shape_bounds(scene, y, id, low, high) != TB_STATUS_OK) {
        tb__v3_copy(low, m.x); /* as the quick bound's reach: a point */
        tb__v3_copy(high, m.x);
    }
    for (int k = 0; k < 3; ++k) {
        r[k] = fmax(fabs(low[k] - m.x[k]), fabs(high[k] - m.x[k]));
    }
    m.reach = tb__v3_norm(r);
    m.half = tb__contact_half_thickness(scene, id);
    return m;
}

/* Whether a's and b's balls of reach (which hold them at any orientation) can meet at the
 * velocities they have: they touch or overlap, or their centres approach to within the sum of
 * their reaches. */
static bool can_meet(const mover_state *a, const mover_state *b)
{
    double dx[3], dv[3];
    for (int k = 0; k < 3; ++k) {
        dx[k] = b->x[k] - a->x[k], dv[k] = b->v[k] - a->v[k];
    }
    const double reach = a->reach + b->reach, along = tb__v3_dot(dx, dv), dv2 = tb__v3_dot(dv, dv);
    if (tb__v3_dot(dx, dx) <= reach * reach) {
        return true;
    }
    if (!(along < 0.0)) {
        return false; /* apart and parting (or at rest relative to each other) */
    }
    const double closest2 = tb__v3_dot(dx, dx) - along * along / dv2; /* nearest centres, ^2 */
    return closest2 <= reach * reach;
}

/* The longest step in which b cannot pass through a or a through b (s): the thinner one's
 * half-thickness over a bound on their relative speed anywhere in both, |v_b - v_a| + |w_a| r_a
 * + |w_b| r_b (r: the reaches); INFINITY where at their velocities they cannot meet. Like the
 * quick bound, it holds while the velocities stay as they are, and is checked again at every
 * advance and frame. */
static double pair_tunnel_step(const mover_state *a, const mover_state *b, double *closing)
{
    const double half = fmin(a->half, b->half);
    double dv[3];
    for (int k = 0; k < 3; ++k) {
        dv[k] = b->v[k] - a->v[k];
    }
    *closing =
        tb__v3_norm(dv) + tb__v3_norm(a->omega) * a->reach + tb__v3_norm(b->omega) * b->reach;
    if (!(half < INFINITY) || !(*closing > 0.0) || !can_meet(a, b)) {
        return INFINITY;
    }
    return half / *closing;
}

double tb__contact_tunnel_pairs(const tb__contact_params *contact, const tb_scene *scene,
                                const double *y, char *which, size_t size)
{
    double limit = INFINITY;
    for (size_t i = 0; i < contact->body_count; ++i) {
        const size_t ia = contact->bodies[i];
        if (ia >= scene->body_count || tb__scene_body_collision_shape(scene, ia) == NULL) {
            continue;
        }
        const mover_state a = mover_at(scene, y, ia);
        for (size_t j = i + 1; j < contact->body_count; ++j) {
            const size_t ib = contact->bodies[j];
            if (ib >= scene->body_count || tb__scene_body_collision_shape(scene, ib) == NULL) {
                continue;
            }
            const mover_state b = mover_at(scene, y, ib);
            double closing = 0.0;
            const double step = pair_tunnel_step(&a, &b, &closing);
            if (step < limit) {
                const size_t thin = a.half <= b.half ? ia : ib, other = thin == ia ? ib : ia;
                limit = step;
                snprintf(which, size,
                         "body %zu (\"%s\") could pass through body %zu (\"%s\", %.3g m thick) "
                         "in one step, closing at up to %.3g m/s",
                         other, scene->names[other], thin, scene->names[thin],
                         2.0 * fmin(a.half, b.half), closing);
            }
        }
    }
    return limit;
}
