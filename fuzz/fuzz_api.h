/* The C-API fuzz target's shared parts: the harness (one scene, its integrators, the user
 * callbacks' settings), the invariants checked after every call, and the trace that prints an
 * input as the C calls it makes (TUMBLE_FUZZ_TRACE=1), from which a finding's reproducer is
 * written. */
#ifndef TUMBLE_FUZZ_API_H
#define TUMBLE_FUZZ_API_H

#include "fuzz_input.h"

#include "tumble/tumble.h"

#include <stdio.h>

/* Bounds on one input's work, so that a slow input is a defect of the library (a loop without a
 * budget), not of the harness: few bodies and effects, small step budgets, few frames. */
#define FUZZ_MAX_OPERATIONS 48
#define FUZZ_MAX_BODIES 8
#define FUZZ_MAX_USER_EFFECTS 4
#define FUZZ_MAX_INTEGRATORS 2
#define FUZZ_MAX_STEPS 500           /* max_steps of the integrators that advance */
#define FUZZ_MAX_FRAMES 40           /* frames a run may hand to its callback before it stops */
#define FUZZ_MAX_EVALUATIONS 2000000 /* derivative evaluations in one input, all calls */

/* What a user effect does when the derivative calls it. */
typedef enum fuzz_user_kind {
    FUZZ_USER_FORCE,   /* tb_effect_add_force on a chosen id (maybe out of range) */
    FUZZ_USER_TORQUE,  /* tb_effect_add_torque on a chosen id */
    FUZZ_USER_FAIL,    /* returns `result` (recoverable > 0 or fatal < 0) */
    FUZZ_USER_REENTER, /* calls tb_integrator_advance from inside the derivative */
    FUZZ_USER_READ,    /* reads the state through the read-outs */
    FUZZ_USER_KIND_COUNT
} fuzz_user_kind;

typedef struct fuzz_user_effect {
    struct fuzz_harness *harness;
    fuzz_user_kind kind;
    size_t id;
    double vector[3];
    double point[3];
    int result;
} fuzz_user_effect;

/* What the frame callback of tb_scene_run does at frame `at_frame`. */
typedef enum fuzz_frame_kind {
    FUZZ_FRAME_CONTINUE,   /* nothing (the harness still stops after FUZZ_MAX_FRAMES) */
    FUZZ_FRAME_CANCEL,     /* returns non-zero */
    FUZZ_FRAME_ADD_BODY,   /* adds a body: the run's integrator is on the old layout */
    FUZZ_FRAME_ADD_GROUND, /* adds a ground plane: new effect-owned states */
    FUZZ_FRAME_ADD_EFFECT, /* adds a drag: an effect the run has not seen */
    FUZZ_FRAME_SET_STATE,  /* moves body 0 */
    FUZZ_FRAME_CONTACT,    /* sets body 0's contact points: changes the layout */
    FUZZ_FRAME_KIND_COUNT
} fuzz_frame_kind;

typedef struct fuzz_harness {
    fuzz_input *in;
    tb_scene *scene;
    tb_integrator *integrators[FUZZ_MAX_INTEGRATORS];
    tb_integrator_def definitions[FUZZ_MAX_INTEGRATORS]; /* what each was made from */
    fuzz_user_effect users[FUZZ_MAX_USER_EFFECTS];
    size_t user_count;
    fuzz_frame_kind frame_kind;
    size_t at_frame;
    int in_derivative;    /* a derivative (through an integrator) is running */
    int callback_changed; /* a callback changed the scene's layout or bodies */
    long evaluations;     /* derivative evaluations so far (budget FUZZ_MAX_EVALUATIONS) */
    int trace;
} fuzz_harness;

/* The scene as it was before a call, to compare with after. */
typedef struct fuzz_snapshot {
    double *state;
    size_t state_size;
    size_t bodies;
    size_t effects;
} fuzz_snapshot;

/* How a call may leave the scene when it fails. */
typedef enum fuzz_failure_rule {
    FUZZ_UNCHANGED, /* a refused call changes nothing: bit-identical state, same counts */
    FUZZ_LAST_GOOD, /* a failed step leaves the last good (finite) state; refusals before
                       any step (bad argument, stale layout, busy) still change nothing */
    FUZZ_HAS_RUN    /* a run that has delivered frames (and maybe changed the scene from its
                       callback) and then failed: the last good (finite) state */
} fuzz_failure_rule;

void fuzz_snapshot_take(const fuzz_harness *h, fuzz_snapshot *out);
void fuzz_snapshot_free(fuzz_snapshot *snapshot);

/* The invariants after a call named `call` that returned status with detail (may be NULL when
 * the call has no object to hold one): aborts, naming the call and what broke, on a violation. */
void fuzz_check(const fuzz_harness *h, const fuzz_snapshot *before, tb_status status,
                const char *detail, const char *call, fuzz_failure_rule rule);
void fuzz_check_unchanged(const fuzz_harness *h, const fuzz_snapshot *before, const char *call,
                          tb_status status);
void fuzz_check_state_finite(const fuzz_harness *h, const char *call);
void fuzz_fail(const char *call, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3), noreturn))
#endif
    ;

/* Trace: with h->trace set, prints one line of C to stderr. */
void fuzz_trace(const fuzz_harness *h, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* A double as C source ("NAN", "-INFINITY", "0x1p-1074" style exact hex); the buffers rotate,
 * so up to 64 may be used in one trace line. */
const char *fuzz_c_double(double value);
const char *fuzz_c_vector(const double *values, size_t count);
const char *fuzz_c_id(size_t id);

/* The operations, in fuzz_api_build.c (bodies, mass, effects) and fuzz_api_run.c
 * (integrators, advances, runs, callbacks). */
void fuzz_op_add_body(fuzz_harness *h);
void fuzz_op_add_effect(fuzz_harness *h);
void fuzz_op_contact_points(fuzz_harness *h);
void fuzz_op_set_state(fuzz_harness *h);
void fuzz_op_mass(fuzz_harness *h);
void fuzz_op_create_integrator(fuzz_harness *h);
void fuzz_op_advance(fuzz_harness *h);
void fuzz_op_run(fuzz_harness *h);
void fuzz_op_read(fuzz_harness *h);
void fuzz_op_null_arguments(fuzz_harness *h);
void fuzz_op_differential(fuzz_harness *h); /* in fuzz_api_differential.c */

/* An id: mostly a body of the scene, sometimes one past the end or a huge value. */
size_t fuzz_body_id(fuzz_harness *h);

/* Fills props from the input through one of the mass constructors (or as raw numbers); returns
 * the constructor's status. */
tb_status fuzz_mass_properties(fuzz_harness *h, tb_mass_properties *out_props);

#endif
