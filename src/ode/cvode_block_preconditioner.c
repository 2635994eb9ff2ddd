/* The block-diagonal preconditioner for CVODE's Krylov solver (see the header). LU with
 * partial pivoting by SUNDIALS' small dense routines. */
#include "ode/cvode_block_preconditioner.h"

#include "core/validate.h"

#include <sundials/sundials_dense.h>

#include <stdlib.h>
#include <string.h>

struct tb__block_preconditioner {
    size_t n, size, blocks;
    double *matrix;        /* per block, size x size column-major: P, then its LU factors */
    sunindextype *pivots;  /* size per block */
    double *shifted;       /* f at the perturbed state, n */
    double *saved;         /* per block: the perturbed component's value */
    double *increments;    /* per block: its increment */
    sunrealtype **columns; /* size column pointers into one block of matrix */
};

tb__block_preconditioner *tb__block_preconditioner_create(size_t n, size_t block_size)
{
    tb__block_preconditioner *p = calloc(1, sizeof *p);
    if (p == NULL) {
        return NULL;
    }
    p->n = n;
    p->size = block_size;
    p->blocks = n / block_size;
    size_t matrix_doubles = 0;
    p->matrix = tb__size_product(n, block_size, &matrix_doubles)
                    ? tb__malloc_array(matrix_doubles, sizeof(double))
                    : NULL;
    p->pivots = tb__malloc_array(n, sizeof(sunindextype));
    p->shifted = tb__malloc_array(n, sizeof(double));
    p->saved = tb__malloc_array(p->blocks, 2 * sizeof(double));
    p->columns = tb__malloc_array(block_size, sizeof(sunrealtype *));
    if (p->matrix == NULL || p->pivots == NULL || p->shifted == NULL || p->saved == NULL ||
        p->columns == NULL) {
        tb__block_preconditioner_destroy(p);
        return NULL;
    }
    p->increments = p->saved + p->blocks;
    return p;
}

void tb__block_preconditioner_destroy(tb__block_preconditioner *p)
{
    if (p != NULL) {
        free(p->matrix);
        free(p->pivots);
        free(p->shifted);
        free(p->saved);
        free(p->columns);
        free(p);
    }
}

/* Points columns at block b's matrix. */
static sunrealtype **block_columns(const tb__block_preconditioner *p, size_t b)
{
    double *block = p->matrix + b * p->size * p->size;
    for (size_t j = 0; j < p->size; ++j) {
        p->columns[j] = block + j * p->size;
    }
    return p->columns;
}

/* Column k of every block of P = I - gamma J from one perturbed evaluation. */
static int difference_column(tb__block_preconditioner *p, size_t k, double t, double *y,
                             const double *fy, double gamma, const double *weights,
                             double min_increment, tb__block_rhs f, void *ctx)
{
    const size_t size = p->size;
    for (size_t b = 0; b < p->blocks; ++b) {
        const size_t j = b * size + k;
        p->saved[b] = y[j];
        p->increments[b] = tb__difference_increment(y[j], min_increment, weights[j]);
        y[j] += p->increments[b];
    }
    const int rc = f(t, y, p->shifted, ctx);
    for (size_t b = 0; b < p->blocks; ++b) {
        y[b * size + k] = p->saved[b];
    }
    if (rc != 0) {
        return rc;
    }
    for (size_t b = 0; b < p->blocks; ++b) {
        double *column = p->matrix + (b * size + k) * size;
        const double *f_shift = p->shifted + b * size, *f_base = fy + b * size;
        const double scale = -gamma / p->increments[b];
        for (size_t i = 0; i < size; ++i) {
            column[i] = scale * (f_shift[i] - f_base[i]) + (i == k ? 1.0 : 0.0);
        }
    }
    return 0;
}

int tb__block_preconditioner_setup(tb__block_preconditioner *p, double t, double *y,
                                   const double *fy, double gamma, const double *weights,
                                   double min_increment, tb__block_rhs f, void *ctx, long *evals)
{
    for (size_t k = 0; k < p->size; ++k) {
        ++*evals;
        const int rc = difference_column(p, k, t, y, fy, gamma, weights, min_increment, f, ctx);
        if (rc != 0) {
            return rc;
        }
    }
    const sunindextype size = (sunindextype)p->size;
    for (size_t b = 0; b < p->blocks; ++b) {
        if (SUNDlsMat_denseGETRF(block_columns(p, b), size, size, p->pivots + b * p->size) != 0) {
            return 1;
        }
    }
    return 0;
}

void tb__block_preconditioner_solve(const tb__block_preconditioner *p, const double *r, double *z)
{
    if (z != r) {
        memcpy(z, r, p->n * sizeof(double));
    }
    const sunindextype size = (sunindextype)p->size;
    for (size_t b = 0; b < p->blocks; ++b) {
        SUNDlsMat_denseGETRS(block_columns(p, b), size, p->pivots + b * p->size, z + b * p->size);
    }
}
