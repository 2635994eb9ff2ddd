/* BDF's sparse linear solver: the system's own Jacobian (tb_ode_system.jacobian) in a
 * compressed-sparse-row SUNMatrix_Sparse, factorised by KLU. The system writes pattern and values
 * at every evaluation; KLU keeps the symbolic analysis of the last pattern and redoes it only
 * when the pattern changed (SUNLinSol_KLUReInit), since a refactorisation on another pattern
 * would be wrong. The pattern must hold the diagonal, so that CVODE's I - gamma J keeps it.
 * Room grows only before a step, when the system's capacity grew. */
#include "ode/cvode_internal.h"
#include "ode/sparse_copy.h"

#include "core/detail.h"
#include "core/validate.h"

#include <cvode/cvode.h>

#ifdef TB_HAVE_KLU
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct tb__cvode_sparse {
    tb_ode_sparse J;          /* what the system writes */
    tb__klu_pattern analysed; /* the pattern KLU analysed last */
    N_Vector state;           /* the state at CVODE's internal time, for the capacity */
    long analyses;            /* symbolic analyses (pattern changes) */
};

void tb__cvode_sparse_free(tb__cvode *cvode)
{
    tb__cvode_sparse *sparse = cvode->sparse;
    if (sparse == NULL) {
        return;
    }
    free(sparse->J.row_starts);
    free(sparse->J.columns);
    free(sparse->J.values);
    free(sparse->analysed.analysed);
    if (sparse->state != NULL) {
        N_VDestroy(sparse->state);
    }
    free(sparse);
    cvode->sparse = NULL;
}

/* Room for capacity entries in J, the analysed copy and the matrix (when it exists). */
static bool make_room(tb__cvode *cvode, size_t capacity)
{
    tb__cvode_sparse *sparse = cvode->sparse;
    /* J's capacity grows last, once everything else has room */
    return tb__klu_pattern_reserve(&sparse->analysed, sparse->J.n, capacity) &&
           (cvode->matrix == NULL ||
            SUNSparseMatrix_Reallocate(cvode->matrix, (sunindextype)capacity) == 0) &&
           tb__ode_sparse_reserve(&sparse->J, capacity);
}

tb_status tb__cvode_sparse_create(tb_integrator *integrator, tb_error *error)
{
    tb__cvode *cvode = integrator->cvode;
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    if (system->jacobian.evaluate == NULL) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.linear_solver: sparse needs the system's jacobian "
                             "(tb_ode_system.jacobian), which this system has not");
    }
    cvode->sparse = calloc(1, sizeof *cvode->sparse);
    tb__cvode_sparse *sparse = cvode->sparse;
    if (sparse == NULL ||
        (sparse->J.row_starts = tb__malloc_array(n + 1, sizeof(size_t))) == NULL ||
        (sparse->state = N_VClone(cvode->y)) == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "sparse Jacobian for n = %zu", n);
    }
    sparse->J.n = n;
    sparse->analysed.entries = (size_t)-1;
    /* room for the diagonal: y is not read before the first step, where the system's capacity
     * is asked (tb__cvode_sparse_refresh) */
    const size_t capacity = n;
    if (!make_room(cvode, capacity)) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "sparse Jacobian for n = %zu", n);
    }
    cvode->matrix = SUNSparseMatrix((sunindextype)n, (sunindextype)n, (sunindextype)capacity,
                                    CSR_MAT, cvode->context);
    cvode->linear =
        cvode->matrix == NULL ? NULL : SUNLinSol_KLU(cvode->y, cvode->matrix, cvode->context);
    /* AMD, for a pattern symmetric by blocks (a coupling goes both ways): KLU's default COLAMD
     * spent 73% of BDF's time refactorising on the dice, AMD cut the run to a quarter */
    const int ordering =
        cvode->linear != NULL ? SUNLinSol_KLUSetOrdering(cvode->linear, 0) : SUNLS_SUCCESS;
    return cvode->linear == NULL || ordering != SUNLS_SUCCESS
               ? tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "KLU solver for n = %zu", n)
               : TB_STATUS_OK;
}

int tb__cvode_sparse_refresh(tb_integrator *integrator, sunrealtype tn)
{
    tb__cvode *cvode = integrator->cvode;
    tb__cvode_sparse *sparse = cvode->sparse;
    if (sparse == NULL) {
        return CV_SUCCESS;
    }
    const double *state = N_VGetArrayPointer(cvode->y);
    if (cvode->started) { /* y may hold an interpolated output: take CVODE's own y_n */
        const int flag = cvode->ops->get_dky(cvode->mem, tn, 0, sparse->state);
        if (flag != CV_SUCCESS) {
            return flag;
        }
        state = N_VGetArrayPointer(sparse->state);
    }
    const tb_ode_system *system = &integrator->system;
    const size_t capacity = system->jacobian.capacity(cvode->t_origin + tn, state, system->ctx);
    if (capacity < sparse->J.n || (capacity > sparse->J.capacity && !make_room(cvode, capacity))) {
        snprintf(cvode->message, sizeof cvode->message,
                 "system.jacobian.capacity: %zu entries for n = %zu (at least the diagonal; 0: "
                 "the system could not build its pattern) or out of memory for them",
                 capacity, sparse->J.n);
        return CV_MEM_FAIL;
    }
    return CV_SUCCESS;
}

int tb__cvode_sparse_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, void *user_data,
                              N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    (void)tmp2, (void)tmp3;
    tb_integrator *integrator = user_data;
    tb__cvode *cvode = integrator->cvode;
    tb__cvode_sparse *sparse = cvode->sparse;
    const tb_ode_system *system = &integrator->system;
    /* ARKStep with a split passes f_I = f - f_E; the system's Jacobian is of f and takes f (its
     * difference quotients subtract it: with f_I they were off by f_E / increment) */
    int rc = cvode->split_work != NULL ? tb__sundials_explicit_part(t, y, tmp1, user_data) : 0;
    if (rc == 0 && cvode->split_work != NULL) {
        N_VLinearSum(1.0, fy, 1.0, tmp1, tmp1);
        fy = tmp1;
    }
    rc = rc != 0
             ? rc
             : system->jacobian.evaluate(tb__sundials_system_time(cvode, t), N_VGetArrayPointer(y),
                                         N_VGetArrayPointer(fy), &sparse->J, system->ctx);
    const size_t entries = rc == 0 ? sparse->J.row_starts[sparse->J.n] : 0;
    if (rc != 0 || entries > (size_t)SUNSparseMatrix_NNZ(A)) {
        snprintf(cvode->message, sizeof cvode->message,
                 "system.jacobian.evaluate returned %d at t = %.17g%s", rc,
                 cvode->t_origin + (double)t,
                 rc == 0 ? " with more entries than its capacity" : "");
        return rc > 0 ? rc : -1;
    }
    if (!tb__klu_copy(&sparse->J, false, 0.0, A, &sparse->analysed)) {
        sparse->analyses++;
        return SUNLinSol_KLUReInit(cvode->linear, A, SUNSparseMatrix_NNZ(A),
                                   SUNKLU_REINIT_PARTIAL) == SUNLS_SUCCESS
                   ? 0
                   : -1;
    }
    return 0;
}

long tb__cvode_sparse_analyses(const tb__cvode *cvode)
{
    return cvode->sparse != NULL ? cvode->sparse->analyses : 0;
}

#else /* built without KLU (cmake/TumbleDependencies.cmake): the sparse solver is refused */

tb_status tb__cvode_sparse_create(tb_integrator *integrator, tb_error *error)
{
    (void)integrator;
    return tb__set_error(error, TB_STATUS_UNSUPPORTED,
                         "def.linear_solver: sparse needs SUNDIALS' KLU solver, which this build "
                         "of tumble has not (libsuitesparse-dev; cmake -DTUMBLE_WITH_KLU=ON)");
}

int tb__cvode_sparse_refresh(tb_integrator *integrator, sunrealtype tn)
{
    (void)integrator, (void)tn;
    return CV_SUCCESS;
}

int tb__cvode_sparse_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, void *user_data,
                              N_Vector tmp1, N_Vector tmp2, N_Vector tmp3)
{
    (void)t, (void)y, (void)fy, (void)A, (void)user_data, (void)tmp1, (void)tmp2, (void)tmp3;
    return -1;
}

long tb__cvode_sparse_analyses(const tb__cvode *cvode)
{
    (void)cvode;
    return 0;
}

void tb__cvode_sparse_free(tb__cvode *cvode)
{
    (void)cvode;
}

#endif
