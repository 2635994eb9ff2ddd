/* The contact's sparse Jacobian (tb_ode_system.jacobian of a scene whose bodies touch) against
 * central difference quotients of the scene's own derivative, column by column, on a box
 * resting on the ground and a box on a box (on the ground), with and without friction.
 *
 * What is checked, and the tolerance of each:
 * - the pattern holds every dependence: a central quotient outside it is exactly 0 (the
 *   derivative's rows do not move at all when a column they do not depend on moves);
 * - the kinematic rows (dx/dt = P/M, dq/dt = 1/2 omega q) are analytic: against the central
 *   quotient (error h^2 |f'''| / 6 with the Jacobian's own increment h = sqrt(eps) max(|y_c|,
 *   s_c), s_c the component's natural size: about 1e-16 relative) within 1e-8 of the row's
 *   largest entry times its column's size, which leaves room for the rounding of f;
 * - the loads' and friction states' rows are forward quotients on colour groups: each entry
 *   within its own truncation error of the central quotient, 2 (h/2 |f''| + 2 eps |f| / h)
 *   + 1e-9 of the row's scale, with |f''| measured by the second difference at the same h
 *   (a kink of the law between y - h and y + h makes that bound large, and says so);
 * - the pair's coupling is in it: the upper box's vertical force grows as the lower box rises
 *   (d F_z,B / d z_A > 0). */
#include "tumble/tumble.h"

#include "fixtures.h"

#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define EDGE 0.1 /* m, the boxes' edge */

/* Body slot s: centre height z, tilted by angle (rad) about axis (0: x, 1: y), moving at v and
 * turning at omega (world; L = I omega, I the box's 1/6 m a^2). */
static void place(double *y, size_t s, double z, int axis, double angle, const double v[3],
                  const double omega[3])
{
    double *b = y + TB_STATE_SIZE * s;
    const double x[3] = {0.001 * (double)s, -0.002 * (double)s, z};
    memcpy(b + TB_STATE_X, x, sizeof x);
    b[TB_STATE_Q] = cos(0.5 * angle);
    b[TB_STATE_Q + 1] = axis == 0 ? sin(0.5 * angle) : 0.0;
    b[TB_STATE_Q + 2] = axis == 1 ? sin(0.5 * angle) : 0.0;
    b[TB_STATE_Q + 3] = 0.0;
    for (int k = 0; k < 3; ++k) {
        b[TB_STATE_P + k] = v[k]; /* m = 1 kg */
        b[TB_STATE_L + k] = EDGE * EDGE / 6.0 * omega[k];
    }
}

/* One box on the ground, or two stacked; friction on or off everywhere. */
static tb_scene *make_scene(int boxes, int friction)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {EDGE, EDGE, EDGE}, origin[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < boxes; ++k) {
        test_add_box(scene, 1.0, size, origin);
    }
    double *y = tb_scene_states(scene);
    const double v0[3] = {1e-3, 5e-4, -2e-4}, w0[3] = {0.01, -0.02, 0.03};
    const double v1[3] = {-2e-4, 3e-4, 1e-4}, w1[3] = {-0.02, 0.01, 0.02};
    /* the lowest corner 1.5 um deep, the highest 0.5 um: every corner touches, none near the
     * law's onset */
    place(y, 0, 0.5 * EDGE - 1e-6, 1, 1e-5, v0, w0);
    if (boxes > 1) {
        place(y, 1, 1.5 * EDGE - 2.5e-6, 0, 1e-5, v1, w1);
    }
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    if (!friction) {
        ground.static_friction = ground.kinetic_friction = 0.0;
        contact.static_friction = contact.kinetic_friction = 0.0;
    }
    const tb_status added = tb_scene_add_ground(scene, &ground);
    if (added != TB_STATUS_OK) {
        print_error("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(added, TB_STATUS_OK);
    if (boxes > 1) {
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    }
    return scene;
}

/* Entry (r, c) of J, or NAN when it is not in the pattern. */
static double entry(const tb_ode_sparse *J, size_t r, size_t c)
{
    for (size_t e = J->row_starts[r]; e < J->row_starts[r + 1]; ++e) {
        if (J->columns[e] == c) {
            return J->values[e];
        }
    }
    return NAN;
}

typedef struct quotients {
    double *central; /* n x n, row-major */
    double *bound;   /* n x n: the forward quotient's truncation and rounding error */
} quotients;

/* Central quotients of f at y, column c with the Jacobian's own increment h_c =
 * sqrt(eps) max(|y_c|, s_c), and each entry's forward-quotient error bound. */
static quotients central_quotients(const tb_ode_system *system, double *y, const double *scale)
{
    const size_t n = system->n;
    quotients Q = {calloc(n * n, sizeof(double)), calloc(n * n, sizeof(double))};
    double *f0 = calloc(n, sizeof(double)), *fp = calloc(n, sizeof(double));
    double *fm = calloc(n, sizeof(double));
    assert_non_null(Q.central), assert_non_null(Q.bound), assert_non_null(fm);
    assert_int_equal(system->derivative(0.0, y, f0, system->ctx), 0);
    for (size_t c = 0; c < n; ++c) {
        const double keep = y[c], h = sqrt(DBL_EPSILON) * fmax(fabs(keep), scale[c]);
        y[c] = keep + h;
        assert_int_equal(system->derivative(0.0, y, fp, system->ctx), 0);
        y[c] = keep - h;
        assert_int_equal(system->derivative(0.0, y, fm, system->ctx), 0);
        y[c] = keep;
        for (size_t r = 0; r < n; ++r) {
            Q.central[r * n + c] = (fp[r] - fm[r]) / (2.0 * h);
            const double second = fabs(fp[r] - 2.0 * f0[r] + fm[r]) / (2.0 * h);
            const double rounding = 2.0 * DBL_EPSILON * (fabs(f0[r]) + fabs(fp[r])) / h;
            Q.bound[r * n + c] = 2.0 * (second + rounding);
        }
    }
    free(f0), free(fp), free(fm);
    return Q;
}

/* Each row's scale: its largest |central quotient| times its column's natural size. */
static double row_scale(const quotients *Q, size_t n, size_t r, const double *scale)
{
    double largest = 0.0;
    for (size_t c = 0; c < n; ++c) {
        largest = fmax(largest, fabs(Q->central[r * n + c]) * scale[c]);
    }
    return largest;
}

static void check_rows(const tb_ode_sparse *J, const quotients *Q, const double *scale,
                       size_t bodies)
{
    const size_t n = J->n;
    for (size_t r = 0; r < n; ++r) {
        const double row = row_scale(Q, n, r, scale);
        const size_t part = r < TB_STATE_SIZE * bodies ? r % TB_STATE_SIZE : TB_STATE_SIZE;
        const bool kinematic = part < TB_STATE_P;
        for (size_t c = 0; c < n; ++c) {
            const double d = Q->central[r * n + c], a = entry(J, r, c);
            if (isnan(a)) { /* not in the pattern: the derivative does not depend on it */
                if (d != 0.0) {
                    print_error("row %zu depends on column %zu (%g) outside the pattern\n", r, c,
                                d);
                }
                assert_true(d == 0.0);
                continue;
            }
            const double tolerance =
                kinematic ? 1e-8 * row / scale[c] : Q->bound[r * n + c] + 1e-9 * row / scale[c];
            if (!(fabs(a - d) <= tolerance)) {
                print_error("J[%zu][%zu] = %.9g, quotient %.9g, tolerance %.3g\n", r, c, a, d,
                            tolerance);
            }
            assert_true(fabs(a - d) <= tolerance);
        }
    }
}

static void check_scene(int boxes, int friction)
{
    tb_scene *scene = make_scene(boxes, friction);
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    assert_non_null(system.jacobian.evaluate);
    const size_t n = system.n;
    double *y = tb_scene_states(scene), *scale = calloc(n, sizeof(double));
    assert_non_null(scale);
    /* a step boundary: the friction slots the touching points took are held from here */
    assert_int_equal(system.post_step(0.0, y, system.ctx), 0);
    for (size_t k = TB_STATE_SIZE * (size_t)boxes; k < n && friction; ++k) {
        y[k] = 1e-8 * (double)(1 + k % 3); /* stretched anchors, inside the cone */
    }
    assert_int_equal(tb_scene_absolute_tolerances(scene, 1.0, scale), TB_STATUS_OK);
    const size_t capacity = system.jacobian.capacity(0.0, y, system.ctx);
    assert_true(capacity >= n);
    tb_ode_sparse J = {n, capacity, calloc(n + 1, sizeof(size_t)), calloc(capacity, sizeof(size_t)),
                       calloc(capacity, sizeof(double))};
    double *fy = calloc(n, sizeof(double));
    assert_non_null(J.values), assert_non_null(fy);
    assert_int_equal(system.derivative(0.0, y, fy, system.ctx), 0);
    assert_int_equal(system.jacobian.evaluate(0.0, y, fy, &J, system.ctx), 0);
    quotients Q = central_quotients(&system, y, scale);
    check_rows(&J, &Q, scale, (size_t)boxes);
    if (boxes > 1) { /* the upper box's vertical force rises with the lower box */
        const double coupling = entry(&J, TB_STATE_SIZE + TB_STATE_P + 2, TB_STATE_X + 2);
        assert_true(coupling > 0.0);
    }
    free(Q.central), free(Q.bound), free(fy), free(scale);
    free(J.row_starts), free(J.columns), free(J.values);
    tb_scene_destroy(scene);
}

static void test_a_box_on_the_ground_without_friction(void **state)
{
    (void)state;
    check_scene(1, 0);
}

static void test_a_box_on_the_ground_with_friction(void **state)
{
    (void)state;
    check_scene(1, 1);
}

static void test_a_box_on_a_box_without_friction(void **state)
{
    (void)state;
    check_scene(2, 0);
}

static void test_a_box_on_a_box_with_friction(void **state)
{
    (void)state;
    check_scene(2, 1);
}

/* Three 10 cm, 0.5 kg boxes stacked on the ground under BDF with the sparse Jacobian. At rest
 * each contact carries the weight above it and sinks that many penetrations (the law's
 * stiffness is set so that a body sinks one penetration p under its own weight: the ground 3p
 * under three boxes, the pairs 2p and p), so the top box stands 6p below its undeflected
 * 0.25 m. Tolerance: 5% of 6p (the settling rings down in milliseconds; BDF's own error on a
 * position is about rtol times the body's 4 cm scale, 1e-10 m). And BDF is not held to the
 * contact's oscillation at rest: its last step exceeds 10 periods of omega = sqrt(g / p). */
static void test_a_stack_rests_at_its_static_deflection_under_sparse_bdf(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const double size[3] = {EDGE, EDGE, EDGE};
    for (int k = 0; k < 3; ++k) {
        const double x[3] = {0.0, 0.0, 0.5 * EDGE + EDGE * k};
        test_add_box(scene, 0.5, size, x);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator_def def = test_integrator_def(TB_METHOD_CVODE_BDF, 0.0, 1e-6);
    def.linear_solver = TB_LINEAR_SOLVER_SPARSE;
    tb_integrator *integrator = NULL;
    const tb_status created = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    if (created == TB_STATUS_UNSUPPORTED) { /* built without KLU */
        tb_scene_destroy(scene);
        return;
    }
    assert_int_equal(created, TB_STATUS_OK);
    for (int frame = 1; frame <= 60; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
    }
    const double p = ground.penetration, *y = tb_scene_states(scene);
    const double sunk = 2.5 * EDGE - y[2 * TB_STATE_SIZE + TB_STATE_X + 2];
    print_message("top box sunk %.4g m (6p = %.4g m)\n", sunk, 6.0 * p);
    assert_true(fabs(sunk - 6.0 * p) <= 0.05 * 6.0 * p);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    assert_true(stats.last_step > 10.0 * 2.0 * 3.14159265358979 * sqrt(p / 9.81));
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_box_on_the_ground_without_friction),
        cmocka_unit_test(test_a_box_on_the_ground_with_friction),
        cmocka_unit_test(test_a_box_on_a_box_without_friction),
        cmocka_unit_test(test_a_box_on_a_box_with_friction),
        cmocka_unit_test(test_a_stack_rests_at_its_static_deflection_under_sparse_bdf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
