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
 * (omega h)^2). The matrix is speculative (rosenbrock_linear.c): the Jacobian at the start or at
 * a predictor of the end, whichever entry is larger; and after the step, where the Jacobian at
 * its end holds an entry more than twice the matrix's, the step is taken again with it
 * (TB__ROS2_REFINES times at most). Any matrix keeps the order, so none of this changes a step
 * on a smooth system whose Jacobian does not grow. */
#include "ode/rosenbrock.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

/* gamma = 1 + 1/sqrt(2) */
#define TB__ROS2_GAMMA 1.7071067811865475

/* Times a step is taken again with the Jacobian at its end merged in (tb__rosenbrock_refine) */
#define TB__ROS2_REFINES 2

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

int tb__rosenbrock_step(tb_integrator *integrator, double t, double h, double t_last,
                        const double *y, double *y_new, double *work, long *evals)
{
    const tb_ode_system *system = &integrator->system;
    double *fy = tb__rosenbrock_start_rate(integrator);
    ++*evals;
    int rc = system->derivative(t, y, fy, system->ctx);
    if (rc == 0) {
        rc = tb__rosenbrock_factor(integrator, t, h, TB__ROS2_GAMMA, y, fy);
    }
    rc = rc != 0 ? rc : stages(integrator, t_last, h, y, fy, y_new, work, evals);
    for (int pass = 0; rc == 0 && pass < TB__ROS2_REFINES; ++pass) {
        bool changed = false;
        rc = tb__rosenbrock_refine(integrator, t + h, h, TB__ROS2_GAMMA, y_new, &changed);
        if (rc != 0 || !changed) {
            break;
        }
        rc = stages(integrator, t_last, h, y, fy, y_new, work, evals);
    }
    return rc;
}
