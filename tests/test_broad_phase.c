/* The broad phase (src/contact/broad_phase.c) against a check of all N (N - 1) / 2 pairs of
 * boxes: exactly the same set of overlapping pairs (closed intervals on the three axes), each
 * once, on random scenes of every kind the binning has to survive (a box filled in three
 * dimensions, sizes over seven decades, huge and infinite boxes, zero-size and coincident ones,
 * clusters 1e15 m apart, a sparse cloud with more cells wanted than boxes, a floor, a column), in
 * batches of any size; and the pairs in an order fixed by the boxes alone; a sweep limited to
 * the pairs with an active box gives the full sweep's, in its order. No tolerance: the sets
 * are compared exactly. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geometry.h"
#include "span.h"
#include "contact/broad_phase.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_BOXES = 1000 };

static bool boxes_overlap(const tb__aabb *a, const tb__aabb *b)
{
    for (int k = 0; k < 3; ++k) {
        if (a->max[k] < b->min[k] || b->max[k] < a->min[k]) {
            return false;
        }
    }
    return true;
}

static void set_box(tb__aabb *b, const double centre[3], const double half[3])
{
    for (int k = 0; k < 3; ++k) {
        b->min[k] = centre[k] - half[k];
        b->max[k] = centre[k] + half[k];
    }
}

/* Box i of count in a scene of kind `kind` (0..7; fill mixes them for 8); b[-1] is box i - 1. */
static void random_box(uint64_t *rng, int kind, size_t i, size_t count, tb__aabb *b)
{
    double c[3], h[3];
    const double side = 0.1 * cbrt((double)count); /* kind 0: packed about 0.1 m apart */
    for (int k = 0; k < 3; ++k) {
        switch (kind) {
        case 0: /* a box filled in three dimensions, like bench_contact's spheres */
            c[k] = test_uniform(rng, 0.0, side);
            h[k] = 0.05 + test_uniform(rng, 0.0, 0.01);
            break;
        case 1: /* sizes over seven decades, each axis its own */
            c[k] = test_uniform(rng, -10.0, 10.0);
            h[k] = pow(10.0, test_uniform(rng, -6.0, 1.0));
            break;
        case 2: /* small boxes and a few huge ones */
            c[k] = test_uniform(rng, -1.0, 1.0);
            h[k] = i % 50 == 7 ? 1e6 : i % 50 == 23 ? 1e300 : 1e-2;
            break;
        case 3: /* zero-size points and plates on a coarse grid: many coincide or touch exactly */
            c[k] = floor(test_uniform(rng, 0.0, 5.0));
            h[k] = i % 3 == 0 ? 0.0 : i % 3 == 1 && k == 2 ? 0.0 : 0.5;
            break;
        case 4: /* clusters far apart */
            c[k] = (i % 4 == 0   ? 0.0
                    : i % 4 == 1 ? 1e9
                    : i % 4 == 2 ? -1e12
                                 : 3e15) +
                   test_uniform(rng, -1.0, 1.0);
            h[k] = 0.3;
            break;
        case 5: /* tiny boxes in a huge space: more cells wanted than boxes; every other one a
                   near copy of the one before, so that some meet */
            c[k] = i % 2 == 1 ? 0.5 * (b[-1].min[k] + b[-1].max[k]) + 1e-4
                              : test_uniform(rng, -1e6, 1e6);
            h[k] = 1e-4;
            break;
        case 6: /* a floor: one layer */
            c[k] = test_uniform(rng, -10.0, 10.0) * (k == 2 ? 0.01 : 1.0);
            h[k] = test_uniform(rng, 0.1, 0.5);
            break;
        default: /* a column */
            c[k] = k == 2 ? test_uniform(rng, 0.0, 50.0) : test_uniform(rng, -0.2, 0.2);
            h[k] = test_uniform(rng, 0.05, 0.3);
            break;
        }
    }
    set_box(b, c, h);
    if (kind == 2 && i == 11) { /* a box as large as doubles go, and one infinite along x */
        b->min[0] = b->min[1] = b->min[2] = -DBL_MAX;
        b->max[0] = b->max[1] = b->max[2] = DBL_MAX;
    } else if (kind == 2 && i == 31) {
        b->min[0] = -INFINITY;
        b->max[0] = INFINITY;
    }
}

static void fill(uint64_t *rng, int kind, size_t count, tb__aabb *boxes)
{
    for (size_t i = 0; i < count; ++i) {
        /* kind 8: each box of a random kind (a kind-5 copy copies whatever came before) */
        const int k = kind < 8 ? kind : (int)test_uniform(rng, 0.0, 8.0);
        random_box(rng, k, i, count, &boxes[i]);
    }
}

/* Sweeps in batches of `batch`, checking each pair's indices and that none comes twice (seen:
 * count * count), and returns a hash of the pairs in the order they came (FNV-1a). */
static uint64_t sweep(tb__broad_phase *bp, size_t count, size_t batch, unsigned char *seen,
                      size_t *found)
{
    tb__index_pair pairs[128];
    uint64_t hash = 14695981039346656037u;
    size_t n;
    *found = 0;
    while ((n = tb__broad_phase_next(bp, pairs, batch)) > 0) {
        assert_true(n <= batch);
        for (size_t k = 0; k < n; ++k) {
            assert_true(pairs[k].first < pairs[k].second);
            assert_true(pairs[k].second < count);
            assert_int_equal(seen[pairs[k].first * count + pairs[k].second]++, 0);
            hash = (hash ^ (uint64_t)pairs[k].first) * 1099511628211u;
            hash = (hash ^ (uint64_t)pairs[k].second) * 1099511628211u;
        }
        *found += n;
    }
    return hash;
}

/* The broad phase's pairs are exactly the all-pairs check's, whatever the scene; a fresh broad
 * phase gives them in the same order as one that sorted other boxes before. */
static void test_broad_phase_finds_exactly_the_pairs_of_the_all_pairs_check(void **state)
{
    (void)state;
    uint64_t rng = 2026;
    static const size_t counts[] = {0, 1, 2, 3, 17, 100, 400, MAX_BOXES};
    /* under memcheck up to 400 boxes: the same cases, a sixth of the pairs */
    const size_t sizes = sizeof counts / sizeof counts[0] - (tb_test_short() ? 1 : 0);
    tb__broad_phase bp, fresh;
    assert_int_equal(tb__broad_phase_init(&bp, MAX_BOXES), TB_STATUS_OK);
    unsigned char *seen = malloc((size_t)MAX_BOXES * MAX_BOXES);
    assert_non_null(seen);
    size_t total = 0;
    for (int kind = 0; kind <= 8; ++kind) {
        for (size_t s = 0; s < sizes; ++s) {
            const size_t count = counts[s];
            fill(&rng, kind, count, bp.boxes);
            tb__broad_phase_sort(&bp, count);
            assert_true(bp.cells[0] * bp.cells[1] <= (count > 0 ? count : 1));
            memset(seen, 0, count * count);
            const size_t batch = 1 + (size_t)(kind * 13 + (int)s * 29) % 128;
            size_t found;
            const uint64_t order = sweep(&bp, count, batch, seen, &found);
            size_t expected = 0;
            for (size_t i = 0; i < count; ++i) {
                for (size_t j = i + 1; j < count; ++j) {
                    const bool overlap = boxes_overlap(&bp.boxes[i], &bp.boxes[j]);
                    expected += overlap;
                    assert_int_equal(seen[i * count + j], overlap);
                }
            }
            assert_int_equal(found, expected);
            total += found;
            /* the same boxes in a broad phase that never saw others, in one batch size more */
            assert_int_equal(tb__broad_phase_init(&fresh, count), TB_STATUS_OK);
            memcpy(fresh.boxes, bp.boxes, count * sizeof *bp.boxes);
            tb__broad_phase_sort(&fresh, count);
            memset(seen, 0, count * count);
            size_t again;
            assert_true(sweep(&fresh, count, batch % 128 + 1, seen, &again) == order);
            assert_int_equal(again, found);
            tb__broad_phase_free(&fresh);
        }
    }
    assert_true(total > 10000); /* the scenes do overlap */
    free(seen);
    tb__broad_phase_free(&bp);
}

/* A box filled in three dimensions is binned across two axes (the point of the cells: a strip
 * across one would hold a column as tall as the box), a floor across one, and a box as wide as
 * the scene makes one cell. */
static void test_broad_phase_bins_a_filled_box_across_two_axes(void **state)
{
    (void)state;
    uint64_t rng = 7;
    tb__broad_phase bp;
    assert_int_equal(tb__broad_phase_init(&bp, MAX_BOXES), TB_STATUS_OK);
    fill(&rng, 0, MAX_BOXES, bp.boxes); /* 10 boxes across each axis */
    tb__broad_phase_sort(&bp, MAX_BOXES);
    assert_true(bp.cells[0] >= 5 && bp.cells[1] >= 5);
    fill(&rng, 6, MAX_BOXES, bp.boxes);
    tb__broad_phase_sort(&bp, MAX_BOXES);
    assert_int_equal(bp.bin_axes[1], 2); /* the floor's thin axis */
    assert_true(bp.cells[0] >= 10 && bp.cells[1] == 1);
    const double half[3] = {100, 100, 100}, origin[3] = {0, 0, 0};
    set_box(&bp.boxes[0], origin, half);
    tb__broad_phase_sort(&bp, MAX_BOXES);
    assert_true(bp.cells[0] * bp.cells[1] <= 4); /* cells as wide as the widest box */
    tb__broad_phase_free(&bp);
}

/* All the pairs of a sweep, in order, in batches of batch; *count of them (free the array). */
static tb__index_pair *collect(tb__broad_phase *bp, size_t batch, size_t *count)
{
    size_t capacity = 1024, n;
    tb__index_pair *all = malloc(capacity * sizeof *all);
    assert_non_null(all);
    *count = 0;
    while ((n = tb__broad_phase_next(bp, all + *count, batch)) > 0) {
        *count += n;
        if (capacity - *count < 128) {
            capacity *= 2;
            all = realloc(all, capacity * sizeof *all);
            assert_non_null(all);
        }
    }
    return all;
}

/* A sweep limited to the pairs with an active box gives exactly the full sweep's pairs with an
 * active box, in the same order (the contact sums its forces in that order), whatever the scene
 * and however many boxes are active: the scan back from each active box finds every inactive
 * box that reaches it, the huge and infinite boxes (kind 2) included. */
static void test_broad_phase_limited_sweep_keeps_the_full_sweeps_active_pairs_in_order(void **state)
{
    (void)state;
    uint64_t rng = 23;
    static const size_t counts[] = {0, 1, 2, 17, 100, 400, MAX_BOXES};
    static const double shares[] = {0.0, 0.02, 0.2, 0.5, 1.0}; /* of the boxes active */
    const size_t sizes = sizeof counts / sizeof counts[0] - (tb_test_short() ? 1 : 0);
    tb__broad_phase bp;
    assert_int_equal(tb__broad_phase_init(&bp, MAX_BOXES), TB_STATUS_OK);
    size_t limited_pairs = 0;
    for (int kind = 0; kind <= 8; ++kind) {
        for (size_t s = 0; s < sizes; ++s) {
            const size_t count = counts[s];
            fill(&rng, kind, count, bp.boxes);
            tb__broad_phase_sort(&bp, count);
            size_t full_count;
            tb__index_pair *full = collect(&bp, 1 + (size_t)kind * 7, &full_count);
            for (size_t a = 0; a < sizeof shares / sizeof shares[0]; ++a) {
                for (size_t i = 0; i < count; ++i) {
                    bp.active[i] = test_uniform(&rng, 0.0, 1.0) < shares[a];
                }
                tb__broad_phase_sort_active(&bp, count);
                size_t n;
                tb__index_pair *limited = collect(&bp, 1 + (size_t)(kind + (int)a) * 11, &n);
                size_t k = 0;
                for (size_t f = 0; f < full_count; ++f) {
                    if (bp.active[full[f].first] || bp.active[full[f].second]) {
                        assert_true(k < n);
                        assert_int_equal(limited[k].first, full[f].first);
                        assert_int_equal(limited[k].second, full[f].second);
                        ++k;
                    }
                }
                assert_int_equal(k, n);
                limited_pairs += n;
                free(limited);
            }
            free(full);
        }
    }
    assert_true(limited_pairs > 10000); /* the active boxes do meet others */
    tb__broad_phase_free(&bp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_broad_phase_finds_exactly_the_pairs_of_the_all_pairs_check),
        cmocka_unit_test(test_broad_phase_bins_a_filled_box_across_two_axes),
        cmocka_unit_test(
            test_broad_phase_limited_sweep_keeps_the_full_sweeps_active_pairs_in_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
