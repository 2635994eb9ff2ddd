/* The general stability guard: how fast a scene's fastest modes are, and so the largest fixed
 * step each method takes without amplifying them. Every mode is bounded from the body and
 * effect that make it, split by where its eigenvalues lie:
 *   oscillatory (near the imaginary axis): rotation (|omega|: the quaternion turns at
 *     |omega| / 2 and the gyroscopic modes of the Euler equations at most at |omega|, since
 *     |I_i - I_j| <= I_k), springs (sqrt(k w)), ground contact's bounce, rocking and bristles;
 *   decaying (on the negative real axis): drag (b / m, 2 c |v| / m and the angular twins
 *     over I_min), overdamped springs (c w), overdamped contact.
 * Rotation and quadratic drag grow with the state, so the guard runs on a state: at creation
 * and again at every advance (tb__scene_check_step). */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

/* Where a method's stability region ends (|h lambda|), on the imaginary axis where one step
 * amplifies an oscillation by 1% (the root of |R(i y)| = 1.01: Euler 1 + y^2, midpoint
 * 1 + y^4 / 4; RK4 is stable to 2.83 and 2.78 keeps the margin of the real axis), and on the
 * negative real axis where |R(x)| = 1 (Euler and midpoint 2, RK4 2.785). */
static void step_limits(tb_method method, double *imaginary, double *real)
{
    switch (method) {
    case TB_METHOD_EULER:
        *imaginary = 0.14, *real = 2.0;
        return;
    case TB_METHOD_MIDPOINT:
        *imaginary = 0.53, *real = 2.0;
        return;
    case TB_METHOD_RK4:
        *imaginary = 2.78, *real = 2.785;
        return;
    default:
        *imaginary = INFINITY, *real = INFINITY;
        return;
    }
}

/* The smallest step limit found so far and what sets it. */
typedef struct guard {
    double imaginary, real; /* the method's limits */
    double dt;
    char which[TB_DETAIL_SIZE];
} guard;

/* A mode of rate `rate` (1/s): lowers the limit if it is the fastest so far, naming it. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 4, 5)))
#endif
static void
consider(guard *g, double rate, bool oscillatory, const char *format, ...)
{
    const double dt = (oscillatory ? g->imaginary : g->real) / rate;
    if (!(rate > 0.0) || !(dt < g->dt)) {
        return;
    }
    g->dt = dt;
    va_list args;
    va_start(args, format);
    const int length = vsnprintf(g->which, sizeof g->which, format, args);
    va_end(args);
    if (length >= 0 && (size_t)length < sizeof g->which) {
        snprintf(g->which + length, sizeof g->which - (size_t)length, ", rate %.3g 1/s", rate);
    }
}

static double smallest_moment_inverse(const tb__body *b)
{
    return fmax(b->inv_moments[0], fmax(b->inv_moments[1], b->inv_moments[2]));
}

/* 1/m + |r|^2 / I_min: the largest inverse mass a force at offset r can meet. */
static double inverse_mass_at(const tb_scene *scene, size_t body, const double r[3])
{
    if (body == TB_WORLD) {
        return 0.0;
    }
    const tb__body *b = &scene->bodies[body];
    return b->inv_mass + tb__v3_dot(r, r) * smallest_moment_inverse(b);
}

static void rotation_modes(guard *g, const tb_scene *scene, const double *y)
{
    for (size_t i = 0; i < scene->body_count; ++i) {
        double omega[3];
        tb__angular_velocity(&scene->bodies[i], y + TB_STATE_SIZE * i, omega);
        const double spin = tb__v3_norm(omega);
        if (spin * g->dt > g->imaginary) {
            consider(g, spin, true, "body %zu (\"%s\") spinning at %.3g rad/s", i, scene->names[i],
                     spin);
        }
    }
}

static void spring_modes(guard *g, const tb_scene *scene, size_t index)
{
    const tb__effect *e = &scene->effects[index];
    const double w = inverse_mass_at(scene, e->body, e->point) +
                     inverse_mass_at(scene, e->other, e->other_point);
    consider(g, sqrt(e->param[0] * w), true, "effect %zu (a spring of stiffness %g N/m)", index,
             e->param[0]);
    consider(g, e->param[1] * w, false, "effect %zu (a spring of damping %g N s/m)", index,
             e->param[1]);
}

/* Drag on one body: F = -(b + c |v|) v has rate (b + 2 c |v|) / m along v; the torque's twin
 * (b_w + 2 c_w |omega|) / I_min. */
static void drag_body_modes(guard *g, const tb_scene *scene, size_t index, size_t i,
                            const double *y)
{
    const tb__effect *e = &scene->effects[index];
    const tb__body *b = &scene->bodies[i];
    const double *s = y + TB_STATE_SIZE * i;
    const double speed = tb__v3_norm(s + TB_STATE_P) * b->inv_mass;
    consider(g, (e->param[0] + 2.0 * e->param[1] * speed) * b->inv_mass, false,
             "effect %zu (drag) on body %zu (\"%s\") at %.3g m/s", index, i, scene->names[i],
             speed);
    if (e->param[2] != 0.0 || e->param[3] != 0.0) {
        double omega[3];
        tb__angular_velocity(b, s, omega);
        const double spin = tb__v3_norm(omega);
        consider(g, (e->param[2] + 2.0 * e->param[3] * spin) * smallest_moment_inverse(b), false,
                 "effect %zu (angular drag) on body %zu (\"%s\") at %.3g rad/s", index, i,
                 scene->names[i], spin);
    }
}

static void drag_modes(guard *g, const tb_scene *scene, size_t index, const double *y)
{
    const size_t body = scene->effects[index].body;
    if (body != TB_ALL_BODIES) {
        drag_body_modes(g, scene, index, body, y);
        return;
    }
    for (size_t i = 0; i < scene->body_count; ++i) {
        drag_body_modes(g, scene, index, i, y);
    }
}

/* a^2: how much faster than bouncing the body rocks on its contact points. Rotating the body
 * by theta moves point j by theta x r_j, so the rotational stiffness is at most
 * sum k_j [r_j x]^T [r_j x] = sum k_j (|r_j|^2 1 - r_j r_j^T), the inertia tensor of point
 * masses k_j at the arms; against I_body its largest generalised eigenvalue, bounded by the
 * largest row sum of |I^-1/2 A I^-1/2| (Gershgorin), is a^2 omega0^2 with
 * A = M sum share_j (|r_j|^2 1 - r_j r_j^T) / sum share_j (the points carrying the body share
 * 1). Each arm reaches the point's sphere, |r_j| + radius. A box on its corners gives 3, a
 * light body on wide points ~1e2; bouncing alone gives 1. */
static double rocking_factor(const tb_scene *scene, size_t first, size_t end)
{
    double A[3][3] = {{0}}, shares = 0.0;
    for (size_t j = first; j < end; ++j) {
        const tb__contact *c = &scene->contacts[j];
        const double length = tb__v3_norm(c->r), reach = length + c->radius;
        const double scale = length > 0.0 ? reach / length : 0.0;
        const double r[3] = {c->r[0] * scale, c->r[1] * scale, c->r[2] * scale};
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 3; ++l) {
                A[k][l] += c->share * ((k == l ? reach * reach : 0.0) - r[k] * r[l]);
            }
        }
        shares += c->share;
    }
    const tb__body *b = &scene->bodies[scene->contacts[first].body];
    double a2 = 1.0;
    for (int k = 0; k < 3; ++k) {
        double row = 0.0;
        for (int l = 0; l < 3; ++l) {
            row += fabs(A[k][l]) * sqrt(b->inv_moments[k] * b->inv_moments[l]);
        }
        a2 = fmax(a2, b->mass * row / shares);
    }
    return a2;
}

/* Ground contact of one body whose points are contacts[first, end). Each point's stiffness is
 * its share of M g / penetration and its damping 2 zeta sqrt(k m share), so every mode has the
 * same ratio of damping to stiffness: bouncing has omega0 = sqrt(g / penetration) and damping
 * ratio zeta, rocking omega0 a and zeta a; overdamped, the fast root is
 * omega0 a (zeta a + sqrt((zeta a)^2 - 1)). The bristles' tangential modes are sqrt(a^2 g s0). */
static void ground_body_modes(guard *g, const tb_scene *scene, size_t index, size_t first,
                              size_t end)
{
    const tb__effect *e = &scene->effects[index];
    const size_t i = scene->contacts[first].body;
    const double a = sqrt(rocking_factor(scene, first, end));
    const double omega0 = sqrt(e->param[1] / e->param[2]), zeta = a * e->param[3];
    if (zeta > 1.0) {
        consider(g, omega0 * a * (zeta + sqrt(zeta * zeta - 1.0)), false,
                 "effect %zu (ground contact) on body %zu (\"%s\"), rocking %.3g times faster "
                 "than it bounces",
                 index, i, scene->names[i], a);
    } else {
        consider(g, omega0 * a, true, "effect %zu (ground contact) on body %zu (\"%s\")", index, i,
                 scene->names[i]);
    }
    consider(g, sqrt(a * a * e->param[1] * e->param[7]), true,
             "effect %zu (ground friction bristles) on body %zu (\"%s\")", index, i,
             scene->names[i]);
}

static void ground_modes(guard *g, const tb_scene *scene, size_t index)
{
    size_t first = 0;
    for (size_t j = 1; j <= scene->contact_count; ++j) {
        if (j == scene->contact_count || scene->contacts[j].body != scene->contacts[first].body) {
            ground_body_modes(g, scene, index, first, j);
            first = j;
        }
    }
}

/* The largest stable step of method for the scene at state y, and what limits it. */
static void stable_step(const tb_scene *scene, const double *y, tb_method method, guard *g)
{
    step_limits(method, &g->imaginary, &g->real);
    g->dt = INFINITY;
    g->which[0] = '\0';
    if (!isfinite(g->imaginary)) {
        return; /* adaptive: error control chooses the step */
    }
    rotation_modes(g, scene, y);
    for (size_t k = 0; k < scene->effect_count; ++k) {
        switch (scene->effects[k].kind) {
        case TB__SPRING:
            spring_modes(g, scene, k);
            break;
        case TB__DRAG:
            drag_modes(g, scene, k, y);
            break;
        case TB__GROUND:
            ground_modes(g, scene, k);
            break;
        default: /* constant forces and torques add no rate; user effects are not known */
            break;
        }
    }
}

tb_status tb_scene_max_stable_step(const tb_scene *scene, tb_method method, double *out_dt,
                                   char *out_which)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_dt == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_dt is NULL");
    }
    guard g;
    stable_step(scene, scene->states, method, &g);
    *out_dt = g.dt;
    if (out_which != NULL) {
        snprintf(out_which, TB_DETAIL_SIZE, "%s", g.which);
    }
    return TB_STATUS_OK;
}

tb_status tb__scene_check_step(const tb_scene *scene, const double *y, tb_method method, double dt,
                               char *detail)
{
    if (scene->allow_unstable) {
        return TB_STATUS_OK;
    }
    guard g;
    stable_step(scene, y, method, &g);
    if (!(dt > g.dt)) {
        return TB_STATUS_OK;
    }
    return tb__set_detail(detail, TB_STATUS_UNSTABLE_STEP,
                          "dt: %g s is beyond %s's stability limit for %s: use dt <= %.3g s, an "
                          "adaptive method (cvode-adams, cvode-bdf), or allow_unstable",
                          dt, tb_method_name(method), g.which, g.dt);
}
