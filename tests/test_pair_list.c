/* The candidate pairs kept between passes with a skin (src/contact/pair_list.c) against a check
 * of all N (N - 1) / 2 pairs of boxes at every pass of a moving scene: exactly its pairs, in its
 * order (by first index, then second) whenever the list holds them, and each pair once when it
 * cannot; and the contact derivative, which reads the pairs, the same bits at a state whatever
 * states were evaluated before. No tolerance: pairs and bits are compared exactly. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "geometry.h"
#include "contact/pair_list.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

enum { BOXES = 300, PASSES = 400, SNAPSHOTS = 4 };

static bool boxes_overlap(const tb__aabb *a, const tb__aabb *b)
{
    for (int k = 0; k < 3; ++k) {
        if (a->max[k] < b->min[k] || b->max[k] < a->min[k]) {
            return false;
        }
    }
    return true;
}

static void set_box(tb__aabb *b, const double centre[3], double half)
{
    for (int k = 0; k < 3; ++k) {
        b->min[k] = centre[k] - half;
        b->max[k] = centre[k] + half;
    }
}

/* The pass's pairs from the list in batches of batch; their count. */
static size_t pass_pairs(tb__pair_list *list, size_t batch, tb__index_pair *out)
{
    size_t count = 0, n;
    while ((n = tb__pair_list_next(list, out + count, batch)) > 0) {
        assert_true(n <= batch);
        count += n;
    }
    return count;
}

/* The all-pairs check of boxes [0, count), in order of (first, second), keeping only the pairs
 * with an active box when limited; their count. */
static size_t all_pairs(const tb__aabb *boxes, const unsigned char *active, size_t count,
                        bool limited, tb__index_pair *out)
{
    size_t found = 0;
    for (size_t i = 0; i < count; ++i) {
        for (size_t j = i + 1; j < count; ++j) {
            if (boxes_overlap(&boxes[i], &boxes[j]) && (!limited || active[i] || active[j])) {
                out[found].first = i;
                out[found].second = j;
                ++found;
            }
        }
    }
    return found;
}

/* The list's pass against the all-pairs check: the same pairs in the same order when the list
 * holds them (at most its capacity), else the same set with each pair once. */
static void check_pass(tb__pair_list *list, const unsigned char *active, size_t count, bool limited,
                       size_t batch, unsigned char *seen)
{
    static tb__index_pair got[BOXES * BOXES / 2], expected[BOXES * BOXES / 2];
    tb__pair_list_begin(list, count, limited);
    const size_t n = pass_pairs(list, batch, got);
    const size_t m = all_pairs(list->bounds, active, count, limited, expected);
    assert_int_equal(n, m);
    if (m <= list->pair_capacity) {
        for (size_t k = 0; k < m; ++k) {
            assert_int_equal(got[k].first, expected[k].first);
            assert_int_equal(got[k].second, expected[k].second);
        }
        return;
    }
    memset(seen, 0, count * count);
    for (size_t k = 0; k < n; ++k) {
        assert_true(got[k].first < got[k].second && got[k].second < count);
        assert_int_equal(seen[got[k].first * count + got[k].second]++, 0);
    }
    for (size_t k = 0; k < m; ++k) {
        assert_int_equal(seen[expected[k].first * count + expected[k].second], 1);
    }
}

/* Boxes 5-15 cm across packed in a cube, drifting each pass by up to 0.4 % of their size (the
 * skin is 5 %: a box leaves its grown box after some 25 passes), a few jumping 20 cm at
 * once, every 10th pass back at an earlier pass's boxes, every 50 passes a new set of active boxes
 * and a limited sweep for 25 of them (every 5 passes some boxes made inactive or active);
 * batches of 1 to 128. Every pass gives the all-pairs check's
 * pairs in its order; the list was built again for boxes that left their skin and kept between. */
static void test_pair_list_gives_the_all_pairs_checks_pairs_in_order_at_every_pass(void **state)
{
    (void)state;
    uint64_t rng = 4711;
    tb__pair_list list;
    assert_int_equal(tb__pair_list_init(&list, BOXES), TB_STATUS_OK);
    static double centre[BOXES][3], half[BOXES], velocity[BOXES][3];
    static tb__aabb snapshots[SNAPSHOTS][BOXES];
    unsigned char *seen = malloc((size_t)BOXES * BOXES);
    assert_non_null(seen);
    for (size_t i = 0; i < BOXES; ++i) {
        half[i] = test_uniform(&rng, 0.025, 0.075);
        for (int k = 0; k < 3; ++k) {
            centre[i][k] = test_uniform(&rng, 0.0, 0.6);
            velocity[i][k] = test_uniform(&rng, -0.004, 0.004) * half[i];
        }
    }
    bool limited = false;
    size_t taken = 0;
    for (size_t pass = 0; pass < PASSES; ++pass) {
        for (size_t i = 0; i < BOXES; ++i) {
            const bool jump = test_uniform(&rng, 0.0, 1.0) < 2e-4;
            for (int k = 0; k < 3; ++k) {
                centre[i][k] += jump ? test_uniform(&rng, -0.2, 0.2) : velocity[i][k];
            }
            set_box(&list.bounds[i], centre[i], half[i]);
        }
        if (pass % 10 == 9) { /* an earlier pass's boxes again */
            memcpy(list.bounds, snapshots[(pass / 10) % taken], sizeof snapshots[0]);
        } else if (pass % 11 == 0) {
            memcpy(snapshots[(pass / 11) % SNAPSHOTS], list.bounds, sizeof snapshots[0]);
            taken += taken < SNAPSHOTS;
        }
        if (pass % 25 == 0) {
            limited = pass % 50 == 25;
            for (size_t i = 0; i < BOXES; ++i) {
                list.broad.active[i] = !limited || test_uniform(&rng, 0.0, 1.0) < 0.3;
            }
        } else if (limited && pass % 5 == 0) { /* some fall asleep (the list may be kept) or
                                                    wake (it may not) */
            for (size_t i = 0; i < BOXES; ++i) {
                const double u = test_uniform(&rng, 0.0, 1.0);
                list.broad.active[i] = pass % 10 == 5 ? list.broad.active[i] && u < 0.8
                                                      : list.broad.active[i] || u < 0.05;
            }
        }
        const size_t batch = 1 + (pass * 37) % 128;
        check_pass(&list, list.broad.active, BOXES, limited, batch, seen);
    }
    /* built again when boxes left their skin, the active set changed or an old state came back;
     * kept for most passes */
    assert_true(list.builds > 20 && list.builds < PASSES / 2);
    free(seen);
    tb__pair_list_free(&list);
}

/* A cluster shrinking from every box overlapping every other (more pairs than the list holds,
 * with and without the skin) to boxes apart: each pass gives the all-pairs check's pairs, in its
 * order whenever there are no more than the list holds, each once otherwise. */
static void test_pair_list_gives_every_pair_once_when_it_cannot_hold_them(void **state)
{
    (void)state;
    enum { N = 200 };
    uint64_t rng = 99;
    tb__pair_list list;
    assert_int_equal(tb__pair_list_init(&list, N), TB_STATUS_OK);
    unsigned char *seen = malloc((size_t)N * N);
    assert_non_null(seen);
    static double direction[N][3];
    for (size_t i = 0; i < N; ++i) {
        for (int k = 0; k < 3; ++k) {
            direction[i][k] = test_uniform(&rng, -1.0, 1.0);
        }
    }
    size_t streamed = 0, held = 0;
    for (int pass = 0; pass < 200; ++pass) {
        const double spread = 0.01 * pow(1.03, pass); /* 1 cm to 3.7 m */
        for (size_t i = 0; i < N; ++i) {
            const double c[3] = {spread * direction[i][0], spread * direction[i][1],
                                 spread * direction[i][2]};
            set_box(&list.bounds[i], c, 0.05);
            list.broad.active[i] = 1;
        }
        check_pass(&list, list.broad.active, N, pass % 2 == 1, 1 + (size_t)pass % 64, seen);
        streamed += list.streaming;
        held += !list.streaming;
    }
    assert_true(streamed > 5 && held > 5); /* both ways were taken */
    free(seen);
    tb__pair_list_free(&list);
}

/* A box with a NaN bound meets only the boxes the sweep bins beside it (broad_phase.h), so no
 * all-pairs check holds there; but its pairs still depend on the boxes alone: a list whose skin
 * shrank over passes with more pairs than it holds gives the same pairs, in the same order, as a
 * list that saw nothing else. */
static void test_pair_list_with_a_nan_bound_gives_what_a_fresh_list_gives(void **state)
{
    (void)state;
    enum { N = 200 };
    uint64_t rng = 8;
    tb__pair_list fresh, used;
    assert_int_equal(tb__pair_list_init(&fresh, N), TB_STATUS_OK);
    assert_int_equal(tb__pair_list_init(&used, N), TB_STATUS_OK);
    static tb__index_pair first[N * N / 2], second[N * N / 2];
    for (int pass = 0; pass < 3; ++pass) { /* every box on every other: the skin is halved */
        for (size_t i = 0; i < N; ++i) {
            set_box(&used.bounds[i], (double[]){0.0, 0.0, 0.001 * pass}, 0.05);
        }
        tb__pair_list_begin(&used, N, false);
        assert_true(pass_pairs(&used, 64, first) > used.pair_capacity);
    }
    assert_true(used.share < fresh.share);
    for (size_t i = 0; i < N; ++i) {
        const double c[3] = {test_uniform(&rng, 0.0, 0.5), test_uniform(&rng, 0.0, 0.5),
                             test_uniform(&rng, 0.0, 0.5)};
        set_box(&fresh.bounds[i], c, test_uniform(&rng, 0.02, 0.08));
    }
    fresh.bounds[17].max[1] = NAN;
    memcpy(used.bounds, fresh.bounds, N * sizeof *fresh.bounds);
    tb__pair_list_begin(&fresh, N, false);
    tb__pair_list_begin(&used, N, false);
    const size_t n = pass_pairs(&fresh, 64, first);
    assert_int_equal(pass_pairs(&used, 7, second), n);
    assert_memory_equal(first, second, n * sizeof first[0]);
    assert_true(n > N);
    tb__pair_list_free(&fresh);
    tb__pair_list_free(&used);
}

/* A box at x = +infinity reaching across all of y (a body thrown off to infinity, as a step
 * that blew up may ask the derivative about) meets no box with a finite x: the all-pairs check
 * finds none of its pairs. Growing it by a skin (a share of its infinite side) made its x bounds
 * inf - inf = NaN, and the sweep of the grown boxes then found pairs by the order it had sorted
 * them in before: neither the boxes' pairs nor the same for a list used before. Twenty scenes
 * of 60 boxes, each checked by a fresh list and by one list kept across them, exactly. */
static void test_pair_list_with_an_infinite_box_gives_the_boxes_pairs(void **state)
{
    (void)state;
    enum { N = 60, SCENES = 20 };
    uint64_t rng = 23;
    tb__pair_list used;
    assert_int_equal(tb__pair_list_init(&used, N), TB_STATUS_OK);
    static unsigned char active[N], seen[N * N];
    memset(active, 1, sizeof active);
    for (int scene = 0; scene < SCENES; ++scene) {
        tb__pair_list fresh;
        assert_int_equal(tb__pair_list_init(&fresh, N), TB_STATUS_OK);
        for (size_t i = 0; i < N; ++i) {
            const double c[3] = {test_uniform(&rng, 0.0, 3.0), test_uniform(&rng, 0.0, 3.0),
                                 test_uniform(&rng, 0.0, 3.0)};
            set_box(&fresh.bounds[i], c, test_uniform(&rng, 0.1, 0.4));
        }
        const size_t far = (size_t)test_uniform(&rng, 0.0, N - 0.5);
        fresh.bounds[far].min[0] = fresh.bounds[far].max[0] = INFINITY;
        fresh.bounds[far].min[1] = -INFINITY;
        fresh.bounds[far].max[1] = INFINITY;
        memcpy(fresh.broad.active, active, N);
        memcpy(used.bounds, fresh.bounds, N * sizeof *fresh.bounds);
        memcpy(used.broad.active, active, N);
        check_pass(&fresh, active, N, false, 64, seen);
        check_pass(&used, active, N, false, 7, seen);
        tb__pair_list_free(&fresh);
    }
    tb__pair_list_free(&used);
}

/* A lattice of balls 1 mm into each other on a floor, jostled with random speeds and spins (so
 * each ball's six contact and friction forces differ), under gravity, ground and contact. */
static tb_scene *jostled_balls(void)
{
    uint64_t rng = 17;
    tb_scene *scene = test_empty_scene();
    for (int i = 0; i < 5; ++i) {
        for (int j = 0; j < 5; ++j) {
            for (int k = 0; k < 4; ++k) {
                const double x[3] = {0.099 * i + test_uniform(&rng, -3e-4, 3e-4),
                                     0.099 * j + test_uniform(&rng, -3e-4, 3e-4),
                                     0.0505 + 0.099 * k + test_uniform(&rng, -3e-4, 3e-4)};
                const double v[3] = {test_uniform(&rng, -0.1, 0.1), test_uniform(&rng, -0.1, 0.1),
                                     test_uniform(&rng, -0.1, 0.1)};
                const size_t id = test_add_ball(scene, NULL, 0.5, 0.05, x, v);
                const double omega[3] = {test_uniform(&rng, -3.0, 3.0),
                                         test_uniform(&rng, -3.0, 3.0),
                                         test_uniform(&rng, -3.0, 3.0)};
                assert_int_equal(tb_scene_set_velocity(scene, id, v, omega), TB_STATUS_OK);
            }
        }
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    const tb_status added = tb_scene_add_ground(scene, &ground);
    if (added != TB_STATUS_OK) {
        print_message("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(added, TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

/* y (n doubles) with each of the first balls moved by up to reach along each axis. */
static void moved(const double *y, size_t n, size_t balls, double reach, uint64_t *rng, double *out)
{
    memcpy(out, y, n * sizeof *out);
    for (size_t s = 0; s < TB_STATE_SIZE * balls; s += TB_STATE_SIZE) {
        for (int k = 0; k < 3; ++k) {
            out[s + TB_STATE_X + k] += test_uniform(rng, -reach, reach);
        }
    }
}

/* The derivative is a pure function of (t, y) with the list kept between evaluations: at y it is
 * the same bits in a scene that never evaluated anything else as after evaluating states within
 * the skin of y (the list built there serves y), states beyond it (built again), and those
 * again, in either order. Then it is no accident of one scene: y's derivative differs from a
 * nearby state's, and its momentum rates show the contact (not gravity alone). */
static void test_the_derivative_is_the_same_bits_whatever_was_evaluated_before(void **state)
{
    (void)state;
    tb_scene *fresh = jostled_balls(), *used = jostled_balls();
    const size_t n = tb_scene_state_size(fresh);
    double *y = malloc(6 * n * sizeof *y);
    assert_non_null(y);
    double *near = y + n, *far = y + 2 * n, *first = y + 3 * n, *other = y + 4 * n,
           *again = y + 5 * n;
    memcpy(y, tb_scene_states_const(fresh), n * sizeof *y);
    uint64_t rng = 5;
    const size_t balls = tb_scene_body_count(fresh);
    moved(y, n, balls, 2e-4, &rng, near); /* well inside the skin (5 % of 10 cm) */
    moved(y, n, balls, 0.03, &rng, far);  /* out of it */
    assert_int_equal(tb_scene_derivative(0.0, y, first, fresh), 0);
    const double *sequences[4][3] = {
        {far, far, far}, {near, near, near}, {far, near, far}, {near, far, near}};
    for (int s = 0; s < 4; ++s) {
        for (int e = 0; e < 3; ++e) {
            assert_int_equal(tb_scene_derivative(0.0, sequences[s][e], other, used), 0);
        }
        assert_int_equal(tb_scene_derivative(0.0, y, again, used), 0);
        assert_memory_equal(first, again, n * sizeof *y);
    }
    assert_int_equal(tb_scene_derivative(0.0, near, other, fresh), 0);
    assert_int_equal(tb_scene_derivative(0.0, y, again, fresh), 0);
    assert_memory_equal(first, again, n * sizeof *y);
    assert_int_equal(tb_scene_derivative(0.0, near, other, fresh), 0);
    assert_true(memcmp(first, other, n * sizeof *y) != 0);
    /* a ball in the middle of the lattice is pushed sideways by its neighbours (its weight,
     * 4.9 N, is all gravity would give, and only upwards-downwards) */
    const size_t middle = (2 * 5 + 2) * 4 + 1;
    const double *rate = first + TB_STATE_SIZE * middle + TB_STATE_P;
    assert_true(fabs(rate[0]) + fabs(rate[1]) > 1.0);
    free(y);
    tb_scene_destroy(fresh);
    tb_scene_destroy(used);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pair_list_gives_the_all_pairs_checks_pairs_in_order_at_every_pass),
        cmocka_unit_test(test_pair_list_gives_every_pair_once_when_it_cannot_hold_them),
        cmocka_unit_test(test_pair_list_with_a_nan_bound_gives_what_a_fresh_list_gives),
        cmocka_unit_test(test_pair_list_with_an_infinite_box_gives_the_boxes_pairs),
        cmocka_unit_test(test_the_derivative_is_the_same_bits_whatever_was_evaluated_before),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
