/* What CVODE and ARKStep call back: the right-hand side, the projection, the dense Jacobian and the
 * block-diagonal preconditioner. user_data is always the tb_integrator. */
#include "ode/cvode_internal.h"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <math.h>

double tb__sundials_system_time(const tb__cvode *cvode, double tau)
{
    const double t = cvode->t_origin + tau;
    return t < cvode->break_at ? t : nextafter(cvode->break_at, -INFINITY);
}

/* f (the system's derivative, or its split's explicit part) at the solver's time tau
 * (t = tb__sundials_system_time), keeping its failures. */
static int evaluate_part(tb_integrator *integrator, tb_ode_derivative f, double tau,
                         const double *y, double *dydt)
{
    tb__cvode *cvode = integrator->cvode;
    const double t = tb__sundials_system_time(cvode, tau);
    /* A fatal failure stays fatal for the rest of the run: SUNDIALS 6's fixed-point solver
     * (Adams) reports a failed system function as a recoverable convergence failure, and
     * CVODE would otherwise keep shrinking the step towards the failing time. */
    if (cvode->derivative_status < 0) {
        return cvode->derivative_status;
    }
    const tb_ode_system *system = &integrator->system;
    const int rc = f(t, y, dydt, system->ctx);
    if (rc != 0) {
        cvode->derivative_status = rc;
        cvode->derivative_time = t;
        return rc; /* CVODE's convention is the layer's: > 0 recoverable, < 0 fatal */
    }
    /* A NaN or infinite derivative is kept as the cause and made a recoverable failure: a
     * smaller step may avoid it, and otherwise CVODE's error test would fail on it anyway. */
    const size_t bad = tb__first_non_finite(dydt, system->n);
    if (bad < system->n) {
        cvode->non_finite_index = bad;
        cvode->non_finite_value = dydt[bad];
        cvode->non_finite_time = t;
        return 1;
    }
    return 0;
}

static int evaluate(tb_integrator *integrator, double tau, const double *y, double *dydt)
{
    return evaluate_part(integrator, integrator->system.derivative, tau, y, dydt);
}

int tb__cvode_derivative(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    return evaluate(user_data, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

int tb__sundials_explicit_part(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    tb_integrator *integrator = user_data;
    return evaluate_part(integrator, integrator->system.split.explicit_part, t,
                         N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

int tb__sundials_implicit_part(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data)
{
    tb_integrator *integrator = user_data;
    N_Vector explicit_part = integrator->cvode->split_work;
    int rc = tb__cvode_derivative(t, y, ydot, user_data);
    rc = rc != 0 ? rc : tb__sundials_explicit_part(t, y, explicit_part, user_data);
    if (rc == 0) {
        N_VLinearSum(1.0, ydot, -1.0, explicit_part, ydot);
    }
    return rc;
}

/* The post-step hook as a CVODE projection (BDF): corr = hook(ycur) - ycur. */
int tb__cvode_project(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps, N_Vector err,
                      void *user_data)
{
    (void)eps;
    (void)err; /* the error estimate is left unprojected: a conservative estimate */
    tb_integrator *integrator = user_data;
    N_VScale(1.0, ycur, corr);
    const double t_system = integrator->cvode->t_origin + t;
    if (integrator->system.post_step(t_system, N_VGetArrayPointer(corr), integrator->system.ctx) !=
        0) {
        return -1;
    }
    N_VLinearSum(1.0, corr, -1.0, ycur, corr);
    return 0;
}

/* The smallest difference-quotient increment, min_increment of tb__difference_increment:
 * fetches the error weights into cvode->weights and returns 1000 |h| u n ||f||_w (1 if
 * f = 0). */
static double increment_floor(tb__cvode *cvode, N_Vector fy)
{
    sunrealtype h = 0.0;
    cvode->ops->current_step(cvode->mem, &h);
    cvode->ops->err_weights(cvode->mem, cvode->weights);
    const double f_norm = N_VWrmsNorm(fy, cvode->weights);
    return f_norm != 0.0 ? 1000.0 * fabs(h) * SUN_UNIT_ROUNDOFF * (double)N_VGetLength(fy) * f_norm
                         : 1.0;
}

/* Dense Jacobian by forward differences, column by column. CVODE's built-in version allocates
 * a vector wrapper on every call; this one allocates nothing. */
int tb__cvode_dense_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *user_data,
                             N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    (void)tmp2, (void)tmp3;
    tb_integrator *integrator = user_data;
    tb__cvode *cvode = integrator->cvode;
    const sunindextype n = N_VGetLength(y);
    const double min_increment = increment_floor(cvode, fy);
    double *y_data = N_VGetArrayPointer(y), *f_data = N_VGetArrayPointer(fy);
    double *f_shift = N_VGetArrayPointer(tmp1), *w = N_VGetArrayPointer(cvode->weights);
    for (sunindextype j = 0; j < n; ++j) {
        const double saved = y_data[j];
        const double increment = tb__difference_increment(saved, min_increment, w[j]);
        y_data[j] = saved + increment;
        const int rc = cvode->implicit_rhs(t, y, tmp1, user_data);
        cvode->jacobian_evals++;
        y_data[j] = saved;
        if (rc != 0) {
            return rc;
        }
        double *column = SUNDenseMatrix_Column(J, j);
        for (sunindextype i = 0; i < n; ++i) {
            column[i] = (f_shift[i] - f_data[i]) / increment;
        }
    }
    return 0;
}

/* What Newton's matrix is of: f, or ARKStep's f_I = f - f_E with a split (the fy the
 * preconditioner's difference quotients subtract is then f_I). */
static int block_rhs(double t, double *y, double *f_out, void *ctx)
{
    tb_integrator *integrator = ctx;
    N_Vector split = integrator->cvode->split_work;
    int rc = evaluate(integrator, t, y, f_out);
    if (rc != 0 || split == NULL) {
        return rc;
    }
    double *explicit_part = N_VGetArrayPointer(split);
    rc = evaluate_part(integrator, integrator->system.split.explicit_part, t, y, explicit_part);
    for (size_t i = 0; rc == 0 && i < integrator->system.n; ++i) {
        f_out[i] -= explicit_part[i];
    }
    return rc;
}

/* The block-diagonal preconditioner (systems of independent blocks). J is not kept between
 * setups, to save its memory, so every setup forms it anew (jok is ignored). */
int tb__cvode_block_setup(sunrealtype t, N_Vector y, N_Vector fy, sunbooleantype jok,
                          sunbooleantype *jcur, sunrealtype gamma, void *user_data)
{
    (void)jok;
    tb_integrator *integrator = user_data;
    tb__cvode *cvode = integrator->cvode;
    *jcur = SUNTRUE;
    const double min_increment = increment_floor(cvode, fy);
    return tb__block_preconditioner_setup(cvode->block_preconditioner, t, N_VGetArrayPointer(y),
                                          N_VGetArrayPointer(fy), gamma,
                                          N_VGetArrayPointer(cvode->weights), min_increment,
                                          block_rhs, integrator, &cvode->jacobian_evals);
}

int tb__cvode_block_solve(sunrealtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z,
                          sunrealtype gamma, sunrealtype delta, int lr, void *user_data)
{
    (void)t, (void)y, (void)fy, (void)gamma, (void)delta, (void)lr;
    const tb_integrator *integrator = user_data;
    tb__block_preconditioner_solve(integrator->cvode->block_preconditioner, N_VGetArrayPointer(r),
                                   N_VGetArrayPointer(z));
    return 0;
}
