/* The contact's sparse Jacobian (tb_ode_system.jacobian of a scene whose bodies touch) against
 * central difference quotients of the scene's own derivative, column by column: a box resting on
 * the ground (through its shape, or its eight corner points), a box on a box (on the ground), a
 * ball on a box and a ball on the ground, with and without friction, at rest (the anchors stretched
 * inside the cone: sticking) and sliding (5 cm/s across, the anchors past the cone: capped friction
 * and plastic slip), and with too few friction slots (the memoryless law at the points without
 * one).
 *
 * What is checked, and the tolerance of each:
 * - the pattern holds every dependence: a central quotient outside it is exactly 0 (the
 *   derivative's rows do not move at all when a column they do not depend on moves);
 * - the kinematic rows (dx/dt = P/M, dq/dt = 1/2 omega q) are analytic: against the central
 *   quotient (error h^2 |f'''| / 6 with the Jacobian's own increment h = sqrt(eps) max(|y_c|,
 *   s_c), s_c the component's natural size: about 1e-16 relative) within 1e-8 of the row's
 *   largest entry times its column's size, which leaves room for the rounding of f;
 * - the loads' and the anchors' rows are the contact law's analytic derivatives with some terms
 *   neglected (src/scene/jacobian_rows.h), all of them in the bodies' position columns (x, q):
 *   - against a momentum (P, L) or anchor column nothing is neglected: each entry within the
 *     central quotient's own truncation error, 2 (h/2 |f''| + 2 eps |f| / h), plus EXACT = 1e-6
 *     of the largest entry of its row group (force, torque or slot rows) in its column group
 *     (rounding: the loads are sums of terms about 1e6 times the difference they change by);
 *   - against a position column, within the truncation error plus NEGLECTED = 1e-2 of its row
 *     group's scale (the largest |entry| times column size over the group's rows: what a
 *     natural-size change of one state does to the loads; for torque rows at least the force
 *     rows' at the half edge, the arm the neglected forces act at) over its column's size. The
 *     neglected terms against that scale: the turning normal and the moving arms,
 *     |f| / (k |r|) <= (1 + mu_s) d / r = 1.6 * 2.5 um / 5 cm = 8e-5 and, sliding,
 *     |w| / (omega |r|) = (5 cm/s) / (1750 rad/s * 5 cm) = 6e-4 in the loads and the slide's
 *     speed turned with the normal into the anchor's normal part (which pushes nothing and
 *     relaxes at the release rate): 4.3e-3 of the slot's rows measured; the dashpots' effective
 *     masses held fixed, 2 zeta |d'| / (omega d) = 2 * 0.35 * 3 um/s / (1750 rad/s * 0.5 um) =
 *     2.4e-3 at rest (4e-4 sliding: the normal speed is the slide's 5 cm/s through the faces'
 *     1e-5 rad tilt), and the friction dashpot's, sqrt(k_t m_t) |v_t| / (2 d k) = 2e-4 at rest
 *     (0 sliding: the anchor lies along the slip, so the capped force's direction does not
 *     depend on it). The largest miss found is printed (4.3e-3 sliding, 6e-4 at rest);
 * - the pair's coupling is in it: the upper body's vertical force grows as the lower box rises
 *   (d F_z,B / d z_A > 0). */
#include "tumble/tumble.h"

#include "fixtures.h"

#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#define EDGE 0.1 /* m, the boxes' edge and the balls' diameter */
/* The tolerances' relative parts (above): the neglected terms' bound in position columns, the
 * rounding elsewhere. */
#define NEGLECTED 1e-2
#define EXACT 1e-6
/* m/s: the slide's speed; m: the anchors' stretch when sliding (past the cone's ~0.5 um) */
#define SLIDE 0.05
#define STRETCH 3e-6

/* A scene to check: one body on the ground or two stacked, the upper one a box or a ball. */
typedef struct case_def {
    int bodies;             /* 1: on the ground; 2: the second on the first, on the ground */
    bool ball;              /* the upper body a ball of diameter EDGE */
    bool friction;          /* friction on or off everywhere */
    bool sliding;           /* the upper body slides at SLIDE, the anchors past the cone */
    size_t friction_points; /* the contact's slots (0: its default) */
    bool points;            /* the lower box meets the ground at its 8 corner points */
    bool others;            /* a spring between the two bodies and drag: quotients' rows */
} case_def;

/* Body slot s: centre height z, tilted by angle (rad) about axis (0: x, 1: y), moving at v and
 * turning at omega (world; L = I omega with I = m a^2 / 6, the 1 kg box's). */
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

/* The bodies at rest or sliding: at rest they creep at a few um/s, slowly enough that the
 * dashpots' neglected mass terms stay small (above); sliding, the upper body moves at SLIDE
 * across without turning, the lower one (of two) is still. The lowest corner of a box is 1.5 um
 * deep, the highest 0.5 um: every corner touches, none near the law's onset. */
static void place_bodies(double *y, const case_def *c)
{
    const double v0[3] = {1e-6, 5e-7, -2e-7}, w0[3] = {1e-5, -2e-5, 3e-5};
    const double v1[3] = {-2e-7, 3e-7, 1e-7}, w1[3] = {-2e-5, 1e-5, 2e-5};
    const double slide[3] = {SLIDE, 0.4 * SLIDE, 0.0}, still[3] = {0.0, 0.0, 0.0};
    const bool top = c->bodies == 1;
    const double *v_low = c->sliding ? (top ? slide : still) : v0;
    const double *v_high = c->sliding ? slide : v1;
    const double low = c->ball && top ? 0.5 * EDGE - 1.5e-6 : 0.5 * EDGE - 1e-6;
    place(y, 0, low, 1, 1e-5, v_low, c->sliding ? still : w0);
    if (c->bodies > 1) {
        place(y, 1, 1.5 * EDGE - 2.5e-6, 0, 1e-5, v_high, c->sliding ? still : w1);
    }
}

static tb_scene *make_scene(const case_def *c)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {EDGE, EDGE, EDGE}, origin[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < c->bodies; ++k) {
        if (c->ball && k == c->bodies - 1) {
            test_add_ball(scene, NULL, 1.0, 0.5 * EDGE, origin, NULL);
        } else {
            test_add_box(scene, 1.0, size, origin);
        }
    }
    if (c->points) { /* before the ground, which sizes its states by them */
        tb_contact_point corners[8];
        size_t count = 0;
        assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    }
    place_bodies(tb_scene_states(scene), c);
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    contact.friction_points = c->friction_points;
    if (!c->friction) {
        ground.static_friction = ground.kinetic_friction = 0.0;
        contact.static_friction = contact.kinetic_friction = 0.0;
    }
    const tb_status added = tb_scene_add_ground(scene, &ground);
    if (added != TB_STATUS_OK) {
        print_error("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(added, TB_STATUS_OK);
    if (c->bodies > 1) {
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    }
    if (c->others) { /* effects without analytic rows, beside the contact's */
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = 0, spring.body_b = 1;
        spring.point_a[0] = spring.point_b[1] = 0.5 * EDGE;
        spring.stiffness = 1e4, spring.damping = 10.0, spring.rest_length = 0.05;
        assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
        tb_drag_def drag = tb_drag_def_default();
        drag.linear = 0.5, drag.quadratic = 2.0, drag.angular = 0.01;
        assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
    }
    return scene;
}

/* The anchors: inside the cone at rest (sticking); sliding, STRETCH along the slide (past the
 * cone: the capped force and the plastic slip): a slot's in the world (or the lower box's frame,
 * turned 1e-5 rad), a ground point's in the plane's basis t1 = n x e_x = e_y, t2 = n x t1 =
 * -e_x. */
static void stretch_anchors(double *y, size_t n, const case_def *c)
{
    const double along[3] = {1.0 / sqrt(1.16), 0.4 / sqrt(1.16), 0.0};
    const double in_plane[2] = {along[1], -along[0]};
    const size_t first = TB_STATE_SIZE * (size_t)c->bodies, points = c->points ? 2 * 8 : 0;
    for (size_t k = first; k < n && c->friction; ++k) {
        const bool point = k < first + points;
        const double slide = point ? in_plane[(k - first) % 2] : along[(k - first - points) % 3];
        y[k] = c->sliding ? STRETCH * slide : 1e-8 * (double)(1 + k % 3);
    }
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

/* Where the states lie: the bodies', then the ground points' deflections (two each), then the
 * friction slots' (three each). */
typedef struct layout {
    size_t bodies, point_states;
} layout;

/* The components [first, end) of component k's group: the body's position rows or columns (x),
 * its q, its force (P) or torque (L) rows or momentum columns, a ground point's deflection, or a
 * friction slot's. */
static void group_of(size_t k, const layout *L, size_t *first, size_t *end)
{
    static const size_t starts[] = {TB_STATE_X, TB_STATE_Q, TB_STATE_P, TB_STATE_L, TB_STATE_SIZE};
    if (k < TB_STATE_SIZE * L->bodies) {
        const size_t base = k - k % TB_STATE_SIZE, part = k % TB_STATE_SIZE;
        size_t g = 0;
        while (part >= starts[g + 1]) {
            ++g;
        }
        *first = base + starts[g];
        *end = base + starts[g + 1];
    } else if (k < TB_STATE_SIZE * L->bodies + L->point_states) { /* ground points' two */
        *first = k - (k - TB_STATE_SIZE * L->bodies) % 2;
        *end = *first + 2;
    } else { /* friction slots' three */
        *first = k - (k - TB_STATE_SIZE * L->bodies - L->point_states) % 3;
        *end = *first + 3;
    }
}

/* The largest |entry| of rows [r0, r1) in columns [c0, c1). */
static double largest_in(const quotients *Q, size_t n, size_t r0, size_t r1, size_t c0, size_t c1)
{
    double largest = 0.0;
    for (size_t r = r0; r < r1 && r < n; ++r) {
        for (size_t c = c0; c < c1 && c < n; ++c) {
            largest = fmax(largest, fabs(Q->central[r * n + c]));
        }
    }
    return largest;
}

/* The scale of row r's group: its largest |entry| times its column's natural size (the change
 * of the loads a natural-size change of any one state makes); a torque group's at least its
 * force group's times the half edge, the arm the neglected forces act at (a ball's torque has no
 * spring of its own). */
static double rows_scale(const quotients *Q, size_t n, size_t r, const double *scale,
                         const layout *L)
{
    size_t r0, r1;
    group_of(r, L, &r0, &r1);
    double largest = 0.0;
    for (size_t k = r0; k < r1 && k < n; ++k) {
        largest = fmax(largest, row_scale(Q, n, k, scale));
    }
    if (r0 < TB_STATE_SIZE * L->bodies && r0 % TB_STATE_SIZE == TB_STATE_L) {
        const size_t forces = r0 - TB_STATE_L + TB_STATE_P;
        largest = fmax(largest, 0.5 * EDGE * rows_scale(Q, n, forces, scale, L));
    }
    return largest;
}

/* The largest |entry| of entry (r, c)'s row group in its column group. */
static double block_scale(const quotients *Q, size_t n, size_t r, size_t c, const layout *L)
{
    size_t r0, r1, c0, c1;
    group_of(r, L, &r0, &r1);
    group_of(c, L, &c0, &c1);
    return largest_in(Q, n, r0, r1, c0, c1);
}

static bool kinematic_row(size_t r, const layout *L)
{
    return r < TB_STATE_SIZE * L->bodies && r % TB_STATE_SIZE < TB_STATE_P;
}

/* A body's x or q column: where the neglected (geometric and effective-mass) terms are. */
static bool position_column(size_t c, const layout *L)
{
    return c < TB_STATE_SIZE * L->bodies && c % TB_STATE_SIZE < TB_STATE_P;
}

/* The tolerance of entry (r, c) (above): kinematic rows against their own row's scale. */
static double tolerance_of(const quotients *Q, size_t n, size_t r, size_t c, const double *scale,
                           const layout *L)
{
    if (kinematic_row(r, L)) {
        return 1e-8 * row_scale(Q, n, r, scale) / scale[c];
    }
    if (position_column(c, L)) {
        return Q->bound[r * n + c] + NEGLECTED * rows_scale(Q, n, r, scale, L) / scale[c];
    }
    return Q->bound[r * n + c] + EXACT * block_scale(Q, n, r, c, L);
}

static void check_rows(const tb_ode_sparse *J, const quotients *Q, const double *scale,
                       const layout *L)
{
    const size_t n = J->n;
    double worst = 0.0; /* the largest miss beyond the truncation error, against its block */
    for (size_t r = 0; r < n; ++r) {
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
            const double tolerance = tolerance_of(Q, n, r, c, scale, L);
            const double block = rows_scale(Q, n, r, scale, L) / scale[c];
            if (block > 0.0 && !kinematic_row(r, L) && position_column(c, L)) {
                worst = fmax(worst, (fabs(a - d) - Q->bound[r * n + c]) / block);
            }
            if (!(fabs(a - d) <= tolerance)) {
                print_error("J[%zu][%zu] = %.9g, quotient %.9g, tolerance %.3g\n", r, c, a, d,
                            tolerance);
            }
            assert_true(fabs(a - d) <= tolerance);
        }
    }
    print_message("largest miss beyond truncation: %.3g of its block\n", worst);
}

static void check_scene(const case_def *c)
{
    tb_scene *scene = make_scene(c);
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    assert_non_null(system.jacobian.evaluate);
    const size_t n = system.n, bodies = (size_t)c->bodies;
    const layout L = {bodies, c->points ? 2 * 8 : 0};
    double *y = tb_scene_states(scene), *scale = calloc(n, sizeof(double));
    assert_non_null(scale);
    /* a step boundary: the friction slots the touching points took are held from here */
    assert_int_equal(system.post_step(0.0, y, system.ctx), 0);
    stretch_anchors(y, n, c);
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
    check_rows(&J, &Q, scale, &L);
    if (bodies > 1) { /* the upper body's vertical force rises with the lower box */
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
    check_scene(&(case_def){.bodies = 1});
}

static void test_a_box_sticking_on_the_ground(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 1, .friction = true});
}

static void test_a_box_sliding_on_the_ground(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 1, .friction = true, .sliding = true});
}

static void test_a_box_on_a_box_without_friction(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2});
}

static void test_a_box_sticking_on_a_box(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .friction = true});
}

static void test_a_box_sliding_on_a_box(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .friction = true, .sliding = true});
}

/* The ground's own contact points (two deflection states each) instead of the box's shape. */
static void test_a_box_on_its_points_sticking(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .friction = true, .points = true});
}

static void test_a_box_on_its_points_sliding(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 1, .friction = true, .sliding = true, .points = true});
}

/* A spring between the boxes and drag on both: their rows are difference quotients of their own
 * part of the derivative, added to the contact's analytic rows. */
static void test_a_box_sliding_on_a_box_with_a_spring_and_drag(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .friction = true, .sliding = true, .others = true});
}

/* One slot for the pair's four points: three have the memoryless law. */
static void test_a_box_on_a_box_short_of_friction_slots(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .friction = true, .friction_points = 1});
}

static void test_a_ball_on_a_box(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 2, .ball = true, .friction = true});
}

static void test_a_ball_sliding_on_the_ground(void **state)
{
    (void)state;
    check_scene(&(case_def){.bodies = 1, .ball = true, .friction = true, .sliding = true});
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
        cmocka_unit_test(test_a_box_sticking_on_the_ground),
        cmocka_unit_test(test_a_box_sliding_on_the_ground),
        cmocka_unit_test(test_a_box_on_a_box_without_friction),
        cmocka_unit_test(test_a_box_sticking_on_a_box),
        cmocka_unit_test(test_a_box_sliding_on_a_box),
        cmocka_unit_test(test_a_box_sliding_on_a_box_with_a_spring_and_drag),
        cmocka_unit_test(test_a_box_on_a_box_short_of_friction_slots),
        cmocka_unit_test(test_a_box_on_its_points_sticking),
        cmocka_unit_test(test_a_box_on_its_points_sliding),
        cmocka_unit_test(test_a_ball_on_a_box),
        cmocka_unit_test(test_a_ball_sliding_on_the_ground),
        cmocka_unit_test(test_a_stack_rests_at_its_static_deflection_under_sparse_bdf),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
