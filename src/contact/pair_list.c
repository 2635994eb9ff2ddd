/* The candidate pairs kept between passes with a skin: a sweep of grown boxes once, then at each
 * pass a check that every box stayed inside its grown box and the sweep's test on the kept
 * pairs (Verlet lists, as molecular dynamics keeps neighbours; here in the canonical order, so
 * that a pass gives the same pairs in the same order as a build from scratch). */
#include "contact/pair_list.h"

#include "core/validate.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The skin at first, as a share of a box's largest side (adapt_skin changes it). RK4's step on
 * the example scenes moves a body a few thousandths of its size or less, so a few percent keep a
 * list for hundreds of passes, and grown boxes meet few more boxes than the boxes do (measured:
 * docs/performance.md, "Candidate pairs kept with a skin"). */
#define SKIN_SHARE 0.05

/* Candidates the list holds a box. With the skin bench_contact_work's jostled lattice of 5 cm
 * spheres makes 10.5 a box, its pile of boxes 8.8, and the events' look-ahead (a 5 cm margin) on
 * the spheres 42. */
#define PAIRS_PER_BOX 64

/* Pairs read from the sweep at a time while the list is built. */
#define SWEEP_BATCH 64

tb_status tb__pair_list_init(tb__pair_list *list, size_t box_capacity)
{
    memset(list, 0, sizeof *list);
    const size_t n = box_capacity > 0 ? box_capacity : 1;
    /* the kept pairs' indices are 32 bits: half the memory of the broad phase's */
    const size_t pairs =
        n <= UINT32_MAX && n <= (SIZE_MAX - 64) / PAIRS_PER_BOX ? PAIRS_PER_BOX * n + 64 : 0;
    if (pairs == 0 || tb__broad_phase_init(&list->broad, box_capacity) != TB_STATUS_OK) {
        tb__pair_list_free(list);
        return TB_STATUS_OUT_OF_MEMORY;
    }
    list->bounds = tb__malloc_array(n, sizeof *list->bounds);
    list->built_active = calloc(n, 1);
    list->pairs = tb__malloc_array(pairs, sizeof *list->pairs);
    list->scratch = tb__malloc_array(pairs, sizeof *list->scratch);
    list->counts = tb__malloc_array(n + 1, sizeof *list->counts);
    if (list->bounds == NULL || list->built_active == NULL || list->pairs == NULL ||
        list->scratch == NULL || list->counts == NULL) {
        tb__pair_list_free(list);
        return TB_STATUS_OUT_OF_MEMORY;
    }
    list->pair_capacity = pairs;
    list->share = SKIN_SHARE;
    return TB_STATUS_OK;
}

void tb__pair_list_free(tb__pair_list *list)
{
    tb__broad_phase_free(&list->broad);
    free(list->bounds);
    free(list->built_active);
    free(list->pairs);
    free(list->scratch);
    free(list->counts);
    memset(list, 0, sizeof *list);
}

void tb__pair_list_invalidate(tb__pair_list *list)
{
    list->valid = false;
}

/* box grown by share of its largest side on every side into out; the box itself for share 0,
 * and for an infinite skin (a side of infinite length), which would make an infinite bound NaN
 * (inf - inf) and the grown box's pairs depend on the sweep's order, not on the boxes. */
static void grow(const tb__aabb *box, double share, tb__aabb *out)
{
    double side = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double s = box->max[k] - box->min[k];
        side = s > side ? s : side;
    }
    const double skin = share > 0.0 && isfinite(share * side) ? share * side : 0.0;
    for (int k = 0; k < 3; ++k) {
        out->min[k] = box->min[k] - skin;
        out->max[k] = box->max[k] + skin;
    }
}

/* Sweeps the pass's boxes grown by share into the list; false when it cannot hold them all. */
static bool sweep_into_list(tb__pair_list *list, size_t count, bool limited, double share)
{
    tb__broad_phase *bp = &list->broad;
    for (size_t b = 0; b < count; ++b) {
        grow(&list->bounds[b], share, &bp->boxes[b]);
    }
    if (limited) {
        tb__broad_phase_sort_active(bp, count);
    } else {
        tb__broad_phase_sort(bp, count);
    }
    tb__index_pair batch[SWEEP_BATCH];
    size_t n = 0, got;
    while ((got = tb__broad_phase_next(bp, batch, SWEEP_BATCH)) > 0) {
        if (got > list->pair_capacity - n) {
            return false;
        }
        for (size_t k = 0; k < got; ++k, ++n) { /* indices below the box capacity: 32 bits */
            list->pairs[n].first = (uint32_t)batch[k].first;
            list->pairs[n].second = (uint32_t)batch[k].second;
        }
    }
    list->pair_count = n;
    return true;
}

/* Stable counting sort of pairs[0, n) by key (0: first, 1: second; below count) into to. */
static void count_sort(size_t *counts, size_t count, const tb__list_pair *from, tb__list_pair *to,
                       size_t n, int key)
{
    memset(counts, 0, (count + 1) * sizeof *counts);
    for (size_t k = 0; k < n; ++k) {
        ++counts[1 + (key == 0 ? from[k].first : from[k].second)];
    }
    for (size_t b = 0; b < count; ++b) {
        counts[b + 1] += counts[b];
    }
    for (size_t k = 0; k < n; ++k) {
        to[counts[key == 0 ? from[k].first : from[k].second]++] = from[k];
    }
}

/* The candidates in canonical order, by (first, second): by second, then stably by first, in
 * O(boxes + pairs). */
static void canonical_order(tb__pair_list *list, size_t count)
{
    count_sort(list->counts, count, list->pairs, list->scratch, list->pair_count, 1);
    count_sort(list->counts, count, list->scratch, list->pairs, list->pair_count, 0);
}

/* The next build's skin: halved when the grown boxes made more pairs than the list holds (down
 * to none), doubled back towards SKIN_SHARE when they filled under a quarter of it. Only how
 * often the list is built depends on it, never the pairs a pass gives. */
static void adapt_skin(tb__pair_list *list, bool overflowed)
{
    const double least = SKIN_SHARE / 64.0;
    if (overflowed) {
        list->share = list->share > least ? 0.5 * list->share : 0.0;
    } else if (list->pair_count < list->pair_capacity / 4 && list->share < SKIN_SHARE) {
        list->share = list->share > 0.0 ? fmin(2.0 * list->share, SKIN_SHARE) : least;
    }
}

/* Whether a bound of boxes [0, count) is NaN. */
static bool any_nan(const tb__aabb *boxes, size_t count)
{
    int nan = 0;
    for (size_t b = 0; b < count; ++b) {
        for (int k = 0; k < 3; ++k) {
            nan |= (boxes[b].min[k] != boxes[b].min[k]) | (boxes[b].max[k] != boxes[b].max[k]);
        }
    }
    return nan != 0;
}

/* Builds the list for the pass: the grown boxes' pairs; if too many, the boxes' own pairs; if
 * still too many, the pass streams the sweep instead. A box with a NaN bound meets the boxes the
 * sweep bins beside it (broad_phase.h), which grown boxes would change: such a pass takes the
 * boxes' own pairs, so that they depend on its boxes alone, not on the skin of the moment. */
static void build(tb__pair_list *list, size_t count, bool limited)
{
    ++list->builds;
    const bool skinned = list->share > 0.0 && !any_nan(list->bounds, count);
    list->valid = skinned && sweep_into_list(list, count, limited, list->share);
    const bool overflowed = skinned && !list->valid;
    list->valid = list->valid || sweep_into_list(list, count, limited, 0.0);
    adapt_skin(list, overflowed || !list->valid);
    if (!list->valid) {
        list->streaming = true; /* the sweep again from its start, its boxes the pass's */
        if (limited) {
            tb__broad_phase_sort_active(&list->broad, count);
        } else {
            tb__broad_phase_sort(&list->broad, count);
        }
        return;
    }
    canonical_order(list, count);
    memcpy(list->built_active, list->broad.active, count);
    list->built_count = count;
    list->built_limited = limited;
}

/* Whether the list still holds every pair of the pass: the same boxes, each inside its grown box
 * of the build (a NaN bound is not), and, if the build kept only the pairs with an active box,
 * a limited pass whose active boxes were active then (a box fallen asleep keeps the list). */
static bool list_holds(const tb__pair_list *list, size_t count, bool limited)
{
    if (!list->valid || count != list->built_count || (list->built_limited && !limited)) {
        return false;
    }
    int inside = 1;
    const unsigned char *active = list->broad.active;
    for (size_t b = 0; b < count; ++b) {
        const tb__aabb *now = &list->bounds[b], *grown = &list->broad.boxes[b];
        for (int k = 0; k < 3; ++k) { /* no branch per box: most stay inside */
            inside &= (now->min[k] >= grown->min[k]) & (now->max[k] <= grown->max[k]);
        }
        inside &= !list->built_limited | !active[b] | list->built_active[b];
    }
    return inside != 0;
}

void tb__pair_list_begin(tb__pair_list *list, size_t count, bool limited)
{
    ++list->passes;
    list->streaming = false;
    list->limited = limited;
    list->next = 0;
    if (!list_holds(list, count, limited)) {
        build(list, count, limited);
    }
}

/* The sweep's test: closed intervals on the three axes (a NaN bound meets). */
static int boxes_meet(const tb__aabb *a, const tb__aabb *b)
{
    return !(a->max[0] < b->min[0]) & !(b->max[0] < a->min[0]) & !(a->max[1] < b->min[1]) &
           !(b->max[1] < a->min[1]) & !(a->max[2] < b->min[2]) & !(b->max[2] < a->min[2]);
}

size_t tb__pair_list_next(tb__pair_list *list, tb__index_pair *out, size_t capacity)
{
    if (list->streaming) {
        return tb__broad_phase_next(&list->broad, out, capacity);
    }
    size_t written = 0, next = list->next;
    const tb__aabb *bounds = list->bounds;
    const unsigned char *active = list->broad.active;
    const int every = !list->limited; /* else only the pairs with an active box */
    while (written < capacity && next < list->pair_count) {
        const tb__list_pair *c = &list->pairs[next++];
        out[written].first = c->first; /* kept when they meet: no branch to miss */
        out[written].second = c->second;
        written += boxes_meet(&bounds[c->first], &bounds[c->second]) &
                   (every | active[c->first] | active[c->second]);
    }
    list->next = next;
    return written;
}
