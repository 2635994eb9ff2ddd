/* Private to a ground plane's shapes (effect_ground_shapes.c, the law; effect_ground_pool.c, the
 * bookkeeping of which bodies it meets and the friction pool sized for them): what the plane
 * keeps about the bodies it meets through their shapes. */
#ifndef TUMBLE_GROUND_SHAPES_INTERNAL_H
#define TUMBLE_GROUND_SHAPES_INTERNAL_H

#include "contact/contact_pairs.h"
#include "effects/contact_friction.h"
#include "effects/ground_shapes.h"
#include "scene/body_motion.h"

/* What tb__ground_shapes_changed changed, as it was: the pool it replaced (kept until
 * tb__ground_shapes_settled frees it, or puts it back) and the counts. */
typedef struct tb__ground_pool_change {
    tb__friction_pool *pool;
    size_t pool_bodies, fixed_states, slots_wanted, ids_wanted, met_bound;
} tb__ground_pool_change;

typedef struct tb__ground_shapes {
    /* the law's, friction's constants (pairs, bodies, lookahead unused); friction: NULL or pool */
    tb__contact_params law;
    size_t pool_bodies; /* ids below this may hold slots */
    double presliding;  /* m, the pool's scale */
    /* TB__GROUND_SLOTS_PER_SHAPE per body met through its shape, 1 + the largest such id (an
     * upper bound), at least the bodies met: at the last refresh, kept by note_points since */
    size_t slots_wanted, ids_wanted, met_bound;
    tb__ground_note undo;          /* what the last note_points changed, as it was */
    tb__ground_pool_change change; /* what the last shapes_changed changed, as it was */
    /* has_points[i]: body i has contact points, for i below capacity (bodies past it have
     * none: points are set by tb_scene_set_contact_points, whose check notes the flag) */
    unsigned char *has_points;
    size_t capacity;
} tb__ground_shapes;

/* Whether the ground meets body id through its shape: it can move, has one and no contact
 * points. */
static inline bool tb__ground_shapes_meet(const tb__ground_shapes *shapes, const tb_scene *scene,
                                          size_t id)
{
    return !tb__body_fixed(scene, id) && !(id < shapes->capacity && shapes->has_points[id]) &&
           tb__scene_body_collision_shape(scene, id) != NULL;
}

#endif
