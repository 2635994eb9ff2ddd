/* The contact geometry allocates nothing once set up: the narrow phase on every pair of shape
 * types (libccd's MPR included) and against a plane, and whole passes of the contact-pairs hook
 * (broad phase and narrow phase) over a scene. malloc and friends are replaced for the process,
 * as in test_allocation.c, and counted around the calls. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geometry.h"
#include "contact/contact_pairs.h"
#include "contact/narrow_phase.h"
#include "counting_malloc.h"
#include "tumble/tumble.h"

#include <stdlib.h>

static tb_shape shape_of(int type)
{
    static const double vertices[] = {0, 0, 0, 0.2, 0, 0, 0, 0.2, 0, 0, 0, 0.2, 0.1, 0.1, 0.1};
    tb_shape s = tb_shape_default();
    s.type = (tb_shape_type)type;
    s.radius = 0.1;
    s.length = 0.2;
    s.size[0] = s.size[1] = s.size[2] = 0.2;
    s.semi_axes[0] = s.semi_axes[1] = s.semi_axes[2] = 0.1;
    s.vertices = vertices;
    s.vertex_count = 5;
    return s;
}

static void test_narrow_phase_allocates_nothing(void **state)
{
    (void)state;
    tb__collision_shape *shapes[7];
    const long at_start = counted_allocations;
    for (int t = 0; t < 7; ++t) {
        const tb_shape s = shape_of(TB_SHAPE_SPHERE + t);
        shapes[t] = test_shape(&s);
    }
    assert_true(counted_allocations >=
                at_start + 7); /* the counter is live: making shapes is seen */
    const double axis[3] = {1, 2, 3};
    double pa[7], pb[7];
    test_pose(pa, 0, 0, 0, axis, 0.3);
    test_pose(pb, 0.03, 0.02, 0.01, axis, -0.8);
    tb__contact_manifold m;
    int touching = 0;
    const long before = counted_allocations;
    for (int a = 0; a < 7; ++a) {
        for (int b = 0; b < 7; ++b) {
            touching += tb__collide(shapes[a], pa, shapes[b], pb, 0.01, &m) > 0;
        }
        touching += tb__collide_plane((const double[]){0, 0, 1}, 0.05, shapes[a], pa, 0.0, &m) > 0;
    }
    assert_int_equal(counted_allocations, before);
    assert_true(touching >= 49); /* every pair overlaps here: every routine ran */
    for (int t = 0; t < 7; ++t) {
        free(shapes[t]);
    }
}

static void test_contact_pair_passes_allocate_nothing(void **state)
{
    (void)state;
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    uint64_t rng = 3;
    for (int i = 0; i < 200; ++i) {
        tb_body_def body = tb_body_def_default();
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &body.mass, NULL),
                         TB_STATUS_OK);
        body.position[0] = test_uniform(&rng, 0, 3);
        body.position[1] = test_uniform(&rng, 0, 3);
        test_random_quaternion(&rng, body.orientation);
        assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
        const tb_shape s = shape_of(TB_SHAPE_SPHERE + i % 7);
        assert_int_equal(tb_scene_set_body_shape(scene, (size_t)i, &s), TB_STATUS_OK);
    }
    tb__contact_pairs *pairs = NULL;
    assert_int_equal(tb__contact_pairs_create(scene, NULL, 0, 0.01, &pairs, NULL), TB_STATUS_OK);
    tb__pair_contact out[8];
    size_t found = 0;
    const long before = counted_allocations;
    for (int pass = 0; pass < 10; ++pass) {
        tb_scene_states(scene)[0] += 0.01; /* a body moves: the sort has work */
        tb__contact_pairs_begin(pairs, scene, tb_scene_time(scene), tb_scene_states(scene));
        size_t n;
        while ((n = tb__contact_pairs_next(pairs, scene, tb_scene_states(scene), out, 8)) > 0) {
            found += n;
        }
    }
    assert_int_equal(counted_allocations, before);
    assert_true(found > 10);
    tb__contact_pairs_destroy(pairs);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_narrow_phase_allocates_nothing),
        cmocka_unit_test(test_contact_pair_passes_allocate_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
