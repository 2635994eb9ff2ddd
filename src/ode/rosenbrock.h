/* Private: the linearly implicit (Rosenbrock) fixed-step method. The stepper (rosenbrock.c) is
 * SUNDIALS-free; its linear algebra, the matrix I - h gamma J factorised once a step and solved
 * once a stage, is in rosenbrock_linear.c, the only one of the two that includes SUNDIALS. */
#ifndef TUMBLE_ROSENBROCK_H
#define TUMBLE_ROSENBROCK_H

#include "ode/integrator.h"

#include <stdbool.h>
#include <stddef.h>

/* The largest n whose Jacobian is a dense matrix: difference quotients (n derivatives a step)
 * for a system without tb_ode_system.jacobian, or the system's own in a build without KLU.
 * Past it creation is refused (TB_STATUS_UNSUPPORTED naming n). */
#define TB__ROSENBROCK_DENSE_MAX 512

/* What tb__rosenbrock_factor and tb__rosenbrock_solve return when the linear algebra failed (a
 * singular matrix, a capacity below n, memory): its message is in tb__rosenbrock_message. Not
 * a derivative's return (those are passed on as they are). */
#define TB__ROSENBROCK_LINEAR_FAILED (-0x7f5eb00c)

/* The shortest part a step is halved into (rosenbrock.c: 7 halvings), where its change is not
 * trusted or the system's split_limit is shorter (tb_ode_events). */
#define TB__ROSENBROCK_FINEST 128

/* The parts a scene's tunnelling guard lets rosenbrock split a step into at the bound (two of
 * its 7 halvings, leaving five to the trust check; the guard refuses a dt whose quarter is still
 * too long): enough for the dominoes' last fall (2 parts) and a ball meeting a 1 cm plate at
 * 3.1 m/s (3), while a body thrown off fast (the base's dice at 1/240 s, a die closing at 29.6
 * m/s: 5 parts) or the paddle's 10 m/s against a 2 cm ball (5 parts; in 8 parts the ball
 * leaves right, at 15.3 m/s, but the boxes beside it at 19.2 and 12.8 m/s for 15.0, and the
 * scene's impact check stops the run at 0.046 s) is still refused. */
#define TB__ROSENBROCK_TUNNEL_PARTS 4

typedef struct tb__rosenbrock tb__rosenbrock;

/* Allocates the solver for the integrator's system (integrator->rosenbrock): everything but the
 * growth of a sparse Jacobian's room, which happens in tb__rosenbrock_factor only when the
 * system's capacity grows. On failure frees what it took. */
tb_status tb__rosenbrock_create(tb_integrator *integrator, tb_error *error);
void tb__rosenbrock_destroy(tb_integrator *integrator);

/* Evaluates J = df/dy at (t, y), where f(t, y) = fy (the system's own, or difference quotients
 * made speculative for a contact switching on in the step of size h), and factorises
 * I - h gamma J. Counts
 * the Jacobian and its derivatives in the integrator's stats. 0, a derivative's or the Jacobian's
 * non-zero return, or TB__ROSENBROCK_LINEAR_FAILED. */
int tb__rosenbrock_factor(tb_integrator *integrator, double t, double h, double gamma,
                          const double *y, const double *fy);

/* After a step to (t, y) with the last factorisation: the Jacobian there, in each column where an
 * entry is more than twice the matrix's (and matters at this step, above 1 / (gamma h)), is added
 * to the matrix's, refactorised; *changed says whether any was (a contact the step made). 0, a
 * derivative's or the Jacobian's non-zero return, or TB__ROSENBROCK_LINEAR_FAILED. */
int tb__rosenbrock_refine(tb_integrator *integrator, double t, double h, double gamma,
                          const double *y, bool *changed);

/* Overwrites x[0..n) with (I - h_gamma J)^-1 x, the last factorisation's. 0 or
 * TB__ROSENBROCK_LINEAR_FAILED. */
int tb__rosenbrock_solve(tb_integrator *integrator, double *x);

/* n doubles of the solver's for f(t, y) at the step's start, kept through the step. */
double *tb__rosenbrock_start_rate(tb_integrator *integrator);

/* n doubles of the solver's for the middle of a step halved at depth (< TB__ROSENBROCK_LEVELS). */
double *tb__rosenbrock_level(tb_integrator *integrator, int depth);
#define TB__ROSENBROCK_LEVELS 8
/* Whether tb__rosenbrock_factor merges the predictor's difference quotients in (default true). */
void tb__rosenbrock_speculate(tb_integrator *integrator, bool on);
/* Counts a halved step. */
void tb__rosenbrock_count_split(tb_integrator *integrator);

/* Reusing a factorisation across steps: whether the last one was made for a step of this h (and
 * held: the step taken with it was trusted) and can be tried again without a new Jacobian; hold
 * marks it so (h 0: none); a system without its own Jacobian never holds one (no J to probe). */
bool tb__rosenbrock_can_reuse(const tb_integrator *integrator, double h);
void tb__rosenbrock_hold(tb_integrator *integrator, double h);

/* Whether the held matrix describes the step from y to y_new ending at (t, f_end), along its
 * change (one derivative; rosenbrock_linear.c says the test); floor in y's units. 0 or a
 * derivative's non-zero return. */
int tb__rosenbrock_probe(tb_integrator *integrator, double t, double h, double gamma,
                         const double *y, const double *y_new, const double *f_end, double floor,
                         bool *ok);

/* Why the last TB__ROSENBROCK_LINEAR_FAILED ("" if none). */
const char *tb__rosenbrock_message(const tb_integrator *integrator);

/* One step of the method from (t, y) into y_new, as a tb__step_fn (fixed_step.c calls it for the
 * row whose linearly_implicit is set), with the integrator for its solver. work: 2n doubles. */
int tb__rosenbrock_step(tb_integrator *integrator, double t, double h, double t_last,
                        const double *y, double *y_new, double *work, long *evals);

#endif
