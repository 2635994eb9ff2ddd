/* Friction slots depend only on their own pair's history (issue 23): a box landing flat and
 * straight down on a ground plane or a slab takes up no tangential force (a fresh stick anchor has
 * zero stretch, and nothing slides at its corners), whatever another box far away does meanwhile,
 * sliding while it lands or having bounced just before; and the other box's motion is the same
 * whichever of the two the scene holds first. Under CVODE Adams in one advance, whose post-step
 * hook runs only at the output: before, new contacts took provisional slots in the pass's body
 * order, so the falling box took over the sliding one's loaded slots when it came first in that
 * order, and the slots the bouncing box left loaded when it did not. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#define G 9.81

static const double cube[3] = {0.1, 0.1, 0.1}; /* m, 1 kg */

/* What the other box does: slides from the start (0.4 m/s along x on the plane, still sliding
 * when the falling box lands at 0.045 s: it stops after 0.4 / (mu_k g) = 0.082 s), or lands
 * from 0.1 m at 0.5 m/s along x (at 0.143 s) and bounces off (restitution 0.3: up at 0.42 m/s,
 * in the air for 0.086 s), before the falling box lands (from 0.13 m, at 0.163 s). */
typedef enum other_motion { SLIDING, BOUNCED } other_motion;

typedef struct two_boxes {
    tb_scene *scene;
    size_t falling, other;
} two_boxes;

static size_t add_cube(tb_scene *scene, const double x[3], const double v[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, cube, &def.mass, NULL), TB_STATUS_OK);
    memcpy(def.position, x, sizeof def.position);
    memcpy(def.velocity, v, sizeof def.velocity);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, cube, sizeof shape.size);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

/* What the boxes land on: the ground plane z = 0, or a static 2 x 1 x 0.1 m slab whose top is
 * z = 0, met by contact between bodies (both with their defaults). */
typedef enum surface { PLANE, SLAB } surface;

static void add_surface(tb_scene *scene, surface kind)
{
    if (kind == PLANE) {
        tb_ground_def ground = tb_ground_def_default();
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        return;
    }
    tb_body_def def = tb_body_def_default();
    def.motion = TB_MOTION_STATIC;
    def.position[2] = -0.05;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, (double[]){2.0, 1.0, 0.1}, 3 * sizeof(double));
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
}

/* The two boxes 0.5 m apart (they never meet) under gravity -g z. Order 0: the falling box is
 * the first body, the other at x = +0.5 m; order 1: the falling box comes last and the other is
 * mirrored to x = -0.5 m moving along -x. So the falling box comes first in the ground's pass (by
 * body) in one order and last in the other, and in the contact's (a sweep along the boxes'
 * bounds) too, where mirroring turns the pair order round. */
static two_boxes make_scene(surface kind, other_motion motion, int order)
{
    two_boxes out = {test_empty_scene(), 0, 0};
    assert_int_equal(tb_scene_add_gravity(out.scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    const double side = order == 0 ? 1.0 : -1.0;
    const double drop = motion == SLIDING ? 0.01 : 0.13;
    const double falling_x[3] = {0.0, 0.0, 0.05 + drop}, still[3] = {0, 0, 0};
    const double other_x[3] = {0.5 * side, 0.0, motion == SLIDING ? 0.05 : 0.15};
    const double other_v[3] = {(motion == SLIDING ? 0.4 : 0.5) * side, 0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
        if ((k == 0) == (order == 0)) {
            out.falling = add_cube(out.scene, falling_x, still);
        } else {
            out.other = add_cube(out.scene, other_x, other_v);
        }
    }
    add_surface(out.scene, kind);
    return out;
}

/* Runs the scene to `seconds` in one advance (one output) under method. */
static void run(two_boxes *boxes, tb_method method, double seconds)
{
    tb_integrator_def def = test_integrator_def(method, 0.0, tb_integrator_def_default().rtol);
    def.max_steps = 10000000;
    tb_integrator *integrator = test_integrator(boxes->scene, &def);
    assert_int_equal(tb_integrator_advance(integrator, seconds), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
}

static const double *position(const two_boxes *boxes, size_t id)
{
    return tb_scene_states_const(boxes->scene) + TB_STATE_SIZE * id + TB_STATE_X;
}

/* The falling box lands level with no tangential velocity at any corner, so the law gives it no
 * tangential force: it stays at x = y = 0 exactly (every tangential term is an exact 0, so not
 * even rounding moves it; the bound 1e-12 m only allows for a compiler's reassociation). Before,
 * under Adams it took over loaded slots and was pushed 2.7 to 16 mm, on the plane and on the
 * slab alike (and up to 2.4e-9 m under BDF, from slots taken within one step). The other box's
 * positions in the two orders (the second mirrored back) agree to 2e-6 m: the orders permute y,
 * so CVODE's error norms sum in another order and its steps and Newton iterations differ at
 * rounding, which moves the result within the error control's reach (rtol 1e-6 of the 0.03-0.15
 * m travelled, amplified by the bounce's impact); measured 7e-11 to 2.8e-7 m, where before
 * Adams's differed by 4.3e-5 to 1.2e-4 m. */
static void test_a_box_landing_flat_takes_up_no_other_pairs_deflection(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    const char *surfaces[] = {"plane", "slab"}, *motions[] = {"sliding", "bounced"};
    for (int c = 0; c < 8; ++c) {
        const tb_method method = methods[c % 2];
        const surface kind = (surface)(c / 2 % 2);
        const other_motion motion = (other_motion)(c / 4);
        double other[2][3];
        for (int order = 0; order < 2; ++order) {
            two_boxes boxes = make_scene(kind, motion, order);
            run(&boxes, method, 0.3);
            const double *x = position(&boxes, boxes.falling);
            print_message("%-11s %s, other %s, order %d: the falling box moved (%.3e, %.3e) m\n",
                          tb_method_name(method), surfaces[kind], motions[motion], order, x[0],
                          x[1]);
            assert_true(fabs(x[0]) <= 1e-12 && fabs(x[1]) <= 1e-12);
            assert_true(fabs(x[2] - 0.05) < 1e-3); /* landed: resting on the surface */
            memcpy(other[order], position(&boxes, boxes.other), sizeof other[order]);
            tb_scene_destroy(boxes.scene);
        }
        /* order 1 mirrored back */
        const double apart = hypot(other[0][0] + other[1][0], other[0][1] - other[1][1]);
        print_message("%-11s %s, other %s: its positions in the two orders %.3e m apart\n",
                      tb_method_name(method), surfaces[kind], motions[motion], apart);
        assert_true(apart <= 2e-6);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_box_landing_flat_takes_up_no_other_pairs_deflection),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
