/* Private: a ground plane against the collision shapes of bodies without contact points
 * (effect_ground_shapes.c), called by the ground's row (effect_ground.c). The plane is body A of
 * a pair with each such body, infinitely heavy and at rest: the narrow phase's plane manifold
 * (contact/narrow_phase.h, tb__collide_plane), the normal law of contact between bodies at the
 * effective mass of the points' centre of pressure, and its friction (effects/contact_friction.h:
 * stick anchors in a pool of slots matched across steps, the memoryless law for a point without
 * one). A body with contact points keeps the points' law (effect_ground.c), bit for bit. */
#ifndef TUMBLE_GROUND_SHAPES_H
#define TUMBLE_GROUND_SHAPES_H

#include "effects/effect_ground.h"

/* Friction slots per body the ground meets through its shape (a box's 4 corners on a face). */
#define TB__GROUND_SLOTS_PER_SHAPE 4

/* Makes ground->shapes for def (the law's constants from ground, already filled) and the scene
 * now: which bodies have points, and a friction pool of TB__GROUND_SLOTS_PER_SHAPE slots for
 * each body with a shape and no points now (none when there are none, so that a scene of points
 * keeps its layout: effect->fixed_states); shapes set later grow it (tb__ground_shapes_changed).
 * A point that finds every slot held has the memoryless law. The scene's detail names what
 * failed. */
tb_status tb__ground_shapes_create(tb_scene *scene, const tb_ground_def *def, tb__effect *effect);
void tb__ground_shapes_release(tb__effect *effect);

/* Refuses, before the ground is added (it is effect scene->effect_count), a shape that meets it
 * and is too large for its penetration (tb__contact_check_shape_size). Flags refreshed first. */
tb_status tb__ground_shapes_check_sizes(const tb__effect *effect, tb_scene *scene);

/* The ground's check_shape op: body id's new shape, if the ground meets it, as
 * tb__contact_check_shape_size takes it. */
tb_status tb__ground_check_shape(const tb__effect *effect, tb_scene *scene, size_t id);

/* The ground's shapes_changed op for body id: a pool with room for TB__GROUND_SLOTS_PER_SHAPE
 * slots per body it meets through its shape now and for their ids, grown by doubling when short
 * (its state count then grows, and the scene lays the states out again, which zeroes every
 * effect's states, as any change of layout does: the anchors start unloaded). A pool with room
 * already changes nothing; the bodies are counted again (O(bodies + points)) only when an upper
 * bound of their number, raised by each body given a shape, passes the pool's room, so that n
 * shapes set one by one cost O(n log n). The old pool is kept until the shapes_settled op
 * (tb__ground_shapes_settled), which frees it, or puts it and the counts back when the change
 * was refused (by this effect, a later one or the layout). The scene's detail names a failure. */
tb_status tb__ground_shapes_changed(tb__effect *effect, tb_scene *scene, size_t id);
void tb__ground_shapes_settled(tb__effect *effect, bool undo);

/* Which bodies have contact points, noted again for the scene now: at every start check, so at
 * every change of points (tb_scene_set_contact_points checks), every integrator's creation and
 * every state set from outside. A body without points meets the ground through its shape
 * whenever it has one, set before or after the ground. Allocates only when the body count has
 * grown; TB_STATUS_OUT_OF_MEMORY (detail) and nothing changed otherwise. */
tb_status tb__ground_shapes_refresh(const tb__effect *effect, const tb_scene *scene, char *detail);

/* Body id's flag alone, after its points were set (has_points: it has some now), and the counts
 * of bodies met through their shapes with it: tb__ground_shapes_refresh's work for one body, so
 * that n bodies given points one by one cost O(n). TB_STATUS_OUT_OF_MEMORY (detail), nothing
 * changed, when the flags cannot grow. */
typedef struct tb__ground_note { /* what note_points changed (body id's flag), as it was */
    size_t id, slots_wanted, ids_wanted, met_bound;
    bool had;
} tb__ground_note;
tb_status tb__ground_shapes_note_points(const tb__effect *effect, const tb_scene *scene, size_t id,
                                        bool has_points, char *detail);
/* tb__effect_stepping.uncheck_points: puts back what the last note_points changed (a check after
 * it, this effect's or another's, refused the points). */
void tb__ground_shapes_unnote(const tb__effect *effect);

/* Whether the ground meets body id through its shape: it can move, has one and no points. */
bool tb__ground_meets_shape(const tb__effect *effect, const tb_scene *scene, size_t id);

/* The ground's hooks for those bodies; each does nothing for a ground with none. */
void tb__ground_shapes_apply(const tb__effect *effect, const tb_scene *scene, double t,
                             const double *y, double *dydt);
void tb__ground_shapes_rate(const tb__effect *effect, const tb_scene *scene, const double *y,
                            tb__effect_rate *out);
/* The friction pool's states with the body each slot's pair holds (the Jacobian's pattern). */
void tb__ground_shapes_state_owners(const tb__effect *effect, const tb_scene *scene,
                                    tb__coupling_visit visit, void *ctx);
/* Refuses the shape of a body among [first, end) starting deeper than limit (m) in the plane,
 * naming the body. */
tb_status tb__ground_shapes_check_start(const tb__effect *effect, const tb_scene *scene,
                                        const double *y, size_t first, size_t end, double limit,
                                        char *detail);
void tb__ground_shapes_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  double *gap);
void tb__ground_shapes_post_step(const tb__effect *effect, const tb_scene *scene, const double *y);
/* Its step_start op: the same where the pool's last boundary was not at scene->time. */
void tb__ground_shapes_step_start(const tb__effect *effect, const tb_scene *scene, const double *y);
/* Its restart op: the pool's (tb__friction_restart). */
void tb__ground_shapes_restart(const tb__effect *effect, const tb_scene *scene, double t,
                               const double *y);

/* Whether the ground meets body id through its shape (it has one and no contact points); if so
 * its deepest point's depth in the plane at y (m) and how many of its points touch (depth > 0). */
bool tb__ground_shape_touch(const tb__effect *effect, const tb_scene *scene, const double *y,
                            size_t id, double *depth, int *points);

/* The ground's event pairs (tb__effect_stepping.event_pairs) of the bodies it meets through
 * their shapes, within TB__EVENT_LOOKAHEAD at y (the scene's time): each body's deepest point
 * against the plane, body_b TB_WORLD; written into out[total ..) while capacity lasts. Returns
 * total plus their number. */
size_t tb__ground_shapes_event_pairs(const tb__effect *effect, const tb_scene *scene,
                                     const double *y, tb__event_pair *out, size_t capacity,
                                     size_t total);

#endif
