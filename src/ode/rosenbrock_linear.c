/* The Rosenbrock method's linear algebra: M = I - h gamma J formed once a step and factorised,
 * then solved once a stage. Three ways, chosen at creation:
 *   - sparse (a system with tb_ode_system.jacobian, in a build with KLU, n above
 *     TB__ROSENBROCK_SMALL): the system's CSR pattern in a SUNMatrix_Sparse, factorised by
 *     SUNDIALS' KLU; its symbolic analysis is redone only when the pattern changed (a contact
 *     made or broken) or a refactorisation fails (factor_own), and allocates;
 *   - dense from the system's Jacobian (small n, or no KLU, up to TB__ROSENBROCK_DENSE_MAX);
 *   - dense difference quotients, n derivatives a step, for a system without a Jacobian.
 * Dense factorisations are SUNDIALS' SUNLinSol_Dense (LU with partial pivoting). Nothing is
 * allocated after creation except the sparse room, when the system's capacity grows. */
#include "ode/rosenbrock.h"
#include "ode/sparse_copy.h"

#include "core/detail.h"
#include "core/validate.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#ifdef TB_HAVE_KLU
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>
#endif

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Up to this n a system's own Jacobian is factorised dense, in a build with KLU too: KLU
 * analyses each new pattern (a contact made or broken) anew, which allocates, where a dense LU
 * allocates nothing after creation; above it, KLU (allocating at pattern changes, as BDF's
 * sparse solver does, docs/integrators.md). */
#define TB__ROSENBROCK_SMALL 32

/* The matrix takes a column of the Jacobian ahead or at the step's end (tb__rosenbrock_refine)
 * where one of its entries is this many times the matrix's: a contact switching on, not the
 * rounding of two quotients of one stiffness, which added would double the column */
#define TB__ROSENBROCK_REFINE_RATIO 2.0

struct tb__rosenbrock {
    SUNContext context;
    SUNMatrix matrix; /* M: CSR sparse or dense */
    SUNLinearSolver linear;
    N_Vector x;                         /* a shell over the caller's array (N_VSetArrayPointer) */
    bool sparse;                        /* KLU path */
    bool own_jacobian;                  /* the system's jacobian (else difference quotients) */
    tb_ode_sparse J;                    /* what the system writes at (t, y) */
    tb_ode_sparse ahead;                /* ... at the step's end (tb__rosenbrock_refine) */
    double *predicted, *predicted_rate; /* the predictor and its derivative, n each */
    double *start_rate;                 /* f(t, y) at the step's start, n */
    double *levels;                     /* TB__ROSENBROCK_LEVELS middles of halved steps, n each */
    long splits;                        /* halved steps */
    double held_h; /* the step the factorisation was made for and passed with; 0: none to reuse */
    double *jw_d;  /* J d of the held matrix, n (tb__rosenbrock_probe) */
    bool plain;    /* no speculation (tb__rosenbrock_speculate) */
#ifdef TB_HAVE_KLU
    tb__klu_pattern analysed; /* the pattern KLU analysed last */
#endif
    double *shifted, *column; /* difference quotients: y with one component moved, its f */
    double *dense_ahead;      /* difference quotients at the predictor, n x n */
    double *gaps;             /* the system's root functions at the start and the predictor */
    char message[TB_DETAIL_SIZE];
};

static tb_status rosenbrock_fail(tb_error *error, const char *what, size_t n)
{
    return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "rosenbrock: %s for n = %zu", what, n);
}

/* Room for capacity entries in both Jacobians, the analysed copy and the sparse matrix. */
static bool make_room(tb__rosenbrock *r, size_t capacity)
{
#ifdef TB_HAVE_KLU
    if (!tb__klu_pattern_reserve(&r->analysed, r->J.n, capacity)) {
        return false;
    }
#endif
    if (!tb__ode_sparse_reserve(&r->J, capacity) || !tb__ode_sparse_reserve(&r->ahead, capacity)) {
        return false;
    }
#ifdef TB_HAVE_KLU
    if (r->sparse && r->matrix != NULL &&
        SUNSparseMatrix_Reallocate(r->matrix, (sunindextype)capacity) != 0) {
        return false;
    }
#endif
    return true;
}

/* The matrix and its solver: KLU on a CSR matrix with room for the diagonal, or dense LU. */
static tb_status make_solver(tb__rosenbrock *r, size_t n, tb_error *error)
{
#ifdef TB_HAVE_KLU
    if (r->sparse) {
        r->matrix =
            SUNSparseMatrix((sunindextype)n, (sunindextype)n, (sunindextype)n, CSR_MAT, r->context);
        r->linear = r->matrix == NULL ? NULL : SUNLinSol_KLU(r->x, r->matrix, r->context);
        /* AMD: the contact pattern is symmetric by blocks (cvode_sparse.c measured it) */
        if (r->linear == NULL || SUNLinSol_KLUSetOrdering(r->linear, 0) != SUNLS_SUCCESS) {
            return rosenbrock_fail(error, "KLU solver", n);
        }
        return SUNLinSolInitialize(r->linear) == SUNLS_SUCCESS ? TB_STATUS_OK
                                                               : rosenbrock_fail(error, "KLU", n);
    }
#endif
    r->matrix = SUNDenseMatrix((sunindextype)n, (sunindextype)n, r->context);
    r->linear = r->matrix == NULL ? NULL : SUNLinSol_Dense(r->x, r->matrix, r->context);
    if (r->linear == NULL || SUNLinSolInitialize(r->linear) != SUNLS_SUCCESS) {
        return rosenbrock_fail(error, "dense LU", n);
    }
    return TB_STATUS_OK;
}

/* The Jacobian's buffers: the system's CSR (room for the diagonal; more when its capacity asks),
 * or the difference quotients' two state vectors. */
static tb_status make_jacobian(tb__rosenbrock *r, size_t n, size_t roots, tb_error *error)
{
    r->J.n = r->ahead.n = n;
#ifdef TB_HAVE_KLU
    r->analysed.entries = (size_t)-1;
#endif
    r->start_rate = tb__malloc_array(n, sizeof(double));
    r->levels = tb__malloc_array(n, TB__ROSENBROCK_LEVELS * sizeof(double));
    if (r->start_rate == NULL || r->levels == NULL) {
        return rosenbrock_fail(error, "state", n);
    }
    r->jw_d = tb__malloc_array(n, sizeof(double));
    r->shifted = tb__malloc_array(n, sizeof(double));
    r->column = tb__malloc_array(n, sizeof(double));
    if (r->jw_d == NULL || r->shifted == NULL || r->column == NULL) {
        return rosenbrock_fail(error, "probe", n);
    }
    r->predicted = tb__malloc_array(n, sizeof(double));
    r->predicted_rate = tb__malloc_array(n, sizeof(double));
    r->gaps = tb__malloc_array(2 * roots + 1, sizeof(double));
    if (r->predicted == NULL || r->predicted_rate == NULL || r->gaps == NULL) {
        return rosenbrock_fail(error, "predictor", n);
    }
    if (r->own_jacobian) {
        r->J.row_starts = tb__malloc_array(n + 1, sizeof(size_t));
        r->ahead.row_starts = tb__malloc_array(n + 1, sizeof(size_t));
        return r->J.row_starts != NULL && r->ahead.row_starts != NULL && make_room(r, n)
                   ? TB_STATUS_OK
                   : rosenbrock_fail(error, "Jacobian", n);
    }
    r->dense_ahead = tb__malloc_array(n * n, sizeof(double));
    return r->dense_ahead != NULL ? TB_STATUS_OK
                                  : rosenbrock_fail(error, "difference quotients", n);
}

tb_status tb__rosenbrock_create(tb_integrator *integrator, tb_error *error)
{
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    const bool own = system->jacobian.evaluate != NULL;
    bool sparse = false;
#ifdef TB_HAVE_KLU
    sparse = own && n > TB__ROSENBROCK_SMALL;
#endif
    if (!sparse && n > TB__ROSENBROCK_DENSE_MAX) {
        return tb__set_error(error, TB_STATUS_UNSUPPORTED,
                             "system.n: rosenbrock factorises a dense %zu x %zu matrix here (%s), "
                             "at most %d unknowns; give the system a sparse Jacobian "
                             "(tb_ode_system.jacobian) in a build with KLU, or use another method",
                             n, n, own ? "this build has no KLU" : "the system has no Jacobian",
                             TB__ROSENBROCK_DENSE_MAX);
    }
    tb__rosenbrock *r = calloc(1, sizeof *r);
    integrator->rosenbrock = r;
    if (r == NULL) {
        return rosenbrock_fail(error, "solver", n);
    }
    r->sparse = sparse;
    r->own_jacobian = own;
#if SUNDIALS_VERSION_MAJOR >= 7
    const int flag = SUNContext_Create(SUN_COMM_NULL, &r->context);
#else
    const int flag = SUNContext_Create(NULL, &r->context);
#endif
    tb_status status = flag != 0 ? rosenbrock_fail(error, "SUNContext", n) : TB_STATUS_OK;
    if (status == TB_STATUS_OK) {
        r->x = N_VMake_Serial((sunindextype)n, integrator->y, r->context);
        status =
            r->x == NULL
                ? rosenbrock_fail(error, "vector", n)
                : make_jacobian(r, n, system->events.roots != NULL ? system->events.root_count : 0,
                                error);
    }
    if (status == TB_STATUS_OK) {
        status = make_solver(r, n, error);
    }
    if (status != TB_STATUS_OK) {
        tb__rosenbrock_destroy(integrator);
    }
    return status;
}

void tb__rosenbrock_destroy(tb_integrator *integrator)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    if (r == NULL) {
        return;
    }
    SUNLinSolFree(r->linear);
    SUNMatDestroy(r->matrix);
    if (r->x != NULL) {
        N_VDestroy(r->x); /* made with N_VMake_Serial: the array is not freed */
    }
    if (r->context != NULL) {
        SUNContext_Free(&r->context);
    }
    free(r->J.row_starts);
    free(r->J.columns);
    free(r->J.values);
    free(r->ahead.row_starts);
    free(r->ahead.columns);
    free(r->ahead.values);
    free(r->predicted);
    free(r->predicted_rate);
    free(r->gaps);
    free(r->start_rate);
    free(r->levels);
#ifdef TB_HAVE_KLU
    free(r->analysed.analysed);
#endif
    free(r->shifted);
    free(r->jw_d);
    free(r->dense_ahead);
    free(r->column);
    free(r);
    integrator->rosenbrock = NULL;
}

static int linear_failed(tb__rosenbrock *r, const char *what, long flag, double t)
{
    snprintf(r->message, sizeof r->message, "rosenbrock: %s (%ld) in the step from t = %.17g", what,
             flag, t);
    return TB__ROSENBROCK_LINEAR_FAILED;
}

/* Dense J (column-major, n x n, into out) from difference quotients: column j is
 * (f(t, y + d e_j) - f(t, y)) / d with d = sqrt(eps) max(|y_j|, 1), one derivative each. */
static int dense_quotients(tb_integrator *integrator, double t, const double *y, const double *fy,
                           double *out)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    const double root_eps = sqrt(DBL_EPSILON);
    memcpy(r->shifted, y, n * sizeof(double));
    for (size_t j = 0; j < n; ++j) {
        const double d = root_eps * fmax(fabs(y[j]), 1.0);
        r->shifted[j] = y[j] + d;
        integrator->stats.derivative_evals++;
        integrator->stats.jacobian_derivative_evals++;
        const int rc = system->derivative(t, r->shifted, r->column, system->ctx);
        r->shifted[j] = y[j];
        if (rc != 0) {
            return rc;
        }
        for (size_t i = 0; i < n; ++i) {
            out[j * n + i] = (r->column[i] - fy[i]) / d;
        }
    }
    return 0;
}

/* Dense M from the system's CSR J (held between steps, rosenbrock.h). */
static void dense_from_sparse(tb__rosenbrock *r, double h_gamma)
{
    const size_t n = r->J.n;
    SUNMatZero(r->matrix);
    for (size_t i = 0; i < n; ++i) {
        for (size_t e = r->J.row_starts[i]; e < r->J.row_starts[i + 1]; ++e) {
            SUNDenseMatrix_Column(r->matrix, (sunindextype)r->J.columns[e])[i] =
                -h_gamma * r->J.values[e];
        }
        SUNDenseMatrix_Column(r->matrix, (sunindextype)i)[i] += 1.0;
    }
}

/* One evaluation of the system's Jacobian at (t, y) into J, checked against its room. */
static int evaluate(tb_integrator *integrator, double t, const double *y, const double *fy,
                    tb_ode_sparse *J)
{
    const tb_ode_system *system = &integrator->system;
    const int rc = system->jacobian.evaluate(t, y, fy, J, system->ctx);
    if (rc == 0 && J->row_starts[J->n] > J->capacity) {
        return linear_failed(integrator->rosenbrock,
                             "system.jacobian.evaluate wrote more entries than its capacity",
                             (long)J->row_starts[J->n], t);
    }
    return rc;
}

/* Speculative activation, for dense difference quotients. A contact's force is k d for depth d > 0
 * and nothing before, so the Jacobian at a step's start has no stiffness for a contact that
 * switches on in the step, and the step is explicit in it: at omega h = 14 (a die at 1/240 s) that
 * multiplies the impact speed by about (omega h)^2 / 2. The matrix is therefore the Jacobian at (t,
 * y) plus, in each column where one of its entries is larger in magnitude, that at a predictor of
 * the step's end, the explicit midpoint y + h f(t + h/2, y + h/2 f(t, y)) (second order, so that
 * it carries a body's fall through gravity, h^2 g / 2): a contact in force at the start or at the
 * predicted end is implicit. ROS2 keeps its order 2 with any matrix (a W-method). The predictor is
 * only a probe: it may overshoot. */
static int predict(tb_integrator *integrator, double t, double h, const double *y, const double *fy)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    for (size_t i = 0; i < n; ++i) {
        r->predicted[i] = y[i] + 0.5 * h * fy[i];
    }
    integrator->stats.derivative_evals += 2;
    integrator->stats.jacobian_derivative_evals += 2;
    int rc = system->derivative(t + 0.5 * h, r->predicted, r->predicted_rate, system->ctx);
    for (size_t i = 0; rc == 0 && i < n; ++i) {
        r->predicted[i] = y[i] + h * r->predicted_rate[i];
    }
    return rc != 0 ? rc : system->derivative(t + h, r->predicted, r->predicted_rate, system->ctx);
}

/* Whether the system wrote the same pattern into ahead as into J. */
static bool same_pattern(const tb__rosenbrock *r)
{
    const size_t n = r->J.n, entries = r->J.row_starts[n];
    return r->ahead.row_starts[n] == entries &&
           memcmp(r->ahead.row_starts, r->J.row_starts, (n + 1) * sizeof(size_t)) == 0 &&
           memcmp(r->ahead.columns, r->J.columns, entries * sizeof(size_t)) == 0;
}

/* Dense M = I - h_gamma J, J the difference quotients at (t, y) and at the predictor. */
static int dense_speculative(tb_integrator *integrator, double t, double h, const double *y,
                             const double *fy, double h_gamma)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const size_t n = integrator->system.n;
    double *m = SUNDenseMatrix_Data(r->matrix);
    int rc = dense_quotients(integrator, t, y, fy, m);
    rc = rc != 0 || r->plain ? rc : predict(integrator, t, h, y, fy);
    if (rc == 0 && !r->plain &&
        dense_quotients(integrator, t + h, r->predicted, r->predicted_rate, r->dense_ahead) == 0) {
        tb__add_larger_columns(m, r->dense_ahead, n * n, NULL, n, TB__ROSENBROCK_REFINE_RATIO, 0.0,
                               r->column);
    }
    if (rc != 0) {
        return rc;
    }
    for (size_t e = 0; e < n * n; ++e) {
        m[e] *= -h_gamma;
    }
    for (size_t j = 0; j < n; ++j) {
        m[j * n + j] += 1.0;
    }
    return 0;
}

/* J from the system at (t, y) into r->J (the predictor only at onsets: rosenbrock.c), its room
 * grown first to the capacity the system asks at (t, y). */
static int own_jacobian(tb_integrator *integrator, double t, const double *y, const double *fy)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t capacity = system->jacobian.capacity(t, y, system->ctx);
    if (capacity < r->J.n || (capacity > r->J.capacity && !make_room(r, capacity))) {
        return linear_failed(r,
                             "system.jacobian.capacity below n (the system could not build its "
                             "pattern) or out of memory for it; capacity",
                             (long)capacity, t);
    }
    return evaluate(integrator, t, y, fy, &r->J);
}

/* Whether a root function (for a scene: a body's nearest gap, negative where it touches) falls
 * from the start to the predictor below zero and below twice its start: a contact that switches on
 * in the step, or one the step would press far deeper (an impact made and gone within the step,
 * which the refinement at the step's end cannot see). A resting contact keeps its gap. */
static bool onset_predicted(const tb__rosenbrock *r, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        const double start = r->gaps[k], ahead = r->gaps[count + k];
        if (ahead < 0.0 && ahead < 2.0 * fmin(start, 0.0)) {
            return true;
        }
    }
    return false;
}

/* Speculative activation with the system's own Jacobian, only where the predictor foresees an
 * onset: always taking the predictor's Jacobian made resting steps over-stiff (the explicit
 * predictor overshoots a stiff contact at omega h >> 1) and halved them, and never taking it let
 * an impact shorter than the step store energy (Newton's cradle at 1/240 s threw a ball off). */
static int speculate_at_onsets(tb_integrator *integrator, double t, double h, const double *y,
                               const double *fy)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t count = system->events.roots != NULL ? system->events.root_count : 0;
    if (r->plain || count == 0 || system->events.roots(t, y, r->gaps, system->ctx) != 0) {
        return 0;
    }
    int rc = predict(integrator, t, h, y, fy);
    if (rc != 0 || system->events.roots(t + h, r->predicted, r->gaps + count, system->ctx) != 0 ||
        !onset_predicted(r, count)) {
        return rc > 0 ? 0 : rc;
    }
    rc = evaluate(integrator, t + h, r->predicted, r->predicted_rate, &r->ahead);
    if (rc == 0 && same_pattern(r)) {
        tb__add_larger_columns(r->J.values, r->ahead.values, r->J.row_starts[r->J.n], r->J.columns,
                               r->J.n, TB__ROSENBROCK_REFINE_RATIO, 0.0, r->column);
    }
    return rc > 0 ? 0 : rc; /* a derivative that fails ahead leaves the start's Jacobian */
}

/* M = I - h_gamma J from r->J (the system's), factorised. */
static int factor_own(tb__rosenbrock *r, double t, double h_gamma)
{
    if (!r->sparse) {
        dense_from_sparse(r, h_gamma);
    }
#ifdef TB_HAVE_KLU
    if (r->sparse && !tb__klu_copy(&r->J, true, h_gamma, r->matrix, &r->analysed) &&
        SUNLinSol_KLUReInit(r->linear, r->matrix, SUNSparseMatrix_NNZ(r->matrix),
                            SUNKLU_REINIT_PARTIAL) != SUNLS_SUCCESS) {
        return linear_failed(r, "SUNLinSol_KLUReInit failed on a new pattern", 0, t);
    }
#endif
    int flag = SUNLinSolSetup(r->linear, r->matrix);
#ifdef TB_HAVE_KLU
    /* KLU refactorises a known pattern on its last pivot order and fails at a zero pivot of it,
     * the matrix not singular (a contact's entries kept at 0, a halved h): factorised afresh
     * first (the dominoes at 1/240 s: 1 142 of 1 215 halvings were this, docs/performance.md) */
    if (flag != SUNLS_SUCCESS && r->sparse &&
        SUNLinSol_KLUReInit(r->linear, r->matrix, SUNSparseMatrix_NNZ(r->matrix),
                            SUNKLU_REINIT_PARTIAL) == SUNLS_SUCCESS) {
        flag = SUNLinSolSetup(r->linear, r->matrix);
    }
#endif
    return flag == SUNLS_SUCCESS
               ? 0
               : linear_failed(r, "I - h gamma J is singular: SUNLinSolSetup returned", flag, t);
}

int tb__rosenbrock_factor(tb_integrator *integrator, double t, double h, double gamma,
                          const double *y, const double *fy)
{
    const double h_gamma = h * gamma;
    tb__rosenbrock *r = integrator->rosenbrock;
    r->message[0] = '\0';
    integrator->stats.jacobian_evals++;
    if (!r->own_jacobian) {
        const int rc = dense_speculative(integrator, t, h, y, fy, h_gamma);
        const int flag = rc != 0 ? SUNLS_SUCCESS : SUNLinSolSetup(r->linear, r->matrix);
        return rc != 0 ? rc
               : flag == SUNLS_SUCCESS
                   ? 0
                   : linear_failed(r, "I - h gamma J is singular: SUNLinSolSetup returned", flag,
                                   t);
    }
    int rc = own_jacobian(integrator, t, y, fy);
    rc = rc != 0 ? rc : speculate_at_onsets(integrator, t, h, y, fy);
    return rc != 0 ? rc : factor_own(r, t, h_gamma);
}

int tb__rosenbrock_refine(tb_integrator *integrator, double t, double h, double gamma,
                          const double *y, bool *changed)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    *changed = false;
    if (!r->own_jacobian) {
        return 0;
    }
    integrator->stats.derivative_evals++;
    integrator->stats.jacobian_derivative_evals++;
    int rc = system->derivative(t, y, r->predicted_rate, system->ctx);
    rc = rc != 0 ? rc : evaluate(integrator, t, y, r->predicted_rate, &r->ahead);
    if (rc != 0 || !same_pattern(r)) {
        return rc > 0 ? 0 : rc;
    }
    *changed =
        tb__add_larger_columns(r->J.values, r->ahead.values, r->J.row_starts[n], r->J.columns, n,
                               TB__ROSENBROCK_REFINE_RATIO, 1.0 / (gamma * h), r->column) > 0;
    if (!*changed) {
        return 0;
    }
    integrator->stats.jacobian_evals++;
    return factor_own(r, t, h * gamma);
}

/* out = J d, J the matrix's (r->J, CSR) */
static void multiply(const tb_ode_sparse *J, const double *d, double *out)
{
    for (size_t i = 0; i < J->n; ++i) {
        double sum = 0.0;
        for (size_t e = J->row_starts[i]; e < J->row_starts[i + 1]; ++e) {
            sum += J->values[e] * d[J->columns[e]];
        }
        out[i] = sum;
    }
}

bool tb__rosenbrock_can_reuse(const tb_integrator *integrator, double h)
{
    const tb__rosenbrock *r = integrator->rosenbrock;
    return r->own_jacobian && !r->plain && r->held_h == h;
}

void tb__rosenbrock_hold(tb_integrator *integrator, double h)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    r->held_h = r->own_jacobian ? h : 0.0;
}

/* The held matrix's J against the Jacobian at the step's end along the step's change d = y_new -
 * y, one derivative: J_end d = (f(t, y_new + e d) - f(t, y_new)) / e with e |d| = sqrt(eps)
 * max(|y_new|, 1). The matrix describes the step where, component by component, gamma h
 * |J_end d - J d| <= |d| + gamma h |J d| + floor (tb__rosenbrock_refine's ratio 2 along d): a
 * contact made in the step puts k times the step's approach into J_end d, absent from J d. */
int tb__rosenbrock_probe(tb_integrator *integrator, double t, double h, double gamma,
                         const double *y, const double *y_new, const double *f_end, double floor,
                         bool *ok)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    const tb_ode_system *system = &integrator->system;
    const size_t n = system->n;
    double size = 1.0, step = 0.0;
    for (size_t i = 0; i < n; ++i) {
        r->column[i] = y_new[i] - y[i]; /* d, until the derivative overwrites it */
        size = fmax(size, fabs(y_new[i]));
        step = fmax(step, fabs(r->column[i]));
    }
    *ok = true;
    if (step == 0.0) {
        return 0;
    }
    multiply(&r->J, r->column, r->jw_d);
    const double e = sqrt(DBL_EPSILON) * size / step;
    for (size_t i = 0; i < n; ++i) {
        r->shifted[i] = y_new[i] + e * r->column[i];
    }
    integrator->stats.derivative_evals++;
    integrator->stats.jacobian_derivative_evals++;
    const int rc = system->derivative(t, r->shifted, r->column, system->ctx);
    const double h_gamma = h * gamma;
    for (size_t i = 0; rc == 0 && *ok && i < n; ++i) {
        const double d = y_new[i] - y[i], end = (r->column[i] - f_end[i]) / e;
        *ok = h_gamma * fabs(end - r->jw_d[i]) <= fabs(d) + h_gamma * fabs(r->jw_d[i]) + floor;
    }
    return rc;
}

int tb__rosenbrock_solve(tb_integrator *integrator, double *x)
{
    tb__rosenbrock *r = integrator->rosenbrock;
    N_VSetArrayPointer(x, r->x);
    const int flag = SUNLinSolSolve(r->linear, r->matrix, r->x, r->x, 0.0);
    return flag == SUNLS_SUCCESS ? 0 : linear_failed(r, "SUNLinSolSolve returned", flag, NAN);
}

double *tb__rosenbrock_start_rate(tb_integrator *integrator)
{
    return integrator->rosenbrock->start_rate;
}

double *tb__rosenbrock_level(tb_integrator *integrator, int depth)
{
    return integrator->rosenbrock->levels + (size_t)depth * integrator->system.n;
}

void tb__rosenbrock_speculate(tb_integrator *integrator, bool on)
{
    integrator->rosenbrock->plain = !on;
}

void tb__rosenbrock_count_split(tb_integrator *integrator)
{
    integrator->rosenbrock->splits++;
}

const char *tb__rosenbrock_message(const tb_integrator *integrator)
{
    return integrator->rosenbrock != NULL ? integrator->rosenbrock->message : "";
}
