/* Every pair of collision shapes in a head-on impact, under one method (the ctest's argument):
 * a 1 kg body at 2 m/s into a 3 kg one at rest, restitution e = 0.8, no gravity, no ground. The
 * shapes turn by unequal angles about the line of approach (x), so faces meet rotated against
 * each other, and B sits 3 mm off that line in y and 2 mm in z, so nothing is symmetric. For each
 * of the 28 pairs (7 shape types, with repetition) the run must
 *   - succeed (CVODE must not stop with too much work, as it did for the 12 pairs with a
 *     cylinder, mesh hull or points hull under Adams: issue 19, item 4);
 *   - keep the total linear momentum (2 kg m/s): the contact's forces are equal and opposite, a
 *     linear invariant that every Runge-Kutta and linear multistep method keeps to round-off;
 *     BDF's Newton corrections come from difference quotients, whose rows do not cancel to the
 *     bit: 1e-9 relative for the fixed-step methods and Adams, 1e-6 for BDF;
 *   - part: at the end no point of the pair overlaps and B moves away from A along x;
 *   - part at e times the approach speed, measured on the centres of mass along x: every shape
 *     is symmetric about its centre and presents a face, side or pole centred on the line of
 *     approach, so the hit is central up to the 3.6 mm offset (a moment arm that changes the
 *     effective mass by (3.6 mm / 5 cm)^2, about 0.5 %): within 5 % for the fixed steps (the
 *     issue's bound for RK4 at its default step; the law's restitution is exact at the reduced
 *     mass) and 2 % for CVODE at its default tolerances. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "meshes.h"
#include "near.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SHAPE_KINDS 7
#define RESTITUTION 0.8
#define SPEED 2.0
#define GAP 0.004  /* m between the bodies at t = 0: they touch at 2 ms */
#define SPAN 0.012 /* s: the push lasts under 1 ms; 8 ms more to part by 13 mm */

static const char *const kind_names[SHAPE_KINDS] = {"sphere",    "box",  "capsule", "cylinder",
                                                    "ellipsoid", "mesh", "points"};

/* The half-extent along x of each kind as placed below (turning about x keeps it), m. */
static const double half_x[SHAPE_KINDS] = {0.1, 0.1, 0.06, 0.08, 0.1, 0.09, 0.09};

static double mesh_box_vertices[24], points_vertices[24], points_radii[8];

static void fill_boxes(void)
{
    for (int k = 0; k < 8; ++k) {
        const double sx = k & 1 ? 1.0 : -1.0, sy = k & 2 ? 1.0 : -1.0, sz = k & 4 ? 1.0 : -1.0;
        const double mesh[3] = {0.09 * sx, 0.08 * sy, 0.07 * sz};
        const double points[3] = {0.06 * sx, 0.05 * sy, 0.04 * sz};
        memcpy(mesh_box_vertices + 3 * k, mesh, sizeof mesh);
        memcpy(points_vertices + 3 * k, points, sizeof points);
        points_radii[k] = 0.03;
    }
}

/* The shape of a kind in its shape frame: faces, a flat end or a pole facing +-x, except the
 * capsule, whose axis (shape z) lies across x. */
static tb_shape shape_of(int kind)
{
    tb_shape s = tb_shape_default();
    static const tb_shape_type types[SHAPE_KINDS] = {
        TB_SHAPE_SPHERE,    TB_SHAPE_BOX,    TB_SHAPE_CAPSULE, TB_SHAPE_CYLINDER,
        TB_SHAPE_ELLIPSOID, TB_SHAPE_CONVEX, TB_SHAPE_POINTS};
    s.type = types[kind];
    s.radius = kind == 0 ? 0.1 : kind == 2 ? 0.06 : 0.09;
    s.length = kind == 2 ? 0.1 : 0.16;
    memcpy(s.size, (double[]){0.2, 0.16, 0.12}, sizeof s.size);
    memcpy(s.semi_axes, (double[]){0.1, 0.08, 0.06}, sizeof s.semi_axes);
    s.vertices = kind == 5 ? mesh_box_vertices : points_vertices;
    s.vertex_count = 8;
    s.radii = kind == 6 ? points_radii : NULL;
    return s;
}

/* Mass properties of a kind at mass m: the primitives' own, the box's for the mesh and the
 * points (the test asks for momentum and restitution, which any inertia keeps). */
static tb_mass_properties mass_of(int kind, double m)
{
    tb_mass_properties props;
    tb_status status;
    if (kind == 0) {
        status = tb_mass_from_sphere(TB_MASS_GIVEN, m, 0.1, &props, NULL);
    } else if (kind == 2) {
        status = tb_mass_from_capsule(TB_MASS_GIVEN, m, 0.06, 0.1, &props, NULL);
    } else if (kind == 3) {
        status = tb_mass_from_cylinder(TB_MASS_GIVEN, m, 0.09, 0.16, &props, NULL);
    } else if (kind == 4) {
        status =
            tb_mass_from_ellipsoid(TB_MASS_GIVEN, m, (double[]){0.1, 0.08, 0.06}, &props, NULL);
    } else {
        status = tb_mass_from_box(TB_MASS_GIVEN, m, (double[]){0.18, 0.16, 0.14}, &props, NULL);
    }
    assert_int_equal(status, TB_STATUS_OK);
    return props;
}

/* Turned by angle about x; a cylinder's axis first laid along x (its flat end forward), a
 * capsule's along y (its side forward). */
static void orientation_of(int kind, double angle, double q[4])
{
    const double c = cos(0.5 * angle), s = sin(0.5 * angle), h = sqrt(0.5);
    if (kind == 3) { /* rot_x(angle) rot_y(90 deg) */
        q[0] = c * h, q[1] = s * h, q[2] = c * h, q[3] = s * h;
    } else if (kind == 2) { /* rot_x(angle - 90 deg): shape z to world y at angle 0 */
        const double half = 0.5 * angle - 0.25 * 3.14159265358979323846;
        const double c2 = cos(half), s2 = sin(half);
        q[0] = c2, q[1] = s2, q[2] = 0.0, q[3] = 0.0;
    } else {
        q[0] = c, q[1] = s, q[2] = 0.0, q[3] = 0.0;
    }
}

static size_t add_body(tb_scene *scene, int kind, double m, double angle, const double x[3],
                       double v)
{
    tb_body_def def = tb_body_def_default();
    def.mass = mass_of(kind, m);
    memcpy(def.position, x, 3 * sizeof(double));
    def.velocity[0] = v;
    orientation_of(kind, angle, def.orientation);
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    const tb_shape shape = shape_of(kind);
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

typedef struct outcome {
    tb_status status;
    double momentum_error; /* |P - P0| / |P0| */
    double restitution;    /* separation over approach speed of the centres, along x */
    double depth;          /* the deepest overlap at the end, m (< 0: apart) */
    long steps;
} outcome;

static outcome impact(int kind_a, int kind_b, tb_method method)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    const double xa = -half_x[kind_a] - 0.5 * GAP, xb = half_x[kind_b] + 0.5 * GAP;
    add_body(scene, kind_a, 1.0, 0.37, (double[]){xa, 0.0, 0.0}, SPEED);
    add_body(scene, kind_b, 3.0, 1.19, (double[]){xb, 0.003, 0.002}, 0.0);
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = RESTITUTION;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (!tb_method_is_adaptive(method)) {
        def.dt = 0.0; /* the scene's default step; CVODE keeps its default tolerances */
    }
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    outcome o = {.status = tb_integrator_advance(integrator, SPAN)};
    tb_integrator_stats stats;
    assert_int_equal(tb_integrator_get_stats(integrator, &stats), TB_STATUS_OK);
    o.steps = stats.steps;
    tb_integrator_destroy(integrator);
    const double *y = tb_scene_states(scene);
    const double *pa = y + TB_STATE_P, *pb = y + TB_STATE_SIZE + TB_STATE_P;
    const double dp[3] = {pa[0] + pb[0] - SPEED, pa[1] + pb[1], pa[2] + pb[2]};
    o.momentum_error = sqrt(dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2]) / SPEED;
    o.restitution = (pb[0] / 3.0 - pa[0]) / SPEED;
    tb_contact_touch touch;
    size_t count = 0;
    assert_int_equal(tb_scene_contact_touching(scene, y, &touch, 1, &count), TB_STATUS_OK);
    o.depth = count > 0 ? touch.depth : -INFINITY;
    tb_scene_destroy(scene);
    return o;
}

static tb_method method_under_test;

static void test_every_shape_pair_parts_at_e_keeping_momentum(void **state)
{
    (void)state;
    fill_boxes();
    const tb_method method = method_under_test;
    const bool adaptive = tb_method_is_adaptive(method);
    const double momentum_tolerance = method == TB_METHOD_CVODE_BDF ? 1e-6 : 1e-9;
    /* Euler is first order: its error in e at its default step is of order h omega, larger
     * since the dashpot's sizing at the effective mass lengthened that step (5.0 % on two
     * spheres here, 13 % at e = 0.5 in docs/effects.md); 10 % for it */
    const double restitution_tolerance =
        adaptive ? 0.02 : (method == TB_METHOD_EULER ? 0.10 : 0.05);
    int failures = 0;
    for (int a = 0; a < SHAPE_KINDS; ++a) {
        for (int b = a; b < SHAPE_KINDS; ++b) {
            const outcome o = impact(a, b, method);
            const bool ok = o.status == TB_STATUS_OK && o.momentum_error <= momentum_tolerance &&
                            o.depth < 0.0 && o.restitution > 0.0 &&
                            fabs(o.restitution / RESTITUTION - 1.0) <= restitution_tolerance;
            print_message("%-11s %-9s %-9s %-22s steps %6ld  dP/P %.1e  e %.5f  depth %.2e%s\n",
                          tb_method_name(method), kind_names[a], kind_names[b],
                          tb_status_string(o.status), o.steps, o.momentum_error, o.restitution,
                          o.depth, ok ? "" : "  FAILS");
            failures += !ok;
        }
    }
    print_message("%d of 28 pairs fall short (momentum within %.0e, e within %.0f %%)\n", failures,
                  momentum_tolerance, 100.0 * restitution_tolerance);
    assert_int_equal(failures, 0);
}

int main(int argc, char **argv)
{
    if (argc != 2 || tb_method_from_name(argv[1], &method_under_test) != TB_STATUS_OK) {
        fprintf(stderr, "usage: test_contact_shape_pairs METHOD\n");
        return 2;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_shape_pair_parts_at_e_keeping_momentum),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
