/* The box-box test's bound on the edge axes (narrow_box.c, edge_cannot_win) skips an axis only
 * where the full separating axis test would pass it over, so every manifold is the same to the
 * bit: this test compiles narrow_box.c a second time with the bound off (its functions renamed
 * ref_*) and compares the library's box pairs against it, with the frames worked out per pair
 * and given beforehand as the pair finder gives them, bit for bit (no tolerance: the bound
 * must change nothing), on the configurations where the bound is tight or loose:
 *   - boxes of unequal sizes resting face on face, aligned or turned about the normal, at depths
 *     of 1e-9 to 1e-3 m and gaps within the margin (the pile's pairs, where the bound skips);
 *   - random turns at random near-touching offsets (edges and corners meeting);
 *   - nearly parallel edges, turned by 1e-9 to 1e-2 rad from aligned (the bound's slack grows
 *     as the axes turn parallel; below 1e-3 rad it hands the axis to the full test);
 *   - quaternions off unit length by up to 1e-6, which the pose's frames inherit (the slack
 *     grows with the frames' defect);
 *   - and, on two cubes at rest, that the bound does skip (else the above would prove nothing),
 *     and stands aside for a mirrored frame (a reflection, for which its closed form is wrong).
 * The one-face floor (one_face_above) likewise: every pair is also tested below levels about its
 * gap floor against the reference, which has it off. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

/* the reference: the same source, the bound off, its external functions renamed */
#define TB__BOX_EDGE_BOUND 0
#define tb__box_sphere_candidate ref_box_sphere_candidate
#define tb__box_sphere ref_box_sphere
#define tb__box_capsule ref_box_capsule
#define tb__box_box ref_box_box
#define tb__box_box_framed ref_box_box_framed
#define tb__box_frame_at ref_box_frame_at
#define tb__box_box_gap_floor ref_box_box_gap_floor
#define tb__box_box_below ref_box_box_below
#include "contact/narrow_box.c"
#undef tb__box_sphere_candidate
#undef tb__box_sphere
#undef tb__box_capsule
#undef tb__box_box
#undef tb__box_box_framed
#undef tb__box_frame_at
#undef tb__box_box_gap_floor
#undef tb__box_box_below
int tb__box_box(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                tb__contact_manifold *out);
int tb__box_box_framed(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       double margin, tb__contact_manifold *out);
void tb__box_frame_at(const double pose[TB__POSE_SIZE], tb__box_frame *out);
int tb__box_box_below(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__box_frame *frame_a, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                      double level, double margin, tb__contact_manifold *out);

#include "geometry.h"

#include <stdlib.h>
#include <string.h>

#define MARGIN 1e-3 /* m: the contact effect's (TB__CONTACT_MARGIN) */
#define TRIALS 40000

/* The same count, normal and points, bit for bit (points past count are not part of it). */
static int same_manifold(const tb__contact_manifold *x, const tb__contact_manifold *y)
{
    return x->count == y->count && memcmp(x->normal, y->normal, sizeof x->normal) == 0 &&
           memcmp(x->points, y->points, (size_t)x->count * sizeof x->points[0]) == 0;
}

/* The look-ahead's test below a level (tb__box_box_below, whose one-face floor passes a pair
 * over after one face axis where the six would) against the reference at levels at, a rounding
 * either side of and around the pair's gap floor, and at 0 and 5 cm: the same manifold, or the
 * same passing over, bit for bit. */
static void check_levels(const tb__collision_shape *a, const double pa[TB__POSE_SIZE],
                         const tb__box_frame *fa, const tb__collision_shape *b,
                         const double pb[TB__POSE_SIZE], const tb__box_frame *fb)
{
    const double floor = ref_box_box_gap_floor(a, pa, fa, b, pb, fb);
    const double levels[] = {floor,
                             nextafter(floor, -INFINITY),
                             nextafter(floor, INFINITY),
                             floor - 1e-3,
                             floor + 1e-3,
                             0.0,
                             0.05};
    for (size_t k = 0; k < sizeof levels / sizeof levels[0]; ++k) {
        tb__contact_manifold got, want;
        const int n = ref_box_box_below(a, pa, fa, b, pb, fb, levels[k], 0.05, &want);
        assert_int_equal(tb__box_box_below(a, pa, fa, b, pb, fb, levels[k], 0.05, &got), n);
        if (!same_manifold(&got, &want)) {
            fail_msg("below %a: manifolds differ", levels[k]);
        }
    }
}

/* Both orders of the pair through the library and the reference; returns the touching count. */
static int check_pair(const tb__collision_shape *a, const double pa[TB__POSE_SIZE],
                      const tb__collision_shape *b, const double pb[TB__POSE_SIZE])
{
    tb__contact_manifold got, want;
    for (int order = 0; order < 2; ++order) {
        const tb__collision_shape *first = order == 0 ? a : b, *second = order == 0 ? b : a;
        const double *p1 = order == 0 ? pa : pb, *p2 = order == 0 ? pb : pa;
        const int n = ref_box_box(first, p1, second, p2, MARGIN, &want);
        tb__box_frame f1, f2; /* the pair finder's way: frames worked out beforehand */
        tb__box_frame_at(p1, &f1);
        tb__box_frame_at(p2, &f2);
        check_levels(first, p1, &f1, second, p2, &f2);
        for (int framed = 0; framed < 2; ++framed) {
            assert_int_equal(framed
                                 ? tb__box_box_framed(first, p1, &f1, second, p2, &f2, MARGIN, &got)
                                 : tb__box_box(first, p1, second, p2, MARGIN, &got),
                             n);
            if (!same_manifold(&got, &want)) {
                fail_msg("manifolds differ: a at (%a %a %a | %a %a %a %a), b at (%a %a %a | %a "
                         "%a %a %a)",
                         p1[0], p1[1], p1[2], p1[3], p1[4], p1[5], p1[6], p2[0], p2[1], p2[2],
                         p2[3], p2[4], p2[5], p2[6]);
            }
        }
    }
    return got.count;
}

/* q scaled to length 1 + stretch. */
static void stretch(double q[4], double amount)
{
    for (int k = 0; k < 4; ++k) {
        q[k] *= 1.0 + amount;
    }
}

/* b resting on a (the top face at z = a's half height) at depth d, turned by angle about z and
 * tilted by tilt about a random horizontal axis, shifted sideways by up to half a's face. */
static int resting_pair(uint64_t *rng, const tb__collision_shape *a, const tb__collision_shape *b,
                        double *out_depth)
{
    double pa[TB__POSE_SIZE], pb[TB__POSE_SIZE], turn[4], tilt[4];
    test_pose(pa, test_uniform(rng, -1, 1), test_uniform(rng, -1, 1), test_uniform(rng, 0, 1),
              (const double[]){0, 0, 1}, 0.0);
    const double depth =
        pow(10.0, test_uniform(rng, -9, -3)) * (test_uniform(rng, 0, 1) < 0.8 ? 1 : -1);
    const double aligned = test_uniform(rng, 0, 1) < 0.5 ? 0.0 : test_uniform(rng, -3.2, 3.2);
    test_pose(pb, 0, 0, 0, (const double[]){0, 0, 1}, aligned);
    memcpy(turn, pb + 3, sizeof turn);
    const double phi = test_uniform(rng, 0, 6.3);
    test_pose(pb, 0, 0, 0, (const double[]){cos(phi), sin(phi), 0},
              test_uniform(rng, 0, 1) < 0.5 ? 0.0 : pow(10.0, test_uniform(rng, -9, -2)));
    memcpy(tilt, pb + 3, sizeof tilt);
    tb__q_mul(pb + 3, tilt, turn);
    pb[0] = pa[0] + test_uniform(rng, -0.5, 0.5) * a->half[0];
    pb[1] = pa[1] + test_uniform(rng, -0.5, 0.5) * a->half[1];
    pb[2] = pa[2] + a->half[2] + b->half[2] - depth;
    *out_depth = depth;
    return check_pair(a, pa, b, pb);
}

static void test_resting_boxes_match_the_full_test(void **state)
{
    (void)state;
    uint64_t rng = 7;
    tb__collision_shape *cube = test_box(0.1, 0.1, 0.1), *die = test_box(0.05, 0.05, 0.05);
    tb__collision_shape *board = test_box(0.9, 0.9, 0.1), *domino = test_box(0.01, 0.024, 0.048);
    const tb__collision_shape *shapes[4] = {cube, die, board, domino};
    int touching = 0;
    for (int n = 0; n < TRIALS; ++n) {
        double depth;
        const int count = resting_pair(&rng, shapes[n % 4], shapes[(n / 4) % 4], &depth);
        touching += count > 0;
    }
    assert_true(touching > TRIALS / 2); /* most rest in contact: the bound's case */
    free(cube);
    free(die);
    free(board);
    free(domino);
}

/* Random sizes, turns and offsets near touching, some frames off unit length, some parallel. */
static void test_random_boxes_match_the_full_test(void **state)
{
    (void)state;
    uint64_t rng = 11;
    int touching = 0;
    for (int n = 0; n < TRIALS; ++n) {
        tb__collision_shape *a = test_box(test_uniform(&rng, 0.01, 1), test_uniform(&rng, 0.01, 1),
                                          test_uniform(&rng, 0.01, 1));
        tb__collision_shape *b = test_box(test_uniform(&rng, 0.01, 1), test_uniform(&rng, 0.01, 1),
                                          test_uniform(&rng, 0.01, 1));
        double pa[TB__POSE_SIZE], pb[TB__POSE_SIZE];
        test_random_quaternion(&rng, pa + 3);
        if (n % 3 == 0) { /* b nearly parallel to a */
            double small[4], axis[3];
            test_random_quaternion(&rng, small);
            tb__v3_set(axis, small[1], small[2], small[3]);
            test_pose(pb, 0, 0, 0, axis, pow(10.0, test_uniform(&rng, -9, -2)));
            memcpy(small, pb + 3, sizeof small);
            tb__q_mul(pb + 3, small, pa + 3);
        } else {
            test_random_quaternion(&rng, pb + 3);
        }
        if (n % 5 == 0) {
            stretch(pa + 3, test_uniform(&rng, -1e-6, 1e-6));
            stretch(pb + 3, test_uniform(&rng, -1e-6, 1e-6));
        }
        /* centres apart by about the sum of the half diagonals' projections: near touching */
        double direction[3] = {test_uniform(&rng, -1, 1), test_uniform(&rng, -1, 1),
                               test_uniform(&rng, -1, 1)};
        const double reach = 0.5 * (tb__v3_norm(a->half) + tb__v3_norm(b->half));
        for (int k = 0; k < 3; ++k) {
            pa[k] = test_uniform(&rng, -1, 1);
            pb[k] = pa[k] + direction[k] * reach * test_uniform(&rng, 0.6, 1.4);
        }
        touching += check_pair(a, pa, b, pb) > 0;
        free(a);
        free(b);
    }
    assert_true(touching > TRIALS / 10 && touching < TRIALS - TRIALS / 10);
}

/* The bound at work and aside, through box_pose directly: two aligned cubes resting 1 um deep
 * have every edge axis that is not parallel (i != j) skipped (the pile's case: those axes are
 * the face axes again, and cannot beat the best face by the edges' preference); with one frame
 * mirrored (a reflection, which no quaternion gives: the closed form assumes right-handed
 * frames) none is. */
static void test_the_bound_skips_at_rest_and_stands_aside_when_mirrored(void **state)
{
    (void)state;
    const double half[3] = {0.05, 0.05, 0.05}, center_a[3] = {0, 0, 0};
    const double center_b[3] = {0.03, 0.02, 0.1 - 1e-6};
    tb__box_frame frame_a, frame_b;
    box_pose A = {.center = center_a, .half = half, .frame = &frame_a};
    box_pose B = {.center = center_b, .half = half, .frame = &frame_b};
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            A.axis[i][k] = B.axis[i][k] = i == k ? 1.0 : 0.0;
        }
    }
    memcpy(frame_a.axis, A.axis, sizeof A.axis);
    frame_from_axes(&frame_a);
    const double size = 0.3, scale = 0.05 + 0.1 + 2.0 * size;
    for (int mirrored = 0; mirrored < 2; ++mirrored) {
        B.axis[2][2] = mirrored ? -1.0 : 1.0;
        memcpy(frame_b.axis, B.axis, sizeof B.axis);
        frame_from_axes(&frame_b);
        double faces[2][3];
        pair_dots dots;
        face_separations(&A, &B, center_b, faces, &dots);
        const double best = faces[0][2]; /* the deepest face: -1 um */
        assert_true(mirrored ? isinf(dots.defect) : dots.defect < 1e-14);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                const bool skipped =
                    edge_cannot_win(&A, &B, &dots, scale, i, j, best + 1e-6 * size);
                assert_int_equal(skipped, !mirrored && i != j);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resting_boxes_match_the_full_test),
        cmocka_unit_test(test_random_boxes_match_the_full_test),
        cmocka_unit_test(test_the_bound_skips_at_rest_and_stands_aside_when_mirrored),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
