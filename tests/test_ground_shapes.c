/* A ground plane meets the collision shape of a body that has no contact points (issue 20: a box
 * given a shape through the C API used to fall through the plane with no error): the plane's
 * narrow-phase manifold, the normal law of contact between bodies and its friction. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define G 9.81

/* The four shapes of the tests, each 0.2 m tall along its z and centred: a 0.4 x 0.4 x 0.2 m box,
 * a sphere of radius 0.1 m, a cylinder of radius 0.1 m, and the convex hull of an octagonal
 * prism of circumradius 0.1 m. */
static const double octagon_prism[16 * 3] = {
    0.1,  0.0, -0.1, 0.0707107,  0.0707107,  -0.1, 0.0, 0.1,  -0.1, -0.0707107, 0.0707107,  -0.1,
    -0.1, 0.0, -0.1, -0.0707107, -0.0707107, -0.1, 0.0, -0.1, -0.1, 0.0707107,  -0.0707107, -0.1,
    0.1,  0.0, 0.1,  0.0707107,  0.0707107,  0.1,  0.0, 0.1,  0.1,  -0.0707107, 0.0707107,  0.1,
    -0.1, 0.0, 0.1,  -0.0707107, -0.0707107, 0.1,  0.0, -0.1, 0.1,  0.0707107,  -0.0707107, 0.1};

/* A body of mass m with shape type (its mass properties the solid's, centred) and no contact
 * points, its shape frame turned by q (NULL: level) with its centre at x. */
static size_t add_shaped(tb_scene *scene, tb_shape_type type, double m, const double x[3],
                         const double q[4])
{
    tb_body_def def = tb_body_def_default();
    tb_shape shape = tb_shape_default();
    shape.type = type;
    const double box[3] = {0.4, 0.4, 0.2};
    if (type == TB_SHAPE_BOX) {
        memcpy(shape.size, box, sizeof box);
        assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, m, box, &def.mass, NULL), TB_STATUS_OK);
    } else if (type == TB_SHAPE_SPHERE) {
        shape.radius = 0.1;
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, m, 0.1, &def.mass, NULL), TB_STATUS_OK);
    } else { /* a cylinder, and the prism's mass as the cylinder's it nearly fills */
        shape.radius = 0.1;
        shape.length = 0.2;
        shape.vertices = octagon_prism;
        shape.vertex_count = 16;
        assert_int_equal(tb_mass_from_cylinder(TB_MASS_GIVEN, m, 0.1, 0.2, &def.mass, NULL),
                         TB_STATUS_OK);
    }
    memcpy(def.position, x, sizeof def.position);
    if (q != NULL) {
        memcpy(def.orientation, q, sizeof def.orientation);
    }
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    size_t points = 1;
    assert_int_equal(tb_scene_body_contact_point_count(scene, id, &points), TB_STATUS_OK);
    assert_int_equal(points, 0);
    return id;
}

/* A scene under gravity -g z with the plane of normal (-sin a, 0, cos a) through the origin. */
static tb_scene *scene_on_plane(double degrees, tb_ground_def *ground)
{
    const double a = degrees * PI / 180.0;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    ground->normal[0] = -sin(a);
    ground->normal[1] = 0.0;
    ground->normal[2] = cos(a);
    return scene;
}

static double height_of(const tb_scene *scene, size_t id)
{
    return tb_scene_states_const(scene)[TB_STATE_SIZE * id + 2];
}

/* Each shape set down level on the plane (its bottom at depth 0) rests, after the impact's
 * ringing has died (e^(-zeta omega t) = e^-110 by 1 s), with its centre sunk by the static
 * deflection M g / k: the points share the stiffness k = M omega^2 = M g / penetration, so the
 * deflection is the law's penetration (1e-4 m here) whatever the shape and the mass. Tolerance
 * 1e-3 of it, 1e-7 m: CVODE's error at rtol 1e-8 is 1e-9 m on the 0.1 m height, and the residual
 * of the ringing and the rounding of 0.1 m far less. */
static void rest_at_static_deflection(tb_method method, double rtol)
{
    const tb_shape_type types[4] = {TB_SHAPE_BOX, TB_SHAPE_SPHERE, TB_SHAPE_CYLINDER,
                                    TB_SHAPE_CONVEX};
    const double masses[4] = {8.0, 2.0, 3.0, 0.5};
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-4;
    tb_scene *scene = scene_on_plane(0.0, &ground);
    for (int k = 0; k < 4; ++k) {
        add_shaped(scene, types[k], masses[k], (double[]){1.0 * k, 0.0, 0.1}, NULL);
    }
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, rtol);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    for (size_t k = 0; k < 4; ++k) {
        const double sunk = 0.1 - height_of(scene, k);
        if (fabs(sunk - ground.penetration) > 1e-3 * ground.penetration) {
            print_message("%s body %zu: sunk %.9g m, penetration %g m\n", tb_method_name(method), k,
                          sunk, ground.penetration);
        }
        assert_true(fabs(sunk - ground.penetration) <= 1e-3 * ground.penetration);
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_shapes_without_points_rest_at_the_static_deflection(void **state)
{
    (void)state;
    rest_at_static_deflection(TB_METHOD_EULER, 0.0); /* at the scene's default step */
    rest_at_static_deflection(TB_METHOD_MIDPOINT, 0.0);
    rest_at_static_deflection(TB_METHOD_RK4, 0.0);
    rest_at_static_deflection(TB_METHOD_CVODE_BDF, 1e-8);
    rest_at_static_deflection(TB_METHOD_CVODE_ADAMS, 1e-8);
}

/* A body of two pieces (a dumbbell: two 5 cm spheres 0.4 m apart, set through the C API with no
 * contact points) meets the plane through both pieces and rests at the static deflection, as a
 * single shape does (same law, same tolerance as above); before bodies of several pieces met
 * the plane it fell through it. */
static void test_a_body_of_several_pieces_rests_on_the_plane(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-4;
    tb_scene *scene = scene_on_plane(0.0, &ground);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 2.0, (double[]){0.5, 0.1, 0.1}, &def.mass, NULL),
        TB_STATUS_OK);
    def.position[2] = 0.05;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape_piece pieces[2] = {tb_shape_piece_default(), tb_shape_piece_default()};
    for (int k = 0; k < 2; ++k) {
        pieces[k].shape.type = TB_SHAPE_SPHERE;
        pieces[k].shape.radius = 0.05;
        pieces[k].position[0] = k == 0 ? -0.2 : 0.2;
    }
    assert_int_equal(tb_scene_set_body_pieces(scene, id, pieces, 2), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double sunk = 0.05 - height_of(scene, id);
    assert_true(fabs(sunk - ground.penetration) <= 1e-3 * ground.penetration);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Along the slope's downhill direction (-cos a, 0, -sin a), the velocity of body 0. */
static double downhill_speed(const tb_scene *scene, double a)
{
    tb_body_state s;
    assert_int_equal(tb_scene_get_state(scene, 0, &s), TB_STATUS_OK);
    tb_mass_properties mass;
    assert_int_equal(tb_scene_get_mass(scene, 0, &mass), TB_STATUS_OK);
    return (-cos(a) * s.P[0] - sin(a) * s.P[2]) / mass.mass;
}

/* The acceleration down a slope of `degrees` of a body of shape type (a sphere or a box) set on
 * it at rest, from its speed at 0.5 s and 1 s (past the start's presliding and settling). */
static double slope_acceleration(tb_shape_type type, double degrees, double mu_s, double mu_k,
                                 double *speed, bool ground_first)
{
    const double a = degrees * PI / 180.0;
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = mu_s;
    ground.kinetic_friction = mu_k;
    tb_scene *scene = scene_on_plane(degrees, &ground);
    const double q[4] = {cos(-a / 2), 0.0, sin(-a / 2), 0.0}; /* turns z onto the normal */
    const double *n = ground.normal;
    if (ground_first) {
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    }
    add_shaped(scene, type, 2.0, (double[]){0.1 * n[0], 0.0, 0.1 * n[2]}, q);
    if (!ground_first) {
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    }
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-7);
    assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
    const double v0 = downhill_speed(scene, a);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double v1 = downhill_speed(scene, a);
    if (speed != NULL) {
        *speed = v1;
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return (v1 - v0) / 0.5;
}

/* A solid sphere rolls without slipping while the friction it needs, (2/7) tan(theta) of the
 * normal force, is below mu_s N: a = 5/7 g sin(theta). Below it slides at g (sin - mu_k cos).
 * Tolerance 1 %: the sphere rolls on a radius shorter by its static deflection (1e-5 of it), and
 * the stick anchor's presliding creep is 5e-7 m over the half second, 4e-6 m/s^2 (CVODE at
 * rtol 1e-7 adds 1e-7 relative). */
static void test_sphere_rolls_at_five_sevenths_or_slides(void **state)
{
    (void)state;
    const double theta = 20.0 * PI / 180.0; /* (2/7) tan = 0.104 */
    const double rolling = slope_acceleration(TB_SHAPE_SPHERE, 20.0, 0.6, 0.5, NULL, false);
    const double rolls = 5.0 / 7.0 * G * sin(theta);
    print_message("rolling: %.6g m/s^2, 5/7 g sin = %.6g\n", rolling, rolls);
    assert_true(fabs(rolling - rolls) <= 0.01 * rolls);
    const double sliding = slope_acceleration(TB_SHAPE_SPHERE, 20.0, 0.05, 0.05, NULL, false);
    const double slides = G * (sin(theta) - 0.05 * cos(theta));
    print_message("sliding: %.6g m/s^2, g (sin - mu_k cos) = %.6g\n", sliding, slides);
    assert_true(fabs(sliding - slides) <= 0.01 * slides);
}

/* A block on an incline holds while tan(theta) < mu_s (0.6) and slides at g (sin - mu_k cos)
 * above it (mu_k 0.5). Holding: its acceleration below 1e-4 m/s^2 and its speed below 1e-6 m/s
 * at 1 s, whether the ground was added before the block was given its shape or after (the plane's
 * friction slots then grow for it); a memoryless law would creep at its regularisation speed times
 * load / (mu_s N), millimetres per second. The stick anchor's deflection under the load is at
 * most presliding (5e-7 m), reached in the first milliseconds. Sliding: within 2 % (the slip is
 * 0.1 m/s by 0.5 s, ten times the Stribeck velocity, so mu is mu_k within e^-100). */
static void test_block_holds_below_mu_s_and_slides_above(void **state)
{
    (void)state;
    for (int first = 0; first < 2; ++first) { /* the ground added after the block, or before */
        double creep;
        const double holds =
            slope_acceleration(TB_SHAPE_BOX, atan(0.5) * 180.0 / PI, 0.6, 0.5, &creep, first);
        print_message("holding at tan 0.5: %.3g m/s^2, %.3g m/s\n", holds, creep);
        assert_true(fabs(holds) < 1e-4);
        assert_true(fabs(creep) < 1e-6);
    }
    const double theta = atan(0.7);
    const double sliding =
        slope_acceleration(TB_SHAPE_BOX, theta * 180.0 / PI, 0.6, 0.5, NULL, false);
    const double slides = G * (sin(theta) - 0.5 * cos(theta));
    print_message("sliding at tan 0.7: %.6g m/s^2, g (sin - mu_k cos) = %.6g\n", sliding, slides);
    assert_true(fabs(sliding - slides) <= 0.02 * slides);
}

/* A box dropped flat from 0.5 m lands on its four corners together and leaves at e times the
 * speed it hit with. Measured at depth 0 (height 0.1 m) going down and up, from frames 1e-5 s
 * apart, linearly interpolated (error (g + a) dt^2 / 8 in speed, negligible). Tolerance 1 %:
 * gravity acts through the push too, g pi / omega = 3 mm/s against 3.1 m/s (0.1 %), and CVODE's
 * error at rtol 1e-9. */
static void test_box_dropped_flat_bounces_with_the_restitution(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-6;
    ground.restitution = 0.5;
    tb_scene *scene = scene_on_plane(0.0, &ground);
    add_shaped(scene, TB_SHAPE_BOX, 8.0, (double[]){0.0, 0.0, 0.6}, NULL);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-9);
    double before = 0.0, after = 0.0, z_last = 0.6, v_last = 0.0;
    for (double t = 0.3; t < 0.34 && after == 0.0; t += 1e-5) {
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        const double z = height_of(scene, 0) - 0.1;
        const double v = tb_scene_states_const(scene)[9] / 8.0;
        if (z_last > 0.0 && z <= 0.0) {
            before = v_last + (v - v_last) * z_last / (z_last - z);
        } else if (z_last < 0.0 && z >= 0.0) {
            after = v_last + (v - v_last) * -z_last / (z - z_last);
        }
        z_last = z;
        v_last = v;
    }
    print_message("in %.6g m/s, out %.6g m/s: e = %.6g\n", before, after, -after / before);
    assert_true(before < -3.0);
    assert_true(fabs(-after / before - ground.restitution) <= 0.01 * ground.restitution);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A box dropped flat from 0.5 m touches down at t = sqrt(2 h / g) (free fall until then): CVODE
 * finds the event there, its gap falling through zero, within 1e-6 s at rtol 1e-8 (the root's
 * tolerance; issue 20). The event's gap is the deepest corner's, the shape's own. */
static void test_touchdown_is_an_event_at_the_fall_time(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(0.0, &ground);
    add_shaped(scene, TB_SHAPE_BOX, 8.0, (double[]){0.0, 0.0, 0.6}, NULL);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-8);
    const double fall = sqrt(2.0 * 0.5 / G);
    assert_int_equal(tb_integrator_advance(integrator, fall + 1e-4), TB_STATUS_OK);
    tb_integrator_events events;
    assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
    print_message("event at %.9g s (%ld), fall %.9g s\n", events.last_time, events.count, fall);
    assert_int_equal(events.count, 1);
    assert_int_equal(events.last_root, 0);
    assert_int_equal(events.last_direction, -1);
    assert_true(fabs(events.last_time - fall) <= 1e-6);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A shape starting deeper than 10 penetrations in the plane is refused as a body's points are,
 * the detail naming the body: when the ground is added (nothing added: the effect count stays),
 * and when an integrator is made on a scene whose body was given its shape after the ground. */
static void test_shape_deep_in_the_plane_is_refused_naming_the_body(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(0.0, &ground);
    add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){0.0, 0.0, 0.09}, NULL); /* 1 cm deep */
    const size_t effects = tb_scene_effect_count(scene);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "body 0 (\"body0\")"));
    assert_int_equal(tb_scene_effect_count(scene), effects);
    tb_scene_destroy(scene);

    scene = scene_on_plane(0.0, &ground);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){0.0, 0.0, 0.09}, NULL);
    tb_integrator *integrator = NULL;
    const tb_integrator_def def = test_integrator_def(TB_METHOD_RK4, 1e-4, 0.0);
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_null(integrator);
    print_message("%s\n", tb_scene_detail(scene));
    assert_non_null(strstr(tb_scene_detail(scene), "body 0 (\"body0\")"));
    tb_scene_destroy(scene);
}

/* The 8 kg box set level on the level plane of penetration 1e-4 m, its bottom at depth 0. */
static tb_scene *box_set_on_the_plane(tb_ground_def *ground)
{
    ground->penetration = 1e-4;
    tb_scene *scene = scene_on_plane(0.0, ground);
    add_shaped(scene, TB_SHAPE_BOX, 8.0, (double[]){0.0, 0.0, 0.1}, NULL);
    assert_int_equal(tb_scene_add_ground(scene, ground), TB_STATUS_OK);
    return scene;
}

/* The read-out of what touches (tb_scene_contact_touching) lists a body the ground meets through
 * its shape: a box resting flat, its 4 bottom corners, depth the static deflection (within 1e-3
 * of it, as the rest test). */
static void test_touching_lists_a_shape_on_the_ground(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = box_set_on_the_plane(&ground);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-8);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    tb_contact_touch touch[2];
    size_t count = 0;
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), touch, 2, &count),
        TB_STATUS_OK);
    assert_int_equal(count, 1);
    assert_int_equal(touch[0].body_a, 0);
    assert_int_equal(touch[0].body_b, TB_WORLD);
    assert_int_equal(touch[0].points, 4);
    assert_true(fabs(touch[0].depth - ground.penetration) <= 1e-3 * ground.penetration);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A box at rest on the ground through its shape falls asleep (its island, itself, slow for
 * TB_SLEEP_TIME) and stays where it rested: asleep, its derivative is 0, its friction slots
 * frozen. Within 1e-9 m of where it was at 1 s (it had stopped: e^-110 of its ringing left). */
static void test_shape_on_the_ground_falls_asleep_where_it_rests(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = box_set_on_the_plane(&ground);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double rested = height_of(scene, 0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0 + 2.0 * TB_SLEEP_TIME), TB_STATUS_OK);
    size_t asleep = 0;
    assert_int_equal(tb_scene_asleep_count(scene, &asleep), TB_STATUS_OK);
    assert_int_equal(asleep, 1);
    assert_true(fabs(height_of(scene, 0) - rested) <= 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A body with contact points keeps the points' law whether or not it also has a shape: the same
 * box with its 8 corners as points, with and without a box shape, moves bit for bit alike. */
static void test_points_keep_their_law_when_the_body_has_a_shape(void **state)
{
    (void)state;
    double y[3][TB_STATE_SIZE];
    for (int shaped = 0; shaped < 3; ++shaped) { /* 2: the points set after the plane */
        tb_ground_def ground = tb_ground_def_default();
        tb_scene *scene = scene_on_plane(10.0, &ground);
        const double size[3] = {0.4, 0.4, 0.2};
        const size_t id = add_shaped(scene, TB_SHAPE_BOX, 8.0, (double[]){0, 0, 0.3}, NULL);
        if (!shaped) {
            assert_int_equal(tb_scene_set_body_shape(scene, id, NULL), TB_STATUS_OK);
        }
        if (shaped == 2) {
            assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        }
        tb_contact_point corners[8];
        size_t count;
        assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, id, corners, count, 4), TB_STATUS_OK);
        if (shaped < 2) {
            assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        }
        tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
        assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
        memcpy(y[shaped], tb_scene_states_const(scene), sizeof y[shaped]);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    assert_memory_equal(y[0], y[1], sizeof y[0]);
    assert_memory_equal(y[0], y[2], sizeof y[0]);
}

/* Points set body by body are checked body by body (tb_scene_set_contact_points checks the body's
 * own points and shape, not every point's depth again: O(n) for n bodies, bench_setup). A body
 * whose points are removed meets the plane through its shape again, and its shape's depth is
 * checked then: a 0.1 m ball 1 cm deep (100 penetrations of 1e-4 m) carried by a point at its
 * centre is refused when the point goes, naming the body, nothing changed. */
static void test_removing_points_checks_the_shape_they_held_up(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(0.0, &ground);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    const size_t clear = add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){1.0, 0.0, 0.5}, NULL);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    def.position[2] = 0.09;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    const tb_contact_point centre = {{0.0, 0.0, 0.0}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, id, &centre, 1, 1), TB_STATUS_OK);
    tb_shape ball = tb_shape_default();
    ball.type = TB_SHAPE_SPHERE;
    ball.radius = 0.1;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &ball), TB_STATUS_OK);
    const size_t size = tb_scene_state_size(scene);
    double before[2 * TB_STATE_SIZE + 64];
    assert_true(size <= sizeof before / sizeof before[0]);
    memcpy(before, tb_scene_states_const(scene), size * sizeof(double));
    assert_int_equal(tb_scene_set_contact_points(scene, id, NULL, 0, 0),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "body 1 (\"body1\"): its shape starts"));
    size_t points = 0;
    assert_int_equal(tb_scene_body_contact_point_count(scene, id, &points), TB_STATUS_OK);
    assert_int_equal(points, 1);
    assert_int_equal(tb_scene_state_size(scene), size);
    assert_memory_equal(tb_scene_states_const(scene), before, size * sizeof(double));
    assert_int_equal(tb_scene_set_contact_points(scene, clear, &centre, 1, 1), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, clear, NULL, 0, 0), TB_STATUS_OK);
    tb_scene_destroy(scene);
}

/* Points refused (one starting 0.4 m below the plane) leave the plane meeting the ball's shape:
 * the refused call noted the body as one with points, so the plane skipped its shape and the
 * ball, resting at z = 0.1 m, fell through it (z = -3.5 m one second later) under the integrator
 * made before. It rests there still: its centre sinks by the penetration (8e-7 m by default);
 * the tolerance, 1e-5 m, is 12 penetrations and far from the 4.9 m of a free fall. */
static void test_refused_points_leave_the_plane_under_the_shape(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(0.0, &ground);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    const size_t id = add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){0.0, 0.0, 0.1}, NULL);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-8);
    assert_int_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_OK);
    const tb_contact_point deep = {{0.0, 0.0, -0.5}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, id, &deep, 1, 1),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_integrator_advance(integrator, 1.2), TB_STATUS_OK);
    assert_true(fabs(height_of(scene, id) - 0.1) < 1e-5);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* The same with two planes: a wall at x = -1 (added first) takes the points (the point is 0.6 m
 * clear of it) and the floor refuses them; the wall had noted the body as one with points and
 * kept that, so the ball rolling at 1 m/s passed through the wall (x = -1.44 m at 2 s). Now it
 * meets the wall within a second and comes back: its centre never passes x = -0.9 m, the wall
 * less its radius (the tolerance: the law's penetration, 8e-7 m, is far below the 0.5 m margin
 * of the passing ball). */
static void test_points_refused_by_one_plane_leave_the_others_as_they_were(void **state)
{
    (void)state;
    tb_ground_def wall = tb_ground_def_default(), floor = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(0.0, &floor);
    wall.normal[0] = 1.0;
    wall.normal[2] = 0.0;
    wall.offset = -1.0;
    assert_int_equal(tb_scene_add_ground(scene, &wall), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_ground(scene, &floor), TB_STATUS_OK);
    const size_t id = add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){0.0, 0.0, 0.1}, NULL);
    assert_int_equal(
        tb_scene_set_velocity(scene, id, (double[]){-1.0, 0.0, 0.0}, (double[]){0.0, 0.0, 0.0}),
        TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-8);
    assert_int_equal(tb_integrator_advance(integrator, 0.05), TB_STATUS_OK);
    const tb_contact_point deep = {{0.0, 0.0, -0.5}, 0.0};
    assert_int_equal(tb_scene_set_contact_points(scene, id, &deep, 1, 1),
                     TB_STATUS_INVALID_ARGUMENT);
    double least = INFINITY;
    for (int k = 1; k <= 40; ++k) {
        assert_int_equal(tb_integrator_advance(integrator, 0.05 * k), TB_STATUS_OK);
        least = fmin(least, tb_scene_states_const(scene)[TB_STATE_SIZE * id]);
    }
    assert_true(least > -0.9 - 1e-6);
    assert_true(tb_scene_states_const(scene)[TB_STATE_SIZE * id] > -0.9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A box on a slope of 28 degrees (tan 0.53, between mu_k 0.5 and mu_s 0.6) is held by its stick
 * anchors alone. A second body given a shape after the plane grows the plane's friction pool and
 * the states are laid out again; with three static bodies (no state) before them, that layout
 * put the effects' states at 13 doubles per body, not per body with a state: past the end of y
 * (F106), and the box slid 0.27 m in a second under RK4 (what lay past y). Held, it moves by its
 * anchor's deflection, at most presliding (5e-7 m) along the slope; tolerance 1e-5 m. */
static void test_a_shape_set_beside_static_bodies_keeps_the_anchors_in_the_state(void **state)
{
    (void)state;
    const double degrees = 28.0, a = degrees * PI / 180.0;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = scene_on_plane(degrees, &ground);
    for (int k = 0; k < 3; ++k) {
        tb_body_def fixed = tb_body_def_default();
        fixed.motion = TB_MOTION_STATIC;
        fixed.position[0] = -100.0 - k;
        fixed.position[2] = 100.0;
        assert_int_equal(tb_scene_add_body(scene, &fixed, NULL), TB_STATUS_OK);
    }
    const double q[4] = {cos(-a / 2), 0.0, sin(-a / 2), 0.0}, up = 0.1 - 5e-7;
    const size_t box =
        add_shaped(scene, TB_SHAPE_BOX, 8.0, (double[]){-sin(a) * up, 0.0, cos(a) * up}, q);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    add_shaped(scene, TB_SHAPE_SPHERE, 1.0, (double[]){-50.0, 0.0, 5.0}, NULL);
    const double x0 = tb_scene_states_const(scene)[TB_STATE_SIZE * 0];
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double moved = tb_scene_states_const(scene)[TB_STATE_SIZE * 0] - x0;
    print_message("the box moved %.3g m along x (slot 0 is body %zu)\n", moved, box);
    assert_true(fabs(moved) < 1e-5);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shapes_without_points_rest_at_the_static_deflection),
        cmocka_unit_test(test_a_body_of_several_pieces_rests_on_the_plane),
        cmocka_unit_test(test_sphere_rolls_at_five_sevenths_or_slides),
        cmocka_unit_test(test_block_holds_below_mu_s_and_slides_above),
        cmocka_unit_test(test_box_dropped_flat_bounces_with_the_restitution),
        cmocka_unit_test(test_touchdown_is_an_event_at_the_fall_time),
        cmocka_unit_test(test_shape_deep_in_the_plane_is_refused_naming_the_body),
        cmocka_unit_test(test_touching_lists_a_shape_on_the_ground),
        cmocka_unit_test(test_shape_on_the_ground_falls_asleep_where_it_rests),
        cmocka_unit_test(test_points_keep_their_law_when_the_body_has_a_shape),
        cmocka_unit_test(test_removing_points_checks_the_shape_they_held_up),
        cmocka_unit_test(test_refused_points_leave_the_plane_under_the_shape),
        cmocka_unit_test(test_points_refused_by_one_plane_leave_the_others_as_they_were),
        cmocka_unit_test(test_a_shape_set_beside_static_bodies_keeps_the_anchors_in_the_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
