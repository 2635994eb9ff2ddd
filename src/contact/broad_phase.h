/* Private: the broad phase, sweep and prune in cells. Axis-aligned boxes are binned into a grid
 * of cells across the two axes of smaller spread of their centres (cells as wide as the widest
 * box along each, so a box meets boxes of its own cell and the eight around it only), sorted by
 * cell and then by lower bound along the axis of largest spread, and swept: each box is tested
 * against the boxes of its cell and of the neighbouring cells that start after it and before it
 * ends. One axis alone scans every box in a slab through the scene, which grows as sqrt(N) a
 * body on a floor (bench_contact_geometry); strips across one more axis still scan a column as
 * tall as the scene, N^(1/3) bodies in a box filled in three dimensions (bench_contact's
 * spheres); the cells keep the scan to a box's neighbourhood in both. A scene one box deep
 * across an axis has one cell across it (strips); one body as wide as the scene makes one cell:
 * plain sweep and prune. There are at most as many cells as boxes: a sparse scene gets cells
 * wider than its boxes.
 *
 * Sorting is a merge sort that skips merges of runs already in order, so a scene that moved
 * little since the last call sorts in about N steps and any scene in N log N; ties are broken
 * by index, so the order and the pairs depend on the boxes alone, never on earlier calls.
 *
 * Pairs come out in batches through a cursor that the broad phase keeps: a full batch is
 * never an error, the caller handles it and asks for the next. So nothing needs to grow inside
 * the derivative, and all memory is allocated once for a capacity of boxes.
 *
 * A sweep may be limited to the pairs with an active box (the boxes of moving bodies, where most
 * rest asleep): the cursor then visits only the active boxes and the inactive ones that meet an
 * active box after them along the axis (found by a scan back from each active box, no farther
 * than the widest box), so a sleeping pile costs a sort and no sweep; the pairs come out in the
 * full sweep's order with the others left out. */
#ifndef TUMBLE_BROAD_PHASE_H
#define TUMBLE_BROAD_PHASE_H

#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct tb__aabb {
    double min[3], max[3]; /* world, m */
} tb__aabb;

/* A box in the sweep's order, with its index: the scan reads these in a row. */
typedef struct tb__sorted_box {
    tb__aabb box;
    size_t index;
} tb__sorted_box;

typedef struct tb__index_pair {
    size_t first, second; /* indices into the boxes, first < second */
} tb__index_pair;

typedef struct tb__broad_phase {
    size_t capacity;        /* boxes allocated */
    size_t count;           /* boxes in use, set by tb__broad_phase_sort */
    tb__aabb *boxes;        /* capacity; the caller fills [0, count) before sorting */
    size_t *order;          /* capacity: box indices sorted by cell, then lower bound on axis */
    tb__sorted_box *sorted; /* capacity: boxes[order[p]] at p, copied by the sort, so the sweep
                               reads neighbours from one run of memory instead of through order */
    size_t *scratch;        /* capacity: the merge sort's buffer */
    size_t *cell;           /* capacity: each box's cell, u * cells[1] + v */
    size_t *cell_start;     /* capacity + 1: where each cell starts in order */
    size_t cells[2];        /* cells across bin_axes[0] (u) and bin_axes[1] (v); product <= count */
    int axis, bin_axes[2];  /* the sweep axis and the axes across the cells, 0..2 */
    /* The sweep's place: order[cursor] against order[next] (< end), in its own cell (phase 0)
     * or the neighbouring cell around[phase - 1] (phase 1..around_count: the cells around cell
     * hint_cell that are on the grid) and hint[n] where the boxes after the cursor's begin in
     * around[n]: the cursor moves along the axis in its cell, so each neighbour is walked once
     * per cell, not searched once per box. */
    size_t cursor, next, end;
    int phase;
    size_t hint_cell, around_count, around[8], hint[8];
    /* The limited sweep (tb__broad_phase_sort_active): active[i] for box i, 1 when active
     * (capacity; the caller fills [0, count)); the positions the cursor visits, ascending
     * (visit_count of them, visits[visit_next] the next), and a mark per position (capacity,
     * all 0 between sorts) while they are gathered. skipping: the cursor visits only those (all
     * positions when a bound is not finite: the scan back needs finite ones). */
    unsigned char *active, *marked;
    size_t *visits;
    size_t visit_count, visit_next;
    bool limited, skipping;
} tb__broad_phase;

/* Allocates room for capacity boxes (capacity 0 is allowed); on failure bp is left empty and
 * TB_STATUS_OUT_OF_MEMORY returned. */
tb_status tb__broad_phase_init(tb__broad_phase *bp, size_t capacity);
void tb__broad_phase_free(tb__broad_phase *bp);

/* Sorts boxes [0, count) (count <= capacity) and rewinds the cursor. */
void tb__broad_phase_sort(tb__broad_phase *bp, size_t count);

/* The same, for a sweep that gives only the pairs with at least one active box (active[i]
 * filled for the boxes [0, count)), in the order tb__broad_phase_sort's sweep gives them. */
void tb__broad_phase_sort_active(tb__broad_phase *bp, size_t count);

/* Writes up to capacity pairs of overlapping boxes (closed intervals on all three axes) after
 * the cursor and returns how many; 0 when the sweep is done. Every overlapping pair comes out
 * exactly once per sweep, in an order fixed by the boxes (boxes with a NaN bound excepted: they
 * meet on the axes where the bound is NaN, but only boxes of the cells they are binned beside). */
size_t tb__broad_phase_next(tb__broad_phase *bp, tb__index_pair *out, size_t capacity);

#endif
