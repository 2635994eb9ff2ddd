/* The linearly implicit fixed-step method "rosenbrock": ROS2, the two-stage Rosenbrock-W method
 * of J. G. Verwer, E. J. Spee, J. G. Blom and W. Hundsdorfer, "A second-order Rosenbrock method
 * applied to photochemical dispersion problems", SIAM J. Sci. Comput. 20 (1999) 1456-1480,
 * eq. (2.4) with gamma = 1 + 1/sqrt(2):
 *
 *     (I - gamma h J) k1 = f(t, y)
 *     (I - gamma h J) k2 = f(t + h, y + h k1) - 2 k1
 *     y_new = y + 3/2 h k1 + 1/2 h k2
 *
 * It is of order 2 for any matrix J (a W-method), so a Jacobian that is exact only at the step's
 * start (t, y), or that leaves out df/dt, keeps the order. Its stability function on y' = lambda y
 * is R(z) = (1 + (1 - 2 gamma) z) / (1 - gamma z)^2 (the z^2 term's coefficient
 * gamma^2 - 2 gamma + 1/2 vanishes at this gamma): |R| <= 1 on the whole left half-plane and
 * R -> 0 as z -> infinity, L-stable, so a contact's fast mode is damped out rather than kept
 * ringing when h is longer than its period. One Jacobian and one factorisation a step, two
 * derivatives and two solves.
 *
 * A penalty contact's stiffness exists only where bodies overlap, so J at the step's start
 * misses a contact made inside the step, and the step is then explicit in it (a blow-up by
 * (omega h)^2). After the step, where the Jacobian at its end holds an entry more than twice the
 * matrix's, the step is taken again with that entry's column of it added (TB__ROS2_REFINES times at
 * most). Dense difference quotients (a system without its own Jacobian, which has no refinement)
 * take the matrix speculatively instead: the Jacobian at the start plus, in each column where one
 * of its entries is larger, that of a predictor of the end (whole columns keep the momentum:
 * sparse_copy.h). With the system's own Jacobian the predictor's is merged only where the system's
 * root functions (a scene's gaps) foresee an onset: a gap falling below zero, or to below twice its
 * depth at the start, between the start and the predictor. Always merged, the explicit predictor's
 * overshoot into a far deeper contact at omega h >> 1 made resting steps over-stiff and halved (the
 * stack at 1/240 s cost 10 times more); never merged, an impact shorter than the step, made at the
 * stage and gone by the end (which the refinement cannot see), stored energy (Newton's cradle at
 * 1/240 s threw a ball off at 9.4 m/s; test_an_impact_inside_a_step_stores_no_energy). Any matrix
 * keeps the order, so none of this changes a step on a smooth system whose Jacobian does not grow.
 *
 * Where contact points come and go inside the step (a die's corner, then an edge) no single
 * matrix describes it and the step can still throw a body off. A step whose change is not
 * explained by the rates at its ends (trusted: no larger than twice h times their sum, and
 * within their range, which a made-up push is not) is therefore taken as two halves, each
 * checked alike, down to 1/128 of the step, which is taken with the start's Jacobian alone; the
 * caller's grid and step count are unchanged, the cost is not (docs/integrators.md measures it). A
 * step longer than the system's split_limit (a scene's tunnelling bound: two bodies that could pass
 * through each other within it) is halved alike before it is tried, so that the scene's guard
 * refuses a step only where a quarter of it is too long (the dominoes at 1/240 s, refused at
 * domino20's fall before).
 *
 * Reuse. Any matrix keeping the order, a factorisation that served a trusted step of the same h
 * is tried again on the next (a halved step's second half included), without a Jacobian: the
 * step stands where it is trusted and the held matrix still describes it along its change
 * (tb__rosenbrock_probe: one derivative against 1-3 Jacobians of 60-240 derivatives each);
 * otherwise it is taken afresh as above. */
#include "ode/rosenbrock.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

/* gamma = 1 + 1/sqrt(2) */
#define TB__ROS2_GAMMA 1.7071067811865475

/* Times a step is taken again with the Jacobian at its end merged in (tb__rosenbrock_refine) */
#define TB__ROS2_REFINES 2

/* Halvings of a step whose solutions disagree (trusted), and how far they may disagree: in
 * size, and outside the range of the rates at the step's ends (by this part of their sum, and
 * this part of the largest |y|) */
#define TB__ROS2_SPLITS 7
#define TB__ROS2_TRUST 2.0
#define TB__ROS2_RANGE 0.25
#define TB__ROS2_RANGE_FLOOR 1e-4
_Static_assert((1 << TB__ROS2_SPLITS) == TB__ROSENBROCK_FINEST, "the finest part, rosenbrock.h");

/* out = y + a p (+ b q when q is not NULL) */
static void combine(double *out, const double *y, double a, const double *p, double b,
                    const double *q, size_t n)
{
    if (q == NULL) {
        for (size_t i = 0; i < n; ++i) {
            out[i] = y[i] + a * p[i];
        }
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        out[i] = y[i] + a * p[i] + b * q[i];
    }
}

/* The two stages from the factorised matrix: k1 from fy (kept), y_new. */
static int stages(tb_integrator *integrator, double t_last, double h, const double *y,
                  const double *fy, double *y_new, double *work, long *evals)
{
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    double *k1 = work, *k2 = work + n;
    memcpy(k1, fy, n * sizeof(double));
    int rc = tb__rosenbrock_solve(integrator, k1);
    if (rc != 0) {
        return rc;
    }
    combine(y_new, y, h, k1, 0.0, NULL, n); /* the second stage's input */
    ++*evals;
    rc = system->derivative(t_last, y_new, k2, system->ctx);
    if (rc != 0) {
        return rc;
    }
    for (size_t i = 0; i < n; ++i) {
        k2[i] -= 2.0 * k1[i];
    }
    rc = tb__rosenbrock_solve(integrator, k2);
    if (rc == 0) {
        combine(y_new, y, 1.5 * h, k1, 0.5 * h, k2, n);
    }
    return rc;
}

static bool all_zero(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        if (v[i] != 0.0) {
            return false;
        }
    }
    return true;
}

/* Whether nothing moves: f(t, y) = 0 and f(t_last, y) = 0 (every body asleep or held, no load
 * changing in time). Then k1 = M^-1 f(t, y) = 0 and k2 = M^-1 (f(t_last, y + h k1) - 2 k1) = 0
 * for any matrix M, so the step is y itself, exactly, without a Jacobian or a factorisation. */
static int still(tb_integrator *integrator, double t_last, const double *y, const double *fy,
                 double *work, long *evals, bool *out)
{
    const tb_ode_system *system = &integrator->system;
    *out = false;
    if (!all_zero(fy, system->n)) {
        return 0;
    }
    ++*evals;
    const int rc = system->derivative(t_last, y, work, system->ctx);
    *out = rc == 0 && all_zero(work, system->n);
    return rc;
}

/* One ROS2 step of size h from (t, y), whose rate is fy, into y_new with up to refines
 * refinements. */
static int one_step(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                    const double *fy, double *y_new, double *work, long *evals, int refines)
{
    int rc = tb__rosenbrock_factor(integrator, t, h, TB__ROS2_GAMMA, y, fy);
    rc = rc != 0 ? rc : stages(integrator, t_last, h, y, fy, y_new, work, evals);
    for (int pass = 0; rc == 0 && pass < refines; ++pass) {
        bool changed = false;
        rc = tb__rosenbrock_refine(integrator, t + h, h, TB__ROS2_GAMMA, y_new, &changed);
        if (rc != 0 || !changed) {
            break;
        }
        rc = stages(integrator, t_last, h, y, fy, y_new, work, evals);
    }
    return rc;
}

/* The largest |y_i|. */
static double largest(const double *y, size_t n)
{
    double size = 0.0;
    for (size_t i = 0; i < n; ++i) {
        size = fmax(size, fabs(y[i]));
    }
    return size;
}

/* The change below which a component is at rest: 1e-9 of the largest |y|. */
static double rest_floor(const double *y, size_t n)
{
    return 1e-9 * largest(y, n);
}

/* Whether a component's change d over the step lies within h times the range of its rates at the
 * ends (f0, f1), widened by TB__ROS2_RANGE of h (|f0| + |f1|) and by floor. A smooth rate that
 * stays between its end values moves y by h times a value between them (the mean value theorem);
 * ROS2's own damping of a linear mode moves it past them by at most (sqrt(2) - 1) / 2 = 0.207 of
 * that sum (the oscillator and the damped oscillator at any h omega and damping ratio). A change
 * outside is a push the ends do not show: a contact made and gone inside the step, or a kick the
 * matrix made up (a die's second corner landing while it slides on the first, thrown forward,
 * docs/integrators.md). */
static bool within_rates(double d, double h, double f0, double f1, double floor)
{
    const double slack = TB__ROS2_RANGE * h * (fabs(f0) + fabs(f1)) + floor;
    return d <= h * fmax(f0, f1) + slack && d >= h * fmin(f0, f1) - slack;
}

/* Whether the step's change is explained by the derivative at its ends: a step that blows up
 * (a contact the matrix does not describe) moves y far more than h times the rates at its start
 * and end, where an implicit step on a stiff mode moves it less (y' = -1000 y at h = 1: 1 against
 * 1000). Component by component, |y_new - y| <= TB__ROS2_TRUST h (|f(t, y)| + |f(t + h, y_new)|),
 * with a floor of 1e-9 of the largest |y| for states at rest; the end's rate goes into
 * work[n..2n). */
static int trusted(tb_integrator *integrator, double t_end, double h, const double *y,
                   const double *y_new, double *work, long *evals, bool *out)
{
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    const double *start = tb__rosenbrock_start_rate(integrator);
    double *end = work + n;
    ++*evals;
    const int rc = system->derivative(t_end, y_new, end, system->ctx);
    const double size = largest(y, n), floor = 1e-9 * size;
    const double range_floor = TB__ROS2_RANGE_FLOOR * size;
    bool ok = rc == 0;
    for (size_t i = 0; ok && i < n; ++i) {
        const double d = y_new[i] - y[i];
        ok = fabs(d) <= TB__ROS2_TRUST * h * (fabs(start[i]) + fabs(end[i])) + floor &&
             within_rates(d, h, start[i], end[i], range_floor);
    }
    *out = ok;
    return rc;
}

/* ROS2 with J = 0, Heun's explicit step y + h/2 (f(t, y) + f(t + h, y + h f(t, y))): what a
 * 128th of a step falls back to where I - gamma h J is singular even without the predictor (a
 * Jacobian with a positive eigenvalue 1 / (gamma h) at a kink of the contact law); h omega there is
 * 0.16 for the dice at 1/240 s, inside its stable range. */
static int heun(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                double *y_new, double *work, long *evals)
{
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    const double *f0 = tb__rosenbrock_start_rate(integrator); /* the step's, at (t, y) */
    double *f1 = work;
    (void)t;
    combine(y_new, y, h, f0, 0.0, NULL, n);
    ++*evals;
    const int rc = system->derivative(t_last, y_new, f1, system->ctx);
    if (rc == 0) {
        combine(y_new, y, 0.5 * h, f0, 0.5 * h, f1, n);
    }
    return rc;
}

/* The step again with the factorisation held from the last one of this h (no Jacobian, no
 * factorisation; order 2 still, a W-method): taken where it is trusted and the held matrix
 * describes it along its change (tb__rosenbrock_probe); *ok false otherwise. */
static int reuse_step(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                      const double *fy, double *y_new, double *work, long *evals, bool *ok)
{
    const tb_ode_system *system = &integrator->system;
    *ok = false;
    int rc = stages(integrator, t_last, h, y, fy, y_new, work, evals);
    rc = rc != 0 ? rc : trusted(integrator, t + h, h, y, y_new, work, evals, ok);
    if (rc == 0 && *ok) {
        rc = tb__rosenbrock_probe(integrator, t + h, h, TB__ROS2_GAMMA, y, y_new, work + system->n,
                                  rest_floor(y, system->n), ok);
    }
    return rc;
}

/* f(t, y) once for the step, whichever way it is taken (the start rate: the stages, the trust
 * check and heun read it); *unmoved where nothing moves, the step then being y itself (still: no
 * matrix made, the held one left as it was). */
static int start(tb_integrator *integrator, double t, double t_last, const double *y, double *y_new,
                 double *work, long *evals, bool *unmoved)
{
    const tb_ode_system *system = &integrator->system;
    double *fy = tb__rosenbrock_start_rate(integrator);
    ++*evals;
    int rc = system->derivative(t, y, fy, system->ctx);
    rc = rc != 0 ? rc : still(integrator, t_last, y, fy, work, evals, unmoved);
    if (rc == 0 && *unmoved) {
        memcpy(y_new, y, system->n * sizeof(double));
    }
    return rc;
}

static int split_step(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                      double *y_new, double *work, long *evals, int depth);

/* The last halving (1/128 of the step, h omega about 0.1 on a contact at 1/240 s): taken with the
 * start's Jacobian alone, neither the predictor's merged in nor the end's, and unchecked. Merged
 * from two states, the matrix had, where a contact was just touching, an
 * eigenvalue near 1 / (gamma h) and threw a die off within 33 us (its energy from 0.20 to 0.54
 * J); a matrix singular even so falls back to Heun's explicit step. */
static int finest_step(tb_integrator *integrator, double t, double h, double t_last,
                       const double *y, const double *fy, double *y_new, double *work, long *evals)
{
    tb__rosenbrock_hold(integrator, 0.0);
    tb__rosenbrock_speculate(integrator, false);
    int rc = one_step(integrator, t, h, t_last, y, fy, y_new, work, evals, 0);
    tb__rosenbrock_speculate(integrator, true);
    return rc == TB__ROSENBROCK_LINEAR_FAILED
               ? heun(integrator, t, h, t_last, y, y_new, work, evals)
               : rc;
}

/* The step as two halves, each taken (and checked, and halved) alike one level deeper. */
static int halves(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                  double *y_new, double *work, long *evals, int depth)
{
    tb__rosenbrock_count_split(integrator);
    double *middle = tb__rosenbrock_level(integrator, depth);
    const double half = 0.5 * h;
    const int rc = split_step(integrator, t, half, t + half, y, middle, work, evals, depth + 1);
    return rc != 0 ? rc
                   : split_step(integrator, t + half, half, t_last, middle, y_new, work, evals,
                                depth + 1);
}

/* Whether the system's split_limit at (t, y) is shorter than h (for a scene: two bodies could
 * pass through each other in the step; tb_ode_events). */
static bool too_long(const tb_integrator *integrator, double t, double h, const double *y)
{
    const tb_ode_system *system = &integrator->system;
    return system->events.split_limit != NULL &&
           h > system->events.split_limit(t, y, h, system->ctx);
}

static int split_step(tb_integrator *integrator, double t, double h, double t_last, const double *y,
                      double *y_new, double *work, long *evals, int depth)
{
    bool unmoved = false;
    int rc = start(integrator, t, t_last, y, y_new, work, evals, &unmoved);
    if (rc != 0 || unmoved) {
        return rc;
    }
    if (depth < TB__ROS2_SPLITS && too_long(integrator, t, h, y)) {
        return halves(integrator, t, h, t_last, y, y_new, work, evals, depth);
    }
    const double *fy = tb__rosenbrock_start_rate(integrator);
    if (depth < TB__ROS2_SPLITS && tb__rosenbrock_can_reuse(integrator, h)) {
        bool reused = false;
        /* any failure (a derivative refusing a state the held matrix threw off) is retried */
        if (reuse_step(integrator, t, h, t_last, y, fy, y_new, work, evals, &reused) == 0 &&
            reused) {
            return 0;
        }
        tb__rosenbrock_hold(integrator, 0.0);
    }
    if (depth >= TB__ROS2_SPLITS) {
        return finest_step(integrator, t, h, t_last, y, fy, y_new, work, evals);
    }
    rc = one_step(integrator, t, h, t_last, y, fy, y_new, work, evals, TB__ROS2_REFINES);
    bool ok = rc == 0;
    if (rc == 0) {
        rc = trusted(integrator, t + h, h, y, y_new, work, evals, &ok);
    }
    tb__rosenbrock_hold(integrator, rc == 0 && ok ? h : 0.0);
    /* a matrix made singular by the speculation is another sign of a step too long */
    const bool halve = rc == TB__ROSENBROCK_LINEAR_FAILED || (rc == 0 && !ok);
    return halve ? halves(integrator, t, h, t_last, y, y_new, work, evals, depth) : rc;
}

int tb__rosenbrock_step(tb_integrator *integrator, double t, double h, double t_last,
                        const double *y, double *y_new, double *work, long *evals)
{
    return split_step(integrator, t, h, t_last, y, y_new, work, evals, 0);
}
