/* Private: the contact effect's checks of its set-up (effect_contact_check.c), kept apart from
 * its forces. */
#ifndef TUMBLE_EFFECT_CONTACT_CHECK_H
#define TUMBLE_EFFECT_CONTACT_CHECK_H

#include "effects/effect_contact.h"

/* How deep a pair may start inside each other, in units of the depth at which the pair's
 * contact carries the heavier body's weight (the ground's rule: 10 penetrations). */
#define TB__CONTACT_START_DEPTH_WEIGHTS 10.0

/* The fastest contact rate omega = sqrt(gravity / penetration) a contact effect accepts, rad/s:
 * its impact lasts pi / omega, 3 ns here, and a faster one needs more than 1e8 steps per
 * simulated second under any method (CVODE's budget of steps runs out; a fixed step is refused
 * for max_steps). Gravity 1e300 m/s^2 passed every check before and failed the run. */
#define TB__CONTACT_RATE_MAX 1e9

/* Refuses (TB_STATUS_INVALID_ARGUMENT, the scene's detail naming the field, its value and the
 * range the others allow) a friction spring whose rate sqrt(gravity static_friction /
 * presliding) overflows or passes TB__CONTACT_RATE_MAX, as the normal law's may not: presliding
 * 1e-300 m asked for steps of 1e-151 s, static_friction 1e300 for 1e-306 s. Names presliding or
 * static_friction, whichever lies further from its default. presliding > 0 checked already. */
tb_status tb__contact_check_friction_rate(tb_scene *scene, double static_friction, double gravity,
                                          double presliding);

/* Refuses (TB_STATUS_INVALID_ARGUMENT, naming the field, the value and the range) a friction
 * pool of more slots than bodies[0 .. count) can ever use: 2 TB__MANIFOLD_POINTS per pair of
 * their pieces (a manifold per piece pair, each point with a slot relaxing beside it; a body
 * without a shape or of one shape counts one piece) or the default's 6 per body, whichever is
 * more (1e7 slots for two balls took 240 MB). Pieces are counted as the bodies have them now.
 * 0 (the default) passes. */
tb_status tb__contact_check_friction_points(tb_scene *scene, size_t friction_points,
                                            const size_t *bodies, size_t count);

/* Refuses a list with no pair that could touch (one body, or no dynamic body) and a listed body
 * without a collision shape (TB_STATUS_INVALID_ARGUMENT, the scene's detail naming it): the
 * effect would never see it touch anything (the scene file's loader refuses the same through
 * it). bodies[0 .. count) are ids checked already. */
tb_status tb__contact_check_shapes(tb_scene *scene, const size_t *bodies, size_t count);

/* Refuses body id's shape (TB_STATUS_INVALID_ARGUMENT, the scene's detail naming the body, the
 * effect at effect_index and its kind) when it reaches so far from the body's centre of mass
 * that a point's depth is known to worse than penetration (m; reach times DBL_EPSILON: the
 * force's rounding would exceed the body's weight), or that the contact's rate, which grows as
 * M reach^2 / I_min, overflows. A body without a shape, or one that cannot move, passes. */
tb_status tb__contact_check_shape_size(tb_scene *scene, size_t id, double penetration,
                                       size_t effect_index, const char *effect_kind);

/* tb__contact_check_shape_size of bodies[0 .. count), for a contact effect about to be added. */
tb_status tb__contact_check_shape_sizes(tb_scene *scene, const size_t *bodies, size_t count,
                                        double penetration);

/* The check_shape row of the contact effect: refuses to remove the shape of a body the effect
 * lists (TB_STATUS_INVALID_ARGUMENT, the scene's detail naming the body and the effect): the
 * effect would silently stop pushing it, though it refuses such a body when it is added; and a
 * listed body's new shape as tb__contact_check_shape_size refuses it. */
tb_status tb__contact_check_shape(const tb__effect *effect, tb_scene *scene, size_t id);

/* Refuses a new contact effect over bodies[0 .. count) (ids, each once) when two of them are
 * also both in an effect of the scene whose row is ops: that pair would be pushed by both, with
 * twice the stiffness and neither effect's restitution. The scene's detail names the pair and
 * the effect. Allocates a scratch array at set-up only. */
tb_status tb__contact_check_shared_pairs(tb_scene *scene, const tb__effect_ops *ops,
                                         const size_t *bodies, size_t count);

/* The check_start row of the contact effect: refuses a state y in which a pair starts deeper
 * inside each other than TB__CONTACT_START_DEPTH_WEIGHTS times the depth at which it carries the
 * heavier body's weight (the force there launches them apart), naming both bodies and the
 * depth in detail (TB_DETAIL_SIZE bytes). */
tb_status tb__contact_check_start(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  char *detail);

/* How much lighter than body id a point of its shape's surface can be, along the normal
 * (normal true) or across it, at y (>= 1; effect_contact.c): the lightness the contact's rate
 * bounds use, for a body's shape meeting a ground plane too (effect_ground_shapes.c). */
double tb__contact_lightness(const tb_scene *scene, const double *y, size_t id, bool normal);

#endif
