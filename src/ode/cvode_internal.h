/* Private: the CVODE backend's state, shared by cvode_integrator.c (creation, stepping,
 * statistics) and cvode_callbacks.c (what CVODE calls back). */
#ifndef TUMBLE_CVODE_INTERNAL_H
#define TUMBLE_CVODE_INTERNAL_H

#include "ode/cvode_block_preconditioner.h"
#include "ode/integrator.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <stdbool.h>

typedef struct tb__cvode tb__cvode;
typedef struct tb__cvode_sparse tb__cvode_sparse;

struct tb__cvode {
    SUNContext context;
    void *mem;
    N_Vector y;       /* wraps the caller's array: no copy */
    N_Vector weights; /* error weights, for the dense Jacobian's increments */
    SUNMatrix matrix;
    SUNLinearSolver linear;
    SUNNonlinearSolver nonlinear;
    double *y_seen;           /* y as last handed out; a difference means the caller changed it */
    bool band_preconditioner; /* CVBandPrec attached (its counters exist) */
    tb__block_preconditioner *block_preconditioner; /* for systems of independent blocks */
    tb__cvode_sparse *sparse; /* BDF with the system's sparse Jacobian (cvode_sparse.c) */
    bool started;             /* the first step since creation or restart has been taken */
    double break_stop;        /* the stop time set at the system's next break (INFINITY: none) */
    bool stale;               /* CVODE's history went past the last good output (a non-finite
                                 output was refused): restart from y before the next step */
    unsigned long long rhs_generation; /* the system's, at the last (re)start */
    double t_origin;       /* CVODE integrates in tau = t - t_origin, from tau = 0 at creation
                              and every restart, so a start at t = 1e16 (where CVODE's first
                              step would not move t) works like one at 0 */
    long jacobian_evals;   /* derivative calls made by our dense Jacobian */
    int derivative_status; /* last non-zero return of the derivative, and its time (t) */
    double derivative_time;
    size_t non_finite_index; /* a derivative value that was NaN or infinite (its index, value
                                and time), n if none since the call began */
    double non_finite_value, non_finite_time;
    int *roots_found;             /* root_count flags from CVodeGetRootInfo (cvode_events.c) */
    N_Vector y_step;              /* with a step limit: the state at CVODE's internal time */
    N_Vector dydt_step;           /* and its derivative */
    tb_integrator_stats base;     /* counts from before the last CVodeReInit, which zeroes them */
    char message[TB_DETAIL_SIZE]; /* CVODE's last message, captured instead of printed */
};

/* CVODE's right-hand side (user_data is the tb_integrator): the system's derivative, keeping
 * its failures in derivative_status. */
int tb__cvode_derivative(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

/* The post-step hook as a CVODE projection (BDF). */
int tb__cvode_project(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps, N_Vector err,
                      void *user_data);

/* Dense difference-quotient Jacobian (BDF, dense linear solver). */
int tb__cvode_dense_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J, void *user_data,
                             N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);

/* The block-diagonal preconditioner's setup and solve (BDF, Krylov, systems of blocks). */
int tb__cvode_block_setup(sunrealtype t, N_Vector y, N_Vector fy, sunbooleantype jok,
                          sunbooleantype *jcur, sunrealtype gamma, void *user_data);
int tb__cvode_block_solve(sunrealtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z,
                          sunrealtype gamma, sunrealtype delta, int lr, void *user_data);

/* CVODE set-up failed in call: TB_STATUS_SOLVER_FAILED naming the flag and CVODE's message. */
tb_status tb__cvode_setup_failed(tb__cvode *cvode, const char *call, int flag, tb_error *error);

/* The nonlinear and linear solvers for the def's method and linear_solver (cvode_linear.c). */
tb_status tb__cvode_set_solvers(tb_integrator *integrator, const tb_integrator_def *def,
                                tb_error *error);

/* The sparse linear solver (cvode_sparse.c): create makes the matrix and KLU from the system's
 * capacity at its start (cvode->matrix, cvode->linear); refresh asks the capacity again at
 * CVODE's internal time tn before a step and grows the room (CVODE's flag); jacobian is CVODE's
 * CVLsJacFn; analyses counts the symbolic analyses (pattern changes). */
tb_status tb__cvode_sparse_create(tb_integrator *integrator, tb_error *error);
int tb__cvode_sparse_refresh(tb_integrator *integrator, sunrealtype tn);
int tb__cvode_sparse_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix A, void *user_data,
                              N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
long tb__cvode_sparse_analyses(const tb__cvode *cvode);
void tb__cvode_sparse_free(tb__cvode *cvode);

/* Events and step limits (cvode_events.c). events_init registers the system's root functions
 * and makes what the step limit needs, at creation; events_free frees it. marches: the system
 * has roots or a step limit, so run() steps with tb__cvode_march, one CVODE step at a time, each
 * within the limit, counting events; to tau_out (CV_NORMAL: y then interpolated there) or for
 * one step or event (CV_ONE_STEP). Returns CVODE's flag; *tau_reached as CVode's tret; or
 * TB__CV_EVENT_RESTART: it stopped at an event at *tau_reached (y there) before tau_out (or in
 * CV_ONE_STEP), where the system's at_event changed its right-hand side, so CVODE must restart
 * from there. */
#define TB__CV_EVENT_RESTART 1000
tb_status tb__cvode_events_init(tb_integrator *integrator, tb_error *error);
void tb__cvode_events_free(tb__cvode *cvode);
bool tb__cvode_marches(const tb_integrator *integrator);
int tb__cvode_march(tb_integrator *integrator, double tau_out, int mode, double horizon,
                    sunrealtype *tau_reached);

#endif
