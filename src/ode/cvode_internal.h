/* Private: the state of the SUNDIALS backends, CVODE (cvode_integrator.c) and ARKODE's ARKStep
 * (arkode_integrator.c). The two differ only in a table of calls (tb__sundials_ops): the
 * stepping, outputs and restarts (cvode_run.c), events (cvode_events.c), linear solvers
 * (cvode_linear.c, cvode_sparse.c) and callbacks (cvode_callbacks.c) serve both through it. */
#ifndef TUMBLE_CVODE_INTERNAL_H
#define TUMBLE_CVODE_INTERNAL_H

#include "ode/cvode_block_preconditioner.h"
#include "ode/integrator.h"

#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

#include <stdbool.h>

typedef struct tb__cvode tb__cvode;
typedef struct tb__cvode_sparse tb__cvode_sparse;

/* SUNDIALS' callback shapes, the same for CVODE and ARKStep (CVRhsFn and ARKRhsFn, ...). */
typedef int (*tb__sun_rhs)(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);
typedef int (*tb__sun_roots)(sunrealtype t, N_Vector y, sunrealtype *g, void *user_data);
typedef int (*tb__sun_jacobian)(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix J,
                                void *user_data, N_Vector tmp1, N_Vector tmp2, N_Vector tmp3);
typedef int (*tb__sun_prec_setup)(sunrealtype t, N_Vector y, N_Vector fy, sunbooleantype jok,
                                  sunbooleantype *jcur, sunrealtype gamma, void *user_data);
typedef int (*tb__sun_prec_solve)(sunrealtype t, N_Vector y, N_Vector fy, N_Vector r, N_Vector z,
                                  sunrealtype gamma, sunrealtype delta, int lr, void *user_data);

/* The calls in which CVODE and ARKStep differ by name only: same arguments, same return flags
 * (ARK_SUCCESS = CV_SUCCESS, ARK_ROOT_RETURN = CV_ROOT_RETURN, ARK_ONE_STEP = CV_ONE_STEP, ...),
 * and the backend's own restart, counters and freeing. */
typedef struct tb__sundials_ops tb__sundials_ops;
struct tb__sundials_ops {
    const char *name; /* "CVODE", "ARKODE", in messages */
    int (*evolve)(void *mem, sunrealtype tout, N_Vector yout, sunrealtype *tret, int mode);
    int (*get_dky)(void *mem, sunrealtype t, int k, N_Vector dky);
    int (*current_time)(void *mem, sunrealtype *tn);
    int (*current_step)(void *mem, sunrealtype *h);
    int (*err_weights)(void *mem, N_Vector weights);
    int (*set_stop_time)(void *mem, sunrealtype tstop);
    int (*root_init)(void *mem, int count, tb__sun_roots g);
    int (*no_inactive_root_warn)(void *mem);
    int (*root_info)(void *mem, int *found);
    int (*ss_tolerances)(void *mem, sunrealtype rtol, sunrealtype atol);
    int (*sv_tolerances)(void *mem, sunrealtype rtol, N_Vector atol);
    int (*set_max_num_steps)(void *mem, long steps);
    int (*set_init_step)(void *mem, sunrealtype h);
    int (*set_max_step)(void *mem, sunrealtype h);
    int (*set_linear_solver)(void *mem, SUNLinearSolver solver, SUNMatrix matrix);
    int (*set_jac_fn)(void *mem, tb__sun_jacobian jacobian);
    int (*set_preconditioner)(void *mem, tb__sun_prec_setup setup, tb__sun_prec_solve solve);
    int (*band_prec_init)(void *mem, sunindextype n, sunindextype upper, sunindextype lower);
    int (*band_prec_rhs_evals)(void *mem, long *evals);
    char *(*flag_name)(long flag); /* allocated: the caller frees it */
    int hook_flags[2];             /* the flags that say the post-step hook failed (these differ) */
    /* the backend's own: restart from y at tau = 0 (counters zeroed), read its counters (the
     * base not added), free its memory */
    int (*reinit)(tb_integrator *integrator);
    void (*read_counters)(const tb_integrator *integrator, tb_integrator_stats *out);
    void (*free_mem)(void **mem);
};

struct tb__cvode {
    const tb__sundials_ops *ops;
    tb__sun_rhs implicit_rhs; /* what Newton's Jacobian is of: f (CVODE), ARKStep's f_I */
    int order;                /* ARKStep's tables' order (stats); 0 for CVODE */
    N_Vector split_work;      /* ARKStep with a split: f_E at the implicit part's state */
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
    double break_at;          /* that break as the system's t (INFINITY: none), for system_time */
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

/* The shared creation (cvode_setup.c): create allocates integrator->cvode with the context, the
 * vector over y and the copy of y (the backend then makes its memory, and calls
 * set_tolerances_and_options, the solvers and events_init); created remembers y and the
 * generation once all is made; destroy frees what either made. validate checks the def's
 * adaptive fields. capture_message is the error handler that keeps SUNDIALS' last message. */
tb_status tb__sundials_create(tb_integrator *integrator, const tb__sundials_ops *ops,
                              tb_error *error);
tb_status tb__sundials_validate(const tb_integrator *integrator, const tb_integrator_def *def,
                                tb_error *error);
tb_status tb__sundials_set_tolerances_and_options(tb_integrator *integrator,
                                                  const tb_integrator_def *def, tb_error *error);
void tb__sundials_created(tb_integrator *integrator);
void tb__sundials_destroy(tb_integrator *integrator);

/* A stage of a backend's creation: its own memory (CVodeCreate or ARKStepCreate and what only it
 * sets), or its last settings. */
typedef tb_status (*tb__sundials_stage)(tb_integrator *integrator, const tb_integrator_def *def,
                                        tb_error *error);
/* The whole creation in its order (validate, create, memory, tolerances and options, solvers,
 * events, finish when not NULL, created); on a failure frees what was made. */
tb_status tb__sundials_make(tb_integrator *integrator, const tb_integrator_def *def,
                            const tb__sundials_ops *ops, tb__sundials_stage memory,
                            tb__sundials_stage finish, tb_error *error);
#if SUNDIALS_VERSION_MAJOR >= 7
void tb__sundials_capture_message(int line, const char *function, const char *file, const char *msg,
                                  SUNErrCode code, void *data, SUNContext context);
#else
void tb__sundials_capture_message(int code, const char *module, const char *function, char *msg,
                                  void *data);
#endif
unsigned long long tb__sundials_rhs_generation(const tb_ode_system *system);
void tb__sundials_flag_name(const tb__cvode *cvode, int flag, char *out, size_t size);

/* The shared stepping (cvode_run.c): the backends' advance, step, reset and get_stats. */
tb_status tb__sundials_advance(tb_integrator *integrator, double t_target);
tb_status tb__sundials_step(tb_integrator *integrator);
tb_status tb__sundials_reset(tb_integrator *integrator, double t);
void tb__sundials_get_stats(const tb_integrator *integrator, tb_integrator_stats *stats);

/* The system's t for the solver's time tau: t_origin + tau, but the largest double below the
 * next break (break_at) from it on. A step to a break evaluates f at its end (ARKStep's last
 * stage and its interpolant's end derivative; CVODE's corrector, where tn + h rounds onto it), and
 * the piece after a break may differ in t alone (a step key jumps a body): the step sees the
 * piece it lies in, its left limit, as a fixed step's last stage does (fixed_step.c). */
double tb__sundials_system_time(const tb__cvode *cvode, double tau);

/* CVODE's right-hand side (user_data is the tb_integrator): the system's derivative, keeping
 * its failures in derivative_status. */
int tb__cvode_derivative(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

/* ARKStep's split (tb_ode_system.split): f_E, and f_I = f - f_E (f_E into cvode->split_work). */
int tb__sundials_explicit_part(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);
int tb__sundials_implicit_part(sunrealtype t, N_Vector y, N_Vector ydot, void *user_data);

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
 * from there; or TB__CV_STOPPED: a callback at a step (a contact event) destroyed the
 * integrator, which stops there. */
#define TB__CV_EVENT_RESTART 1000
#define TB__CV_STOPPED 1001
tb_status tb__cvode_events_init(tb_integrator *integrator, tb_error *error);
void tb__cvode_events_free(tb__cvode *cvode);
bool tb__cvode_marches(const tb_integrator *integrator);
int tb__cvode_march(tb_integrator *integrator, double tau_out, int mode, double horizon,
                    sunrealtype *tau_reached);

#endif
