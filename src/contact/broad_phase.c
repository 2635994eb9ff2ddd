/* Sweep and prune (Baraff's thesis, 1992; as MuJoCo and Bullet use it) in cells: bin the boxes
 * into a grid of cells across two axes, sort each cell's lower bounds along the third, and each
 * box meets only the boxes of its cell and the eight around it that start before it ends. */
#include "contact/broad_phase.h"

#include "core/validate.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* No cell: before the first sweep. */
#define NO_CELL ((size_t)-1)

tb_status tb__broad_phase_init(tb__broad_phase *bp, size_t capacity)
{
    memset(bp, 0, sizeof *bp);
    const size_t n = capacity > 0 ? capacity : 1;
    if (n == (size_t)-1) {
        return TB_STATUS_OUT_OF_MEMORY; /* n + 1 cell starts */
    }
    bp->boxes = tb__malloc_array(n, sizeof *bp->boxes);
    bp->order = tb__malloc_array(n, sizeof *bp->order);
    bp->sorted = tb__malloc_array(n, sizeof *bp->sorted);
    bp->scratch = tb__malloc_array(n, sizeof *bp->scratch);
    bp->cell = tb__malloc_array(n, sizeof *bp->cell);
    bp->cell_start = tb__malloc_array(n + 1, sizeof *bp->cell_start);
    bp->active = calloc(n, 1);
    bp->marked = calloc(n, 1);
    bp->visits = tb__malloc_array(n, sizeof *bp->visits);
    if (bp->boxes == NULL || bp->order == NULL || bp->sorted == NULL || bp->scratch == NULL ||
        bp->cell == NULL || bp->cell_start == NULL || bp->active == NULL || bp->marked == NULL ||
        bp->visits == NULL) {
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
    free(bp->cell);
    free(bp->cell_start);
    free(bp->active);
    free(bp->marked);
    free(bp->visits);
    memset(bp, 0, sizeof *bp);
}

/* Box i before box j along the axis: by lower bound, then index (a total order). */
static bool before_on_axis(const tb__broad_phase *bp, size_t i, size_t j)
{
    const double a = bp->boxes[i].min[bp->axis], b = bp->boxes[j].min[bp->axis];
    return a < b || (a == b && i < j);
}

/* Box i before box j in the sort: by cell, then along the axis. */
static bool before(const tb__broad_phase *bp, size_t i, size_t j)
{
    return bp->cell[i] != bp->cell[j] ? bp->cell[i] < bp->cell[j] : before_on_axis(bp, i, j);
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

/* The sweep axis, of largest variance of the box centres, and the two across the cells, the
 * second-largest first. */
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
    bp->bin_axes[0] = variance[a] >= variance[b] ? a : b;
    bp->bin_axes[1] = variance[a] >= variance[b] ? b : a;
}

/* Caps the cells across the two axes (wanted[0] by wanted[1], each >= 1, maybe infinite) at cap
 * in all: the axis that wants fewer than sqrt(cap) keeps them and the other gets the rest; if
 * neither does, sqrt(cap) each. */
static void limit_cells(double wanted[2], double cap)
{
    if (wanted[0] * wanted[1] <= cap) {
        return;
    }
    const double root = floor(sqrt(cap));
    if (wanted[0] <= root) {
        wanted[1] = floor(cap / wanted[0]);
    } else if (wanted[1] <= root) {
        wanted[0] = floor(cap / wanted[1]);
    } else {
        wanted[0] = wanted[1] = root;
    }
}

/* fmin and fmax where a is not NaN (a NaN b leaves a), inline: the loops below run over every
 * box at every derivative. A tie of 0 and -0 may keep the other zero than fmin would; the cells
 * are the same (a zero spread is one cell, and x - 0 = x - -0 for x other than a zero). */
static inline double smaller(double a, double b)
{
    return b < a ? b : a;
}
static inline double larger(double a, double b)
{
    return b > a ? b : a;
}

/* Cells across the two bin axes, at most count in all: as wide as the widest box along each (a
 * little more, so that rounding cannot put two overlapping boxes two cells apart: the error of
 * (min - low) / width is about 1e-16 times the cells across, far below the 1e-6 spare), wider
 * where there would be too many. Each box goes in the cell of its lower bounds; overlapping
 * boxes' lower bounds differ by at most the widest box, so their cells are neighbours. */
static void assign_cells(tb__broad_phase *bp, size_t count)
{
    double low[2], width[2], wanted[2], spread[2];
    for (int j = 0; j < 2; ++j) {
        const int k = bp->bin_axes[j];
        double high = -INFINITY, widest = 0.0;
        low[j] = INFINITY;
        for (size_t i = 0; i < count; ++i) {
            low[j] = smaller(low[j], bp->boxes[i].min[k]);
            high = larger(high, bp->boxes[i].min[k]);
            widest = larger(widest, bp->boxes[i].max[k] - bp->boxes[i].min[k]);
        }
        spread[j] = high - low[j];
        width[j] = widest * (1.0 + 1e-6);
        const double across = spread[j] / width[j]; /* NaN for 0 / 0, inf for x / 0 */
        wanted[j] = spread[j] > 0.0 && across == across ? floor(across) + 1.0 : 1.0;
    }
    limit_cells(wanted, (double)(count > 0 ? count : 1));
    double per_width[2]; /* multiplied, not divided, per box: its rounding is as small */
    for (int j = 0; j < 2; ++j) {
        width[j] = fmax(width[j], spread[j] / wanted[j] * (1.0 + 1e-6));
        per_width[j] = 1.0 / width[j];
        const bool several = wanted[j] > 1.0 && isfinite(width[j]) && isfinite(per_width[j]);
        bp->cells[j] = several ? (size_t)wanted[j] : 1;
        per_width[j] = several ? per_width[j] : 0.0; /* one cell: q is 0 (or NaN), the cell 0 */
    }
    const bool one_cell = bp->cells[0] * bp->cells[1] == 1; /* a table across the scene */
    for (size_t i = 0; i < count && one_cell; ++i) {
        bp->cell[i] = 0;
    }
    for (size_t i = 0; i < count && !one_cell; ++i) {
        size_t at[2];
        for (int j = 0; j < 2; ++j) {
            const double q = floor((bp->boxes[i].min[bp->bin_axes[j]] - low[j]) * per_width[j]);
            const double last = (double)(bp->cells[j] - 1);
            at[j] = !(q > 0.0) ? 0 : q < last ? (size_t)q : (size_t)last;
        }
        bp->cell[i] = at[0] * bp->cells[1] + at[1];
    }
}

void tb__broad_phase_sort(tb__broad_phase *bp, size_t count)
{
    bp->count = count;
    choose_axes(bp, count);
    assign_cells(bp, count);
    /* The order of the last sort is kept when it still names the same boxes: nearly sorted. */
    bool same = true;
    for (size_t i = 0; i < count && same; ++i) {
        same = bp->order[i] < count;
    }
    for (size_t i = 0; !same && i < (bp->capacity > 0 ? bp->capacity : 1); ++i) {
        bp->order[i] = i; /* fewer boxes than last time: start again from a permutation */
    }
    bool sorted = true; /* a scene at rest, or asleep but for a few bodies: one pass */
    for (size_t i = 1; i < count && sorted; ++i) {
        sorted = !before(bp, bp->order[i], bp->order[i - 1]);
    }
    if (!sorted) {
        merge_sort(bp, 0, count);
    }
    const size_t cell_count = bp->cells[0] * bp->cells[1];
    for (size_t c = 0, p = 0; c <= cell_count; ++c) {
        while (p < count && bp->cell[bp->order[p]] < c) {
            ++p;
        }
        bp->cell_start[c] = p;
    }
    for (size_t p = 0; p < count; ++p) {
        bp->sorted[p].box = bp->boxes[bp->order[p]];
        bp->sorted[p].index = bp->order[p];
    }
    bp->cursor = 0;
    bp->phase = -1; /* the cursor's box has not started */
    bp->hint_cell = NO_CELL;
    bp->limited = bp->skipping = false;
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

/* The eight neighbours of a cell, as steps in u and v, in the order the sweep visits them. */
static const int neighbour_du[8] = {-1, -1, -1, 0, 0, 1, 1, 1};
static const int neighbour_dv[8] = {-1, 0, 1, -1, 1, -1, 0, 1};

/* The cells around cell c that are on the grid, in the neighbours' order, into around; returns
 * how many. */
static size_t neighbours(const tb__broad_phase *bp, size_t c, size_t around[8])
{
    const size_t u = c / bp->cells[1], v = c % bp->cells[1];
    size_t count = 0;
    for (int n = 0; n < 8; ++n) {
        const int du = neighbour_du[n], dv = neighbour_dv[n];
        if ((du < 0 && u == 0) || (du > 0 && u + 1 == bp->cells[0]) || (dv < 0 && v == 0) ||
            (dv > 0 && v + 1 == bp->cells[1])) {
            continue; /* off the grid */
        }
        around[count++] = (u + (size_t)(du + 1) - 1) * bp->cells[1] + v + (size_t)(dv + 1) - 1;
    }
    return count;
}

/* The cells around cell c into bp->around, with each one's hint at its start. */
static void enter_cell(tb__broad_phase *bp, size_t c)
{
    bp->around_count = neighbours(bp, c, bp->around);
    for (size_t n = 0; n < bp->around_count; ++n) {
        bp->hint[n] = bp->cell_start[bp->around[n]];
    }
    bp->hint_cell = c;
}

/* Where in cell t (neighbour n) the boxes after box i along the axis begin: walked on from where
 * the cell's previous box stopped. A pair of boxes in neighbouring cells is found from the one
 * that comes first along the axis. */
static size_t first_after(tb__broad_phase *bp, int n, size_t t, size_t i)
{
    const double a = bp->boxes[i].min[bp->axis];
    size_t p = bp->hint[n];
    const size_t end = bp->cell_start[t + 1];
    while (p < end) {
        const tb__sorted_box *m = &bp->sorted[p];
        const double b = m->box.min[bp->axis]; /* stop at the first with before_on_axis(i, m) */
        if (a < b || (a == b && i < m->index)) {
            break;
        }
        ++p;
    }
    bp->hint[n] = p;
    return p;
}

/* Moves the cursor's box to its next phase: its own cell after it, then each neighbouring cell
 * with boxes after it; past the last, to the next box. */
static void next_phase(tb__broad_phase *bp)
{
    const size_t i = bp->order[bp->cursor], c = bp->cell[i];
    if (c != bp->hint_cell) { /* the cursor entered a cell */
        enter_cell(bp, c);
    }
    for (++bp->phase; bp->phase <= (int)bp->around_count; ++bp->phase) {
        if (bp->phase == 0) {
            bp->next = bp->cursor + 1;
            bp->end = bp->cell_start[c + 1];
            return;
        }
        const size_t t = bp->around[bp->phase - 1];
        bp->next = first_after(bp, bp->phase - 1, t, i);
        bp->end = bp->cell_start[t + 1];
        if (bp->next < bp->end) {
            return;
        }
    }
    bp->cursor = !bp->skipping                      ? bp->cursor + 1
                 : bp->visit_next < bp->visit_count ? bp->visits[bp->visit_next++]
                                                    : bp->count;
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
        /* every pair of an active box (or every pair, unlimited); active is allocated zeroed */
        const int every = !bp->limited || bp->active[a->index];
        /* the boxes of this phase that start before a ends, in order */
        size_t next = bp->next;
        while (written < capacity && next < bp->end && !(bp->sorted[next].box.min[axis] > reach)) {
            const tb__sorted_box *b = &bp->sorted[next++];
            const size_t i = a->index, j = b->index;
            out[written].first = i < j ? i : j; /* kept when they overlap: no branch to miss */
            out[written].second = i < j ? j : i;
            written += overlap_others(&a->box, &b->box, axis) & (every | bp->active[j]);
        }
        bp->next = next;
        if (written < capacity) {
            next_phase(bp); /* this phase is done */
        }
    }
    return written;
}

/* The first position in cell t whose box comes after box j along the axis (before_on_axis), by
 * bisection. */
static size_t first_after_box(const tb__broad_phase *bp, size_t t, const tb__sorted_box *j)
{
    const double a = j->box.min[bp->axis];
    size_t low = bp->cell_start[t], high = bp->cell_start[t + 1];
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        const tb__sorted_box *m = &bp->sorted[middle];
        const double b = m->box.min[bp->axis];
        if (a < b || (a == b && j->index < m->index)) {
            high = middle;
        } else {
            low = middle + 1;
        }
    }
    return low;
}

/* Adds to the visits the inactive boxes from which the sweep finds active box pj: those before
 * it along the axis in its cell or a neighbouring one that reach it. A box reaching it starts
 * at most the widest box's length before it (in rounded differences too: rounding is
 * monotone), so the scan back stops there. */
static void reach_back(tb__broad_phase *bp, size_t pj, double widest, size_t *n)
{
    const int axis = bp->axis;
    const tb__sorted_box *j = &bp->sorted[pj];
    const size_t c = bp->cell[j->index];
    size_t cells[9];
    cells[0] = c;
    const size_t cell_count = 1 + neighbours(bp, c, cells + 1);
    for (size_t k = 0; k < cell_count; ++k) {
        const size_t t = cells[k], first = bp->cell_start[t];
        for (size_t p = t == c ? pj : first_after_box(bp, t, j); p > first;) {
            const tb__sorted_box *m = &bp->sorted[--p];
            if (j->box.min[axis] - m->box.min[axis] > widest) {
                break;
            }
            if (!bp->active[m->index] && !bp->marked[p] && !(j->box.min[axis] > m->box.max[axis]) &&
                overlap_others(&m->box, &j->box, axis)) {
                bp->marked[p] = 1;
                bp->visits[(*n)++] = p;
            }
        }
    }
}

/* Sorts positions[0, n) ascending, bottom-up merges through buffer (n entries): qsort would
 * allocate for a long array (glibc's merge sort), and nothing is allocated per derivative. */
static void sort_positions(size_t *positions, size_t n, size_t *buffer)
{
    size_t *from = positions, *to = buffer;
    for (size_t width = 1; width < n; width *= 2) {
        for (size_t low = 0; low < n; low += 2 * width) {
            const size_t middle = low + width < n ? low + width : n;
            const size_t high = middle + width < n ? middle + width : n;
            size_t i = low, j = middle, w = low;
            while (i < middle && j < high) {
                to[w++] = from[j] < from[i] ? from[j++] : from[i++];
            }
            while (i < middle) {
                to[w++] = from[i++];
            }
            while (j < high) {
                to[w++] = from[j++];
            }
        }
        size_t *swap = from;
        from = to;
        to = swap;
    }
    if (from != positions) {
        memcpy(positions, from, n * sizeof *positions);
    }
}

void tb__broad_phase_sort_active(tb__broad_phase *bp, size_t count)
{
    tb__broad_phase_sort(bp, count);
    bp->limited = true;
    const int axis = bp->axis;
    double widest = 0.0, bounds = 0.0;
    size_t n = 0;
    for (size_t p = 0; p < count; ++p) {
        const tb__aabb *box = &bp->sorted[p].box;
        widest = fmax(widest, box->max[axis] - box->min[axis]);
        bounds += box->min[0] + box->min[1] + box->min[2] + box->max[0] + box->max[1] + box->max[2];
        if (bp->active[bp->sorted[p].index]) {
            bp->visits[n++] = p;
        }
    }
    /* the sum is finite only if every bound is */
    bp->skipping = isfinite(bounds) && isfinite(widest);
    if (!bp->skipping) {
        return; /* every position, the pairs without an active box left out */
    }
    for (size_t k = 0, active = n; k < active; ++k) {
        reach_back(bp, bp->visits[k], widest, &n);
    }
    for (size_t k = 0; k < n; ++k) {
        bp->marked[bp->visits[k]] = 0;
    }
    sort_positions(bp->visits, n, bp->scratch); /* the sort is done with its scratch */
    bp->visit_count = n;
    bp->visit_next = n > 0 ? 1 : 0;
    bp->cursor = n > 0 ? bp->visits[0] : count;
}
