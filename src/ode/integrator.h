/* Private: the integrator object and its backends (fixed-step, CVODE, ARKStep). */
#ifndef TUMBLE_INTEGRATOR_H
#define TUMBLE_INTEGRATOR_H

#include "tumble/ode.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct tb_integrator tb_integrator;

/* What a backend does; the public functions in integrator.c validate and dispatch. */
typedef struct tb__backend {
    /* Allocates everything the backend will use; on failure frees what it took. */
    tb_status (*create)(tb_integrator *integrator, const tb_integrator_def *def, tb_error *error);
    tb_status (*advance)(tb_integrator *integrator, double t_target);
    tb_status (*step)(tb_integrator *integrator);
    tb_status (*reset)(tb_integrator *integrator, double t);
    void (*get_stats)(const tb_integrator *integrator, tb_integrator_stats *stats);
    void (*destroy)(tb_integrator *integrator);
} tb__backend;

/* One explicit step from (t, y) to y_new at t + h. A stage at the step's end (c = 1) is
 * evaluated at t_last: t + h, or just below a break the step ends on (fixed_step.c,
 * last_stage_time). work holds 2n doubles of scratch. Returns the derivative's status: 0 ok,
 * anything else stops the step. *evals counts derivative calls. */
typedef int (*tb__step_fn)(const tb_ode_system *system, double t, double h, double t_last,
                           const double *y, double *y_new, double *work, long *evals);

/* The fixed-step methods' steppers (fixed_step.c). */
int tb__euler_step(const tb_ode_system *system, double t, double h, double t_last, const double *y,
                   double *y_new, double *work, long *evals);
int tb__midpoint_step(const tb_ode_system *system, double t, double h, double t_last,
                      const double *y, double *y_new, double *work, long *evals);
int tb__rk4_step(const tb_ode_system *system, double t, double h, double t_last, const double *y,
                 double *y_new, double *work, long *evals);

/* A row of the method table (methods.c), indexed by tb_method: the public facts and how the
 * integrator runs the method. */
/* Groups of settings a method reads (tb_method_check_setting names each setting's group). */
enum {
    TB__READS_DT = 1,            /* dt, threads, the scene's allow_unstable */
    TB__READS_TOLERANCES = 2,    /* rtol, atol, atol_vector, initial_step, max_step, max_order */
    TB__READS_LINEAR_SOLVER = 4, /* linear_solver, preconditioner_half_bandwidth */
    TB__READS_MAX_STEPS = 8,     /* max_steps: every method's step budget */
};

typedef struct tb__method_entry {
    tb_method_info info;
    unsigned reads; /* TB__READS_* */
    const tb__backend *backend;
    tb__step_fn step;       /* explicit fixed-step methods only */
    bool linearly_implicit; /* fixed-step, stepped by tb__rosenbrock_step (rosenbrock.h) */
} tb__method_entry;

extern const tb__method_entry tb__methods[TB_METHOD_COUNT];

/* Whether method (a valid tb_method) reads the setting of that name; false for a name no method
 * reads. The one rule tb_method_check_setting, integrator creation and the loader share. */
bool tb__method_reads(tb_method method, const char *setting);

/* Into out: "applies to adaptive methods (cvode-adams, cvode-bdf), not to rk4", saying which
 * methods read the setting. */
void tb__setting_readers(tb_method method, const char *setting, char *out, size_t size);
extern const tb__backend tb__fixed_step_backend;
extern const tb__backend tb__cvode_backend;
extern const tb__backend tb__arkode_backend;

struct tb_integrator {
    tb_ode_system system;
    tb_method method;
    const tb__method_entry *entry;
    double t;
    double *y;                     /* caller's state, n doubles */
    long max_steps;                /* steps allowed in one advance or step call */
    unsigned long long generation; /* the system's layout generation at creation */
    bool busy;                     /* an advance, step or reset is in progress */
    bool destroy_pending;          /* destroyed from a callback of that call: freed as it ends */
    tb_integrator_stats stats;
    tb_integrator_events events; /* adaptive: written by the CVODE backend (cvode_events.c) */
    char detail[TB_DETAIL_SIZE];
    /* fixed-step */
    double dt;
    double *y_new;       /* candidate state, n doubles; committed to y only when the step is good
                            (chunked: the state before the step, to undo a failed one) */
    double *work;        /* 2n doubles for the stepper (chunked: chunk_work doubles per thread) */
    void *workspace;     /* the allocation y_new and work are in */
    size_t chunk_blocks; /* chunked: blocks per chunk (the lane group's size with lanes) */
    size_t chunk_work;   /* chunked: doubles of work per thread */
    int threads;         /* chunked: threads the chunks are shared among, >= 1 */
    struct tb__onset *onset; /* systems with roots, not chunked: the onset search's buffers */
    struct tb__rosenbrock *rosenbrock; /* linearly implicit: the solver (rosenbrock_linear.c) */
    /* CVODE and ARKStep (cvode_internal.h) */
    struct tb__cvode *cvode;
};

/* Before a stepper's elementwise loop function: compiled for each x86-64 vector width and
 * picked for the processor when the library is loaded (function multi-versioning, GCC and
 * clang on glibc). Elementwise without contraction, so every version gives the same bits. */
#if defined(__x86_64__) && defined(__linux__) && defined(__has_attribute)
#if __has_attribute(target_clones) && !defined(__SANITIZE_ADDRESS__)
#define TB__CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#endif
#endif
#ifndef TB__CLONES
#define TB__CLONES
#endif

/* Index of the first non-finite component of y[0..n), or n if all are finite. */
size_t tb__first_non_finite(const double *y, size_t n);

/* Bytes in a cache line, to which the fixed-step workspace is aligned. */
#define TB__LINE 64

/* The most blocks a lane group may hold (tb_ode_system.blocks.lanes). */
#define TB__MAX_LANES 1024

/* How a step of a part of the system (the whole, or a chunk) failed: status OK for none; rc is
 * the derivative's or the hook's return (TB_STATUS_SOLVER_FAILED: the root function's, or
 * TB__ROSENBROCK_LINEAR_FAILED for the Rosenbrock method's linear algebra), index and value the
 * first non-finite component (of the whole state). tb__fixed_report writes the detail and counts
 * the failed step. */
typedef struct tb__step_failure {
    tb_status status;
    int rc, hook_rc;
    size_t index;
    double value;
} tb__step_failure;

tb_status tb__fixed_report(tb_integrator *integrator, const tb__step_failure *failure, double h,
                           double t_end);

/* The chunked path of the fixed-step methods (chunked_step.c), for systems with block_size:
 * chunk_layout fills chunk_blocks, chunk_work and threads at creation; take_chunked_step takes
 * one step of size h to t_end (its stages at the end at t_last), committing to y only if every
 * chunk succeeded. */
void tb__chunk_layout(tb_integrator *integrator, int threads);
tb_status tb__take_chunked_step(tb_integrator *integrator, double h, double t_last, double t_end);

/* The system's events.check_break at the integrator's time and state (a step, or CVODE's
 * restart, on a break inside a call); TB_STATUS_OK without one. */
tb_status tb__integrator_check_break(tb_integrator *integrator);

/* Fixed steps ending at onsets (fixed_onset.c), for systems with roots that step whole: create
 * allocates the search's buffers (nothing for other systems); forget drops the roots kept from
 * the last step's end (y may have changed); locate writes into *h_onset the step from
 * (t, y0) to the first onset inside the trial step to y1, h if none (a callback's non-zero
 * return is returned); reached counts the event and calls at_event at the committed onset. */
tb_status tb__onset_create(tb_integrator *integrator, tb_error *error);
void tb__onset_destroy(tb_integrator *integrator);
void tb__onset_forget(tb_integrator *integrator);
int tb__onset_locate(tb_integrator *integrator, const double *y0, const double *y1, double h,
                     long *evals, double *h_onset);
void tb__onset_reached(tb_integrator *integrator);

#endif
