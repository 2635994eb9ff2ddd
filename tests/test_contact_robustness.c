/* Contact between bodies given what breaks it: shapes at the ends of their range, pairs starting
 * deep inside each other, a pair in two contact effects. Each refusal names the input and
 * changes nothing; each accepted extreme keeps its geometry exact. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A ball of mass m, radius r, at x on the x axis, named; its shape a sphere of radius r. */
static size_t add_ball(tb_scene *scene, const char *name, double m, double r, double x)
{
    return test_add_ball(scene, name, m, r, (double[]){x, 0.0, 0.0}, NULL);
}

static void assert_detail_has(const char *detail, const char *words)
{
    if (strstr(detail, words) == NULL) {
        fail_msg("detail \"%s\" lacks \"%s\"", detail, words);
    }
}

/* F19: a convex hull's cross products of edge vectors overflowed for cubes of 1e90 m (refused
 * as "all in one plane") and underflowed for 1e-150 m, though both sizes are in the shape's
 * documented range. The hull of a cube is its 8 corners, so its bounds at the identity pose are
 * exactly +-side/2 on every axis (the corners are powers of two times exact halves: no
 * rounding, so the tolerance is 0). */
static void test_convex_hulls_of_every_allowed_size_keep_their_corners(void **state)
{
    (void)state;
    const double sides[] = {1e-150, 1e-40, 1.0, 1e90, 2e100};
    for (size_t s = 0; s < sizeof sides / sizeof sides[0]; ++s) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "cube", 1.0, 0.1, 0.0);
        double corners[27];
        for (int i = 0; i < 8; ++i) {
            for (int k = 0; k < 3; ++k) {
                corners[3 * i + k] = ((i >> k) & 1 ? 0.5 : -0.5) * sides[s];
            }
        }
        for (int k = 0; k < 3; ++k) {
            corners[24 + k] = 0.1 * sides[s]; /* an inner point, dropped */
        }
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_CONVEX;
        shape.vertices = corners;
        shape.vertex_count = 9;
        const tb_status status = tb_scene_set_body_shape(scene, 0, &shape);
        if (status != TB_STATUS_OK) {
            fail_msg("side %g m: %s", sides[s], tb_scene_detail(scene));
        }
        double low[3], high[3];
        assert_int_equal(tb_scene_body_shape_bounds(scene, tb_scene_states(scene), 0, low, high),
                         TB_STATUS_OK);
        for (int k = 0; k < 3; ++k) {
            assert_true(low[k] == -0.5 * sides[s] && high[k] == 0.5 * sides[s]);
        }
        tb_scene_destroy(scene);
    }
}

/* The state array and body and effect counts, to show a refused call changed nothing. Room for
 * 8 bodies and the friction slots of a few contact effects (3 doubles a slot). */
enum { SNAPSHOT_DOUBLES = 2048 };
typedef struct snapshot {
    double y[SNAPSHOT_DOUBLES];
    size_t size, bodies, effects;
} snapshot;

static snapshot take(tb_scene *scene)
{
    snapshot s = {.size = tb_scene_state_size(scene),
                  .bodies = tb_scene_body_count(scene),
                  .effects = tb_scene_effect_count(scene)};
    assert_true(s.size <= SNAPSHOT_DOUBLES);
    memcpy(s.y, tb_scene_states(scene), s.size * sizeof(double));
    return s;
}

static void assert_unchanged(tb_scene *scene, const snapshot *before)
{
    const snapshot after = take(scene);
    assert_int_equal(after.size, before->size);
    assert_int_equal(after.bodies, before->bodies);
    assert_int_equal(after.effects, before->effects);
    assert_memory_equal(after.y, before->y, after.size * sizeof(double));
}

/* Two balls of masses m_a and m_b (radius 0.1 m) overlapping by `overlap` under the default
 * contact; the integrator's status. */
static tb_status start_overlapping(double m_a, double m_b, double overlap, tb_method method,
                                   char *detail)
{
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "left", m_a, 0.1, -0.1);
    add_ball(scene, "right", m_b, 0.1, 0.1 - overlap);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const snapshot before = take(scene);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (method == TB_METHOD_RK4) {
        def.dt = 0.0; /* the scene's default step */
    }
    tb_integrator *integrator = (tb_integrator *)&before; /* must come back NULL on failure */
    const tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    snprintf(detail, 512, "%s", tb_scene_detail(scene));
    if (status != TB_STATUS_OK) {
        assert_null(integrator);
        assert_unchanged(scene, &before);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return status;
}

/* F93: removing the shape of a body a contact effect lists (tb_scene_set_body_shape(NULL)) was
 * taken, and the body silently passed through the others from then on, though the same body
 * without a shape is refused when the effect is added. Now refused, naming the body and the
 * effect, with nothing changed: the shape is still a sphere. A body the effect does not list
 * may lose its shape, and a listed body may have its shape replaced. */
static void test_removing_a_listed_bodys_shape_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "left", 1.0, 0.1, -0.5);
    add_ball(scene, "right", 1.0, 0.1, 0.5);
    add_ball(scene, "aside", 1.0, 0.1, 5.0);
    tb_contact_def contact = tb_contact_def_default();
    contact.bodies = (const size_t[]){0, 1};
    contact.body_count = 2;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const snapshot before = take(scene);
    const tb_shape none = tb_shape_default();
    const tb_shape *removals[] = {NULL, &none};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(tb_scene_set_body_shape(scene, 1, removals[k]),
                         TB_STATUS_INVALID_ARGUMENT);
        assert_detail_has(tb_scene_detail(scene), "body 1 (\"right\") is bodies[1] of effect 0");
        assert_unchanged(scene, &before);
        tb_shape_type type = TB_SHAPE_NONE;
        assert_int_equal(tb_scene_body_shape_type(scene, 1, &type), TB_STATUS_OK);
        assert_int_equal(type, TB_SHAPE_SPHERE);
    }
    assert_int_equal(tb_scene_set_body_shape(scene, 2, NULL), TB_STATUS_OK);
    tb_shape box = tb_shape_default();
    box.type = TB_SHAPE_BOX;
    box.size[0] = box.size[1] = box.size[2] = 0.2;
    assert_int_equal(tb_scene_set_body_shape(scene, 1, &box), TB_STATUS_OK);
    tb_scene_destroy(scene);
}

/* A body of mass m and moments I (kg m^2, all three), at height z, its shape a sphere of radius
 * r: the shape's reach from the centre of mass, by its bounding box, is sqrt(3) r. */
static size_t add_point_mass_ball(tb_scene *scene, double m, double I, double r, double z)
{
    tb_body_def body = tb_body_def_default();
    body.mass.mass = m;
    body.mass.moments[0] = body.mass.moments[1] = body.mass.moments[2] = I;
    body.mass.rotation[0] = 1.0;
    body.position[2] = z;
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = r;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

/* F95: a shape 1e90 m across on 1 kg with I = 1 kg m^2 was taken by tb_scene_add_ground and by
 * tb_scene_set_body_shape beside a plane, and refused only by the default step (1.5e-94 s) and
 * the guard. A point's depth is known to its distance from the centre of mass times 2^-52 at
 * best; past the penetration the contact force is rounding noise larger than the body's weight.
 * Refused now where the shape meets the effect: setting the shape, adding the plane or the
 * contact, naming the body, the penetration and the effect, nothing changed. The rule's reach is
 * sqrt(3) r for a ball: r at half the limit passes, at twice it is refused (a factor of 2 either
 * side, far beyond the rounding of the bound). Moments so small for the mass and reach that
 * M r^2 / I overflows (1e100 kg, 1e-200 kg m^2, r = 1e5 m) are refused the same way. */
static void test_shapes_too_large_for_their_contact_are_refused(void **state)
{
    (void)state;
    const tb_ground_def ground = tb_ground_def_default();
    const double limit = ground.penetration / (sqrt(3.0) * DBL_EPSILON);
    tb_scene *scene = test_empty_scene();
    add_point_mass_ball(scene, 1.0, 1.0, 1e90, 2e90);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "body 0 (\"body0\"): its shape reaches");
    assert_detail_has(tb_scene_detail(scene), "penetration 8e-07 m of effect 0 (a ground plane)");
    assert_int_equal(tb_scene_effect_count(scene), 0);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = 0.5 * limit;
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    const snapshot before = take(scene);
    shape.radius = 2.0 * limit;
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "of effect 0 (a ground plane)");
    assert_unchanged(scene, &before);
    tb_shape_piece piece = tb_shape_piece_default();
    piece.shape = shape;
    assert_int_equal(tb_scene_set_body_pieces(scene, 0, &piece, 1), TB_STATUS_INVALID_ARGUMENT);
    assert_unchanged(scene, &before);
    tb_scene_destroy(scene);

    scene = test_empty_scene(); /* between bodies: the contact's own penetration */
    add_point_mass_ball(scene, 1.0, 1.0, 1e90, 0.0);
    add_point_mass_ball(scene, 1.0, 1.0, 1.0, 1e91);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "of effect 0 (a contact)");
    assert_int_equal(tb_scene_effect_count(scene), 0);
    shape.radius = 1.0;
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const snapshot listed = take(scene);
    shape.radius = 1e90;
    assert_int_equal(tb_scene_set_body_shape(scene, 0, &shape), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "of effect 0 (a contact)");
    assert_unchanged(scene, &listed);
    tb_scene_destroy(scene);

    scene = test_empty_scene(); /* the rate's overflow */
    add_point_mass_ball(scene, 1e100, 1e-200, 1e5, 1e6);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "overflows");
    tb_scene_destroy(scene);
}

/* F95 for contact points: the loader gives a body with a shape its contact points, so a 1e12 m
 * ball over a plane of penetration 1e-4 m (rounding 2.2e-4 m) passed `tumble check`. A point at
 * twice the limit is refused by tb_scene_add_ground and by tb_scene_set_contact_points, naming
 * the body and the point; at half the limit it is taken. */
static void test_contact_points_too_far_for_the_plane_are_refused(void **state)
{
    (void)state;
    const tb_ground_def ground = tb_ground_def_default();
    const double limit = ground.penetration / DBL_EPSILON;
    tb_scene *scene = test_empty_scene();
    add_point_mass_ball(scene, 1.0, 1.0, 1.0, 4.0 * limit);
    tb_contact_point point = {{0.0, 0.0, -2.0 * limit}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "body 0 (\"body0\"): contact point 0 lies");
    assert_int_equal(tb_scene_effect_count(scene), 0);
    point.position[2] = -0.5 * limit;
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    const snapshot before = take(scene);
    point.position[2] = -2.0 * limit;
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "the ground plane's penetration 8e-07 m");
    assert_unchanged(scene, &before);
    /* F116: a point 1e300 m out was refused as "inf m from the body's centre of mass" (the
     * squares of its reach overflowed); the detail now gives its distance */
    point.position[2] = -1e300;
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "points[0]: 1e+300 m from the body's centre");
    assert_unchanged(scene, &before);
    tb_scene_destroy(scene);
}

/* A pair may start inside each other by up to 10 times the depth at which its contact carries
 * the heavier body's weight (the ground's rule of 10 penetrations, with the pair's stiffness
 * M_min omega^2 and omega^2 = g / penetration: 10 penetration M_max / M_min), and never past
 * the middle of the thinner body, not deeper: the contact would launch them apart at about
 * depth omega. Spheres overlap by exactly r_a + r_b -
 * distance, so 0.9 and 1.1 times the limit lie on either side of it by far more than rounding. */
static void test_bodies_starting_deep_inside_each_other_are_refused(void **state)
{
    (void)state;
    const double penetration = tb_contact_def_default().penetration;
    const double ratios[] = {1.0, 100.0};
    char detail[512];
    for (int r = 0; r < 2; ++r) {
        const double limit = 10.0 * penetration * ratios[r];
        for (int m = 0; m < 3; ++m) {
            const tb_method method = m == 0   ? TB_METHOD_RK4
                                     : m == 1 ? TB_METHOD_CVODE_ADAMS
                                              : TB_METHOD_CVODE_BDF;
            assert_int_equal(start_overlapping(1.0, ratios[r], 0.9 * limit, method, detail),
                             TB_STATUS_OK);
            assert_int_equal(start_overlapping(ratios[r], 1.0, 1.1 * limit, method, detail),
                             TB_STATUS_INVALID_ARGUMENT);
            assert_detail_has(detail, "(\"left\") and 1 (\"right\") start");
            assert_detail_has(detail, "inside each other");
        }
    }
    /* a red-team find: the weight's depth grows with the mass ratio (the stiffness is the
     * lighter's), so at 1e6 it was 8 m, and a ball 0.11 m deep in another of radius 0.1 m,
     * past its middle, was taken and thrown out (a 1 g marble 0.21 m deep in a 1 t crate left
     * at 345 m/s). No start lies past the middle of the thinner body: 0.09 m is taken, 0.11 m
     * refused, naming that limit. */
    for (int m = 0; m < 2; ++m) {
        const tb_method method = m == 0 ? TB_METHOD_RK4 : TB_METHOD_CVODE_ADAMS;
        assert_int_equal(start_overlapping(1.0, 1e6, 0.09, method, detail), TB_STATUS_OK);
        assert_int_equal(start_overlapping(1e6, 1.0, 0.11, method, detail),
                         TB_STATUS_INVALID_ARGUMENT);
        assert_detail_has(detail, "deeper than 0.1 m (half the thinner body's thickness)");
    }
    /* a millimetre's overlap of equal balls: about 3.5 m/s of launch */
    assert_int_equal(start_overlapping(1.0, 1.0, 1e-3, TB_METHOD_RK4, detail),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(detail, "0.001 m inside each other");
    print_message("%s\n", detail);
}

/* The same check when a body is moved into another after the effect was added, and not for
 * bodies the effect does not list. */
static void test_a_body_moved_into_another_is_refused_at_the_start(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "a", 1.0, 0.1, -0.5);
    add_ball(scene, "b", 1.0, 0.1, 0.5);
    add_ball(scene, "ghost", 1.0, 0.1, -0.5); /* inside a, but not in the effect */
    tb_contact_def contact = tb_contact_def_default();
    contact.bodies = (const size_t[]){0, 1};
    contact.body_count = 2;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.0;
    tb_integrator *integrator = NULL;
    tb_body_state moved;
    assert_int_equal(tb_scene_get_state(scene, 1, &moved), TB_STATUS_OK);
    moved.x[0] = -0.45; /* 0.15 m inside a */
    assert_int_equal(tb_scene_set_state(scene, 1, &moved), TB_STATUS_OK);
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_null(integrator);
    assert_detail_has(tb_scene_detail(scene), "effect 0 (a contact)");
    assert_detail_has(tb_scene_detail(scene), "0 (\"a\") and 1 (\"b\")");
    moved.x[0] = 0.5;
    assert_int_equal(tb_scene_set_state(scene, 1, &moved), TB_STATUS_OK);
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A pair in two contact effects would be pushed by both: twice the stiffness, so neither
 * effect's sinking nor restitution. Refused, naming the pair and the effect it is in; sets that
 * share one body (a table under two groups of dice) are accepted. */
static void test_a_pair_in_two_contact_effects_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const char *names[] = {"die1", "die2", "table", "die3", "die4"};
    for (int k = 0; k < 5; ++k) {
        add_ball(scene, names[k], 1.0, 0.1, (double)k);
    }
    tb_contact_def first = tb_contact_def_default();
    first.bodies = (const size_t[]){0, 1, 2};
    first.body_count = 3;
    assert_int_equal(tb_scene_add_contact(scene, &first), TB_STATUS_OK);
    tb_contact_def second = tb_contact_def_default();
    second.restitution = 0.8;
    second.bodies = (const size_t[]){3, 2, 4};
    second.body_count = 3;
    assert_int_equal(tb_scene_add_contact(scene, &second), TB_STATUS_OK);
    const snapshot before = take(scene);
    tb_contact_def again = tb_contact_def_default();
    again.bodies = (const size_t[]){4, 0, 1};
    again.body_count = 3;
    assert_int_equal(tb_scene_add_contact(scene, &again), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "0 (\"die1\") and 1 (\"die2\") are both in effect 0");
    assert_unchanged(scene, &before);
    tb_contact_def every = tb_contact_def_default(); /* every body: shares die1, die2 too */
    assert_int_equal(tb_scene_add_contact(scene, &every), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "effect 0 (a contact)");
    assert_unchanged(scene, &before);
    tb_scene_destroy(scene);
}

/* F22: gravity 1e-300 m/s^2 over a penetration of 1e300 m gave omega = sqrt(g / p) = 0 (the
 * quotient underflows): a contact without stiffness, whose push lasts forever, so CVODE's
 * integrator was refused for a def.max_step of inf the user never set. Now the contact itself is
 * refused, naming penetration; an omega that overflows was refused already. */
static void test_a_contact_rate_that_vanishes_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "a", 1.0, 0.1, 0.0);
    const double gravity[] = {1e-300, 1e300}, penetration[] = {1e300, 1e-300};
    for (int k = 0; k < 2; ++k) {
        tb_contact_def contact = tb_contact_def_default();
        contact.gravity = gravity[k];
        contact.penetration = penetration[k];
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_INVALID_ARGUMENT);
        assert_detail_has(tb_scene_detail(scene), "penetration");
        assert_int_equal(tb_scene_effect_count(scene), 0);
    }
    tb_scene_destroy(scene);
}

/* F98: a ground plane lacked the contact's bounds on its rate sqrt(gravity / penetration)
 * (F22): gravity 1e300 m/s^2 was taken (omega 1.1e153 rad/s, a default step of 2.4e-154 s), and
 * 1e-300 m/s^2 over 1e300 m (omega 0: a plane that never pushes back) too. Both are refused now,
 * as the contact's are, naming the field further from its default; a restitution just past 1 is
 * named with all its digits, not rounded to the 1 it is refused against. */
static void test_a_ground_rate_out_of_range_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "a", 1.0, 0.1, 0.0);
    const double gravity[] = {1e300, 1e-300, 9.81}, penetration[] = {8e-7, 1e300, 1e-18};
    const char *named[] = {"gravity: ", "penetration: ", "penetration: "};
    for (int k = 0; k < 3; ++k) {
        tb_ground_def ground = tb_ground_def_default();
        ground.offset = -1.0;
        ground.gravity = gravity[k];
        ground.penetration = penetration[k];
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
        assert_detail_has(tb_scene_detail(scene), named[k]);
        assert_detail_has(tb_scene_detail(scene), "at most 1e+09");
        assert_int_equal(tb_scene_effect_count(scene), 0);
    }
    tb_ground_def ground = tb_ground_def_default();
    ground.offset = -1.0;
    ground.restitution = 1.0000001;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "got 1.0000001");
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = 1.0000001;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "got 1.0000001");
    tb_scene_destroy(scene);
}

/* F23 (found by the contact fuzz target): a ball against a point set with one point 2^64 m out
 * (inside the 1e100 m the shapes allow) sent libccd's MPR round its portal refinement for ever,
 * which has no iteration cap, so one derivative never returned. The query now has a budget of
 * support evaluations and reports no contact when it runs out. The poses are the ones the fuzzer
 * reached (bit for bit); the alarm turns a hang back into a failure. */
static void test_a_far_hull_point_does_not_hang_the_derivative(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "ball", 1.0, 0x1.3333333333334p-3, 0.0);
    add_ball(scene, "points", 1.0, 0.1, 1.0);
    const double points[] = {-0x0.0000000000001p-1022,
                             -0x1.9999999999998p-5,
                             0x0p+0,
                             -0x1.3333333333334p-3,
                             -0x1.9999999999998p-5,
                             0x1.8p+1,
                             -0x1.3333333333334p-3,
                             0x1.3333333333334p-3,
                             0x0p+0,
                             -0x1.9999999999998p-5,
                             0x1.999999999999cp-4,
                             0x1.9999999999998p-5,
                             0x1.999999999999cp-4,
                             0x1p+64,
                             0x1.5p+1,
                             -0x1.3333333333334p-3,
                             0x1.3333333333334p-3,
                             -0x1.8p+1,
                             0x0p+0,
                             -0x1.1111111111111p-8,
                             -0x1.999999999999ap-3,
                             0x1.999999999999ap-3,
                             -0x1.9999999999998p-5,
                             0x1.9999999999998p-5};
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_POINTS;
    shape.vertices = points;
    shape.vertex_count = 8;
    assert_int_equal(tb_scene_set_body_shape(scene, 1, &shape), TB_STATUS_OK);
    const tb_body_state ball = {
        {0x1.9999999999998p-5, 0x1.ddde1a29a8a7cp-4, -0x1.999999999999ap-3},
        {0x1.f5f5fd4009e1dp-1, -0x1.92ad8a11de94fp-3, 0x1.0f4719a5a36c8p-8, -0x1.96eaa67875229p-7},
        {0, 0, 0},
        {0, 0, 0}};
    const tb_body_state set = {{0x1.33334fc75194ep-3, -0x1.33333eccb3d22p-3, 0x1.7ab4333976ce4p-28},
                               {0x1.ffffffffffffdp-1, 0x1.f9544c117a3d2p-26, 0x1.5378a157ec552p-30,
                                -0x1.27bbab9bfe936p-28},
                               {0, 0, 0},
                               {0, 0, 0}};
    assert_int_equal(tb_scene_set_state(scene, 0, &ball), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_state(scene, 1, &set), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    /* a point 2^64 m out has its depth to 2^64 2^-52 m = 4 km (F95): a penetration beyond that
     * keeps the contact; the narrow phase's query, geometry alone, is the same */
    contact.penetration = 1e4;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const size_t size = tb_scene_state_size(scene); /* the bodies' and the friction slots' */
    double *dydt = malloc(size * sizeof *dydt);
    assert_non_null(dydt);
    alarm(20); /* the derivative takes microseconds; a hang is killed */
    assert_int_equal(tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene), 0);
    alarm(0);
    for (size_t i = 0; i < size; ++i) {
        assert_true(isfinite(dydt[i]));
    }
    free(dydt);
    tb_scene_destroy(scene);
}

/* F24: a body of 1e100 kg with moments of 1e-200 kg m^2 and a sphere of 1e100 m (each inside
 * its documented range) makes the contact's rocking rate M |r|^2 / I overflow: no fixed step is
 * stable, and tb_scene_default_step answered OK with dt = 0. Since F95 the contact itself is
 * refused where the shape meets it, naming the overflow, so no integrator or step is asked of
 * such a scene; nothing is added. */
static void test_a_contact_whose_rate_overflows_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    for (int b = 0; b < 2; ++b) {
        tb_body_def def = tb_body_def_default();
        const double inertia[9] = {1e-200, 0, 0, 0, 1e-200, 0, 0, 0, 1e-200};
        assert_int_equal(
            tb_mass_from_tensor(1e100, (const double[]){0, 0, 0}, inertia, &def.mass, NULL),
            TB_STATUS_OK);
        def.position[0] = 3e100 * b;
        assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_SPHERE;
        shape.radius = 1e100;
        assert_int_equal(tb_scene_set_body_shape(scene, (size_t)b, &shape), TB_STATUS_OK);
    }
    const snapshot before = take(scene);
    tb_contact_def contact = tb_contact_def_default();
    contact.penetration = 1e90; /* past the depth's rounding, 1e100 m 2^-52 */
    contact.gravity = 1e90;
    contact.presliding = 1e90; /* the friction spring's rate as slow as the normal law's (F107) */
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_INVALID_ARGUMENT);
    assert_detail_has(tb_scene_detail(scene), "of effect 0 (a contact) overflows");
    assert_unchanged(scene, &before);
    tb_scene_destroy(scene);
}

/* F107: presliding 1e-300 m (contact or plane) was taken and asked for steps of 1e-151 s, and
 * static_friction 1e300 for 1e-306 s (CVODE then stopped on a non-finite derivative). The
 * friction spring's rate sqrt(gravity static_friction / presliding) is now bounded as the normal
 * law's sqrt(gravity / penetration) is, at 1e9 rad/s: with mu_s 0.6 and g 9.81 m/s^2 presliding
 * must be at least 9.81 0.6 / 1e18 = 5.886e-18 m, and with presliding 5e-7 m mu_s at most
 * 1e18 5e-7 / 9.81 = 5.097e10. Each limit is crossed by a factor of 2 either side; the detail
 * names the field, its value and the bound. */
static void test_friction_rates_out_of_range_are_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, "a", 1.0, 0.1, 0.0);
    add_ball(scene, "b", 1.0, 0.1, 0.5);
    const double least = 9.81 * 0.6 / 1e18, most = 1e18 * 5e-7 / 9.81;
    for (int plane = 0; plane < 2; ++plane) {
        const double presliding[] = {1e-300, 0.5 * least, 2 * least, 5e-7, 5e-7};
        const double static_friction[] = {0.6, 0.6, 0.6, 2 * most, 1e300};
        const char *named[] = {"presliding: 1e-300 m", "presliding: ", NULL,
                               "static_friction: ", "static_friction: 1e+300"};
        for (int k = 0; k < 5; ++k) {
            tb_ground_def ground = tb_ground_def_default();
            tb_contact_def contact = tb_contact_def_default();
            ground.offset = -1.0;
            ground.presliding = contact.presliding = presliding[k];
            ground.static_friction = contact.static_friction = static_friction[k];
            const tb_status status =
                plane ? tb_scene_add_ground(scene, &ground) : tb_scene_add_contact(scene, &contact);
            if (named[k] == NULL) {
                assert_int_equal(status, TB_STATUS_OK);
                continue;
            }
            assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
            assert_detail_has(tb_scene_detail(scene), named[k]);
            assert_detail_has(tb_scene_detail(scene), k < 2 ? "at least 5.89e-18 m" : "5.1e+10]");
        }
    }
    assert_int_equal(tb_scene_effect_count(scene), 2); /* the two taken */
    tb_scene_destroy(scene);
    scene = test_empty_scene();
    add_ball(scene, "a", 1.0, 0.1, 0.0);
    add_ball(scene, "b", 1.0, 0.1, 0.5);
    tb_contact_def contact = tb_contact_def_default();
    contact.static_friction = 0.5 * most; /* the other side of mu_s's limit */
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_scene_destroy(scene);
}

/* F108: a contact's friction_points far beyond the points that can ever touch was taken (1e7
 * for two balls: 240 MB of state). Two bodies make one pair, of at most 4 touching points, each
 * with a slot that may still relax beside it: 8; the default, 6 per body, is 12, so 12 slots are
 * the most two bodies take and 13 are refused, naming the field, the value and the range. */
static void test_friction_points_beyond_use_are_refused(void **state)
{
    (void)state;
    const size_t asked[] = {10000000, 13, 12, 1};
    for (int k = 0; k < 4; ++k) {
        tb_scene *scene = test_empty_scene();
        add_ball(scene, "a", 1.0, 0.1, 0.0);
        add_ball(scene, "b", 1.0, 0.1, 0.5);
        const size_t states = tb_scene_state_size(scene);
        tb_contact_def contact = tb_contact_def_default();
        contact.friction_points = asked[k];
        const tb_status status = tb_scene_add_contact(scene, &contact);
        if (k < 2) {
            assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
            assert_detail_has(tb_scene_detail(scene), k == 0 ? "friction_points: 10000000 slots"
                                                             : "friction_points: 13 slots");
            assert_detail_has(tb_scene_detail(scene), "must be in [1, 12]");
            assert_int_equal(tb_scene_effect_count(scene), 0);
            assert_int_equal(tb_scene_state_size(scene), states);
        } else {
            assert_int_equal(status, TB_STATUS_OK);
            assert_int_equal(tb_scene_state_size(scene), states + 3 * asked[k]);
        }
        tb_scene_destroy(scene);
    }
}

/* A 40 cm box (40 kg) resting across the corner where four 1 m tiles of one static floor body
 * meet: each tile is a piece of its own, and each piece pair has its own manifold, so the box's
 * face touches the floor at 4 points per tile, 16 in all, on 4 piece pairs. Effect 1 is a
 * contact between them with friction_points slots; 0.1 s under RK4 at its default step. */
static tb_contact_friction_stats box_across_four_tiles(size_t friction_points, tb_status *status)
{
    const char *json =
        "{\"bodies\": [{\"name\": \"floor\", \"motion\": \"static\", \"shape\": ["
        "{\"type\": \"box\", \"size\": [1, 1, 0.1], \"position\": [-0.5, -0.5, -0.05]},"
        "{\"type\": \"box\", \"size\": [1, 1, 0.1], \"position\": [0.5, -0.5, -0.05]},"
        "{\"type\": \"box\", \"size\": [1, 1, 0.1], \"position\": [-0.5, 0.5, -0.05]},"
        "{\"type\": \"box\", \"size\": [1, 1, 0.1], \"position\": [0.5, 0.5, -0.05]}]},"
        "{\"name\": \"box\", \"density\": 625, \"shape\": {\"type\": \"box\", "
        "\"size\": [0.4, 0.4, 0.4]}, \"position\": [0, 0, 0.1999992]}],"
        "\"effects\": [{\"type\": \"gravity\"}]}";
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "tiles", NULL, &scene, NULL, &error), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    contact.friction_points = friction_points;
    tb_contact_friction_stats stats = {0};
    *status = tb_scene_add_contact(scene, &contact);
    if (*status == TB_STATUS_OK) {
        tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
        assert_int_equal(tb_integrator_advance(integrator, 0.1), TB_STATUS_OK);
        assert_int_equal(tb_scene_contact_friction_stats(scene, 1, &stats), TB_STATUS_OK);
        tb_integrator_destroy(integrator);
    }
    tb_scene_destroy(scene);
    return stats;
}

/* F108's bound counted pairs of bodies, 4 touching points each; pieces meet piece by piece
 * (include/tumble/shape.h), so a box across four tiles of one floor holds 16 points on 4 piece
 * pairs, and the 12 slots the bound allowed two bodies left 4 of them the memoryless law that
 * creeps. The bound is 8 per pair of pieces: 32 here is taken and every touching point holds a
 * slot (overflows exactly 0, at least 16 in use at the peak); 33 is refused; the default's 12
 * run short (overflows counted). */
static void test_friction_points_count_pairs_of_pieces(void **state)
{
    (void)state;
    tb_status status;
    tb_contact_friction_stats stats = box_across_four_tiles(32, &status);
    assert_int_equal(status, TB_STATUS_OK);
    print_message("32 slots: peak in use %zu, overflows %llu\n", stats.peak_in_use,
                  stats.overflows);
    assert_true(stats.overflows == 0 && stats.peak_in_use >= 16);
    box_across_four_tiles(33, &status);
    assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
    stats = box_across_four_tiles(0, &status);
    assert_int_equal(status, TB_STATUS_OK);
    print_message("default: %zu slots, overflows %llu\n", stats.slots, stats.overflows);
    assert_true(stats.slots == 12 && stats.overflows > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_convex_hulls_of_every_allowed_size_keep_their_corners),
        cmocka_unit_test(test_bodies_starting_deep_inside_each_other_are_refused),
        cmocka_unit_test(test_a_body_moved_into_another_is_refused_at_the_start),
        cmocka_unit_test(test_a_pair_in_two_contact_effects_is_refused),
        cmocka_unit_test(test_removing_a_listed_bodys_shape_is_refused),
        cmocka_unit_test(test_shapes_too_large_for_their_contact_are_refused),
        cmocka_unit_test(test_contact_points_too_far_for_the_plane_are_refused),
        cmocka_unit_test(test_a_contact_rate_that_vanishes_is_refused),
        cmocka_unit_test(test_a_ground_rate_out_of_range_is_refused),
        cmocka_unit_test(test_a_far_hull_point_does_not_hang_the_derivative),
        cmocka_unit_test(test_a_contact_whose_rate_overflows_is_refused),
        cmocka_unit_test(test_friction_rates_out_of_range_are_refused),
        cmocka_unit_test(test_friction_points_beyond_use_are_refused),
        cmocka_unit_test(test_friction_points_count_pairs_of_pieces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
