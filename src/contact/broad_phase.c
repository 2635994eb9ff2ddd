/* Sweep and prune (Baraff's thesis, 1992; as MuJoCo and Bullet use it) in strips: bin the
 * boxes into strips across one axis, sort each strip's lower bounds along another, and each box
 * meets only the boxes of its strip and the two beside it that start before it ends. */
#include "contact/broad_phase.h"

#include "core/validate.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

tb_status tb__broad_phase_init(tb__broad_phase *bp, size_t capacity)
{
    memset(bp, 0, sizeof *bp);
    const size_t n = capacity > 0 ? capacity : 1;
    if (n == (size_t)-1) {
        return TB_STATUS_OUT_OF_MEMORY; /* n + 1 strip starts */
    }
    bp->boxes = tb__malloc_array(n, sizeof *bp->boxes);
    bp->order = tb__malloc_array(n, sizeof *bp->order);
    bp->sorted = tb__malloc_array(n, sizeof *bp->sorted);
    bp->scratch = tb__malloc_array(n, sizeof *bp->scratch);
    bp->strip = tb__malloc_array(n, sizeof *bp->strip);
    bp->strip_start = tb__malloc_array(n + 1, sizeof *bp->strip_start);
    if (bp->boxes == NULL || bp->order == NULL || bp->sorted == NULL || bp->scratch == NULL ||
        bp->strip == NULL || bp->strip_start == NULL) {
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
    free(bp->sorted);
    free(bp->scratch);
    free(bp->strip);
    free(bp->strip_start);
    memset(bp, 0, sizeof *bp);
}

/* Box i before box j along the axis: by lower bound, then index (a total order). */
static bool before_on_axis(const tb__broad_phase *bp, size_t i, size_t j)
{
    const double a = bp->boxes[i].min[bp->axis], b = bp->boxes[j].min[bp->axis];
    return a < b || (a == b && i < j);
}

/* Box i before box j in the sort: by strip, then along the axis. */
static bool before(const tb__broad_phase *bp, size_t i, size_t j)
{
    return bp->strip[i] != bp->strip[j] ? bp->strip[i] < bp->strip[j] : before_on_axis(bp, i, j);
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

/* The axes of largest and second-largest variance of the box centres. */
static void choose_axes(tb__broad_phase *bp, size_t count)
{
    double sum[3] = {0}, sum2[3] = {0}, variance[3];
    for (size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
            const double c = 0.5 * (bp->boxes[i].min[k] + bp->boxes[i].max[k]);
            sum[k] += c;
            sum2[k] += c * c;
        }
    }
    for (int k = 0; k < 3; ++k) {
        variance[k] = sum2[k] - sum[k] * sum[k] / (double)(count > 0 ? count : 1);
        variance[k] = variance[k] == variance[k] ? variance[k] : 0.0; /* NaN: last */
    }
    const int first = variance[0] >= variance[1] && variance[0] >= variance[2] ? 0
                      : variance[1] >= variance[2]                             ? 1
                                                                               : 2;
    const int a = (first + 1) % 3, b = (first + 2) % 3;
    bp->axis = first;
    bp->strip_axis = variance[a] >= variance[b] ? a : b;
}

/* Strips across strip_axis as wide as the widest box (a little more, for rounding), at most
 * one per box; each box in the strip of its lower bound. */
static void assign_strips(tb__broad_phase *bp, size_t count)
{
    const int k = bp->strip_axis;
    double low = INFINITY, high = -INFINITY, widest = 0.0;
    for (size_t i = 0; i < count; ++i) {
        low = fmin(low, bp->boxes[i].min[k]);
        high = fmax(high, bp->boxes[i].min[k]);
        widest = fmax(widest, bp->boxes[i].max[k] - bp->boxes[i].min[k]);
    }
    const double width = widest * (1.0 + 1e-6);
    const double strips = width > 0.0 ? floor((high - low) / width) + 1.0 : 1.0;
    bp->strip_count = strips >= 1.0 && strips <= (double)count ? (size_t)strips : 1;
    for (size_t i = 0; i < count; ++i) {
        const double s = bp->strip_count > 1 ? floor((bp->boxes[i].min[k] - low) / width) : 0.0;
        bp->strip[i] = s >= 0.0 && s < (double)bp->strip_count ? (size_t)s
                       : s >= (double)bp->strip_count          ? bp->strip_count - 1
                                                               : 0;
    }
}

void tb__broad_phase_sort(tb__broad_phase *bp, size_t count)
{
    bp->count = count;
    choose_axes(bp, count);
    assign_strips(bp, count);
    /* The order of the last sort is kept when it still names the same boxes: nearly sorted. */
    bool same = true;
    for (size_t i = 0; i < count && same; ++i) {
        same = bp->order[i] < count;
    }
    for (size_t i = 0; !same && i < (bp->capacity > 0 ? bp->capacity : 1); ++i) {
        bp->order[i] = i; /* fewer boxes than last time: start again from a permutation */
    }
    merge_sort(bp, 0, count);
    for (size_t s = 0, p = 0; s <= bp->strip_count; ++s) {
        while (p < count && bp->strip[bp->order[p]] < s) {
            ++p;
        }
        bp->strip_start[s] = p;
    }
    for (size_t p = 0; p < count; ++p) {
        bp->sorted[p].box = bp->boxes[bp->order[p]];
        bp->sorted[p].index = bp->order[p];
    }
    bp->cursor = 0;
    bp->phase = -1; /* the cursor's box has not started */
}

/* Whether the boxes meet on the two axes other than axis (a NaN bound meets), without branches:
 * about a third of a lattice's neighbours along the sweep meet, too few and too many to
 * predict. */
static int overlap_others(const tb__aabb *a, const tb__aabb *b, int axis)
{
    const int k1 = axis == 0 ? 1 : 0, k2 = axis == 2 ? 1 : 2;
    return !(a->max[k1] < b->min[k1]) & !(b->max[k1] < a->min[k1]) & !(a->max[k2] < b->min[k2]) &
           !(b->max[k2] < a->min[k2]);
}

/* Where in strip s the boxes after box i along the axis begin: bisection. A pair of boxes in
 * neighbouring strips is found from the one that comes first along the axis. */
static size_t first_after(const tb__broad_phase *bp, size_t s, size_t i)
{
    const double a = bp->boxes[i].min[bp->axis];
    size_t low = bp->strip_start[s], high = bp->strip_start[s + 1];
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        const tb__sorted_box *m = &bp->sorted[middle];
        const double b = m->box.min[bp->axis]; /* before_on_axis(i, m) */
        if (a < b || (a == b && i < m->index)) {
            high = middle;
        } else {
            low = middle + 1;
        }
    }
    return low;
}

/* Moves the cursor's box to its next phase: its own strip after it, the next strip, the
 * previous one; past the last, to the next box. */
static void next_phase(tb__broad_phase *bp)
{
    const size_t i = bp->order[bp->cursor], s = bp->strip[i];
    for (++bp->phase; bp->phase <= 2; ++bp->phase) {
        if (bp->phase == 0) {
            bp->next = bp->cursor + 1;
            bp->end = bp->strip_start[s + 1];
            return;
        }
        const bool up = bp->phase == 1;
        if (up ? s + 1 < bp->strip_count : s > 0) {
            const size_t t = up ? s + 1 : s - 1;
            bp->next = first_after(bp, t, i);
            bp->end = bp->strip_start[t + 1];
            return;
        }
    }
    ++bp->cursor;
    bp->phase = -1;
}

size_t tb__broad_phase_next(tb__broad_phase *bp, tb__index_pair *out, size_t capacity)
{
    size_t written = 0;
    const int axis = bp->axis;
    while (bp->cursor < bp->count && written < capacity) {
        if (bp->phase < 0) {
            next_phase(bp);
            continue;
        }
        const tb__sorted_box *a = &bp->sorted[bp->cursor];
        const double reach = a->box.max[axis];
        /* the boxes of this phase that start before a ends, in order */
        size_t next = bp->next;
        while (written < capacity && next < bp->end && !(bp->sorted[next].box.min[axis] > reach)) {
            const tb__sorted_box *b = &bp->sorted[next++];
            const size_t i = a->index, j = b->index;
            out[written].first = i < j ? i : j; /* kept when they overlap: no branch to miss */
            out[written].second = i < j ? j : i;
            written += overlap_others(&a->box, &b->box, axis);
        }
        bp->next = next;
        if (written < capacity) {
            next_phase(bp); /* this phase is done */
        }
    }
    return written;
}
