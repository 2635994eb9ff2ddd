/* The contact effect's hook: broad phase over a set of bodies' shapes at y, then the narrow
 * phase on each candidate pair, handed back in batches. */
#include "contact/contact_pairs.h"

#include "core/detail.h"
#include "core/validate.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Candidate pairs fetched from the broad phase at a time. */
#define PAIR_BATCH 64

struct tb__contact_pairs {
    size_t count;  /* bodies in the set */
    size_t *ids;   /* count body ids */
    size_t *local; /* count: the set's index of each box in use (bodies with shapes) */
    double *poses; /* TB__POSE_SIZE * count, at the pass's y */
    double margin;
    tb__broad_phase broad;
    tb__index_pair batch[PAIR_BATCH];
    size_t batch_count, batch_next; /* fetched candidates and the next to test */
    bool skip_asleep;               /* pairs of two asleep bodies are not tested */
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
    }
    if (p == NULL || p->ids == NULL || p->local == NULL || p->poses == NULL ||
        tb__broad_phase_init(&p->broad, count) != TB_STATUS_OK) {
        tb__contact_pairs_destroy(p);
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "contact pairs for %zu bodies",
                              count);
    }
    for (size_t k = 0; k < count; ++k) {
        p->ids[k] = bodies != NULL ? bodies[k] : k;
    }
    p->count = count;
    p->margin = margin;
    *out = p;
    return TB_STATUS_OK;
}

void tb__contact_pairs_destroy(tb__contact_pairs *pairs)
{
    if (pairs != NULL) {
        tb__broad_phase_free(&pairs->broad);
        free(pairs->ids);
        free(pairs->local);
        free(pairs->poses);
        free(pairs);
    }
}

void tb__contact_pairs_skip_asleep(tb__contact_pairs *pairs, bool skip)
{
    pairs->skip_asleep = skip;
}

void tb__contact_pairs_begin(tb__contact_pairs *pairs, const tb_scene *scene, const double *y)
{
    size_t boxes = 0;
    /* every body asleep: no pair to find (the broad phase would list only asleep ones) */
    const bool all_asleep = pairs->skip_asleep && scene->sleep != NULL &&
                            scene->sleep->asleep_count == scene->slot_count;
    for (size_t k = 0; k < pairs->count && !all_asleep; ++k) {
        const size_t id = pairs->ids[k];
        const tb__collision_shape *shape = tb__scene_body_collision_shape(scene, id);
        if (shape == NULL) {
            continue;
        }
        double *pose = pairs->poses + TB__POSE_SIZE * boxes;
        tb__shape_pose(scene, y, id, pose);
        tb__aabb *box = &pairs->broad.boxes[boxes];
        tb__collision_shape_bounds(shape, pose, box->min, box->max);
        for (int i = 0; i < 3; ++i) { /* each box grows by half the margin: pairs within it meet */
            box->min[i] -= 0.5 * pairs->margin;
            box->max[i] += 0.5 * pairs->margin;
        }
        pairs->local[boxes++] = k;
    }
    tb__broad_phase_sort(&pairs->broad, boxes);
    pairs->batch_count = 0;
    pairs->batch_next = 0;
}

/* Runs the narrow phase on box pair c; true when they touch (out filled). */
static bool test_pair(const tb__contact_pairs *pairs, const tb_scene *scene,
                      const tb__index_pair *c, tb__pair_contact *out)
{
    const size_t a = pairs->ids[pairs->local[c->first]];
    const size_t b = pairs->ids[pairs->local[c->second]];
    if (tb__body_fixed(scene, a) && tb__body_fixed(scene, b)) {
        return false; /* neither can move: no force between them can act */
    }
    if (pairs->skip_asleep && tb__pair_resting(scene, a, b)) {
        return false; /* a sleeping island: no narrow phase inside it */
    }
    const bool in_order = a < b;
    const size_t first = in_order ? c->first : c->second, second = in_order ? c->second : c->first;
    out->body_a = in_order ? a : b;
    out->body_b = in_order ? b : a;
    return tb__collide(tb__scene_body_collision_shape(scene, out->body_a),
                       pairs->poses + TB__POSE_SIZE * first,
                       tb__scene_body_collision_shape(scene, out->body_b),
                       pairs->poses + TB__POSE_SIZE * second, pairs->margin, &out->manifold) > 0;
}

size_t tb__contact_pairs_next(tb__contact_pairs *pairs, const tb_scene *scene, const double *y,
                              tb__pair_contact *out, size_t capacity)
{
    (void)y; /* the poses were read from y by tb__contact_pairs_begin */
    size_t written = 0;
    while (written < capacity) {
        if (pairs->batch_next == pairs->batch_count) {
            pairs->batch_count = tb__broad_phase_next(&pairs->broad, pairs->batch, PAIR_BATCH);
            pairs->batch_next = 0;
            if (pairs->batch_count == 0) {
                break;
            }
        }
        const tb__index_pair *c = &pairs->batch[pairs->batch_next++];
        written += test_pair(pairs, scene, c, &out[written]);
    }
    return written;
}
