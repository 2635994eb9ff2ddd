/* Sweep and prune (Baraff's thesis, 1992; as MuJoCo and Bullet use it): sort the boxes'
 * lower bounds along one axis, then each box meets only the boxes that start before it ends.
 * The axis is the one over which the box centres spread most, so a pile on a floor is swept
 * across the floor, not up through it. */
#include "contact/broad_phase.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

tb_status tb__broad_phase_init(tb__broad_phase *bp, size_t capacity)
{
    memset(bp, 0, sizeof *bp);
    const size_t n = capacity > 0 ? capacity : 1;
    if (n > ((size_t)-1) / sizeof(tb__aabb)) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    bp->boxes = malloc(n * sizeof *bp->boxes);
    bp->order = malloc(n * sizeof *bp->order);
    bp->scratch = malloc(n * sizeof *bp->scratch);
    if (bp->boxes == NULL || bp->order == NULL || bp->scratch == NULL) {
        tb__broad_phase_free(bp);
        return TB_STATUS_OUT_OF_MEMORY;
    }
    bp->capacity = capacity;
    for (size_t i = 0; i < n; ++i) {
        bp->order[i] = i;
    }
    return TB_STATUS_OK;
}

void tb__broad_phase_free(tb__broad_phase *bp)
{
    free(bp->boxes);
    free(bp->order);
    free(bp->scratch);
    memset(bp, 0, sizeof *bp);
}

/* Box i before box j: by lower bound on the axis, then by index (a total order). */
static bool before(const tb__broad_phase *bp, size_t i, size_t j)
{
    const double a = bp->boxes[i].min[bp->axis], b = bp->boxes[j].min[bp->axis];
    return a < b || (a == b && i < j);
}

/* Sorts order[low, high) with scratch; a run whose halves are already in order is not merged,
 * so sorted input costs one comparison a level. */
static void merge_sort(tb__broad_phase *bp, size_t low, size_t high)
{
    if (high - low < 2) {
        return;
    }
    const size_t middle = low + (high - low) / 2;
    merge_sort(bp, low, middle);
    merge_sort(bp, middle, high);
    size_t *order = bp->order;
    if (!before(bp, order[middle], order[middle - 1])) {
        return;
    }
    size_t i = low, j = middle, w = low;
    while (i < middle && j < high) {
        bp->scratch[w++] = before(bp, order[j], order[i]) ? order[j++] : order[i++];
    }
    while (i < middle) {
        bp->scratch[w++] = order[i++];
    }
    while (j < high) {
        bp->scratch[w++] = order[j++];
    }
    memcpy(order + low, bp->scratch + low, (high - low) * sizeof *order);
}

/* The axis of largest variance of the box centres. */
static int sweep_axis(const tb__broad_phase *bp, size_t count)
{
    double sum[3] = {0}, sum2[3] = {0};
    for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
            const double c = 0.5 * (bp->boxes[i].min[k] + bp->boxes[i].max[k]);
            sum[k] += c;
            sum2[k] += c * c;
        }
    }
    int axis = 0;
    double best = -1.0;
    for (int k = 0; k < 3; ++k) {
        const double variance = sum2[k] - sum[k] * sum[k] / (double)(count > 0 ? count : 1);
        if (variance > best) {
            best = variance;
            axis = k;
        }
    }
    return axis;
}

void tb__broad_phase_sort(tb__broad_phase *bp, size_t count)
{
    bp->count = count;
    bp->axis = sweep_axis(bp, count);
    /* The order of the last sort is kept when it still names the same boxes: nearly sorted. */
    bool same = true;
    for (size_t i = 0; i < count && same; ++i) {
        same = bp->order[i] < count;
    }
    for (size_t i = 0; !same && i < (bp->capacity > 0 ? bp->capacity : 1); ++i) {
        bp->order[i] = i; /* fewer boxes than last time: start again from a permutation */
    }
    merge_sort(bp, 0, count);
    bp->cursor = 0;
    bp->next = 1;
}

static bool overlap_others(const tb__aabb *a, const tb__aabb *b, int axis)
{
    for (int k = 0; k < 3; ++k) {
        if (k != axis && (a->max[k] < b->min[k] || b->max[k] < a->min[k])) {
            return false;
        }
    }
    return true;
}

size_t tb__broad_phase_next(tb__broad_phase *bp, tb__index_pair *out, size_t capacity)
{
    size_t written = 0;
    const int axis = bp->axis;
    while (bp->cursor < bp->count && written < capacity) {
        const size_t i = bp->order[bp->cursor];
        const tb__aabb *a = &bp->boxes[i];
        if (bp->next >= bp->count || bp->boxes[bp->order[bp->next]].min[axis] > a->max[axis]) {
            ++bp->cursor;
            bp->next = bp->cursor + 1;
            continue;
        }
        const size_t j = bp->order[bp->next++];
        if (overlap_others(a, &bp->boxes[j], axis)) {
            out[written].first = i < j ? i : j;
            out[written++].second = i < j ? j : i;
        }
    }
    return written;
}
