/* Private: the integrator object and the fixed-step stepper table. */
#ifndef TUMBLE_INTEGRATOR_H
#define TUMBLE_INTEGRATOR_H

#include "tumble/ode.h"

/* One explicit step from (t, y) to y_new at t + h. work holds 2n doubles of scratch.
 * Returns the derivative's status: 0 ok, anything else stops the step. *evals counts
 * derivative calls. */
typedef int (*tb__step_fn)(const tb_ode_system *system, double t, double h, const double *y,
                           double *y_new, double *work, long *evals);

typedef struct tb__stepper {
    const char *name;
    int order;
    tb__step_fn step;
} tb__stepper;

/* Indexed by tb_method. */
extern const tb__stepper tb__steppers[TB_METHOD_COUNT];

struct tb_integrator {
    tb_ode_system system;
    tb_method method;
    const tb__stepper *stepper;
    double dt;
    double t;
    double *y;     /* caller's state, n doubles */
    double *y_new; /* candidate state, n doubles; committed to y only when the step is good */
    double *work;  /* 2n doubles for the stepper */
    tb_integrator_stats stats;
    char detail[TB_DETAIL_SIZE];
};

#endif
