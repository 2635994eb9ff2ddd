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
#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* A scene of two ground planes (a floor and a wall) that meet three box shapes through their
 * friction pools, a box resting on the floor so that the floor's anchors hold loaded states, an
 * RK4 integrator 50 ms in, and a fourth box without a shape. */
static tb_scene *two_planes_and_boxes(tb_integrator **out_integrator)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {0.2, 0.2, 0.2};
    for (int i = 0; i < 3; ++i) {
        test_add_box(scene, 1.0, size, (const double[]){0.5 * i, 0, 0.1 - 8e-7});
    }
    tb_body_def body = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &body.mass, NULL), TB_STATUS_OK);
    body.position[0] = 3.0;
    body.position[2] = 1.0;
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (const double[]){0.3, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    ground.normal[0] = 1; /* a wall at x = -5 */
    ground.normal[2] = 0;
    ground.offset = -5;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    *out_integrator = test_integrator_for(scene, TB_METHOD_RK4, 0, 0);
    assert_int_equal(tb_integrator_advance(*out_integrator, 0.05), TB_STATUS_OK);
    return scene;
}

/* A failed call leaves every object as it was (docs/robustness.md, F105): giving the fourth box
 * a shape grows both planes' friction pools and lays the states out again; each allocation of
 * the call is made to fail in turn, and a failure must leave the state array's length and bytes
 * (the floor's loaded anchors among them), the body's lack of a shape and the integrator able to
 * advance, where before the floor kept a grown pool and a new layout (the integrator refused
 * with LAYOUT_CHANGED and the anchors were zeroed) when the wall's pool failed. */
/* A copy of the scene's states (tb_scene_state_size doubles), to compare after a refusal. */
static double *states_copy(tb_scene *scene)
{
    const size_t n = tb_scene_state_size(scene);
    double *copy = malloc(n * sizeof *copy);
    assert_non_null(copy);
    memcpy(copy, tb_scene_states(scene), n * sizeof *copy);
    return copy;
}

static void test_a_shape_refused_for_memory_leaves_every_plane_as_it_was(void **state)
{
    (void)state;
    const double size[3] = {0.2, 0.2, 0.2};
    tb_shape box = tb_shape_default();
    box.type = TB_SHAPE_BOX;
    memcpy(box.size, size, sizeof box.size);
    int refused = 0;
    for (long k = 1; k < 200; ++k) {
        tb_integrator *integrator = NULL;
        tb_scene *scene = two_planes_and_boxes(&integrator);
        const size_t n = tb_scene_state_size(scene);
        double *before = states_copy(scene);
        bool loaded = false; /* the anchors hold something a new layout would zero */
        for (size_t i = 13 * 4; i < n; ++i) {
            loaded = loaded || before[i] != 0.0;
        }
        assert_true(loaded);
        failing_allocation_at = k;
        const tb_status status = tb_scene_set_body_shape(scene, 3, &box);
        const bool failed_here = failing_allocation_at == 0;
        failing_allocation_at = 0;
        if (status == TB_STATUS_OK) {
            assert_false(failed_here); /* every allocation of the call was tried */
            free(before);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
            break;
        }
        refused += 1;
        assert_int_equal(status, TB_STATUS_OUT_OF_MEMORY);
        assert_int_equal(tb_scene_state_size(scene), n);
        assert_memory_equal(tb_scene_states(scene), before, n * sizeof *before);
        tb_shape_type type = TB_SHAPE_BOX;
        assert_int_equal(tb_scene_body_shape_type(scene, 3, &type), TB_STATUS_OK);
        assert_int_equal(type, TB_SHAPE_NONE);
        assert_int_equal(tb_integrator_advance(integrator, 0.06), TB_STATUS_OK);
        free(before);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    assert_true(refused >= 4); /* the shape, both pools and the layout each allocate */
}

/* The same for contact points: a 1 kg ball of radius 0.1 m with a sphere shape rests on a ground
 * plane, met through its shape; giving it 128 contact points (2 states each: past the state
 * array's room) takes the plane's note that it has
 * points (the plane then leaves its shape to the points' law) and lays the states out again.
 * Each allocation of the call is made to fail in turn; a failure must leave the ball held by its
 * shape as before (F118: when the layout failed after the plane had noted the points, the note
 * stayed, the plane skipped the shape, and the ball fell through it under the integrator made
 * before). Held, it stays within 1e-5 m of where it rested (the law's penetration is 8e-7 m). */
static void test_points_refused_for_memory_leave_the_plane_under_the_shape(void **state)
{
    (void)state;
    tb_contact_point points[128];
    for (int k = 0; k < 128; ++k) {
        const double a = 0.05 * k;
        points[k] = (tb_contact_point){{0.05 * cos(a), 0.05 * sin(a), -0.05}, 0.05};
    }
    int refused = 0;
    for (long k = 1; k < 200; ++k) {
        tb_scene *scene = test_empty_scene();
        const double g[3] = {0, 0, -9.81};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        const size_t ball =
            test_add_ball(scene, "ball", 1.0, 0.1, (const double[]){0, 0, 0.1}, NULL);
        tb_ground_def ground = tb_ground_def_default();
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0, 0);
        assert_int_equal(tb_integrator_advance(integrator, 0.05), TB_STATUS_OK);
        const double rest = tb_scene_states_const(scene)[2];
        failing_allocation_at = k;
        const tb_status status = tb_scene_set_contact_points(scene, ball, points, 128, 1);
        const bool failed_here = failing_allocation_at == 0;
        failing_allocation_at = 0;
        if (status == TB_STATUS_OK) {
            assert_false(failed_here);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
            break;
        }
        refused += 1;
        assert_int_equal(status, TB_STATUS_OUT_OF_MEMORY);
        assert_int_equal(tb_integrator_advance(integrator, 0.3), TB_STATUS_OK);
        assert_true(fabs(tb_scene_states_const(scene)[2] - rest) < 1e-5);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    assert_true(refused >= 2); /* the points and the layout each allocate */
}

/* Adding a ground plane or a contact effect that runs out of memory at any of its allocations
 * adds nothing: the effect count, the state's length and bytes (the first plane's loaded
 * anchors among them) as before, and the integrator made before still advances. */
static void test_effects_refused_for_memory_change_nothing(void **state)
{
    (void)state;
    for (int kind = 0; kind < 2; ++kind) {
        int refused = 0;
        for (long k = 1; k < 400; ++k) {
            tb_integrator *integrator = NULL;
            tb_scene *scene = two_planes_and_boxes(&integrator);
            const size_t n = tb_scene_state_size(scene), effects = tb_scene_effect_count(scene);
            double *before = states_copy(scene);
            tb_ground_def ceiling = tb_ground_def_default();
            ceiling.normal[2] = -1.0;
            ceiling.offset = -5.0;
            const tb_contact_def contact = tb_contact_def_default();
            failing_allocation_at = k;
            const tb_status status = kind == 0 ? tb_scene_add_ground(scene, &ceiling)
                                               : tb_scene_add_contact(scene, &contact);
            const bool failed_here = failing_allocation_at == 0;
            failing_allocation_at = 0;
            if (status == TB_STATUS_OK) {
                assert_false(failed_here);
            } else {
                refused += 1;
                assert_int_equal(status, TB_STATUS_OUT_OF_MEMORY);
                assert_int_equal(tb_scene_effect_count(scene), effects);
                assert_int_equal(tb_scene_state_size(scene), n);
                assert_memory_equal(tb_scene_states(scene), before, n * sizeof *before);
                assert_int_equal(tb_integrator_advance(integrator, 0.06), TB_STATUS_OK);
            }
            free(before);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
            if (status == TB_STATUS_OK) {
                break;
            }
        }
        print_message("%s: %d allocations refused in turn\n", kind == 0 ? "ground" : "contact",
                      refused);
        assert_true(refused >= 2);
    }
}

/* Making a second integrator that runs out of memory at any of its allocations makes none
 * (*out NULL), leaves the state's bytes as they were and leaves the first integrator able to
 * advance (a made one would take the scene from it: F30), under RK4 and Euler. Not the methods
 * that make a SUNDIALS context: SUNDIALS 6's SUNContext_Create crashes in SUNLogger_Create when an
 * allocation inside it fails (docs/robustness.md, "Known and left"). */
static void test_an_integrator_refused_for_memory_changes_nothing(void **state)
{
    (void)state;
    const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_EULER};
    for (int m = 0; m < 2; ++m) {
        int refused = 0;
        for (long k = 1; k < 400; ++k) {
            tb_integrator *first = NULL;
            tb_scene *scene = two_planes_and_boxes(&first);
            const size_t n = tb_scene_state_size(scene);
            double *before = states_copy(scene);
            const tb_integrator_def def = test_integrator_def(methods[m], m == 0 ? 0.0 : 1e-3, 0);
            tb_scene_set_allow_unstable(scene, m == 1); /* Euler at 1/1000 s */
            tb_integrator *second = first;
            failing_allocation_at = k;
            const tb_status status = tb_scene_integrator_create(scene, &def, 0.05, &second);
            const bool failed_here = failing_allocation_at == 0;
            failing_allocation_at = 0;
            if (status == TB_STATUS_OK) {
                assert_false(failed_here);
            } else {
                refused += 1;
                assert_int_equal(status, TB_STATUS_OUT_OF_MEMORY);
                assert_null(second);
                assert_memory_equal(tb_scene_states(scene), before, n * sizeof *before);
                assert_int_equal(tb_integrator_advance(first, 0.06), TB_STATUS_OK);
            }
            free(before);
            tb_integrator_destroy(second);
            if (second != first) {
                tb_integrator_destroy(first);
            }
            tb_scene_destroy(scene);
            if (status == TB_STATUS_OK) {
                break;
            }
        }
        print_message("%s: %d allocations refused in turn\n", tb_method_name(methods[m]), refused);
        assert_true(refused >= 2);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_narrow_phase_allocates_nothing),
        cmocka_unit_test(test_contact_pair_passes_allocate_nothing),
        cmocka_unit_test(test_a_shape_refused_for_memory_leaves_every_plane_as_it_was),
        cmocka_unit_test(test_points_refused_for_memory_leave_the_plane_under_the_shape),
        cmocka_unit_test(test_effects_refused_for_memory_change_nothing),
        cmocka_unit_test(test_an_integrator_refused_for_memory_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
