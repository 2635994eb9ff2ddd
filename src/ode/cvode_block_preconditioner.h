/* Private: a block-diagonal preconditioner P = I - gamma J for CVODE's Krylov solver, for
 * systems that declare independent blocks (tb_ode_system.blocks.size). Their Jacobian is block
 * diagonal, so P is exact; it costs block_size derivative evaluations a setup and about
 * block_size + 2 doubles a component (the factors, the pivots, one vector), where a banded
 * preconditioner covering one block costs 2 block_size + 1 evaluations and about 5 block_size
 * doubles. */
#ifndef TUMBLE_CVODE_BLOCK_PRECONDITIONER_H
#define TUMBLE_CVODE_BLOCK_PRECONDITIONER_H

#include <sundials/sundials_types.h>

#include <math.h>
#include <stddef.h>

/* The forward-difference increment for a component y_j with error weight w_j, as CVODE's
 * documentation gives for its own difference quotients: sigma_j = max(sqrt(u) |y_j|,
 * min_increment / w_j), u the unit round-off and min_increment = 1000 |h| u n ||f||_w
 * (1 if f = 0). Shared by the dense Jacobian and this preconditioner. */
static inline double tb__difference_increment(double y, double min_increment, double weight)
{
    return fmax(sqrt(SUN_UNIT_ROUNDOFF) * fabs(y), min_increment / weight);
}

typedef struct tb__block_preconditioner tb__block_preconditioner;

/* NULL when out of memory. */
tb__block_preconditioner *tb__block_preconditioner_create(size_t n, size_t block_size);
void tb__block_preconditioner_destroy(tb__block_preconditioner *p);

/* The derivative as CVODE's setup sees it: f(t, y) into f_out, the layer's return convention. */
typedef int (*tb__block_rhs)(double t, double *y, double *f_out, void *ctx);

/* Forms and factors P = I - gamma J at (t, y), J by forward differences: component k of every
 * block is perturbed at once (blocks do not interact), by tb__difference_increment. y is perturbed
 * and restored in place. Returns 0, the derivative's non-zero return, or 1 if a block is singular
 * (recoverable: CVODE retries). *evals counts derivative calls. */
int tb__block_preconditioner_setup(tb__block_preconditioner *p, double t, double *y,
                                   const double *fy, double gamma, const double *weights,
                                   double min_increment, tb__block_rhs f, void *ctx, long *evals);

/* z = P^-1 r (z may be r). */
void tb__block_preconditioner_solve(const tb__block_preconditioner *p, const double *r, double *z);

#endif
