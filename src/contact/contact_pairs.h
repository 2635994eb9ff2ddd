/* Private: the hook a contact effect calls every derivative. Over a set of bodies with
 * shapes, it runs the broad phase (world bounds at y grown by margin; the candidate pairs kept
 * from an earlier pass while every body stays inside its skin, else sweep and prune again:
 * pair_list.h) and the narrow phase on each candidate, and hands back the touching pairs in
 * batches: the caller gives a buffer of any size, applies the batch and asks for the next until
 * none is left. Memory is allocated at creation for the body set; a pass allocates nothing and
 * reads only y, the scene's bodies and their shapes. Pairs come in an order that depends on y
 * alone (by the set's order of the bodies, pair_list.h), so forces sum in the same order
 * whatever was evaluated before. */
#ifndef TUMBLE_CONTACT_PAIRS_H
#define TUMBLE_CONTACT_PAIRS_H

#include "contact/broad_phase.h"
#include "contact/narrow_phase.h"
#include "tumble/scene.h"

typedef struct tb__pair_contact {
    size_t body_a, body_b; /* body ids, body_a < body_b; the manifold's normal points from a */
    /* the touching pieces of a and b (collision_shape.h; 0 for a plain shape): a body pair of
     * compound bodies comes once per touching piece pair, in the order (piece_a, piece_b) */
    size_t piece_a, piece_b;
    tb__contact_manifold manifold; /* count >= 1 */
} tb__pair_contact;

typedef struct tb__contact_pairs tb__contact_pairs;

/* For bodies[0 .. count) (ids of the scene's bodies, each at most once; bodies NULL: every
 * body of the scene now), margin >= 0 (m; finite). Bodies without a shape when a pass runs
 * are skipped, so shapes may be set or removed later; bodies added later are not included.
 * On failure *out is NULL and detail (TB_DETAIL_SIZE bytes, may be NULL) names the input. */
tb_status tb__contact_pairs_create(const tb_scene *scene, const size_t *bodies, size_t count,
                                   double margin, tb__contact_pairs **out, char *detail);
void tb__contact_pairs_destroy(tb__contact_pairs *pairs);

/* Whether passes skip pairs of two asleep bodies (body_motion.h, tb__pair_resting) before
 * the narrow phase: the contact effect's do; a read-out's (tb_contact_info) do not. Default
 * false. */
void tb__contact_pairs_skip_asleep(tb__contact_pairs *pairs, bool skip);
/* The ids a pair finder accepts: each below the scene's body count, none twice; detail names
 * the first that is not. It stops there, so it reads at most body count + 1 of them: a count
 * beyond the scene's (2^61 + 1) is refused by the pigeonhole without reading on. */
tb_status tb__contact_pairs_check_ids(const tb_scene *scene, const size_t *bodies, size_t count,
                                      char *detail);

/* The level a pass needs a plain box pair's gap (minus its deepest point's depth, m) to be at
 * most for the pair to count (ctx as given, the bodies in increasing order; +infinity: always;
 * -infinity: the pass needs nothing of the pair, whatever its shapes). A pass that only lowers
 * per-body gaps or links pairs below a gap (the look-ahead's event and wake gaps, the wake
 * links) passes over a pair of boxes whose gap floor is above it (tb__collide_below), and over
 * every pair at -infinity: the pair is not handed back, and the pass's result is the same bits.
 * Asked as each pair is tested. Set for the passes that follow (NULL, the default: every
 * pair). */
typedef double (*tb__pair_level)(void *ctx, size_t body_a, size_t body_b);
void tb__contact_pairs_filter(tb__contact_pairs *pairs, tb__pair_level level, void *ctx);

/* Starts a pass at state y (the scene's state array) at time t (bodies without a state are
 * read there): bounds, sort. */
void tb__contact_pairs_begin(tb__contact_pairs *pairs, const tb_scene *scene, double t,
                             const double *y);

/* The pass's next touching pairs, up to capacity (>= 1) of them, into out; returns how many
 * were written, 0 when the pass is done. */
size_t tb__contact_pairs_next(tb__contact_pairs *pairs, const tb_scene *scene, const double *y,
                              tb__pair_contact *out, size_t capacity);

/* Body id's shape pose at (t, y) (collision_shape.h), without checks; NULL shape when it has
 * none. t is where a body without a state is read (the derivative's own t; the scene's time
 * outside a derivative). */
const tb__collision_shape *tb__scene_body_collision_shape(const tb_scene *scene, size_t id);
void tb__shape_pose(const tb_scene *scene, double t, const double *y, size_t id,
                    double out_pose[TB__POSE_SIZE]);

#endif
