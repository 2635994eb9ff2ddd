/* The contact effect's hook: broad phase over a set of bodies' shapes at y, then the narrow
 * phase on each candidate pair, handed back in batches. */
#include "contact/contact_pairs.h"

#include "contact/pair_list.h"
#include "core/detail.h"
#include "core/validate.h"
#include "scene/scene_internal.h"
#include "scene/sleep_frozen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Candidate pairs fetched from the broad phase at a time. */
#define PAIR_BATCH 64

struct tb__contact_pairs {
    size_t count;          /* bodies in the set */
    size_t *ids;           /* count body ids */
    size_t *local;         /* count: the set's index of each box in use (bodies with shapes) */
    double *poses;         /* TB__POSE_SIZE * count, at the pass's y */
    tb__box_frame *frames; /* count: a plain box's frame at its pose, once per pass, not per pair */
    unsigned char *framed; /* count: frames[b] is that of poses[b] (worked out when first needed) */
    double margin;
    tb__pair_list list; /* the broad phase, its candidates kept between passes */
    tb__index_pair batch[PAIR_BATCH];
    size_t batch_count, batch_next; /* fetched candidates and the next to test */
    size_t piece_a, piece_b;        /* the next piece pair of candidate batch_next */
    bool skip_asleep;               /* pairs of two asleep bodies are not tested */
    tb__pair_level level;           /* NULL: every pair (tb__contact_pairs_filter) */
    void *level_ctx;
    /* count: box b's pose, frame and bounds are those of its frozen body (sleep_frozen.h),
     * kept from an earlier pass while the asleep set and the shapes (their generations)
     * stay */
    unsigned char *kept;
    unsigned long long kept_sleep, kept_shapes;
};

tb_status tb__contact_pairs_check_ids(const tb_scene *scene, const size_t *bodies, size_t count,
                                      char *detail)
{
    for (size_t k = 0; bodies != NULL && k < count; ++k) {
        if (bodies[k] >= scene->body_count) {
            return tb__set_detail(detail, TB_STATUS_OUT_OF_RANGE,
                                  "bodies[%zu]: %zu is not a body (the scene has %zu)", k,
                                  bodies[k], scene->body_count);
        }
        for (size_t j = 0; j < k; ++j) {
            if (bodies[j] == bodies[k]) {
                return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                      "bodies[%zu]: body %zu is listed twice (also bodies[%zu])", k,
                                      bodies[k], j);
            }
        }
    }
    return TB_STATUS_OK;
}

static tb_status check_bodies(const tb_scene *scene, const size_t *bodies, size_t count,
                              double margin, char *detail)
{
    if (!isfinite(margin) || margin < 0.0) {
        return tb__set_detail(detail,
                              isfinite(margin) ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_NOT_FINITE,
                              "margin: must be finite and >= 0, got %g", margin);
    }
    return tb__contact_pairs_check_ids(scene, bodies, count, detail);
}

tb_status tb__contact_pairs_create(const tb_scene *scene, const size_t *bodies, size_t count,
                                   double margin, tb__contact_pairs **out, char *detail)
{
    *out = NULL;
    if (bodies == NULL) {
        count = scene->body_count;
    }
    tb_status status = check_bodies(scene, bodies, count, margin, detail);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__contact_pairs *p = calloc(1, sizeof *p);
    const size_t n = count > 0 ? count : 1;
    if (p != NULL) {
        p->ids = tb__malloc_array(n, sizeof *p->ids);
        p->local = tb__malloc_array(n, sizeof *p->local);
        p->poses = tb__malloc_array(n, TB__POSE_SIZE * sizeof(double));
        p->frames = tb__malloc_array(n, sizeof *p->frames);
        p->kept = calloc(n, 1);
        p->framed = calloc(n, 1);
    }
    if (p == NULL || p->ids == NULL || p->local == NULL || p->poses == NULL || p->frames == NULL ||
        p->kept == NULL || p->framed == NULL ||
        tb__pair_list_init(&p->list, count) != TB_STATUS_OK) {
        tb__contact_pairs_destroy(p);
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "contact pairs for %zu bodies",
                              count);
    }
    for (size_t k = 0; k < count; ++k) {
        p->ids[k] = bodies != NULL ? bodies[k] : k;
        p->local[k] = (size_t)-1; /* no box numbered yet */
    }
    p->count = count;
    p->margin = margin;
    *out = p;
    return TB_STATUS_OK;
}

void tb__contact_pairs_destroy(tb__contact_pairs *pairs)
{
    if (pairs != NULL) {
        tb__pair_list_free(&pairs->list);
        free(pairs->ids);
        free(pairs->local);
        free(pairs->poses);
        free(pairs->frames);
        free(pairs->kept);
        free(pairs->framed);
        free(pairs);
    }
}

void tb__contact_pairs_skip_asleep(tb__contact_pairs *pairs, bool skip)
{
    pairs->skip_asleep = skip;
}

/* Whether one of the pairs' bodies is keyframed: it may move into (or carry) asleep bodies. */
static bool any_keyframed(const tb__contact_pairs *pairs, const tb_scene *scene)
{
    for (size_t k = 0; k < pairs->count; ++k) {
        if (tb__body_fixed(scene, pairs->ids[k]) && !tb__body_static(scene, pairs->ids[k])) {
            return true;
        }
    }
    return false;
}

/* Box b's pose and bounds (grown by half the margin each way, so that pairs within it meet)
 * for body id at (t, y); its frame is worked out when a pair first needs it (box_frame). */
static void place_box(tb__contact_pairs *pairs, const tb_scene *scene, double t, const double *y,
                      size_t id, const tb__collision_shape *shape, size_t b)
{
    double *pose = pairs->poses + TB__POSE_SIZE * b;
    tb__shape_pose(scene, t, y, id, pose);
    pairs->framed[b] = 0;
    tb__aabb *box = &pairs->list.bounds[b];
    tb__collision_shape_bounds(shape, pose, box->min, box->max);
    for (int i = 0; i < 3; ++i) {
        box->min[i] -= 0.5 * pairs->margin;
        box->max[i] += 0.5 * pairs->margin;
    }
}

/* Drops the kept boxes when the asleep set or the shapes (and so the boxes' numbering) changed
 * since they were kept. */
static void check_kept(tb__contact_pairs *pairs, const tb_scene *scene)
{
    const unsigned long long sleep = tb__scene_sleep_generation(scene);
    if (sleep != pairs->kept_sleep || scene->effects_generation != pairs->kept_shapes) {
        memset(pairs->kept, 0, pairs->count);
        pairs->kept_sleep = sleep;
        pairs->kept_shapes = scene->effects_generation;
    }
}

void tb__contact_pairs_begin(tb__contact_pairs *pairs, const tb_scene *scene, double t,
                             const double *y)
{
    size_t boxes = 0, resting = 0;
    /* every dynamic body asleep and no keyframed one: no pair to find (the broad phase would
     * list only asleep and static ones) */
    const bool all_asleep = pairs->skip_asleep && scene->sleep != NULL &&
                            scene->sleep->asleep_count == scene->slot_count &&
                            !any_keyframed(pairs, scene);
    check_kept(pairs, scene);
    for (size_t k = 0; k < pairs->count && !all_asleep; ++k) {
        const size_t id = pairs->ids[k];
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
        if (shape == NULL) {
            continue;
        }
        const size_t b = boxes++;
        if (pairs->local[b] != k) { /* the boxes were renumbered: a shape was set or removed */
            tb__pair_list_invalidate(&pairs->list);
            pairs->local[b] = k;
        }
        /* a pair of two resting bodies is skipped (test_pair): the sweep needs only the others */
        const bool rests = tb__body_asleep(scene, id) || tb__body_static(scene, id);
        pairs->list.broad.active[b] = !rests;
        resting += rests;
        const bool frozen = tb__body_frozen(scene, y, id);
        if (!frozen || !pairs->kept[b]) {
            place_box(pairs, scene, t, y, id, shape, b);
            pairs->kept[b] = frozen;
        }
    }
    /* the limited sweep scans back from each active box as well: worth it from half resting */
    tb__pair_list_begin(&pairs->list, boxes,
                        pairs->skip_asleep && 2 * resting >= boxes && resting > 0);
    pairs->batch_count = 0;
    pairs->batch_next = 0;
    pairs->piece_a = pairs->piece_b = 0;
}

/* Plain box b's frame at its pose, worked out once per pose: most boxes of a pass are in no
 * tested pair (a row of dominoes standing apart), and a frame is a function of the pose alone. */
static const tb__box_frame *box_frame(tb__contact_pairs *pairs, size_t b)
{
    if (!pairs->framed[b]) {
        tb__box_frame_at(pairs->poses + TB__POSE_SIZE * b, &pairs->frames[b]);
        pairs->framed[b] = 1;
    }
    return &pairs->frames[b];
}

/* Whether the boxes of two pieces at their world poses come within the margin. */
static bool pieces_near(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                        const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                        double margin)
{
    double min_a[3], max_a[3], min_b[3], max_b[3];
    tb__collision_shape_bounds(a, pose_a, min_a, max_a);
    tb__collision_shape_bounds(b, pose_b, min_b, max_b);
    for (int i = 0; i < 3; ++i) {
        if (min_a[i] - max_b[i] > margin || min_b[i] - max_a[i] > margin) {
            return false;
        }
    }
    return true;
}

void tb__contact_pairs_filter(tb__contact_pairs *pairs, tb__pair_level level, void *ctx)
{
    pairs->level = level;
    pairs->level_ctx = ctx;
}

/* The narrow phase on the pieces, into o (bodies set); returns whether they touch. Two plain
 * boxes (both frames given) are passed over above the pair's level. */
static bool test_pieces(const tb__contact_pairs *pairs, const tb__collision_shape *piece_a,
                        const double world_a[TB__POSE_SIZE], const tb__box_frame *frame_a,
                        const tb__collision_shape *piece_b, const double world_b[TB__POSE_SIZE],
                        const tb__box_frame *frame_b, double level, tb__pair_contact *o)
{
    level = frame_a != NULL && frame_b != NULL ? level : INFINITY;
    return tb__collide_below(piece_a, world_a, frame_a, piece_b, world_b, frame_b, level,
                             pairs->margin, &o->manifold) > 0;
}

/* Runs the narrow phase on box pair c's piece pairs from the pass's next one, writing the
 * touching ones to out (up to capacity); returns how many. c is done when pairs->piece_a is
 * back at 0 (a pair of plain shapes: one test, as before pieces). */
static size_t test_pair(tb__contact_pairs *pairs, const tb_scene *scene, const tb__index_pair *c,
                        tb__pair_contact *out, size_t capacity)
{
    const size_t a = pairs->ids[pairs->local[c->first]];
    const size_t b = pairs->ids[pairs->local[c->second]];
    if (tb__body_fixed(scene, a) && tb__body_fixed(scene, b)) {
        return 0; /* neither can move: no force between them can act */
    }
    if (pairs->skip_asleep && tb__pair_resting(scene, a, b)) {
        return 0; /* a sleeping island: no narrow phase inside it */
    }
    const bool in_order = a < b;
    const double level = pairs->level != NULL
                             ? pairs->level(pairs->level_ctx, in_order ? a : b, in_order ? b : a)
                             : INFINITY;
    if (level == -INFINITY) { /* the pass needs nothing of this pair, whatever its shapes */
        pairs->piece_a = pairs->piece_b = 0;
        return 0;
    }
    const size_t first = in_order ? c->first : c->second, second = in_order ? c->second : c->first;
    const tb__collision_shape *shape_a = tb__scene_body_collision_shape(scene, in_order ? a : b);
    const tb__collision_shape *shape_b = tb__scene_body_collision_shape(scene, in_order ? b : a);
    const size_t count_a = tb__collision_shape_piece_count(shape_a);
    const size_t count_b = tb__collision_shape_piece_count(shape_b);
    const double *pose_a = pairs->poses + TB__POSE_SIZE * first;
    const double *pose_b = pairs->poses + TB__POSE_SIZE * second;
    size_t written = 0;
    while (written < capacity) {
        const size_t i = pairs->piece_a, j = pairs->piece_b;
        const bool last_b = j + 1 == count_b, last = last_b && i + 1 == count_a;
        pairs->piece_a = last ? 0 : last_b ? i + 1 : i;
        pairs->piece_b = last_b ? 0 : j + 1;
        tb__pair_contact *o = &out[written];
        double world_a[TB__POSE_SIZE], world_b[TB__POSE_SIZE];
        const bool plain = count_a == 1 && count_b == 1;
        const tb__collision_shape *piece_a = tb__collision_shape_piece(shape_a, i, pose_a, world_a);
        const tb__collision_shape *piece_b = tb__collision_shape_piece(shape_b, j, pose_b, world_b);
        if (plain || pieces_near(piece_a, world_a, piece_b, world_b, pairs->margin)) {
            o->body_a = in_order ? a : b;
            o->body_b = in_order ? b : a;
            o->piece_a = i;
            o->piece_b = j;
            /* a box shape's one piece is itself at its pose: its frame of the pass (a compound's
             * pieces have poses of their own) */
            const bool box_a = shape_a->type == TB_SHAPE_BOX, box_b = shape_b->type == TB_SHAPE_BOX;
            const tb__box_frame *frame_a = box_a ? box_frame(pairs, first) : NULL;
            const tb__box_frame *frame_b = box_b ? box_frame(pairs, second) : NULL;
            written +=
                test_pieces(pairs, piece_a, world_a, frame_a, piece_b, world_b, frame_b, level, o);
        }
        if (last) {
            break;
        }
    }
    return written;
}

size_t tb__contact_pairs_next(tb__contact_pairs *pairs, const tb_scene *scene, const double *y,
                              tb__pair_contact *out, size_t capacity)
{
    (void)y; /* the poses were read from y by tb__contact_pairs_begin */
    size_t written = 0;
    while (written < capacity) {
        if (pairs->batch_next == pairs->batch_count) {
            pairs->batch_count = tb__pair_list_next(&pairs->list, pairs->batch, PAIR_BATCH);
            pairs->batch_next = 0;
            if (pairs->batch_count == 0) {
                break;
            }
        }
        const tb__index_pair *c = &pairs->batch[pairs->batch_next];
        written += test_pair(pairs, scene, c, &out[written], capacity - written);
        if (pairs->piece_a == 0 && pairs->piece_b == 0) {
            ++pairs->batch_next; /* every piece pair of c tested */
        }
    }
    return written;
}
