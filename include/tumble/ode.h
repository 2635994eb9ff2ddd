/* The generic ODE layer: an integrator advances y' = f(t, y) in place on the caller's array.
 * It knows nothing of rigid bodies; bring any ODE. */
#ifndef TUMBLE_ODE_H
#define TUMBLE_ODE_H

#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Derivative: writes dydt[0..n) from t and y[0..n). Same signature as GSL odeiv2 and CVODE's
 * right-hand side. Returns 0 on success, > 0 for a recoverable failure (an adaptive
 * integrator may retry with a smaller step), < 0 for a fatal one. Must not change y. */
typedef int (*tb_ode_derivative)(double t, const double *y, double *dydt, void *ctx);

/* Post-step hook: may adjust a freshly accepted state y[0..n) at time t (the rigid-body scene
 * renormalises quaternions here). Returns 0 on success, non-zero to stop the run. */
typedef int (*tb_ode_hook)(double t, double *y, void *ctx);

/* An ODE system. The integrator borrows it: ctx must outlive the integrator. */
typedef struct tb_ode_system {
    size_t n;                     /* dimension, > 0 */
    tb_ode_derivative derivative; /* required */
    tb_ode_hook post_step;        /* optional, NULL for none */
    void *ctx;                    /* passed to derivative and post_step */
} tb_ode_system;

/* How to integrate, chosen as data. */
typedef enum tb_method {
    TB_METHOD_EULER = 0, /* explicit Euler, order 1, 1 derivative per step */
    TB_METHOD_MIDPOINT,  /* explicit midpoint (RK2), order 2, 2 derivatives per step */
    TB_METHOD_RK4,       /* classical Runge-Kutta, order 4, 4 derivatives per step */
    TB_METHOD_COUNT
} tb_method;

/* "euler", "midpoint", "rk4"; NULL for an unknown method. */
const char *tb_method_name(tb_method method);

/* Parses a name given by tb_method_name; returns TB_STATUS_INVALID_ARGUMENT if unknown. */
tb_status tb_method_from_name(const char *name, tb_method *out_method);

/* Classical order of accuracy of a method (1, 2, 4). 0 for an unknown method. */
int tb_method_order(tb_method method);

typedef struct tb_integrator_def {
    tb_method method;    /* default TB_METHOD_RK4 */
    double dt;           /* fixed step size in the system's time unit (s for scenes), > 0;
                            default 1/240 */
    int internal_cookie; /* set by tb_integrator_def_default; catches defs not made by it */
} tb_integrator_def;

tb_integrator_def tb_integrator_def_default(void);

/* What an integrator has done since it was created or last reset. */
typedef struct tb_integrator_stats {
    long steps;            /* accepted steps */
    long derivative_evals; /* calls of the derivative */
    long failed_steps;     /* steps rejected (derivative or hook error, non-finite state) */
    double last_step;      /* size of the last accepted step */
} tb_integrator_stats;

typedef struct tb_integrator tb_integrator;

/* Creates an integrator that advances y[0..system->n) from time t0, in place. y stays owned
 * by the caller and must outlive the integrator; y is not read until the first step.
 * All memory the integrator will ever use is allocated here. On failure *out_integrator is
 * NULL and out_error (may be NULL) names the wrong input. */
tb_status tb_integrator_create(const tb_ode_system *system, const tb_integrator_def *def, double t0,
                               double *y, tb_integrator **out_integrator, tb_error *out_error);

/* Frees an integrator; accepts NULL. Does not touch y. */
void tb_integrator_destroy(tb_integrator *integrator);

/* Advances y to t_target (>= current time): whole steps of dt, the last one shortened or
 * slightly stretched (by at most 1e-9 dt) so the run lands exactly on t_target without a
 * sliver step. On failure y holds the state at the last good step, the integrator's time is
 * that step's time, and the detail message names the failure and its time. */
tb_status tb_integrator_advance(tb_integrator *integrator, double t_target);

/* Takes exactly one step of size dt. */
tb_status tb_integrator_step(tb_integrator *integrator);

/* Current time of y. */
double tb_integrator_time(const tb_integrator *integrator);

/* Tells the integrator that the caller changed y (or wants a new time): the next step starts
 * from y at time t. Statistics are kept. */
tb_status tb_integrator_reset(tb_integrator *integrator, double t);

/* Copies the statistics into *out_stats. */
tb_status tb_integrator_get_stats(const tb_integrator *integrator, tb_integrator_stats *out_stats);

/* The method the integrator was created with (TB_METHOD_COUNT for NULL). */
tb_method tb_integrator_method(const tb_integrator *integrator);

/* Detail of the last failure ("" if none); owned by the integrator. */
const char *tb_integrator_detail(const tb_integrator *integrator);

#ifdef __cplusplus
}
#endif

#endif
