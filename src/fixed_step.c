/* Fixed-step explicit Runge-Kutta steppers: Euler, midpoint (RK2) and classical RK4.
 * Each writes the new state into y_new and never touches y, so a failed step loses nothing. */
#include "integrator.h"

#include <stddef.h>

/* out = y + s k */
static void add_scaled(double *out, const double *y, double s, const double *k, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        out[i] = y[i] + s * k[i];
    }
}

/* y_new = y + h f(t, y) */
static int euler_step(const tb_ode_system *system, double t, double h, const double *y,
                      double *y_new, double *work, long *evals)
{
    double *k = work;
    ++*evals;
    int rc = system->derivative(t, y, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_new, y, h, k, system->n);
    return 0;
}

/* k1 = f(t, y); y_new = y + h f(t + h/2, y + h/2 k1) */
static int midpoint_step(const tb_ode_system *system, double t, double h, const double *y,
                         double *y_new, double *work, long *evals)
{
    const size_t n = system->n;
    double *k = work, *y_mid = work + n;
    ++*evals;
    int rc = system->derivative(t, y, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_mid, y, 0.5 * h, k, n);
    ++*evals;
    rc = system->derivative(t + 0.5 * h, y_mid, k, system->ctx);
    if (rc != 0) {
        return rc;
    }
    add_scaled(y_new, y, h, k, n);
    return 0;
}

/* Classical RK4, y_new = y + h/6 (k1 + 2 k2 + 2 k3 + k4), accumulated stage by stage so the
 * workspace is one stage vector and one stage state (2n) instead of four stages. */
static int rk4_step(const tb_ode_system *system, double t, double h, const double *y, double *y_new,
                    double *work, long *evals)
{
    static const double stage_time[4] = {0.0, 0.5, 0.5, 1.0};             /* c_i */
    static const double next_stage[3] = {0.5, 0.5, 1.0};                  /* a_{i+1,i} */
    static const double weight[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6}; /* b_i */
    const size_t n = system->n;
    double *k = work, *y_stage = work + n;
    const double *stage_input = y;
    for (size_t i = 0; i < n; ++i) {
        y_new[i] = y[i];
    }
    for (int s = 0; s < 4; ++s) {
        ++*evals;
        int rc = system->derivative(t + stage_time[s] * h, stage_input, k, system->ctx);
        if (rc != 0) {
            return rc;
        }
        for (size_t i = 0; i < n; ++i) {
            y_new[i] += weight[s] * h * k[i];
        }
        if (s < 3) {
            add_scaled(y_stage, y, next_stage[s] * h, k, n);
            stage_input = y_stage;
        }
    }
    return 0;
}

const tb__stepper tb__steppers[TB_METHOD_COUNT] = {
    [TB_METHOD_EULER] = {"euler", 1, euler_step},
    [TB_METHOD_MIDPOINT] = {"midpoint", 2, midpoint_step},
    [TB_METHOD_RK4] = {"rk4", 4, rk4_step},
};
