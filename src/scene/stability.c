/* The general stability guard: how fast a scene's fastest modes are, and so the largest fixed
 * step each method takes without amplifying them. Every mode is bounded from the body and
 * effect that make it, split by where its eigenvalues lie:
 *   oscillatory (near the imaginary axis): rotation (the quaternion turns at |omega| / 2, the
 *     gyroscopic modes of the Euler equations at most at |omega|, since |I_i - I_j| <= I_k, and
 *     the orientation's coupling through I^-1 L at up to |L| / sqrt(I_min I_mid); each bounded
 *     over the torque-free motion by rotation_rate), springs (sqrt(k w)), ground contact's bounce,
 * rocking and bristles; decaying (on the negative real axis): drag (b / m, 2 c |v| / m and the
 * angular twins over I_min), overdamped springs (c w), overdamped contact. The effects' modes are
 * their rows' estimates (tb__effect_ops.rate, in src/effects/). Rotation and quadratic drag grow
 * with the state, so the guard runs on a state: at creation and again at every advance
 * (tb__scene_check_step). */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "ode/rosenbrock.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

/* The smallest step limit found so far and what sets it. */
typedef struct guard {
    double imaginary, real; /* the method's limits */
    double dt;
    double oscillation; /* the fastest oscillation's rate seen, 1/s */
    double ringing;     /* the effects' fastest natural rate, overdamped modes too, 1/s */
    bool overflowed;    /* a rate that is not a number (inf, NaN): no step can be given */
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
    if (oscillatory && rate > g->oscillation) {
        g->oscillation = rate;
    }
    const bool overflowed = !isfinite(rate); /* inf, or NaN from inf - inf or 0 * inf */
    if (g->overflowed || (!overflowed && (!(rate > 0.0) || !(dt < g->dt)))) {
        return; /* the first rate that is not a number is the one named */
    }
    g->dt = overflowed ? 0.0 : dt;
    g->overflowed = overflowed;
    va_list args;
    va_start(args, format);
    const int length = vsnprintf(g->which, sizeof g->which, format, args);
    va_end(args);
    if (length >= 0 && (size_t)length < sizeof g->which) {
        snprintf(g->which + length, sizeof g->which - (size_t)length, ", rate %.3g 1/s", rate);
    }
}

/* The fastest rotation mode of a body over its torque-free motion from state s (1/s), from what
 * that motion keeps, |L| and the energy E = L . omega / 2, so that a step chosen now holds while
 * the body tumbles (a thin rod flipping about its middle axis reaches |omega| far above its
 * start). With d = 1 / I sorted d_max >= d_mid >= d_min:
 *   |omega|^2 = sum d_i^2 L_i^2 <= d_max sum d_i L_i^2 = 2 E d_max;
 *   the orientation's coupling through omega = R I^-1 R^T L: tilting the body by dtheta with L
 *     fixed changes omega by I^-1 (L x dtheta), whose eigenvalues are 0 and
 *     +-i sqrt(d_2 d_3 L_1^2 + d_1 d_3 L_2^2 + d_1 d_2 L_3^2) <= |L| sqrt(d_max d_mid): 7 000
 *     rad/s for a 1 m, 1 cm rod spinning end over end at 100 rad/s, where RK4 at 1/240 s grew
 *     the spin to 7e4 rad/s within a frame.
 * Both bounds are at least the current |omega| (the first always). */
static double rotation_rate(const tb__body *body, const double *s, double *out_spin)
{
    double omega[3];
    tb__angular_velocity(body, s, omega);
    *out_spin = tb__v3_hypot(omega);
    const double *d = body->inv_moments, *L = s + TB_STATE_L;
    const double d_max = fmax(d[0], fmax(d[1], d[2]));
    const double d_min = fmin(d[0], fmin(d[1], d[2]));
    const double d_mid = d[0] + d[1] + d[2] - d_max - d_min;
    /* in factors that stay finite wherever I omega and I^-1 L are (1e300 rad/s, moments of
     * 1e-200 kg m^2): 2 E = |L| (L / |L|) . omega */
    const double length = tb__v3_hypot(L);
    double along = 0.0;
    for (int k = 0; k < 3 && length > 0.0; ++k) {
        along += L[k] / length * omega[k];
    }
    const double energy_bound = sqrt(length) * sqrt(fmax(along, 0.0)) * sqrt(d_max);
    const double coupling = length * sqrt(d_max) * sqrt(d_mid);
    return fmax(*out_spin, fmax(energy_bound, coupling)); /* NaN and inf pass on to consider */
}

static void rotation_modes(guard *g, const tb_scene *scene, const double *y)
{
    for (size_t slot = 0; slot < scene->slot_count; ++slot) {
        const size_t i = scene->slot_ids[slot];
        double spin;
        const double rate = rotation_rate(&scene->bodies[slot], y + TB_STATE_SIZE * slot, &spin);
        if (!(rate * g->dt <= g->imaginary)) {
            consider(g, rate, true, "body %zu (\"%s\") spinning at %.3g rad/s", i, scene->names[i],
                     spin);
        }
    }
}

/* Effect k's modes, as its row estimates them (tb__effect_ops.rate). */
static void effect_modes(guard *g, const tb_scene *scene, size_t k, const double *y)
{
    const tb__effect *e = &scene->effects[k];
    if (e->ops->rate == NULL) {
        return; /* constant loads add no rate; user effects are not known */
    }
    tb__effect_rate rate;
    e->ops->rate(e, scene, y, &rate);
    g->ringing = fmax(g->ringing, rate.ringing);
    const size_t bodies[2] = {rate.oscillation_body, rate.decay_body};
    const double rates[2] = {rate.oscillation, rate.decay};
    for (int axis = 0; axis < 2; ++axis) {
        const size_t i = bodies[axis];
        consider(g, rates[axis], axis == 0, "effect %zu (a %s) on body %zu (\"%s\"), %s", k,
                 e->ops->name, i, i < scene->body_count ? scene->names[i] : "",
                 axis == 0 ? "oscillating" : "decaying");
    }
}

/* The jointed bodies' modes (the constraints' rate op: src/constraints/joint_rate.c). */
static void constraint_modes(guard *g, const tb_scene *scene, const double *y)
{
    tb__effect_rate rate;
    if (scene->constraint_ops == NULL || scene->constraint_ops->rate == NULL ||
        scene->constraint_ops->rate(scene->constraints, scene, y, &rate) != 0) {
        return; /* a derivative that fails here fails the step too, which reports it */
    }
    const size_t bodies[2] = {rate.oscillation_body, rate.decay_body};
    const double rates[2] = {rate.oscillation, rate.decay};
    for (int axis = 0; axis < 2; ++axis) {
        const size_t i = bodies[axis];
        consider(g, rates[axis], axis == 0, "the joints on body %zu (\"%s\"), %s", i,
                 i < scene->body_count ? scene->names[i] : "",
                 axis == 0 ? "oscillating" : "decaying");
    }
}

/* The largest stable step of method for the scene at state y, and what limits it. */
static void stable_step(const tb_scene *scene, const double *y, tb_method method, guard *g)
{
    /* the method table's limits: |h lambda| where an oscillation grows by at most 1% a step
     * (imaginary axis) and where a decay stops decaying (real axis) */
    tb_method_info info;
    g->dt = INFINITY;
    g->oscillation = 0.0;
    g->ringing = 0.0;
    g->overflowed = false;
    g->which[0] = '\0';
    if (tb_method_get_info(method, &info) != TB_STATUS_OK || info.adaptive) {
        return; /* adaptive: error control chooses the step */
    }
    g->imaginary = info.imaginary_limit;
    g->real = info.real_limit;
    g->oscillation = 0.0; /* rotation is counted only where it limits the step */
    rotation_modes(g, scene, y);
    for (size_t k = 0; k < scene->effect_count; ++k) {
        effect_modes(g, scene, k, y);
    }
    constraint_modes(g, scene, y);
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
    if (out_which != NULL) {
        snprintf(out_which, TB_DETAIL_SIZE, "%s", g.which);
    }
    if (g.overflowed) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NOT_FINITE,
                              "no stable step: the rate of %s is not a number", g.which);
    }
    *out_dt = g.dt;
    return TB_STATUS_OK;
}

/* The tunnelling limit (scene_events.c): a fixed step in which two bodies could close by more
 * than the thinner one's half-thickness is refused, naming them. rosenbrock halves a step
 * longer than the limit inside (tb_ode_events.split_limit), so its dt is refused only where a
 * part of TB__ROSENBROCK_TUNNEL_PARTS is still longer. */
static tb_status check_tunnelling(const tb_scene *scene, const double *y, tb_method method,
                                  double dt, char *detail)
{
    char which[TB_DETAIL_SIZE / 2];
    const double parts = method == TB_METHOD_ROSENBROCK ? TB__ROSENBROCK_TUNNEL_PARTS : 1.0;
    const double limit = tb_method_is_adaptive(method)
                             ? INFINITY
                             : parts * tb__scene_tunnel_step(scene, y, dt, which);
    if (!(dt > limit)) {
        return TB_STATUS_OK;
    }
    return tb__set_detail(detail, TB_STATUS_UNSTABLE_STEP,
                          "dt: %g s is too long for contact: %s: use dt <= %.3g s (dt = 0: the "
                          "scene's default step, %.3g s) or an adaptive method",
                          dt, which, limit, tb__scene_default_step(scene, y, method));
}

tb_status tb__scene_check_step(const tb_scene *scene, const double *y, tb_method method, double dt,
                               char *detail)
{
    if (scene->allow_unstable) {
        return check_tunnelling(scene, y, method, dt, detail);
    }
    guard g;
    stable_step(scene, y, method, &g);
    if (g.overflowed) {
        return tb__set_detail(
            detail, TB_STATUS_UNSTABLE_STEP,
            "dt: no fixed step is stable: the rate of %s is not a number; use "
            "an adaptive method (cvode-adams, cvode-bdf, ark-imex), rosenbrock or allow_unstable",
            g.which);
    }
    if (!(dt > g.dt)) {
        return check_tunnelling(scene, y, method, dt, detail);
    }
    return tb__set_detail(
        detail, TB_STATUS_UNSTABLE_STEP,
        "dt: %g s is beyond %s's stability limit for %s: use dt <= %.3g s (dt = 0: "
        "the scene's default step, %.3g s), an adaptive method (cvode-adams, "
        "cvode-bdf, ark-imex), rosenbrock, or allow_unstable",
        dt, tb_method_name(method), g.which, g.dt, tb__scene_default_step(scene, y, method));
}

/* The default step's rules (tb_scene_default_step): frames at 240 per second, half the stable
 * step, and 12 steps per period of the fastest oscillation. */
#define TB__DEFAULT_STEP (1.0 / 240.0)
#define TB__DEFAULT_STABILITY_MARGIN 0.5
#define TB__DEFAULT_RESOLUTION 0.5

/* h omega at which a method stable on the whole imaginary axis (rosenbrock: L-stable, so it damps
 * what it does not resolve) resolves an oscillation, a bounce's restitution: ROS2 meets e = 0.5
 * within 2% at h omega = 0.1 of the guard's fastest oscillation, 5% at 0.15, 9% at 0.2
 * (test_contact_effect); head_on_balls' e = 0.8 within 1% at 0.18 and 10% at 0.45 */
#define TB__IMPLICIT_RESOLUTION 0.1

double tb__scene_default_step(const tb_scene *scene, const double *y, tb_method method)
{
    if (tb_method_is_adaptive(method)) {
        return INFINITY;
    }
    guard g;
    stable_step(scene, y, method, &g);
    if (g.overflowed) {
        return 0.0; /* no step is stable: tb__scene_check_step names the rate */
    }
    char which[TB_DETAIL_SIZE / 2];
    const double tunnel = tb__scene_tunnel_step(scene, y, 0.0, which);
    const double resolved = isinf(g.imaginary) && g.oscillation > 0.0
                                ? TB__IMPLICIT_RESOLUTION / g.oscillation
                                : INFINITY;
    if (!(TB__DEFAULT_STEP > g.dt) && !(TB__DEFAULT_STEP > tunnel) &&
        !(TB__DEFAULT_STEP > resolved)) {
        return TB__DEFAULT_STEP;
    }
    double limit = fmin(TB__DEFAULT_STABILITY_MARGIN * fmin(g.dt, tunnel), resolved);
    if (g.oscillation > 0.0) {
        limit = fmin(limit, TB__DEFAULT_RESOLUTION / g.oscillation);
    }
    const double n = ceil(TB__DEFAULT_STEP / limit);
    return n < 1e15 ? TB__DEFAULT_STEP / n : limit;
}

/* An impact is a half period of its pair's law, rate omega: resolved at h omega up to the default
 * step's for a method stable on the whole imaginary axis (rosenbrock damps what it does not
 * resolve: above), and up to the stability limit for the others, which keep the restitution
 * there (RK4 gives head_on_balls' e = 0.8 as 0.796 at h omega 1.8 of its 2.8, docs/integrators.md)
 * and whose guard refuses longer steps (but under allow_unstable). */
double tb__scene_impact_resolution(const tb_scene *scene, const double *y, tb_method method,
                                   double *out_oscillation)
{
    guard g;
    stable_step(scene, y, method, &g);
    /* an impact rings at its law's natural rate even where the guard's bound on the rocking
     * damps the fastest mode past critical (a box on its corners: no oscillation at all) */
    *out_oscillation = g.overflowed ? INFINITY : fmax(g.oscillation, g.ringing);
    if (tb_method_is_adaptive(method)) {
        return INFINITY;
    }
    return isinf(g.imaginary) ? TB__IMPLICIT_RESOLUTION : g.imaginary;
}

tb_status tb_scene_default_step(const tb_scene *scene, tb_method method, double *out_dt)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_dt == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_dt is NULL");
    }
    if ((int)method < 0 || method >= TB_METHOD_COUNT) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                              "method: %d is not a method", (int)method);
    }
    const double dt = tb__scene_default_step(scene, scene->states, method);
    if (!(dt > 0.0)) { /* a rate that is not a number (F24): as tb_scene_max_stable_step */
        char which[TB_DETAIL_SIZE];
        double stable = 0.0; /* *out_dt is left alone */
        const tb_status status = tb_scene_max_stable_step(scene, method, &stable, which);
        return status != TB_STATUS_OK ? status
                                      : tb__scene_fail((tb_scene *)scene, TB_STATUS_NOT_FINITE,
                                                       "no default step: %s", which);
    }
    *out_dt = dt;
    return TB_STATUS_OK;
}
