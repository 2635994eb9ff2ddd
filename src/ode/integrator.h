/* Private: the integrator object and its backends (fixed-step, CVODE). */
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

/* One explicit step from (t, y) to y_new at t + h. work holds 2n doubles of scratch.
 * Returns the derivative's status: 0 ok, anything else stops the step. *evals counts
 * derivative calls. */
typedef int (*tb__step_fn)(const tb_ode_system *system, double t, double h, const double *y,
                           double *y_new, double *work, long *evals);

/* The fixed-step methods' steppers (fixed_step.c). */
int tb__euler_step(const tb_ode_system *system, double t, double h, const double *y, double *y_new,
                   double *work, long *evals);
int tb__midpoint_step(const tb_ode_system *system, double t, double h, const double *y,
                      double *y_new, double *work, long *evals);
int tb__rk4_step(const tb_ode_system *system, double t, double h, const double *y, double *y_new,
                 double *work, long *evals);

/* A row of the method table (methods.c), indexed by tb_method: the public facts and how the
 * integrator runs the method. */
/* Groups of tb_integrator_def fields a method reads, besides method and max_steps. */
enum {
    TB__READS_DT = 1,            /* dt */
    TB__READS_TOLERANCES = 2,    /* rtol, atol, atol_vector, initial_step, max_step, max_order */
    TB__READS_LINEAR_SOLVER = 4, /* linear_solver */
};

typedef struct tb__method_entry {
    tb_method_info info;
    unsigned reads; /* TB__READS_* */
    const tb__backend *backend;
    tb__step_fn step; /* fixed-step methods only */
} tb__method_entry;

extern const tb__method_entry tb__methods[TB_METHOD_COUNT];
extern const tb__backend tb__fixed_step_backend;
extern const tb__backend tb__cvode_backend;

struct tb_integrator {
    tb_ode_system system;
    tb_method method;
    const tb__method_entry *entry;
    double t;
    double *y;                     /* caller's state, n doubles */
    long max_steps;                /* steps allowed in one advance or step call */
    unsigned long long generation; /* the system's layout generation at creation */
    bool busy;                     /* an advance, step or reset is in progress */
    tb_integrator_stats stats;
    char detail[TB_DETAIL_SIZE];
    /* fixed-step */
    double dt;
    double *y_new; /* candidate state, n doubles; committed to y only when the step is good */
    double *work;  /* 2n doubles for the stepper */
    /* CVODE */
    struct tb__cvode *cvode;
};

/* Index of the first non-finite component of y[0..n), or n if all are finite. */
size_t tb__first_non_finite(const double *y, size_t n);

#endif
