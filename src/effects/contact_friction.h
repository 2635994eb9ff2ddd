/* Private: static friction between bodies (effect_contact_friction.c, the law at a point in
 * contact_friction_law.c). Each touching point of a pair that holds a slot of the effect's
 * fixed pool keeps a tangential deflection z, three doubles in y in body A's principal frame,
 * and gets the ground's stick-anchor law
 * (effect_ground.c, docs/effects.md "Friction"); a point without a slot gets the memoryless
 * regularised law. The pool is allocated when the effect is added, so the state's length is
 * fixed then and never changes behind an integrator.
 *
 * Which slot a point holds is a function of y and of a slot map that changes only at step
 * boundaries (tb__effect_stepping.post_step after every fixed step, BDF projection and ARKODE
 * step and at every output; step_start before every adaptive step, which gives CVODE Adams one
 * per step too), so that between two boundaries the derivative is a pure function of y:
 *   - a claimed slot is keyed by its pair (a, b) and the point's position in A's principal
 *     frame at the last boundary; the touching points of a pair (depth > 0) take the pair's
 *     claimed slots nearest first (greedy on the distance between keys, which does not depend
 *     on the order the narrow phase lists the points in);
 *   - at a boundary the pair's points within the margin that do not touch yet take its claimed
 *     slots left over, nearest first, and the rest are given slots from the queue: a point that
 *     starts touching within the next step (under the adaptive methods the step limit keeps a pair
 *     apart at a step's start from closing within it, but where the step is already at most
 *     half the shortest push) finds a slot of its own pair, unloaded, whatever other pairs do;
 *   - a touching point left over (one that came from beyond the margin within a step) takes,
 *     provisionally, the next free slot of a queue (the k-th such point of a pass the k-th
 *     queued slot), and none when the queue runs out (then the memoryless law, counted at the
 *     boundary);
 *   - every slot no point holds relaxes z at TB__BRISTLE_RELEASE_RATE, by its own dynamics;
 *   - at a boundary, held slots take the points' positions as keys, provisional ones are claimed
 *     (popped from the queue's head, in the same order), queued slots still loaded above
 *     TB__FRICTION_FREE_DEFLECTION presliding (a provisional point that parted within the step)
 *     leave the queue, and a claimed or set-aside slot no point holds whose deflection has
 *     relaxed below that goes to the queue's tail. None of this changes the derivative at the
 *     boundary's state: a freed or set-aside slot relaxes as an unheld one did, and a queue
 *     changed behind the provisional claims moves no point that touches. */
#ifndef TUMBLE_CONTACT_FRICTION_H
#define TUMBLE_CONTACT_FRICTION_H

#include "contact/contact_law.h"
#include "contact/contact_pairs.h"
#include "effects/effect_contact.h"

/* Doubles of y per slot: z in body A's principal frame, m. */
#define TB__FRICTION_SLOT_STATES 3
/* No slot: the memoryless law. */
#define TB__NO_SLOT ((size_t)-1)

typedef struct tb__friction_pool tb__friction_pool;

/* A pool of `slots` >= 1 slots, all free, for pairs of bodies with ids below `bodies`;
 * presliding (m) scales the freeing threshold. On failure NULL (out of memory). */
tb__friction_pool *tb__friction_pool_create(size_t slots, size_t bodies, double presliding);
void tb__friction_pool_destroy(tb__friction_pool *pool);
size_t tb__friction_pool_slots(const tb__friction_pool *pool);

/* The slots of pair's touching points (depth > 0) at y, TB__NO_SLOT for the others and for
 * points without one; *fresh counts the pass's provisional claims so far (start it at 0). */
void tb__friction_match(const tb__friction_pool *pool, const tb__pair_contact *pair,
                        const tb__motion *motion_a, size_t *fresh,
                        size_t slots[TB__MANIFOLD_POINTS]);

/* dz = -release z for every slot (states: the pool's first state in y and dydt), 0 for the
 * slots of a pair of two asleep bodies (frozen); the derivative then overwrites the slots
 * points hold. */
void tb__friction_relax_all(const tb__friction_pool *pool, const tb_scene *scene, const double *z,
                            double *dz);

/* The Jacobian of tb__friction_relax_all: each slot's diagonal -release (0 when frozen), at
 * states from first_state in y; the points' rows then replace the held slots' (jacobian_rows.h). */
struct tb__jacobian_rows;
void tb__friction_relax_jacobian(const tb__friction_pool *pool, const tb_scene *scene,
                                 size_t first_state, struct tb__jacobian_rows *rows);

/* Friction on B at a touching point with normal force N > 0, normal n (A to B), relative
 * tangential velocity v_t of B against A (world), at a point whose spring has stiffness and
 * damping given (N/m, N s/m): with z (A's frame, q_a A's unit quaternion) the stick anchor,
 * writing dz; with z NULL the memoryless law (dz unused). */
void tb__friction_force(const tb__contact_params *contact, double stiffness, double damping,
                        double N, const double n[3], const double v_t[3], const double q_a[4],
                        const double *z, double *dz, double friction[3]);

/* The memoryless law's regularisation v_reg (m/s) for friction mu_s, gravity g (m/s^2) and
 * presliding (m): its decay mu_s g a^2 / v_reg then stays within the friction spring's own
 * fastest mode (about sqrt(g mu_s / presliding) a^2 at the arms, contact_rate), so a full pool
 * costs no shorter step; 1.7 mm/s at the defaults. */
static inline double tb__contact_slip_velocity(double static_friction, double gravity,
                                               double presliding)
{
    return fmax(TB__FRICTION_REGULARISATION, sqrt(static_friction * gravity * presliding));
}

/* Visits each slot's TB__FRICTION_SLOT_STATES states (first_state: the pool's first state in y)
 * with the pair that claims it, TB_ALL_BODIES for a free slot (the Jacobian's pattern,
 * scene_jacobian.c). A slot taken provisionally inside a step is free here. */
void tb__friction_state_owners(const tb__friction_pool *pool, size_t first_state,
                               tb__coupling_visit visit, void *ctx);

/* What the pool did (include/tumble/effects.h). */
const tb_contact_friction_stats *tb__friction_stats(const tb__friction_pool *pool);

/* The contact effect's post_step op: the slot map's update at a step boundary. */
void tb__friction_post_step(const tb__effect *effect, const tb_scene *scene, const double *y);
/* Its step_start op: the same update (without linking sleeping islands) unless the pool's last
 * boundary was at scene->time (the post-step hook's, at a BDF projection or an ARKODE step). */
void tb__friction_step_start(const tb__effect *effect, const tb_scene *scene, const double *y);
/* Whether a boundary at t would be a new one: the pool's last boundary was not at t. */
bool tb__friction_boundary_due(const tb__friction_pool *pool, double t);

/* An integrator made or reset at t (tb__effect_stepping.restart), z the pool's states in y:
 * unless t is the time of the pool's last boundary (a run continued where it stopped, after a
 * change of a body's state or an added load: the slots keep their points and anchors), the slot
 * map starts again from z alone, so that a run from a state is the same whatever ran on the
 * scene before: every slot free and queued in slot order, those with an unloaded anchor (z = 0)
 * first. A start's anchors are zero, so its queue is a new pool's; a loaded anchor, whose point
 * is not known, relaxes free and is handed out last. The stats count on, but in_use is 0. */
void tb__friction_restart(tb__friction_pool *pool, double t, const double *z);
/* The contact effect's restart op: its pool's. */
void tb__friction_effect_restart(const tb__effect *effect, const tb_scene *scene, double t,
                                 const double *y);

/* The boundary's pass for another owner of a pool (a ground plane, effect_ground_shapes.c):
 * begin, hold each pair's touching points (motion_a: A's motion at the boundary, the frame of
 * the keys; *fresh counts the provisional claims from 0, as tb__friction_match's), then end with
 * the pool's states z (its first state in y) and the count. */
void tb__friction_boundary_begin(tb__friction_pool *pool);
void tb__friction_hold(tb__friction_pool *pool, const tb__pair_contact *pair,
                       const tb__motion *motion_a, size_t *fresh);
void tb__friction_boundary_end(tb__friction_pool *pool, const tb_scene *scene, const double *z,
                               size_t fresh);

#endif
