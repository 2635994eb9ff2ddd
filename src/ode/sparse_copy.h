/* Private: the system's CSR Jacobian (tb_ode_sparse) as the implicit methods hand it to
 * SUNDIALS: its room, and its copy into a SUNMatrix_Sparse beside the pattern KLU last analysed
 * (BDF's sparse solver, cvode_sparse.c; rosenbrock's, rosenbrock_linear.c). Only files that
 * wrap SUNDIALS include it. */
#ifndef TUMBLE_SPARSE_COPY_H
#define TUMBLE_SPARSE_COPY_H

#include "tumble/ode.h"

#include <stdbool.h>
#include <stddef.h>

/* Room for capacity entries in J's columns and values (row_starts are the caller's); false on
 * no memory, J then as it was but for the arrays that did grow. */
bool tb__ode_sparse_reserve(tb_ode_sparse *J, size_t capacity);

/* from's columns added to into's where one of from's entries is larger in magnitude than ratio
 * times into's and than floor (rosenbrock's matrix taking a contact that switches on in the step:
 * the Jacobian ahead's, or at the step's end). Both Jacobians keep every linear invariant of the
 * system (c^T J = 0: a scene's total momentum), and so does their sum, column by column; an entry
 * by entry merge did not (a ball touching one neighbour at the start and the other ahead got one
 * contact's stiffness in its rows and the other's in its neighbours': Newton's cradle lost 0.13 %
 * of its momentum at 1/1000 s), and the column replaced whole dropped a contact the step started
 * with (a die thrown off). count entries over n columns, column_of their columns (NULL: dense
 * column-major n x n); taken: n of scratch. Returns how many columns took from's. */
size_t tb__add_larger_columns(double *into, const double *from, size_t count,
                              const size_t *column_of, size_t n, double ratio, double floor,
                              double *taken);

#ifdef TB_HAVE_KLU
#include <sunmatrix/sunmatrix_sparse.h>

/* The pattern KLU analysed last: n + 1 row starts, then the columns. */
typedef struct tb__klu_pattern {
    sunindextype *analysed;
    size_t entries; /* (size_t)-1 before the first */
} tb__klu_pattern;

/* Room for a pattern of n rows and capacity entries; false on no memory (p unchanged). */
bool tb__klu_pattern_reserve(tb__klu_pattern *p, size_t n, size_t capacity);

/* J into A, as J itself (shifted false) or as I - h_gamma J (shifted: J's pattern holds the
 * diagonal); true when the pattern is the one KLU analysed, else it becomes that one. */
bool tb__klu_copy(const tb_ode_sparse *J, bool shifted, double h_gamma, SUNMatrix A,
                  tb__klu_pattern *p);
#endif

#endif
