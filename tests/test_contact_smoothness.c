/* The contact's right-hand side is continuous where bodies rest (issue 23, item 1; issue 19,
 * item 4). A body resting on another rocks slowly along a prescribed path of poses (a tilt turning
 * round its axis, a spin about it, a slide across the lower body), its base's centre 1 micrometre
 * into the lower body: tilted 1e-5 rad every point of its base stays pressed; tilted 5e-5 rad (a
 * can rocking on its rim) a third of it lifts and lands again. The bodies are at rest, so the
 * derivative is the contact's springs alone, a function of the poses that physics makes
 * continuous (each point of a pressed face pushes in proportion to its depth). Sampled at 4 000
 * poses along the path, the upper body's force and torque change from one sample to the next by
 * about 2 pi / 4 000 of their swing (measured: 2.4e-4 of the mean force, 1.5e-3 on the rim); a
 * jump is a change of more than 2 % of the mean force F0, or of F0 times the base's reach in the
 * torque: ten times that. None may jump. Before the general pairs' manifolds (MPR's single
 * point) the can on a can jumped 140 times, by up to 311 times the mean force, the can on its rim
 * 112 times and the mesh cubes 8 times (by up to 1.35); with clipped faces cut to 4 of their
 * points by depth, 13 and 6 times (by up to 21 %). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SAMPLES 4000
#define SINK 1e-6 /* m: the base's centre below the lower body's top */
#define JUMP 0.02 /* of F0 (force) and F0 R (torque) */

static double mesh_cube[24];

typedef struct resting_case {
    const char *name;
    tb_shape lower, upper;
    double lower_top;    /* m above the lower body's centre */
    double upper_bottom; /* m below the upper body's centre */
    double radius;       /* the upper base's reach from its centre, m */
    double slide;        /* m the upper body slides in x over the path */
    double tilt;         /* rad: the rocking's amplitude */
} resting_case;

static size_t add(tb_scene *scene, const tb_shape *shape, double mass)
{
    tb_body_def def = tb_body_def_default();
    const double moments = 0.01 * mass;
    assert_int_equal(tb_mass_from_tensor(mass, (double[]){0, 0, 0},
                                         (double[]){moments, 0, 0, 0, moments, 0, 0, 0, moments},
                                         &def.mass, NULL),
                     TB_STATUS_OK);
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, id, shape), TB_STATUS_OK);
    return id;
}

/* The upper body's pose at path parameter s in [0, 1]: spin about z, then the tilt, whose
 * axis turns round once; its base's centre SINK below the lower body's top. */
static void pose_at(const resting_case *c, double s, double *y)
{
    const double spin = 0.3 * s, turn = 2.0 * 3.14159265358979323846 * s;
    const double qs[4] = {cos(0.5 * spin), 0.0, 0.0, sin(0.5 * spin)};
    const double half = 0.5 * c->tilt * (0.6 + 0.4 * sin(3.0 * turn));
    const double qt[4] = {cos(half), sin(half) * cos(turn), sin(half) * sin(turn), 0.0};
    double *q = y + TB_STATE_SIZE + TB_STATE_Q;
    q[0] = qt[0] * qs[0] - qt[3] * qs[3];
    q[1] = qt[1] * qs[0] + qt[2] * qs[3];
    q[2] = qt[2] * qs[0] - qt[1] * qs[3];
    q[3] = qt[0] * qs[3] + qt[3] * qs[0];
    double *x = y + TB_STATE_SIZE + TB_STATE_X;
    x[0] = c->slide * s;
    x[1] = 0.1 * c->slide * s;
    x[2] = c->lower_top + c->upper_bottom * cos(2.0 * half) - SINK;
}

/* The number of jumps of the upper body's force and torque along the path. */
static int jumps(const resting_case *c)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    add(scene, &c->lower, 3.0);
    add(scene, &c->upper, 1.0);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    const size_t n = tb_scene_state_size(scene);
    double *y = calloc(n, sizeof(double)), *dydt = calloc(n, sizeof(double));
    double *history = malloc(6 * SAMPLES * sizeof(double));
    assert_true(y != NULL && dydt != NULL && history != NULL);
    memcpy(y, tb_scene_states(scene), n * sizeof(double));
    double mean = 0.0;
    for (int k = 0; k < SAMPLES; ++k) {
        pose_at(c, (double)k / (SAMPLES - 1), y);
        assert_int_equal(tb_scene_derivative(0.0, y, dydt, scene), 0);
        memcpy(history + 6 * k, dydt + TB_STATE_SIZE + TB_STATE_P, 3 * sizeof(double));
        memcpy(history + 6 * k + 3, dydt + TB_STATE_SIZE + TB_STATE_L, 3 * sizeof(double));
        mean += history[6 * k + 2] / SAMPLES;
    }
    int count = 0;
    double largest = 0.0;
    for (int k = 1; k < SAMPLES; ++k) {
        double change = 0.0;
        for (int i = 0; i < 6; ++i) {
            const double scale = i < 3 ? mean : mean * c->radius;
            change = fmax(change, fabs(history[6 * k + i] - history[6 * (k - 1) + i]) / scale);
        }
        largest = fmax(largest, change);
        count += change > JUMP;
    }
    print_message("%-26s mean force %.4g N, largest change %.2e of it, %d jumps over %.0e\n",
                  c->name, mean, largest, count, JUMP);
    assert_true(mean > 0.0);
    free(history);
    free(dydt);
    free(y);
    tb_scene_destroy(scene);
    return count;
}

static tb_shape cylinder(double radius, double length)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CYLINDER;
    s.radius = radius;
    s.length = length;
    return s;
}

static tb_shape box(double x, double y, double z)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_BOX;
    s.size[0] = x, s.size[1] = y, s.size[2] = z;
    return s;
}

static tb_shape mesh(double half)
{
    for (int k = 0; k < 8; ++k) {
        mesh_cube[3 * k] = k & 1 ? half : -half;
        mesh_cube[3 * k + 1] = k & 2 ? half : -half;
        mesh_cube[3 * k + 2] = k & 4 ? half : -half;
    }
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CONVEX;
    s.vertices = mesh_cube;
    s.vertex_count = 8;
    return s;
}

static void test_resting_bodies_push_without_jumps(void **state)
{
    (void)state;
    const resting_case cases[] = {
        {"cylinder standing on a box", box(0.3, 0.3, 0.1), cylinder(0.05, 0.1), 0.05, 0.05, 0.05,
         0.02, 1e-5},
        {"can standing on a can", cylinder(0.05, 0.1), cylinder(0.05, 0.1), 0.05, 0.05, 0.05, 0.004,
         1e-5},
        {"mesh cube on a mesh cube", mesh(0.05), mesh(0.05), 0.05, 0.05, 0.07, 0.004, 1e-5},
        {"can rocking on its rim", cylinder(0.05, 0.1), cylinder(0.05, 0.1), 0.05, 0.05, 0.05,
         0.004, 5e-5},
    };
    int total = 0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        total += jumps(&cases[k]);
    }
    assert_int_equal(total, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resting_bodies_push_without_jumps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
