/* Bodies of several convex pieces (tb_scene_set_body_pieces): their mass properties against the
 * parallel-axis theorem, resting and bouncing on their pieces, never touching themselves, one
 * piece at the identity pose equal to the plain shape bit for bit, and refusals that change
 * nothing. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "near.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define RADIUS 0.05   /* m: the dumbbell's spheres */
#define HALF_BAR 0.2  /* m: each sphere's centre from the dumbbell's middle */
#define DENSITY 1000. /* kg/m^3 */
#define PI 3.14159265358979323846

static tb_shape sphere(double radius)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_SPHERE;
    s.radius = radius;
    return s;
}

static tb_shape box(double x, double y, double z)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_BOX;
    s.size[0] = x, s.size[1] = y, s.size[2] = z;
    return s;
}

static tb_shape_piece piece_at(tb_shape shape, double x, double y, double z)
{
    tb_shape_piece p = tb_shape_piece_default();
    p.shape = shape;
    p.position[0] = x, p.position[1] = y, p.position[2] = z;
    return p;
}

/* Two spheres of radius r at x = -d and +d: mass 2 m, centre at 0, moments 2 (2/5 m r^2) about
 * x and 2 (2/5 m r^2 + m d^2) about y and z (Steiner), m = 4/3 pi r^3 rho. Combined by the
 * library both ways (tb_mass_combine and the scene file's list) to 1e-12 relative (round-off of
 * sums of a few terms). */
static void test_dumbbell_mass_is_the_parallel_axis_theorems(void **state)
{
    (void)state;
    const double m = 4.0 / 3.0 * PI * pow(RADIUS, 3) * DENSITY;
    const double own = 0.4 * m * RADIUS * RADIUS,
                 expected[3] = {2 * own, 2 * (own + m * HALF_BAR * HALF_BAR),
                                2 * (own + m * HALF_BAR * HALF_BAR)};
    tb_mass_part parts[2];
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(
            tb_mass_from_sphere(TB_MASS_DENSITY, DENSITY, RADIUS, &parts[k].props, NULL),
            TB_STATUS_OK);
        memcpy(parts[k].position, (double[3]){k ? HALF_BAR : -HALF_BAR, 0, 0}, 3 * sizeof(double));
        memcpy(parts[k].orientation, (double[4]){1, 0, 0, 0}, 4 * sizeof(double));
    }
    tb_mass_properties combined;
    assert_int_equal(tb_mass_combine(parts, 2, &combined, NULL), TB_STATUS_OK);
    const char *json = "{\"bodies\": [{\"name\": \"dumbbell\", \"density\": 1000, \"shape\": ["
                       "{\"type\": \"sphere\", \"radius\": 0.05, \"position\": [-0.2, 0, 0]},"
                       "{\"type\": \"sphere\", \"radius\": 0.05, \"position\": [0.2, 0, 0],"
                       " \"orientation\": [0, 0, 0, 1]}]}], \"effects\": []}";
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "dumbbell", NULL, &scene, NULL, &error),
                     TB_STATUS_OK);
    tb_mass_properties loaded;
    assert_int_equal(tb_scene_get_mass(scene, 0, &loaded), TB_STATUS_OK);
    const tb_mass_properties *both[2] = {&combined, &loaded};
    for (int k = 0; k < 2; ++k) {
        assert_near(both[k]->mass, 2 * m, 1e-12 * m);
        for (int i = 0; i < 3; ++i) {
            assert_near(both[k]->center[i], 0.0, 1e-12 * HALF_BAR);
            assert_near(both[k]->moments[i], expected[i], 1e-12 * expected[1]);
        }
    }
    size_t count = 0;
    assert_int_equal(tb_scene_body_piece_count(scene, 0, &count), TB_STATUS_OK);
    assert_int_equal(count, 2);
    tb_shape_piece second;
    assert_int_equal(tb_scene_body_piece(scene, 0, 1, &second), TB_STATUS_OK);
    assert_int_equal(second.shape.type, TB_SHAPE_SPHERE);
    assert_true(second.position[0] == 0.2 && second.orientation[3] == 1.0);
    tb_scene_destroy(scene);
}

/* A body of mass M and the given pieces, centre of mass at x (the pieces' frame is the body's
 * shape frame: props' centre at the origin for these symmetric sets). */
static size_t add_compound(tb_scene *scene, const tb_shape_piece *pieces, size_t count, double M,
                           const double x[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, M, (double[3]){0.5, 0.2, 0.2}, &def.mass, NULL),
        TB_STATUS_OK);
    memcpy(def.position, x, sizeof def.position);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_pieces(scene, id, pieces, count), TB_STATUS_OK);
    return id;
}

static void advance(tb_scene *scene, double seconds)
{
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, seconds), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
}

/* A 1 kg dumbbell (two spheres, nothing between them) dropped 1 cm onto a 100 kg slab standing
 * on the ground rests on both spheres: each carries M g / 2 on a spring k = M omega^2
 * (omega^2 = g / penetration, the lighter body's mass), so it sinks pen / 2 into the slab and its
 * centre ends r - pen / 2 above the slab's top; the slab's own sinking is taken out by measuring
 * from its top. Within pen / 10 (the law's damping is at rest; what is left is the fall's
 * ringing and the rolling the step's round-off starts); at rest within 1e-4 m/s. */
static void test_dumbbell_rests_on_a_slab_on_both_pieces(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    tb_body_def slab = tb_body_def_default();
    const double size[3] = {2.0, 2.0, 0.2};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 100.0, size, &slab.mass, NULL), 0);
    slab.position[2] = 0.1;
    size_t slab_id = 0;
    assert_int_equal(tb_scene_add_body(scene, &slab, &slab_id), TB_STATUS_OK);
    const tb_shape slab_shape = box(size[0], size[1], size[2]);
    assert_int_equal(tb_scene_set_body_shape(scene, slab_id, &slab_shape), TB_STATUS_OK);
    tb_contact_point corners[8];
    size_t corner_count = 0;
    tb_contact_points_box(size, corners, 8, &corner_count);
    assert_int_equal(tb_scene_set_contact_points(scene, slab_id, corners, corner_count, 4), 0);
    const tb_shape_piece pieces[2] = {piece_at(sphere(RADIUS), -HALF_BAR, 0, 0),
                                      piece_at(sphere(RADIUS), HALF_BAR, 0, 0)};
    const size_t id = add_compound(scene, pieces, 2, 1.0, (double[3]){0, 0, 0.2 + RADIUS + 0.01});
    assert_int_equal(tb_scene_add_gravity(scene, (double[3]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    advance(scene, 1.0);
    const double *y = tb_scene_states_const(scene);
    const double top = y[TB_STATE_SIZE * slab_id + 2] + 0.5 * size[2];
    const double height = y[TB_STATE_SIZE * id + 2] - top;
    assert_near(height, RADIUS - 0.5 * contact.penetration, 0.1 * contact.penetration);
    double v[3];
    assert_int_equal(tb_scene_body_velocity(scene, y, id, v), TB_STATUS_OK);
    assert_true(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) < 1e-4);
    tb_scene_destroy(scene);
}

/* A 0.1 kg ball moving at 1 m/s along -x, in free space, meets the second piece of a 1 kg body
 * (a plate at x = +0.3 m from its centre; the first piece, at x = -0.3 m, is behind it): the
 * ball comes back (the contact pushes it from that piece), and the pair's momentum is the
 * ball's first momentum to round-off (1e-12 kg m/s: the contact's forces are equal and
 * opposite at one point). */
static void test_a_ball_bounces_off_a_bodys_second_piece(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const tb_shape_piece pieces[2] = {piece_at(box(0.02, 0.2, 0.2), -0.3, 0, 0),
                                      piece_at(box(0.02, 0.2, 0.2), 0.3, 0, 0)};
    const size_t id = add_compound(scene, pieces, 2, 1.0, (double[3]){0, 0, 0});
    const size_t ball =
        test_add_ball(scene, "ball", 0.1, 0.02, (double[3]){0.35, 0, 0}, (double[3]){-1, 0, 0});
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    advance(scene, 0.05);
    const double *y = tb_scene_states_const(scene);
    assert_true(y[TB_STATE_SIZE * ball + TB_STATE_P] > 0.0);
    assert_true(y[TB_STATE_SIZE * ball] > 0.3);
    for (int i = 0; i < 3; ++i) {
        const double P =
            y[TB_STATE_SIZE * ball + TB_STATE_P + i] + y[TB_STATE_SIZE * id + TB_STATE_P + i];
        assert_near(P, i == 0 ? -0.1 : 0.0, 1e-12);
    }
    tb_scene_destroy(scene);
}

/* Two boxes of one body overlapping by 5 cm, alone with a contact effect, at rest in free space:
 * no pair is ever found, so the momenta stay exactly 0 and the pose exactly its start. */
static void test_pieces_of_one_body_never_touch_each_other(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const tb_shape_piece pieces[2] = {piece_at(box(0.2, 0.2, 0.2), -0.075, 0, 0),
                                      piece_at(box(0.2, 0.2, 0.2), 0.075, 0, 0)};
    add_compound(scene, pieces, 2, 1.0, (double[3]){0, 0, 1});
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    double start[TB_STATE_SIZE];
    memcpy(start, tb_scene_states_const(scene), sizeof start);
    advance(scene, 0.05);
    assert_memory_equal(start, tb_scene_states_const(scene), sizeof start);
    size_t touching = 1;
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), NULL, 0, &touching),
        TB_STATUS_OK);
    assert_int_equal(touching, 0);
    tb_scene_destroy(scene);
}

/* A box dropped tilted on another, once with tb_scene_set_body_shape and once as a list of one
 * piece at the identity pose: the same states, bit for bit, after 0.2 s of impacts. */
static tb_scene *tilted_drop(bool as_pieces)
{
    tb_scene *scene = test_empty_scene();
    const double low[3] = {0, 0, 0}, high[3] = {0.02, 0.01, 0.25};
    const tb_shape shape = box(0.3, 0.2, 0.1);
    for (int k = 0; k < 2; ++k) {
        tb_body_def def = tb_body_def_default();
        assert_int_equal(tb_mass_from_box(TB_MASS_DENSITY, 500, shape.size, &def.mass, NULL), 0);
        memcpy(def.position, k ? high : low, sizeof def.position);
        memcpy(def.orientation, (double[4]){cos(0.1), sin(0.1), 0, 0}, sizeof def.orientation);
        size_t id = 0;
        assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
        const tb_shape_piece one = piece_at(shape, 0, 0, 0);
        assert_int_equal(as_pieces ? tb_scene_set_body_pieces(scene, id, &one, 1)
                                   : tb_scene_set_body_shape(scene, id, &shape),
                         TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[3]){0, 0, -9.81}), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    advance(scene, 0.2);
    return scene;
}

static void test_one_piece_at_the_origin_is_the_plain_shape_bit_for_bit(void **state)
{
    (void)state;
    tb_scene *plain = tilted_drop(false), *pieces = tilted_drop(true);
    assert_int_equal(tb_scene_state_size(plain), tb_scene_state_size(pieces));
    assert_memory_equal(tb_scene_states_const(plain), tb_scene_states_const(pieces),
                        tb_scene_state_size(plain) * sizeof(double));
    tb_shape_type type = TB_SHAPE_NONE;
    assert_int_equal(tb_scene_body_shape_type(pieces, 1, &type), TB_STATUS_OK);
    assert_int_equal(type, TB_SHAPE_BOX);
    assert_true(tb_scene_states_const(plain)[TB_STATE_SIZE + 2] < 0.2); /* it fell and hit */
    tb_scene_destroy(plain);
    tb_scene_destroy(pieces);
}

/* What a refusal must leave alone: the body's pieces as read out (with a convex piece's
 * vertices) and the states. */
typedef struct snapshot {
    size_t count;
    tb_shape_piece pieces[2];
    double vertices[2][24];
    double states[TB_STATE_SIZE];
} snapshot;

static void take(const tb_scene *scene, snapshot *s)
{
    memset(s, 0, sizeof *s);
    assert_int_equal(tb_scene_body_piece_count(scene, 0, &s->count), TB_STATUS_OK);
    for (size_t k = 0; k < s->count && k < 2; ++k) {
        assert_int_equal(tb_scene_body_piece(scene, 0, k, &s->pieces[k]), TB_STATUS_OK);
        const tb_shape *shape = &s->pieces[k].shape;
        if (shape->vertices != NULL) {
            memcpy(s->vertices[k], shape->vertices, 3 * shape->vertex_count * sizeof(double));
        }
    }
    memcpy(s->states, tb_scene_states_const(scene), sizeof s->states);
}

static void test_refused_pieces_change_nothing(void **state)
{
    (void)state;
    const double tetrahedron[12] = {0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1};
    tb_shape hull = tb_shape_default();
    hull.type = TB_SHAPE_CONVEX;
    hull.vertices = tetrahedron;
    hull.vertex_count = 4;
    const tb_shape_piece good[2] = {piece_at(hull, 0, 0, 0.1),
                                    piece_at(box(0.1, 0.1, 0.1), 0, 0, 0)};
    tb_shape_piece unnormal[2] = {good[0], good[1]}, far[2] = {good[0], good[1]};
    tb_shape_piece empty[2] = {good[0], piece_at(tb_shape_default(), 0, 0, 0)};
    tb_shape_piece bad_radius[2] = {good[0], piece_at(sphere(-1.0), 0, 0, 0)};
    unnormal[1].orientation[0] = 2.0;
    far[1].position[2] = NAN;
    const struct {
        const tb_shape_piece *pieces;
        size_t count;
        tb_status expected;
        const char *detail; /* the detail's start */
    } cases[] = {
        {NULL, 2, TB_STATUS_NULL_POINTER, "pieces is NULL"},
        {good, 0, TB_STATUS_INVALID_ARGUMENT, "count: must be in [1, 1000000], got 0"},
        {good, 2000000, TB_STATUS_INVALID_ARGUMENT, "count: must be in [1, 1000000]"},
        {unnormal, 2, TB_STATUS_INVALID_ARGUMENT, "pieces[1].orientation: must be a unit"},
        {far, 2, TB_STATUS_NOT_FINITE, "pieces[1].position[2]: must be finite"},
        {empty, 2, TB_STATUS_INVALID_ARGUMENT, "pieces[1].shape.type: a piece must have"},
        {bad_radius, 2, TB_STATUS_INVALID_ARGUMENT, "pieces[1].radius: must be > 0"},
    };
    tb_scene *scene = test_empty_scene();
    add_compound(scene, good, 2, 1.0, (double[3]){0, 0, 1});
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        snapshot before, after;
        take(scene, &before);
        assert_int_equal(tb_scene_set_body_pieces(scene, 0, cases[i].pieces, cases[i].count),
                         cases[i].expected);
        assert_memory_equal(tb_scene_detail(scene), cases[i].detail, strlen(cases[i].detail));
        take(scene, &after);
        assert_memory_equal(&before, &after, sizeof before);
    }
    assert_int_equal(tb_scene_set_body_pieces(scene, 1, good, 2), TB_STATUS_OUT_OF_RANGE);
    tb_shape_piece out;
    assert_int_equal(tb_scene_body_piece(scene, 0, 2, &out), TB_STATUS_OUT_OF_RANGE);
    assert_int_equal(tb_scene_body_piece(scene, 0, 0, NULL), TB_STATUS_NULL_POINTER);
    tb_scene_destroy(scene);
}

/* An OBJ file of two objects ("o"), two 10 cm cubes 10 cm apart along x, is a body of two
 * pieces: each piece has its cube's 8 vertices, and the mass is the two cubes' (2 x 1 kg at
 * 1000 kg/m^3, 1e-12 relative). A 2 cm ball shot down through the gap between them at 1 m/s
 * passes without touching (the body's momentum stays exactly 0): one hull of both cubes would
 * have stopped it. */
static void test_an_obj_of_two_objects_is_a_body_of_two_pieces(void **state)
{
    (void)state;
    char folder[] = "/tmp/tumble_compound_XXXXXX", path[64];
    assert_non_null(mkdtemp(folder));
    snprintf(path, sizeof path, "%s/two_cubes.obj", folder);
    FILE *file = fopen(path, "w");
    assert_non_null(file);
    for (int cube = 0; cube < 2; ++cube) {
        const double x = cube ? 0.1 : -0.1;
        fprintf(file, "o cube%d\n", cube);
        for (int v = 0; v < 8; ++v) {
            fprintf(file, "v %.17g %g %g\n", x + (v & 1 ? 0.05 : -0.05), v & 2 ? 0.05 : -0.05,
                    v & 4 ? 0.05 : -0.05);
        }
        static const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                                        {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
        for (int f = 0; f < 6; ++f) {
            fprintf(file, "f %d %d %d %d\n", faces[f][0] + 8 * cube, faces[f][1] + 8 * cube,
                    faces[f][2] + 8 * cube, faces[f][3] + 8 * cube);
        }
    }
    assert_int_equal(fclose(file), 0);
    const char *json =
        "{\"bodies\": [{\"name\": \"cubes\", \"density\": 1000,"
        " \"shape\": {\"type\": \"mesh\", \"file\": \"two_cubes.obj\"}},"
        " {\"name\": \"ball\", \"mass\": 0.01, \"shape\": {\"type\": \"sphere\", \"radius\": 0.02},"
        "  \"position\": [0, 0, 0.1], \"velocity\": [0, 0, -1]}],"
        " \"effects\": [{\"type\": \"contact\"}]}";
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "cubes", folder, &scene, NULL, &error),
                     TB_STATUS_OK);
    size_t count = 0;
    assert_int_equal(tb_scene_body_piece_count(scene, 0, &count), TB_STATUS_OK);
    assert_int_equal(count, 2);
    for (size_t k = 0; k < 2; ++k) {
        tb_shape_piece piece;
        assert_int_equal(tb_scene_body_piece(scene, 0, k, &piece), TB_STATUS_OK);
        assert_int_equal(piece.shape.type, TB_SHAPE_CONVEX);
        assert_int_equal(piece.shape.vertex_count, 8);
    }
    tb_mass_properties mass;
    assert_int_equal(tb_scene_get_mass(scene, 0, &mass), TB_STATUS_OK);
    assert_near(mass.mass, 2.0, 2e-12);
    advance(scene, 0.25);
    const double *y = tb_scene_states_const(scene);
    assert_true(y[TB_STATE_SIZE + 2] < -0.1); /* the ball went through */
    for (int i = 0; i < 3; ++i) {
        assert_true(y[TB_STATE_P + i] == 0.0);
    }
    tb_scene_destroy(scene);
    remove(path);
    rmdir(folder);
}

/* A ball sunk 0.1 mm into a corner of three pieces (a floor and two walls) touches each: the
 * read-out lists the body pair once, with the three pieces' points (one each, a sphere's
 * manifold) and the depth 0.1 mm (1e-12 m: the closed form's round-off). */
static void test_a_corner_of_three_pieces_is_one_touch_of_three_points(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const tb_shape_piece corner[3] = {piece_at(box(0.2, 0.2, 0.02), 0, 0, -0.01),
                                      piece_at(box(0.02, 0.2, 0.2), -0.11, 0, 0.1),
                                      piece_at(box(0.2, 0.02, 0.2), 0, -0.11, 0.1)};
    add_compound(scene, corner, 3, 1.0, (double[3]){0, 0, 0});
    const double r = 0.05 + 1e-4; /* 0.1 mm into the floor and each wall's inner face */
    test_add_ball(scene, "ball", 0.1, r, (double[3]){-0.1 + 0.05, -0.1 + 0.05, 0.05}, NULL);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_contact_touch touches[4];
    size_t count = 0;
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), touches, 4, &count),
        TB_STATUS_OK);
    assert_int_equal(count, 1);
    assert_int_equal(touches[0].points, 3);
    assert_near(touches[0].depth, 1e-4, 1e-12);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dumbbell_mass_is_the_parallel_axis_theorems),
        cmocka_unit_test(test_dumbbell_rests_on_a_slab_on_both_pieces),
        cmocka_unit_test(test_a_ball_bounces_off_a_bodys_second_piece),
        cmocka_unit_test(test_pieces_of_one_body_never_touch_each_other),
        cmocka_unit_test(test_one_piece_at_the_origin_is_the_plain_shape_bit_for_bit),
        cmocka_unit_test(test_refused_pieces_change_nothing),
        cmocka_unit_test(test_an_obj_of_two_objects_is_a_body_of_two_pieces),
        cmocka_unit_test(test_a_corner_of_three_pieces_is_one_touch_of_three_points),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
