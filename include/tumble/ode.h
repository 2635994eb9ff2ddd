/* The generic ODE layer: an integrator advances y' = f(t, y) in place on the caller's array.
 * It knows nothing of rigid bodies; bring any ODE. */
#ifndef TUMBLE_ODE_H
#define TUMBLE_ODE_H

#include "tumble/export.h"

#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Derivative: writes dydt[0..n) from t and y[0..n). Same signature as GSL odeiv2 and CVODE's
 * right-hand side. Returns 0 on success, > 0 for a recoverable failure (an adaptive
 * integrator may retry with a smaller step), < 0 for a fatal one. Must not change y. */
typedef int (*tb_ode_derivative)(double t, const double *y, double *dydt, void *ctx);

/* Post-step hook: may adjust a freshly accepted state y[0..n) at time t. Returns 0 on success,
 * non-zero to stop the run. */
typedef int (*tb_ode_hook)(double t, double *y, void *ctx);

/* For a system made of independent blocks: the derivative of the blocks
 * [first_block, first_block + block_count), each tb_ode_blocks.size components. y and dydt point
 * at the first of them (component first_block * size of the whole state) and hold
 * block_count * size components. Must give exactly what the whole derivative gives for
 * those components; same return convention. */
typedef int (*tb_ode_block_derivative)(double t, const double *y, double *dydt, size_t first_block,
                                       size_t block_count, void *ctx);

/* The post-step hook for the blocks [first_block, first_block + block_count), y pointing at the
 * first of them; must do to them what post_step does. */
typedef int (*tb_ode_block_hook)(double t, double *y, size_t first_block, size_t block_count,
                                 void *ctx);

/* Optional part of a system: independent blocks. size > 0 declares the system separable into
 * n / size independent blocks (n must be a multiple), the derivative of each block depending on
 * t and that block alone. Fixed-step methods then finish each step a cache-sized chunk of blocks
 * at a time, so the state crosses memory once a step however large it is, with the same
 * arithmetic as the whole-array path; BDF's Krylov solver preconditions block by block. All
 * zero (default) for none. */
typedef struct tb_ode_blocks {
    size_t size;                        /* components per block; 0 for none */
    tb_ode_block_derivative derivative; /* required with size */
    tb_ode_block_hook post_step;        /* required with size if the system's post_step is set;
                                           unused without it */
    /* Optional, with size: the same block functions in lane layout, for the vector unit. A lane
     * group is `lanes` blocks stored component by component: component c of the group's block
     * j at y[c * lanes + j] (and dydt likewise). Fixed-step methods then step a group at a time
     * in that layout (the caller's y keeps its layout). The functions get the group's real
     * blocks [first_block, first_block + block_count), block_count <= lanes; the lanes past
     * block_count hold copies of the last real block and their results are thrown away. They
     * must give, component by component, the bits derivative and post_step give (the steps are
     * then the same either way). lanes 0 (default): none. With integrator threads > 1 these and
     * the block functions are called concurrently on distinct blocks. */
    size_t lanes;
    tb_ode_block_derivative lanes_derivative; /* required with lanes */
    tb_ode_block_hook lanes_post_step;        /* required with lanes if post_step is set */
} tb_ode_blocks;

/* Optional part of a system: its lifetime, for a system that other code can change or step. */
typedef struct tb_ode_lifetime {
    /* The integrator calls acquire(ctx, generation) at the start of every advance, step and
     * reset, and goes ahead only if it returns TB_STATUS_OK; release(ctx) when that call ends,
     * whatever its outcome. generation is what layout_generation(ctx) returned when the
     * integrator was made. acquire refuses with TB_STATUS_LAYOUT_CHANGED when the system's
     * layout (its n, the meaning of its components) changed since then, and with
     * TB_STATUS_BUSY while another call is stepping the system; it writes a message naming why
     * into detail (TB_DETAIL_SIZE bytes). A refused call returns acquire's status and detail and
     * changes nothing. release is called exactly once for every acquire that returned
     * TB_STATUS_OK (also when the call then fails), never after a refusal. layout_generation is
     * called once, at creation. All three NULL (default) for a system nobody else touches, or
     * all three set (TB_STATUS_NULL_POINTER naming the missing one otherwise). */
    unsigned long long (*layout_generation)(void *ctx);
    tb_status (*acquire)(void *ctx, unsigned long long generation, char *detail);
    void (*release)(void *ctx);
    /* Optional, for a system whose right-hand side can change between calls without its layout
     * changing: a number that changes whenever the derivative does. A multistep method (CVODE)
     * compares it at the start of every advance and step and restarts from y when it moved,
     * since its history is of the old right-hand side; one-step methods need nothing. NULL
     * (default): the derivative never changes. */
    unsigned long long (*rhs_generation)(void *ctx);
    /* Optional: tb_integrator_reset(integrator, t)'s check of (t, y) as a state to start from,
     * called after acquire and before the integrator changes anything (a scene refuses a time
     * where keys put a keyframed body inside another). It returns TB_STATUS_OK to go ahead, the
     * system then taking t as y's time, or a refusal with a message in detail (TB_DETAIL_SIZE
     * bytes): the reset returns that status and detail and changes nothing. NULL (default):
     * every finite time is accepted. */
    tb_status (*check_reset)(double t, const double *y, void *ctx, char *detail);
} tb_ode_lifetime;

/* Optional part of a system: events and where the right-hand side loses smoothness. The
 * adaptive methods read roots, step_limit and at_event; the fixed-step methods read roots and
 * at_event for onsets (below; they ignore step_limit); every method reads next_break. */
typedef struct tb_ode_events {
    /* root_count event functions g_0 .. g_{root_count-1}, written by roots(t, y, g, ctx) into
     * g[0..root_count). Each must be continuous in t and y. CVODE checks their signs at the end
     * of every step and locates a sign change (an event) to within about 100 rounding errors of
     * t in the computed solution, whose own error is the integration error; every call then
     * stops there internally, counts the event (tb_integrator_get_events) and goes on, so a
     * step ends on each event. Fixed-step methods (on systems without blocks) compare the signs
     * at each step's start and end and end the step at the first onset inside it, a function
     * falling from above zero to zero or below (for a scene: a gap closing), located on the
     * step's cubic Hermite interpolant to 6e-8 of the step, taking the step again to there
     * (the later steps keep their grid, as at next_break); rising crossings end no step. Steps
     * without an onset inside are those of a system without roots, bit for bit. A root
     * function that returns non-zero fails the call (TB_STATUS_SOLVER_FAILED naming it). 0 and
     * NULL (default): none. */
    size_t root_count;
    int (*roots)(double t, const double *y, double *g, void *ctx);
    /* Optional, read only where roots is set and is root_signs_for: the same functions exact in
     * sign only, each g_i > 0 exactly where roots' is (the values may differ), which may cost
     * less (for a scene: pairs that cannot change a gap's sign are passed over). The fixed-step
     * methods' onset search reads only the signs and calls it in roots' place; the adaptive
     * methods, which locate a root from the values, and rosenbrock's onset prediction, do not.
     * root_signs_for names the roots it answers for: a system that replaces roots (a user's
     * events added to tb_scene_ode_system's, under a ctx of its own) gets roots everywhere
     * without touching either. NULL (default): roots everywhere. */
    int (*root_signs)(double t, const double *y, double *g, void *ctx);
    int (*root_signs_for)(double t, const double *y, double *g, void *ctx);
    /* The longest step (> 0, in the system's time unit) the method may take from the accepted
     * state (t, y), whose derivative is dydt (CVODE's, from its history; NULL before the first
     * step), asked before every step; INFINITY or 0 for no limit. Applies with
     * tb_integrator_def.max_step (the tighter wins). NULL (default): none. */
    double (*step_limit)(double t, const double *y, const double *dydt, void *ctx);
    /* With roots: called where a call stops at an event (CVODE's root, inside an advance as
     * well as at its end; a fixed step's onset), with the state there, which it may change only
     * where it also moves lifetime.rhs_generation (an impact at a joint's stop): the restart then
     * starts from the changed state (an event past the output time: from the output,
     * interpolated before it). The system may change its right-hand side there; when
     * lifetime.rhs_generation then moved, the integrator restarts from (t, y) at once, so that
     * the new right-hand side holds from the event on (an event past the output time: from the
     * output). NULL (default): none. */
    void (*at_event)(double t, const double *y, void *ctx);
    /* The first time after t where the right-hand side is only C1 in t, INFINITY for none. A
     * fixed-step method shortens the step that would cross it so that the step ends on it (the
     * steps after keep their grid), and a step that ends on it evaluates its stage at the end
     * (RK4's last) at the largest double below it, so that the step sees the piece it lies in (a
     * linear key's velocity jumps there); CVODE and ARKODE stop there (the stop time), take f at
     * the largest double below it wherever they ask for it on or past it (a step's end), and
     * restart from it, their history being of the curve before (also where a step reached it past
     * a call's output: the next call restarts there first). NULL (default): none, and every
     * method steps as before, bit for bit. */
    double (*next_break)(double t, void *ctx);
    /* With next_break: whether the call may go on from the break at t it reached with state y
     * (the right-hand side's next piece starts there): TB_STATUS_OK, or a status with detail
     * (TB_DETAIL_SIZE bytes) written, which ends the call there, its time t and the state y,
     * the last good one (no detail written: the integrator writes one naming check_break and
     * the time). Asked where a fixed step ends on a break inside a call, where CVODE or
     * ARKODE restarts on one, and at the start of every advance and step (a call may have ended
     * on a break; a reset is not asked at the time it leaves). NULL (default): every break is
     * taken. */
    tb_status (*check_break)(double t, const double *y, void *ctx, char *detail);
    /* The time until which the system rests from (t, y): its right-hand side zero there and
     * its post-step hook leaving y as it is (a scene all of whose bodies sleep, with nothing
     * that moves them by time: docs/effects.md, "Sleeping"); t itself, or less, where it does
     * not. A fixed-step method's advance then moves its time to that one (or to the call's
     * end, whichever comes first) without taking steps, calls post_step once there, and counts
     * the time in tb_integrator_stats.rest_time; it asks again after each step, so a call
     * that begins awake jumps from the step where the system came to rest, and one at rest
     * all the way is not held to max_steps (it takes none). The adaptive
     * methods do not read it (their steps grow where the right-hand side is zero). NULL
     * (default): every step is taken. */
    double (*rest_until)(double t, const double *y, void *ctx);
    /* The longest step the system lets a method that divides its steps take from (t, y) when
     * asked for a step of h (for a scene: the tunnelling bound, in which no two bodies close by
     * more than the thinner one's half-thickness; its guard then refuses a rosenbrock step only
     * where a quarter of it is still too long). rosenbrock takes a step longer than it as two
     * halves, each asked again, down to 1/128 of the step (TB_METHOD_ROSENBROCK); the caller's
     * grid and step count are unchanged. The other methods do not read it. INFINITY for no
     * limit; NULL (default): none. */
    double (*split_limit)(double t, const double *y, double h, void *ctx);
} tb_ode_events;

/* A sparse n x n matrix in compressed-sparse-row form: row i's entries are
 * values[row_starts[i] .. row_starts[i + 1]), in the columns columns[...] (ascending within a
 * row); row_starts[0] = 0 and row_starts[n] is the number of entries, at most capacity. */
typedef struct tb_ode_sparse {
    size_t n;           /* rows and columns */
    size_t capacity;    /* entries columns and values hold */
    size_t *row_starts; /* n + 1 */
    size_t *columns;    /* capacity */
    double *values;     /* capacity */
} tb_ode_sparse;

/* Optional part of a system: the Jacobian df/dy of its right-hand side as a sparse matrix, for the
 * implicit methods' Newton iteration (BDF and ark-imex with TB_LINEAR_SOLVER_SPARSE). With a split
 * (tb_ode_split) ark-imex's Newton iteration is of the implicit part f_I = f - f_E; this Jacobian
 * of the whole f then stands in for df_I/dy: the difference, df_E/dy, is of the non-stiff part,
 * small against 1/(gamma h), so it slows Newton's convergence a little and changes no result
 * (the residual is of f_I itself). The pattern may change from state to state (a contact
 * graph does); the integrator re-analyses it only when it does. Both NULL (default) for none,
 * or both set. */
typedef struct tb_ode_jacobian {
    /* The most entries the Jacobian can have at the states the next step may visit from the
     * accepted state (t, y), diagonal included: asked before every step (the first one too, y
     * then the initial state). The integrator makes room for the diagonal at creation and grows
     * it only here, so evaluate allocates nothing. A value below n fails the step
     * (TB_STATUS_SOLVER_FAILED naming it). */
    size_t (*capacity)(double t, const double *y, void *ctx);
    /* Writes J = df/dy at (t, y) (fy = f(t, y)), pattern and values: every diagonal entry
     * (zero or not) and at most J->capacity entries (the last capacity asked). A pure function
     * of (t, y), like the derivative; same return convention; must not change y. */
    int (*evaluate)(double t, const double *y, const double *fy, tb_ode_sparse *J, void *ctx);
} tb_ode_jacobian;

/* Optional part of a system: a split of its right-hand side f = f_E + f_I for the implicit-explicit
 * method (TB_METHOD_ARK_IMEX): f_E, the non-stiff part, is given here and taken explicitly; the
 * rest, f_I = f - f_E (the derivative less f_E, at the same t and y), implicitly. The kinematic
 * rows of a mechanical system (dx/dt = v) belong to f_I when its stiff forces are there: a stiff
 * oscillation couples both. Other methods ignore the split. NULL (default): no split, ark-imex
 * takes all of f implicitly. */
typedef struct tb_ode_split {
    /* f_E: same signature and return convention as the derivative, writes every component (zero
     * where f_E has none) */
    tb_ode_derivative explicit_part;
} tb_ode_split;

/* An ODE system: a small core and optional parts, each all zero for none. The integrator
 * borrows it (a copy: the parts are values): ctx must outlive the integrator. */
typedef struct tb_ode_system {
    size_t n;                     /* dimension, > 0 */
    tb_ode_derivative derivative; /* required */
    tb_ode_hook post_step;        /* optional, NULL for none */
    void *ctx;                    /* passed to every callback */

    tb_ode_blocks blocks;     /* independent blocks and their lane layout */
    tb_ode_lifetime lifetime; /* acquire and release by calls, generations */
    tb_ode_events events;     /* roots, step limits, events, breaks */
    tb_ode_jacobian jacobian; /* the sparse Jacobian */
    tb_ode_split split;       /* explicit and implicit parts, for ark-imex */
} tb_ode_system;

/* How to integrate, chosen as data. */
typedef enum tb_method {
    TB_METHOD_EULER = 0,   /* explicit Euler, order 1, 1 derivative per step */
    TB_METHOD_MIDPOINT,    /* explicit midpoint (RK2), order 2, 2 derivatives per step */
    TB_METHOD_RK4,         /* classical Runge-Kutta, order 4, 4 derivatives per step */
    TB_METHOD_CVODE_ADAMS, /* SUNDIALS CVODE, Adams-Moulton orders 1-12, fixed-point
                              iteration: adaptive, for non-stiff problems */
    TB_METHOD_CVODE_BDF,   /* SUNDIALS CVODE, BDF orders 1-5, Newton iteration: adaptive,
                              for stiff problems (stiff springs, heavy damping) */
    TB_METHOD_ROSENBROCK,  /* linearly implicit fixed step (ROS2, Rosenbrock-W), order 2,
                              L-stable: reads dt; the system's Jacobian (tb_ode_system.jacobian)
                              or dense difference quotients (n <= 512); a step its rates do not
                              explain, or longer than the system's events.split_limit, is halved
                              inside, down to 1/128 (docs/integrators.md) */
    TB_METHOD_ARK_IMEX,    /* SUNDIALS ARKODE's ARKStep, additive Runge-Kutta of order 4 (2-5
                              by max_order): the system's split (tb_ode_split) explicit, the
                              rest implicit by Newton; adaptive, one-step, for stiff contact */
    TB_METHOD_COUNT
} tb_method;

/* Every fact about a method: one row of the library's method table (tb_method_get_info).
 *
 * Linear stability: on the test mode y' = lambda y one step multiplies y by R(h lambda). The
 * limits are the largest |h lambda| at which a step does not amplify the mode by more than a
 * stated factor, on the two axes a physical mode lies near: the imaginary axis (undamped
 * oscillation, springs and spinning bodies) and the negative real axis (pure decay, drag and
 * heavy damping). A caller with a mode of rate |lambda| keeps h <= limit / |lambda|. */
typedef struct tb_method_info {
    const char *name; /* "rk4": tb_method_name's spelling (tb_method_from_name takes any case) */
    int order;        /* classical order of a fixed-step method (1, 2, 4); the largest order
                         of an adaptive one (Adams 12, BDF 5, ark-imex 5) */
    int adaptive;     /* 1: error-controlled steps; reads rtol, atol, atol_vector,
                         initial_step, max_step, max_order, max_steps (BDF and ark-imex also
                         linear_solver, preconditioner_half_bandwidth), never dt.
                         0: fixed step; reads dt and max_steps only */
    int multistep;    /* 1: the step uses past steps' history (Adams, BDF), so a state changed
                         from outside costs a restart at order 1; 0: one-step method */
    int derivative_evals_per_step; /* stages of a fixed-step method (1, 2, 4); 0 for an
                                      adaptive one, where it varies (tb_integrator_stats) */
    double imaginary_limit;        /* largest |h lambda| on the imaginary axis at which
                                      |R| <= imaginary_growth; INFINITY for adaptive methods, whose
                                      error control chooses a step that is stable */
    double imaginary_growth;       /* the |R| imaginary_limit is measured at: 1 where the method is
                                      stable on a segment of the axis (RK4: 2 sqrt 2 = 2.828); 1.01
                                      for Euler (0.1418) and midpoint (0.5325), which amplify every
                                      oscillation a little at any h > 0: the limit is where a step
                                      grows it by 1% */
    double real_limit;             /* largest |h lambda| on the negative real axis with |R| <= 1
                                      (Euler and midpoint 2, RK4 2.785); INFINITY for adaptive */
} tb_method_info;

/* Fills *out_info with the method's row. TB_STATUS_NULL_POINTER if out_info is NULL,
 * TB_STATUS_INVALID_ARGUMENT for a value that is not a tb_method (then *out_info is
 * untouched). */
TB_API tb_status tb_method_get_info(tb_method method, tb_method_info *out_info);

/* "euler", "midpoint", "rk4", "cvode-adams", "cvode-bdf", "rosenbrock", "ark-imex"; NULL for an
 * unknown
 * method. */
TB_API const char *tb_method_name(tb_method method);

/* Parses a method name, ignoring ASCII case ("RK4", "CVODE-BDF"). An unknown name gives
 * TB_STATUS_INVALID_ARGUMENT and, in out_error (may be NULL), a message naming it and listing
 * the methods: `unknown method "rk5"; methods: euler, midpoint, rk4, cvode-adams, cvode-bdf,
 * rosenbrock`. NULL name or out_method: TB_STATUS_NULL_POINTER. *out_method is written only on
 * success. */
TB_API tb_status tb_method_parse(const char *name, tb_method *out_method, tb_error *out_error);

/* tb_method_parse without the message. */
TB_API tb_status tb_method_from_name(const char *name, tb_method *out_method);

/* tb_method_info.order; 0 for an unknown method. */
TB_API int tb_method_order(tb_method method);

/* tb_method_info.adaptive: non-zero for the error-controlled methods (CVODE, ark-imex), which take
 * rtol/atol instead of dt; 0 for an unknown method. */
TB_API int tb_method_is_adaptive(tb_method method);

/* Whether a method reads a setting: the one rule the scene loader, the CLI and the bindings
 * ask, so that a setting meant for another method is refused everywhere alike. setting is a
 * tb_integrator_def field's name ("dt", "threads", "rtol", "atol", "atol_vector",
 * "initial_step", "max_step", "max_order", "linear_solver", "preconditioner_half_bandwidth",
 * "max_steps") or "allow_unstable" (the scene's stability guard, which judges fixed steps).
 * TB_STATUS_OK: the method reads it (max_steps: every method). TB_STATUS_UNSUPPORTED: it does
 * not, and out_error (may be NULL) says which methods do, e.g. "applies to adaptive methods
 * (cvode-adams, cvode-bdf), not to rk4", for the caller to prefix with its name for the
 * setting. TB_STATUS_INVALID_ARGUMENT: an unknown method or setting name (listing the names);
 * TB_STATUS_NULL_POINTER: setting is NULL. tests/test_ode.c checks every method's row. */
TB_API tb_status tb_method_check_setting(tb_method method, const char *setting,
                                         tb_error *out_error);

/* Linear solver for the Newton iteration of TB_METHOD_CVODE_BDF and TB_METHOD_ARK_IMEX. */
typedef enum tb_linear_solver {
    TB_LINEAR_SOLVER_AUTO = 0, /* dense up to 64 unknowns (512 without blocks), Krylov above */
    TB_LINEAR_SOLVER_DENSE,    /* dense difference-quotient Jacobian and LU: O(n^3) a setup */
    TB_LINEAR_SOLVER_KRYLOV,   /* matrix-free GMRES with difference-quotient Jacobian-vector
                                  products, preconditioned block by block for a system with
                                  blocks (exact), banded otherwise: O(n) a setup */
    TB_LINEAR_SOLVER_SPARSE    /* the system's own sparse Jacobian (tb_ode_system.jacobian,
                                  required) and KLU's sparse LU: the cost of a setup follows
                                  the entries, not n^3. KLU analyses each new pattern anew,
                                  which allocates: not chosen by auto (docs/integrators.md).
                                  TB_STATUS_UNSUPPORTED in a build without KLU */
} tb_linear_solver;

typedef struct tb_integrator_def {
    tb_method method; /* default TB_METHOD_RK4 */

    /* Fixed-step methods. */
    double dt; /* step size in the system's time unit > 0; default 1/240
                  (tb_scene_integrator_create: 0 for the scene's default step).
                  The times a run reaches must resolve it: doubles near t must be at most
                  dt / 1024 apart (near t = 1e15 they are 0.125 apart), else creation, reset
                  or advance is refused (TB_STATUS_INVALID_ARGUMENT naming dt and the time) */

    /* Adaptive methods: CVODE keeps each step's local error e_i below
     * rtol |y_i| + atol_i (weighted RMS norm). */
    double rtol;               /* relative tolerance, > 0; default 1e-6 */
    double atol;               /* absolute tolerance for every component, >= 0; default 0,
                                  meaning automatic: rtol * 1e-3 (tb_scene_integrator_create
                                  derives its own, tb_scene_absolute_tolerances) */
    const double *atol_vector; /* n absolute tolerances, >= 0, overriding atol; copied at
                                  creation; default NULL */
    long max_steps;      /* every method: steps allowed in one advance or step call, > 0; default
                            100000. Used up: TB_STATUS_TOO_MANY_STEPS naming it and the time
                            reached, y at the last good step. A fixed-step advance whose target is
                            more than max_steps steps of dt away is refused before any step; its
                            steps cut short at a break or an onset have a budget of max_steps of
                            their own */
    double initial_step; /* first step size; 0 (default) lets CVODE estimate it */
    double max_step;     /* largest step size; 0 (default) for no limit. With
                            tb_ode_system.events.step_limit the tighter limit wins */
    int max_order;       /* 0 (default) for the method's largest (Adams 12, BDF 5; ark-imex:
                            its tables' order, 2-5, 0 for 4);
                            CVODE keeps max_order + 1 history vectors, so Adams at 5
                            takes 7 state-sized vectors fewer (docs/performance.md) */
    tb_linear_solver linear_solver;    /* BDF and ark-imex; default TB_LINEAR_SOLVER_AUTO */
    int preconditioner_half_bandwidth; /* Krylov, systems without blocks: half-bandwidth
                                          of the banded difference-quotient preconditioner;
                                          < 0 (default) automatic: 0 (diagonal; a scene's
                                          integrator fills in its own) */

    /* Fixed-step methods on separable systems (blocks.size > 0): threads the chunks of a step
     * are shared among, >= 1, or 0 for one per processor; default 1, so an embedding program
     * keeps its threads to itself. The chunks are the same for any count, so is every bit of
     * the result. The library starts no more than this many (OpenMP, nested in none of the
     * caller's: a call from inside the caller's own OpenMP team runs on one). Systems that are
     * not separable step on one thread. */
    int threads;

    int internal_cookie; /* set by tb_integrator_def_default; catches defs not made by it */
} tb_integrator_def;

TB_API tb_integrator_def tb_integrator_def_default(void);

/* Switches def to another method and puts back to their defaults the fields the new method
 * does not read (dt for an adaptive method; rtol, atol, atol_vector, initial_step, max_step,
 * max_order for a fixed-step one; linear_solver for all but BDF), keeping the others: for a
 * front end overriding the method of a definition read from a scene file.
 * TB_STATUS_NULL_POINTER, or TB_STATUS_INVALID_ARGUMENT for an unknown method (def unchanged). */
TB_API tb_status tb_integrator_def_set_method(tb_integrator_def *def, tb_method method);

/* What an integrator has done since it was created. */
typedef struct tb_integrator_stats {
    long steps;                     /* accepted steps */
    long derivative_evals;          /* all calls of the derivative, including those made to
                                       approximate Jacobians and preconditioners (ark-imex with
                                       a split: calls of the whole derivative, f_E's not
                                       counted) */
    long jacobian_derivative_evals; /* the part of derivative_evals spent on Jacobians and
                                       preconditioners (BDF) */
    long failed_steps;              /* steps rejected: error-test or nonlinear-solver failures
                                       (adaptive), derivative or hook errors, non-finite states */
    long error_test_failures;       /* adaptive: steps whose error estimate was too large */
    long nonlinear_failures;        /* adaptive: nonlinear-solver convergence failures */
    long linear_iterations;         /* Krylov iterations (BDF with the Krylov solver) */
    double last_step;               /* size of the last accepted step */
    double current_step;            /* size the next step will try */
    int last_order;                 /* order of the last step (fixed-step: the method's;
                                       ark-imex: its tables') */
    int current_order;              /* order the next step will use */
    long reinitializations;         /* adaptive: restarts because the state was changed from
                                       outside or tb_integrator_reset was called */
    long nonlinear_iterations;      /* adaptive: iterations of the implicit solve (BDF's Newton,
                                       Adams' fixed point) */
    long jacobian_evals;            /* BDF, ark-imex: Jacobians formed (difference quotients, or the
                                       system's own with TB_LINEAR_SOLVER_SPARSE); preconditioner
                                       set-ups of the Krylov solver not counted */
    double rest_time;               /* fixed-step: time the advances jumped over without steps,
                                       the system at rest (tb_ode_events.rest_until) */
} tb_integrator_stats;

typedef struct tb_integrator tb_integrator;

/* Which fields a method reads (tb_method_info.adaptive): fixed-step methods read dt,
 * threads and max_steps; adaptive ones read rtol, atol, atol_vector, initial_step, max_step,
 * max_order and max_steps, BDF also linear_solver and preconditioner_half_bandwidth. A field the
 * method does not read that differs from tb_integrator_def_default()'s value was meant for another
 * method: creation refuses it (TB_STATUS_INVALID_ARGUMENT naming the field; rtol given to rk4, dt
 * to cvode-bdf). preconditioner_half_bandwidth is exempt (tb_scene_integrator_create fills it in
 * for every method).
 *
 * Re-entrancy: an integrator's advance, step or reset called from inside its own derivative,
 * hook or acquire returns TB_STATUS_BUSY and changes nothing (its detail says why until the
 * call in progress ends; if that call succeeds, the detail is empty again). Reading calls
 * (time, stats, method, detail) work from inside. Destroying an integrator from inside its
 * own callbacks is not allowed.
 *
 * Every call that can fail clears the integrator's detail first (except a refused re-entrant
 * call, whose detail belongs to the call in progress). NaN or infinity in a time or a def
 * field gives TB_STATUS_NOT_FINITE; a finite value out of its domain
 * TB_STATUS_INVALID_ARGUMENT. */

/* Creates an integrator that advances y[0..system->n) from time t0, in place. y stays owned
 * by the caller and must outlive the integrator; y is not read until the first step.
 * All memory the integrator will ever use is allocated here. On failure *out_integrator is
 * NULL and out_error (may be NULL) names the wrong input. */
TB_API tb_status tb_integrator_create(const tb_ode_system *system, const tb_integrator_def *def,
                                      double t0, double *y, tb_integrator **out_integrator,
                                      tb_error *out_error);

/* Frees an integrator; accepts NULL. Does not touch y. Called from a callback of the
 * integrator's own advance, step or reset (a contact event, a hook), it frees it as that call
 * returns. */
TB_API void tb_integrator_destroy(tb_integrator *integrator);

/* Advances y to t_target (>= current time).
 * Fixed-step: whole steps of dt, the last one shortened or slightly stretched (by at most
 * 1e-9 dt) so the run lands exactly on t_target without a sliver step.
 * Adaptive: CVODE steps as its error control decides, possibly past t_target, and y is its
 * interpolated solution at t_target; so the times asked for (the frame rate) do not change
 * the steps taken. The post-step hook is applied to that output (for BDF it also runs inside
 * CVODE as a projection). If y was changed from outside since the last call, CVODE is
 * restarted from it. CVODE counts time from the start (or the last restart), so any finite t0
 * works; the derivative sees the system's own times.
 * Every state handed out is checked: a non-finite component (from a step, CVODE's output or
 * interpolant, or the post-step hook) gives TB_STATUS_STATE_NOT_FINITE naming it, even when
 * the hook also failed on it.
 * On failure y holds the state at the last good step, the integrator's time is that step's
 * time, and the detail message names the failure (CVODE's flag name) and its time. CVODE's
 * CV_TOO_MUCH_WORK is TB_STATUS_TOO_MANY_STEPS. */
TB_API tb_status tb_integrator_advance(tb_integrator *integrator, double t_target);

/* Takes exactly one step: of size dt (fixed-step), or one internal CVODE step; with event
 * functions (tb_ode_system.events.roots) it stops at an event inside that step instead, and the
 * next call goes on to the step's end (fixed-step: at an onset, and the next call takes dt from
 * there). */
TB_API tb_status tb_integrator_step(tb_integrator *integrator);

/* Current time of y. */
TB_API double tb_integrator_time(const tb_integrator *integrator);

/* Tells the integrator that the caller changed y (or wants a new time): the next step starts
 * from y at time t (CVODE restarts at order 1). Statistics keep counting. The system's
 * check_reset, when set, may refuse (t, y); a refused reset changes nothing. */
TB_API tb_status tb_integrator_reset(tb_integrator *integrator, double t);

/* The events an adaptive integrator found since it was created (tb_ode_system.events.roots). */
typedef struct tb_integrator_events {
    long count;         /* events found: one per call-stopping sign change (several functions
                           changing sign at one time count once) */
    double last_time;   /* time of the last one, in the system's time unit; NAN before the first */
    long last_root;     /* the lowest index of the functions that changed sign at last_time, -1
                           before the first (a scene's: tb_scene_ode_system) */
    int last_direction; /* +1: that function rose through zero, -1: it fell; 0 before the
                           first */
} tb_integrator_events;

/* Copies the event counts into *out_events; fixed-step integrators count their onsets.
 * TB_STATUS_NULL_POINTER for a NULL argument. */
TB_API tb_status tb_integrator_get_events(const tb_integrator *integrator,
                                          tb_integrator_events *out_events);

/* Copies the statistics into *out_stats. */
TB_API tb_status tb_integrator_get_stats(const tb_integrator *integrator,
                                         tb_integrator_stats *out_stats);

/* The method the integrator was created with (TB_METHOD_COUNT for NULL). */
TB_API tb_method tb_integrator_method(const tb_integrator *integrator);

/* Detail of the last failure ("" if none); owned by the integrator. */
TB_API const char *tb_integrator_detail(const tb_integrator *integrator);

#ifdef __cplusplus
}
#endif

#endif
