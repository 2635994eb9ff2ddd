/* The box pair's gap floor (narrow_box.c, tb__box_box_gap_floor): the look-ahead's passes skip
 * a pair whose floor lies above what its gap could lower, so the floor must never exceed the
 * gap the full narrow phase gives (minus its deepest point's depth; +infinity with no point).
 * A floor above the gap by one ulp could change an event gap's bits, so the test has no
 * tolerance on that side: floor <= gap, in both orders of the pair, with the frames as the pair
 * finder gives them, over
 *   - random sizes, turns and offsets from overlapping to 1.5 times the reach apart (edges,
 *     corners and faces meeting, pairs apart beyond the margin);
 *   - boxes resting face on face, aligned or turned about the normal, at depths of 1e-9 to
 *     1e-3 m either way, overhanging or not (the deepest corner clipped off: there the gap is
 *     above minus the separation, which the floor is under);
 *   - nearly parallel frames (1e-9 to 1e-2 rad) and quaternions off unit length by up to 1e-6;
 *   - far from the origin (100 m), where the poses' round-off is largest.
 * The floor is the gap's own number where the gap is minus the separation: a small box resting
 * wholly on a larger one (its deepest corner not clipped) has floor within 1e-9 m of the gap (the
 * slack, 1e3 times the round-off times the poses' scale, is ~1e-12 m at unit scale); else it
 * would skip nothing and prove nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "contact/narrow_phase.h"
#include "geometry.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MARGIN 0.05 /* m: the look-ahead's (TB__EVENT_LOOKAHEAD) */
#define TRIALS 40000

/* Minus the deepest point's depth of the pair's manifold (effect_contact_events.c, pair_gap). */
static double manifold_gap(const tb__contact_manifold *m)
{
    double deepest = -INFINITY;
    for (int j = 0; j < m->count; ++j) {
        deepest = fmax(deepest, m->points[j].depth);
    }
    return -deepest;
}

/* Both orders: floor <= gap, bit for bit; returns the largest gap - floor of a touching order
 * (-1 when neither touches). */
static double check_pair(const tb__collision_shape *a, const double pa[TB__POSE_SIZE],
                         const tb__collision_shape *b, const double pb[TB__POSE_SIZE])
{
    double excess = -1.0;
    for (int order = 0; order < 2; ++order) {
        const tb__collision_shape *first = order == 0 ? a : b, *second = order == 0 ? b : a;
        const double *p1 = order == 0 ? pa : pb, *p2 = order == 0 ? pb : pa;
        tb__box_frame f1, f2;
        tb__box_frame_at(p1, &f1);
        tb__box_frame_at(p2, &f2);
        tb__contact_manifold m;
        tb__collide_framed(first, p1, &f1, second, p2, &f2, MARGIN, &m);
        const double gap = manifold_gap(&m);
        const double floor = tb__box_box_gap_floor(first, p1, &f1, second, p2, &f2);
        if (!(floor <= gap)) {
            fail_msg("floor %a above gap %a: a at (%a %a %a | %a %a %a %a), b at (%a %a %a | %a "
                     "%a %a %a)",
                     floor, gap, p1[0], p1[1], p1[2], p1[3], p1[4], p1[5], p1[6], p2[0], p2[1],
                     p2[2], p2[3], p2[4], p2[5], p2[6]);
        }
        excess = m.count > 0 ? fmax(excess, gap - floor) : excess;
    }
    return excess;
}

static void stretch(double q[4], double amount)
{
    for (int k = 0; k < 4; ++k) {
        q[k] *= 1.0 + amount;
    }
}

/* a turn of pb's frame by 1e-9 to 1e-2 rad about a random axis, or a random frame */
static void random_turn(uint64_t *rng, const double qa[4], double qb[4], bool near_parallel)
{
    if (!near_parallel) {
        test_random_quaternion(rng, qb);
        return;
    }
    double small[4], pose[TB__POSE_SIZE];
    test_random_quaternion(rng, small);
    test_pose(pose, 0, 0, 0, (const double[]){small[1], small[2], small[3]},
              pow(10.0, test_uniform(rng, -9, -2)));
    tb__q_mul(qb, pose + 3, qa);
}

static void test_random_pairs_floor_below_gap(void **state)
{
    (void)state;
    uint64_t rng = 23;
    int touching = 0, apart = 0;
    for (int n = 0; n < TRIALS; ++n) {
        tb__collision_shape *a = test_box(test_uniform(&rng, 0.01, 1), test_uniform(&rng, 0.01, 1),
                                          test_uniform(&rng, 0.01, 1));
        tb__collision_shape *b = test_box(test_uniform(&rng, 0.01, 1), test_uniform(&rng, 0.01, 1),
                                          test_uniform(&rng, 0.01, 1));
        double pa[TB__POSE_SIZE], pb[TB__POSE_SIZE];
        test_random_quaternion(&rng, pa + 3);
        random_turn(&rng, pa + 3, pb + 3, n % 3 == 0);
        if (n % 5 == 0) {
            stretch(pa + 3, test_uniform(&rng, -1e-6, 1e-6));
            stretch(pb + 3, test_uniform(&rng, -1e-6, 1e-6));
        }
        const double far = n % 7 == 0 ? 100.0 : 1.0;
        const double direction[3] = {test_uniform(&rng, -1, 1), test_uniform(&rng, -1, 1),
                                     test_uniform(&rng, -1, 1)};
        const double reach = 0.5 * (tb__v3_norm(a->half) + tb__v3_norm(b->half));
        const double spread = test_uniform(&rng, 0.3, 1.5);
        for (int k = 0; k < 3; ++k) {
            pa[k] = far * test_uniform(&rng, -1, 1);
            pb[k] = pa[k] + direction[k] * reach * spread;
        }
        const double excess = check_pair(a, pa, b, pb);
        touching += excess >= 0.0;
        apart += excess < 0.0;
        free(a);
        free(b);
    }
    assert_true(touching > TRIALS / 10 && apart > TRIALS / 10); /* both kinds tried */
}

/* b resting on a's top face at depth d (either way), turned about z, shifted sideways by up to
 * `shift` of a's half face; returns the largest gap - floor (-1: not touching). */
static double resting_pair(uint64_t *rng, const tb__collision_shape *a,
                           const tb__collision_shape *b, double shift, bool turned)
{
    double pa[TB__POSE_SIZE], pb[TB__POSE_SIZE];
    test_pose(pa, test_uniform(rng, -1, 1), test_uniform(rng, -1, 1), test_uniform(rng, 0, 1),
              (const double[]){0, 0, 1}, 0.0);
    const double depth =
        pow(10.0, test_uniform(rng, -9, -3)) * (test_uniform(rng, 0, 1) < 0.8 ? 1 : -1);
    test_pose(pb, 0, 0, 0, (const double[]){0, 0, 1}, turned ? test_uniform(rng, -3.2, 3.2) : 0);
    pb[0] = pa[0] + test_uniform(rng, -shift, shift) * a->half[0];
    pb[1] = pa[1] + test_uniform(rng, -shift, shift) * a->half[1];
    pb[2] = pa[2] + a->half[2] + b->half[2] - depth;
    return check_pair(a, pa, b, pb);
}

static void test_resting_pairs_floor_below_gap_and_tight(void **state)
{
    (void)state;
    uint64_t rng = 29;
    tb__collision_shape *board = test_box(0.9, 0.9, 0.1), *die = test_box(0.05, 0.05, 0.05);
    tb__collision_shape *domino = test_box(0.01, 0.024, 0.048), *cube = test_box(0.1, 0.1, 0.1);
    const tb__collision_shape *shapes[4] = {board, die, domino, cube};
    for (int n = 0; n < TRIALS; ++n) { /* overhanging, turned: floor <= gap only */
        resting_pair(&rng, shapes[n % 4], shapes[(n / 4) % 4], 1.5, n % 2 == 0);
    }
    double worst = 0.0;
    for (int n = 0; n < TRIALS / 4; ++n) { /* a die or a domino wholly on the board */
        const double excess = resting_pair(&rng, board, shapes[1 + n % 2], 0.5, n % 2 == 0);
        assert_true(excess >= 0.0);
        worst = fmax(worst, excess);
    }
    assert_true(worst < 1e-9);
    free(board);
    free(die);
    free(domino);
    free(cube);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_pairs_floor_below_gap),
        cmocka_unit_test(test_resting_pairs_floor_below_gap_and_tight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
