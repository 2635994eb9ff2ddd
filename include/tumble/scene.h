/* A scene: rigid bodies, their states as one flat array, and the effects acting on them.
 * The scene is an ODE system for the generic integrators (tumble/ode.h). */
#ifndef TUMBLE_SCENE_H
#define TUMBLE_SCENE_H

#include "tumble/export.h"

#include "tumble/body.h"
#include "tumble/ode.h"
#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tb_scene tb_scene;

typedef struct tb_scene_def {
    size_t body_capacity;         /* bodies to allocate room for up front; default 16 */
    size_t effect_capacity;       /* effects to allocate room for up front; default 8 */
    bool renormalize_quaternions; /* post-step hook q <- q/|q|; default true */
    bool sleeping;                /* islands of resting bodies sleep (tb_scene_set_sleeping);
                                     default true */
    int internal_cookie;          /* set by tb_scene_def_default */
} tb_scene_def;

TB_API tb_scene_def tb_scene_def_default(void);

/* On failure *out_scene is NULL and out_error (may be NULL) says why. */
TB_API tb_status tb_scene_create(const tb_scene_def *def, tb_scene **out_scene,
                                 tb_error *out_error);

/* Frees the scene and everything it owns; accepts NULL. */
TB_API void tb_scene_destroy(tb_scene *scene);

/* Detail of the scene's last failure ("" if none); owned by the scene. Every function taking
 * the scene clears it first, so after a failure it names that call's wrong input (a NULL
 * output included), never an earlier call's. */
TB_API const char *tb_scene_detail(const tb_scene *scene);

/* --- Bodies ------------------------------------------------------------------------------ */

/* Adds a body; its id is the index 0, 1, ... in order of addition. May grow the state array,
 * which moves it: re-read tb_scene_states() and recreate integrators after adding bodies. */
TB_API tb_status tb_scene_add_body(tb_scene *scene, const tb_body_def *def, size_t *out_id);

TB_API size_t tb_scene_body_count(const tb_scene *scene);

/* Body id's name (owned by the scene), or NULL for an id out of range. */
TB_API const char *tb_scene_body_name(const tb_scene *scene, size_t id);

/* The id of the body called name; TB_STATUS_OUT_OF_RANGE if there is none. */
TB_API tb_status tb_scene_find_body(const tb_scene *scene, const char *name, size_t *out_id);

/* The flat state array: tb_scene_state_size() doubles; the body in slot k at [13 k, 13 k + 13),
 * then the states some effects own (ground friction: 2 per contact point). Only dynamic bodies
 * have a slot (tb_scene_body_slot), given in the order they were added: in a scene of dynamic
 * bodies alone body i's slot is i. Owned by the scene; valid until the next tb_scene_add_body,
 * tb_scene_add_ground or tb_scene_set_contact_points, which may move it and reset the effects'
 * states. */
TB_API double *tb_scene_states(tb_scene *scene);
TB_API size_t tb_scene_state_size(const tb_scene *scene);

/* A body without a state in the state array (static or keyframed): its slot. */
#define TB_NO_SLOT ((size_t)-1)

/* Body id's slot: its 13 states are y[13 slot .. 13 slot + 13); TB_NO_SLOT for a body with no
 * state (a static or keyframed body, whose motion the read-outs give). */
TB_API tb_status tb_scene_body_slot(const tb_scene *scene, size_t id, size_t *out_slot);

/* How body id moves (tb_body_def.motion). Every read-out that takes (y, id) works for every
 * kind: a static body's pose with zero velocities; tb_scene_get_state gives a static body's
 * pose and zero momenta. tb_scene_set_state, tb_scene_set_velocity and per-body loads
 * (forces, torques, drag on one body) refuse a body that is not dynamic
 * (TB_STATUS_INVALID_ARGUMENT, the detail naming it and its kind); per-body effects on every
 * body (gravity, drag) act on dynamic bodies only. */
TB_API tb_status tb_scene_body_motion_kind(const tb_scene *scene, size_t id,
                                           tb_body_motion *out_motion);

/* The time (s) of the scene's states: the time read-outs without a t (tb_scene_frame_values,
 * tb_scene_get_state, ...) read keyframed bodies at. 0 at creation; integrators of the scene
 * keep it at the time of the states they leave (t0 at tb_scene_integrator_create, whose
 * checks read the bodies there; t at tb_integrator_reset; after every fixed step, at every
 * adaptive output) in every scene where it can matter, that is but one of dynamic bodies that
 * do not interact (no hook runs there after a step); tb_scene_derivative never changes it
 * (inside a user effect's callback it is the callback's t); tb_scene_set_time sets it
 * (finite; TB_STATUS_BUSY while stepped). NAN for NULL. */
TB_API double tb_scene_time(const tb_scene *scene);
TB_API tb_status tb_scene_set_time(tb_scene *scene, double t);

/* The force (N, world) and torque (N m, world, about its shape origin) that the bodies put on
 * body id through the scene's effects at state y and the scene's time: a keyframed or static
 * body's reaction (what holding it on its path costs). 0 for a dynamic body is not given:
 * TB_STATUS_INVALID_ARGUMENT. Evaluates the derivative once (allocates its scratch). */
TB_API tb_status tb_scene_body_reaction(tb_scene *scene, const double *y, size_t id,
                                        double out_force[3], double out_torque[3]);
TB_API const double *tb_scene_states_const(const tb_scene *scene);

/* Reads or writes one body's state. set validates it (finite, unit quaternion within 1e-4,
 * which is then normalised exactly) and changes nothing on failure; it and
 * tb_scene_set_velocity return TB_STATUS_BUSY while an integrator steps the scene (from a
 * callback or user effect). */
TB_API tb_status tb_scene_get_state(const tb_scene *scene, size_t id, tb_body_state *out_state);
TB_API tb_status tb_scene_set_state(tb_scene *scene, size_t id, const tb_body_state *state);

/* Sets a body's centre-of-mass velocity (m/s) and angular velocity (rad/s), both world
 * frame, by converting them to P = M v and L = I(t) omega at its current orientation. */
TB_API tb_status tb_scene_set_velocity(tb_scene *scene, size_t id, const double velocity[3],
                                       const double angular_velocity[3]);

/* A body's constant mass properties, as given when it was added. */
TB_API tb_status tb_scene_get_mass(const tb_scene *scene, size_t id, tb_mass_properties *out_mass);

/* --- Read-outs (from a state array y of the scene's size; pass tb_scene_states(scene) for
 * the current state). Quaternions are used normalised. ------------------------------------ */

/* Body (principal) frame -> world rotation matrix, row-major. */
TB_API tb_status tb_scene_body_rotation(const tb_scene *scene, const double *y, size_t id,
                                        double out_R[9]);
/* Centre-of-mass velocity v = P / M, world frame, m/s. */
TB_API tb_status tb_scene_body_velocity(const tb_scene *scene, const double *y, size_t id,
                                        double out_v[3]);
/* Angular velocity omega = R I_body^-1 R^T L, world frame, rad/s. */
TB_API tb_status tb_scene_body_angular_velocity(const tb_scene *scene, const double *y, size_t id,
                                                double out_omega[3]);
/* Pose of the body's shape frame (the frame of tb_body_def.orientation): world position of
 * the shape origin (m) and shape -> world unit quaternion. */
TB_API tb_status tb_scene_body_shape_pose(const tb_scene *scene, const double *y, size_t id,
                                          double out_position[3], double out_orientation[4]);

/* A point fixed in body id, given in its shape frame (m, from the shape origin): its world
 * position (m) and, if out_velocity is not NULL, its velocity v + omega x (p - x) (world, m/s).
 * The one helper for contact points, spring ends, markers and the shape origin. */
TB_API tb_status tb_scene_body_point(const tb_scene *scene, const double *y, size_t id,
                                     const double point[3], double out_position[3],
                                     double out_velocity[3]);
/* Velocity of the shape origin (world, m/s): what a renderer moving the shape frame needs,
 * which differs from the centre of mass's when the body spins and they are apart. */
TB_API tb_status tb_scene_body_shape_velocity(const tb_scene *scene, const double *y, size_t id,
                                              double out_velocity[3]);
/* Angular velocity in the body's shape frame (rad/s): R_shape^T omega, the body-frame omega of
 * Euler's equations when the shape frame is the principal frame (mass.rotation identity). */
TB_API tb_status tb_scene_body_frame_angular_velocity(const tb_scene *scene, const double *y,
                                                      size_t id, double out_omega[3]);

/* Doubles a body takes in tb_scene_frame_values's output. */
#define TB_FRAME_VALUES 13

/* Every body's frame in one call: what a renderer, a writer or a binding stores per frame.
 * Body i's TB_FRAME_VALUES doubles at out_values[13 i]: [0, 3) the world position of its
 * shape-frame origin (m), [3, 7) the shape -> world unit quaternion (w, x, y, z), [7, 10) the
 * shape origin's velocity (world, m/s; tb_scene_body_shape_velocity), [10, 13) the angular
 * velocity (world, rad/s). The layout tb_writer_frame_values reads and tb_writer_frame writes.
 * out_values holds 13 * tb_scene_body_count() doubles, owned by the caller; nothing is
 * allocated. */
TB_API tb_status tb_scene_frame_values(const tb_scene *scene, const double *y, double *out_values);

/* Total kinetic energy, sum P^2 / 2M + omega . L / 2, J. */
TB_API tb_status tb_scene_kinetic_energy(const tb_scene *scene, const double *y,
                                         double *out_energy);
/* Potential energy of the scene's conservative effects, J: gravity (-M g . x per body) and
 * springs (k (|d| - rest)^2 / 2), and soft joints' springs (joints.h). Other effects have
 * none. */
TB_API tb_status tb_scene_potential_energy(const tb_scene *scene, const double *y,
                                           double *out_energy);

/* What the scene's effects conserve (non-zero = conserved): total energy (only gravity and
 * undamped springs act), linear momentum (no force from outside the bodies: only springs
 * between two bodies), angular momentum about any point (the same), and angular momentum
 * about the centre of mass of all bodies (no torque about it from outside: springs between
 * two bodies and uniform gravity, whose torque sum (x_i - c) x M_i g is zero about the centre
 * of mass c). User effects are assumed to conserve nothing. Joints (joints.h) between two
 * dynamic bodies keep all four; a joint to the world or to a static or keyframed body takes
 * momentum; a keyframed support, a motor, a soft joint's damper (soft_damping_ratio > 0) or a
 * stop with restitution below 1 does work (tests/test_joints.c); an undamped soft joint's
 * spring keeps energy, its energy in tb_scene_potential_energy (tests/test_joints_soft.c). */
typedef struct tb_conserved {
    int energy;
    int linear_momentum;
    int angular_momentum;
    int angular_momentum_about_center_of_mass;
} tb_conserved;

TB_API tb_status tb_scene_conserved(const tb_scene *scene, tb_conserved *out_conserved);

/* Total linear momentum, world frame, kg m/s. */
TB_API tb_status tb_scene_linear_momentum(const tb_scene *scene, const double *y, double out_P[3]);
/* Total angular momentum about the world point `point` (m): sum (x_i - point) x P_i + L_i. */
TB_API tb_status tb_scene_angular_momentum(const tb_scene *scene, const double *y,
                                           const double point[3], double out_L[3]);

/* --- Effects (each adds to the forces F and torques tau of the bodies it names) ---------- */

/* Uniform gravitational acceleration g (m/s^2, world frame) on every body: F += M g. */
TB_API tb_status tb_scene_add_gravity(tb_scene *scene, const double g[3]);

typedef enum tb_frame {
    TB_FRAME_WORLD = 0, /* the vector is fixed in the world */
    TB_FRAME_BODY       /* the vector is fixed in the body's shape frame and turns with it */
} tb_frame;

/* Constant force (N) on body id, applied at a point fixed in the body, given in the body's
 * shape frame (m, relative to the shape origin). frame says whether the force's direction is
 * fixed in the world or turns with the body. F += f, tau += (p - x) x f. */
TB_API tb_status tb_scene_add_force(tb_scene *scene, size_t id, const double force[3],
                                    const double point[3], tb_frame frame);

/* Constant torque (N m) on body id, fixed in the world or turning with the body. */
TB_API tb_status tb_scene_add_torque(tb_scene *scene, size_t id, const double torque[3],
                                     tb_frame frame);

TB_API size_t tb_scene_effect_count(const tb_scene *scene);

/* --- Integration ------------------------------------------------------------------------- */

/* The scene as an ODE system: n = tb_scene_state_size(), derivative tb_scene_derivative, post-step
 * hook tb_scene_normalize_quaternions when renormalisation is on (with contact between bodies, a
 * scene hook that also updates the contact's friction slot map outside y: docs/effects.md). When no
 * effect couples bodies or owns states (springs between bodies, ground planes and user effects do),
 * the bodies are the system's blocks (blocks.size 13): fixed-step integrators step them a chunk at
 * a time and BDF's Krylov solver preconditions them body by body (docs/performance.md). The system
 * describes the scene as it is, and its layout_generation/acquire/release hooks keep it so: an
 * integrator made from it claims the scene (older ones stop), and refuses to step once the layout
 * changed (see tb_scene_integrator_create).
 *
 * The scene's parts of the system, in the terms of tumble/ode.h:
 * - post_step renormalises the quaternions (and, where effects or sleep need it, keeps their
 *   state outside y: friction slots, bodies without a state read at the scene's time).
 * - blocks: bodies that do not interact (size 13, lanes for the vector unit).
 * - lifetime: layout_generation claims the scene; acquire refuses a changed layout or a second
 *   stepping call; rhs_generation moves when an effect is added (a force, a spring), so CVODE
 *   restarts on the new right-hand side.
 * - events (with contact): a gap per body as roots (CVODE stops at contact onset and
 *   separation), and with sleeping a second gap per body to the nearest body of the other sleep
 *   state (n + i: body i came within 0.5 mm of it, and the island woke there; at_event wakes
 *   it); tb_integrator_events.last_root is then the body whose gap changed sign, last_direction
 *   -1 a contact onset and +1 a separation; root_signs the same exact in sign only, cheaper,
 *   for the fixed-step onset search, read only while roots is the scene's (tumble/ode.h).
 * step_limit steps long in free flight and short near a contact (docs/effects.md); next_break is a
 *   keyframed body's next key time.
 * - jacobian (with contact, bodies not separable): the contact's sparse Jacobian, its pattern
 *   the bodies' contact graph (docs/integrators.md, "BDF's sparse Jacobian").
 * - split (always): ark-imex's explicit part, the loads of the effects without a mode of their
 *   own (gravity, constant forces, user callbacks); contact, ground, springs, drag, the
 *   kinematic rows and the joints' forces are the implicit rest (docs/integrators.md, "ark-imex").
 * A scene's integrator also fills in the defaults tumble/ode.h leaves to the system: dt 0 is the
 * scene's default step, atol 0 its tolerances per component (tb_scene_absolute_tolerances), and
 * the Krylov preconditioner's automatic half-bandwidth 12 (one body's 13 x 13 block exactly). */
TB_API tb_status tb_scene_ode_system(tb_scene *scene, tb_ode_system *out_system);

/* How a separable scene's bodies are stepped by fixed-step methods (tb_scene_ode_system's
 * lanes): a lane group of bodies at a time laid out component by component, so the derivative,
 * the stages and the renormalisation run across bodies in the vector unit, on the widest path
 * the processor has, chosen at run time; or body by body. Every path gives the same bits
 * (test_vector_paths): they differ in speed only (docs/performance.md). */
typedef enum tb_vector_path {
    TB_VECTOR_PATH_AUTO = 0, /* default: the widest path supported here */
    TB_VECTOR_PATH_NONE,     /* body by body, in the 13-doubles layout */
    TB_VECTOR_PATH_BASELINE, /* lanes, compiled for the build's baseline (x86-64: SSE2) */
    TB_VECTOR_PATH_AVX2,     /* lanes, x86-64 with AVX2 */
    TB_VECTOR_PATH_AVX512,   /* lanes, x86-64 with AVX-512F */
    TB_VECTOR_PATH_COUNT
} tb_vector_path;

/* "auto", "none", "baseline", "avx2", "avx512"; NULL for an unknown path. */
TB_API const char *tb_vector_path_name(tb_vector_path path);

/* Parses a name of tb_vector_path_name (exact spelling). TB_STATUS_INVALID_ARGUMENT for an
 * unknown one, TB_STATUS_NULL_POINTER for NULL; *out_path written only on success. */
TB_API tb_status tb_vector_path_parse(const char *name, tb_vector_path *out_path);

/* Whether this build on this processor can run path (AUTO, NONE and BASELINE always can). */
TB_API bool tb_vector_path_supported(tb_vector_path path);

/* The path AUTO stands for here: the widest supported. */
TB_API tb_vector_path tb_vector_path_best(void);

/* Chooses the path for integrators made afterwards (for tests and benchmarks; the default AUTO
 * is the fastest). TB_STATUS_UNSUPPORTED (detail naming it) for a path this processor or build
 * lacks, TB_STATUS_INVALID_ARGUMENT for an unknown one; the choice is then unchanged. Scenes of
 * fewer than 8 bodies, and scenes whose bodies interact, are stepped body by body on any path. */
TB_API tb_status tb_scene_set_vector_path(tb_scene *scene, tb_vector_path path);

/* The path chosen (AUTO unless set); TB_VECTOR_PATH_COUNT for NULL. */
TB_API tb_vector_path tb_scene_vector_path(const tb_scene *scene);

/* Switches the quaternion-renormalisation hook (takes effect for systems made after). */
TB_API void tb_scene_set_renormalize(tb_scene *scene, bool renormalize);

/* Largest | |q| - 1 | the renormalisation hook has found (and removed) since the scene was
 * made or this was last reset: how far integration pushes quaternions off the unit sphere
 * between renormalisations. Under CVODE the hook runs on every output (and, for BDF, as the
 * projection after every step). */
TB_API double tb_scene_quaternion_drift(const tb_scene *scene);
TB_API void tb_scene_reset_quaternion_drift(tb_scene *scene);

/* Absolute tolerances for adaptive integration, 13 per body, from each body's own scale:
 * with l = sqrt(I_max / M) (its radius of gyration about its largest axis, m),
 *   position  scale * l                 (m)
 *   q         scale                     (dimensionless)
 *   P         scale * M * l / (1 s)     (kg m/s: the momentum of moving l per second)
 *   L         scale * I_max / (1 s)     (kg m^2/s: the spin of 1 rad/s)
 * so errors are measured against the body's own size, mass and a 1-second time scale.
 * and for effect-owned states scale times their natural size (ground friction: the presliding
 * deflection). tb_scene_integrator_create uses them with scale = rtol / 100 when the def
 * leaves atol at 0. out_atol holds tb_scene_state_size() doubles. */
TB_API tb_status tb_scene_absolute_tolerances(const tb_scene *scene, double scale,
                                              double *out_atol);

/* The rigid-body derivative (ctx is the scene): dx = P/M, dq = 1/2 (0, omega) (x) q,
 * dP = F, dL = tau. Pure; allocates nothing. Returns -1 (fatal) if ctx, y or dydt is NULL. */
TB_API int tb_scene_derivative(double t, const double *y, double *dydt, void *ctx);

/* Post-step hook: q <- q / |q| for every body. Returns 1 if some |q| is zero or not finite, -1
 * if ctx or y is NULL. */
TB_API int tb_scene_normalize_quaternions(double t, double *y, void *ctx);

/* The largest fixed step at which method keeps every mode of the scene, at its current state,
 * from growing (oscillations: |h lambda| up to tb_method_info.imaginary_limit, 2.83 for RK4;
 * Euler and midpoint amplify every oscillation, and are held to 1% a step: 0.14 and 0.53;
 * decay: real_limit, 2.785 for RK4, 2 for midpoint and Euler). The
 * rates lambda are bounded from what makes them (docs/physics.md, "Stability"): each body's
 * spin |omega|; springs from k and c with the inverse mass at their ends (rotation included,
 * bounded by the smallest moment); drag (b + 2 c |v|) / M and its angular twin over the
 * smallest moment; ground contact's bounce, rocking on the body's contact arms and friction
 * bristles. User effects are not estimated. INFINITY when nothing limits the step (and for
 * adaptive methods); out_which (may be NULL, TB_DETAIL_SIZE bytes) names the body or effect and
 * its rate. A rate that is not a number (inf, NaN) gives TB_STATUS_NOT_FINITE naming it, and
 * *out_dt is left alone. The one function front ends ask. */
TB_API tb_status tb_scene_max_stable_step(const tb_scene *scene, tb_method method, double *out_dt,
                                          char *out_which);

/* The step a fixed-step integrator made by tb_scene_integrator_create takes when its def.dt is
 * 0 (the scene file's when it gives no dt): 1/240 s where that is stable; otherwise (a stiff
 * contact or spring) the largest 1/(240 n) s, n = 2, 3, ..., within half of
 * tb_scene_max_stable_step and at most 0.5 / rate of the scene's fastest oscillation (a period
 * resolved by 12 steps: a bounce's restitution within 3 % under RK4, docs/effects.md), so that
 * frames at 60 or 240 per second fall on steps. INFINITY for adaptive methods. */
TB_API tb_status tb_scene_default_step(const tb_scene *scene, tb_method method, double *out_dt);

/* Lets fixed-step integrators made on the scene run at a step beyond tb_scene_max_stable_step
 * (default false): for showing what an unstable step does. The scene file's
 * integrator.allow_unstable sets it. */
TB_API void tb_scene_set_allow_unstable(tb_scene *scene, bool allow);
TB_API bool tb_scene_allow_unstable(const tb_scene *scene);

/* --- Sleeping ---------------------------------------------------------------------------- */

/* A body is slow while its centre and the points at its radius of gyration about its softest
 * axis (sqrt(I_max / M)) move slower than TB_SLEEP_SPEED (m/s). */
#define TB_SLEEP_SPEED 1e-4
/* How long (s) every body of an island must have been slow for the island to fall asleep. */
#define TB_SLEEP_TIME 0.5

/* Sleeping islands (default on; docs/effects.md "Sleeping"). In a scene whose bodies interact,
 * bodies linked at a step boundary (a pair the contact effect finds, a spring between them)
 * form islands; a body on a ground plane alone is its own island. An island whose bodies have
 * all been slow for TB_SLEEP_TIME falls asleep: its bodies' derivatives are 0 (their states,
 * and the friction anchors between them and on the ground, stay frozen, bit for bit) and the
 * contact effect skips the narrow phase between two of them. It wakes when a moving body comes
 * within the contact's margin of it, when tb_scene_set_state, tb_scene_set_velocity,
 * tb_scene_set_body_shape or tb_scene_set_contact_points changes one of its bodies (or a write
 * into tb_scene_states is seen at the next boundary), when a body without a state (in no island)
 * is given another shape (every island wakes), or when an effect is added. Decisions happen
 * at step boundaries: after every step of a fixed-step integrator made by
 * tb_scene_integrator_create, at every output of the others (CVODE restarts there). A scene holding
 * a user effect never sleeps. set refuses with TB_STATUS_BUSY while the scene is being stepped;
 * false wakes every body. */
TB_API tb_status tb_scene_set_sleeping(tb_scene *scene, bool sleeping);
TB_API bool tb_scene_sleeping(const tb_scene *scene);
/* How many bodies are asleep now. */
TB_API tb_status tb_scene_asleep_count(const tb_scene *scene, size_t *out_count);
/* Whether body id is asleep now. */
TB_API tb_status tb_scene_body_asleep(const tb_scene *scene, size_t id, bool *out_asleep);

/* Creates an integrator over the scene's own state array at time t0.
 * A fixed-step def with dt 0 takes tb_scene_default_step.
 * A fixed-step def whose dt exceeds tb_scene_max_stable_step is refused with
 * TB_STATUS_UNSTABLE_STEP, the detail naming the body or effect, its rate and the largest
 * stable dt, unless the scene allows unstable steps; the same check runs at the start of every
 * advance, step and reset, since spin and speed can grow (then the call returns
 * TB_STATUS_UNSTABLE_STEP and the state stays where it was). A t0 so large that doubles near it
 * are more than 1e-6 dt apart is refused (TB_STATUS_INVALID_ARGUMENT, naming t0).
 * For adaptive methods a def with atol = 0 and no atol_vector gets
 * tb_scene_absolute_tolerances(scene, rtol / 100), and a negative
 * preconditioner_half_bandwidth gets 12 (each body's 13 x 13 Jacobian block).
 * State: the integrator steps the scene's one state array, starting from it as it is (where
 * an earlier integrator left it, at the t0 given here). Every effect's start check (a body
 * deeper than 10 penetrations in a ground plane, a pair of bodies deep inside each other) runs
 * here, and again at the next advance, step or reset whenever the state was changed since the
 * integrator last left it (tb_scene_set_state, tb_scene_set_velocity, a write through
 * tb_scene_states): the call then returns that check's status (TB_STATUS_INVALID_ARGUMENT,
 * naming the bodies), changing neither the state nor the time.
 * History: what a scene keeps outside the state between steps (which contact point holds which
 * friction slot, which bodies sleep, which joints broke) is started again from the state when
 * an integrator is made or reset at a time before the last run's end (the friction slots: at
 * any time but that end): a run from a state is then the same run, bit for bit, whatever ran on
 * the scene before (a run again from the start, each row of tb_scene_accuracy_sweep). Made or
 * reset where the last run stopped, it continues that run's history.
 * Lifetimes: the integrator steps the scene only while the scene's layout is the one it was
 * made on. Adding a body, a ground plane, contact points, an effect that couples independent
 * bodies, or making another integrator on the scene (tb_scene_integrator_create or
 * tb_integrator_create on tb_scene_ode_system) makes it refuse with
 * TB_STATUS_LAYOUT_CHANGED (its detail says what changed): it never steps a moved state array,
 * and two integrators never step one scene in turns (the newer owns the state).
 * While it steps, the scene is busy: another integrator's advance (from inside a callback)
 * returns TB_STATUS_BUSY, and so do calls that would change the layout. */
TB_API tb_status tb_scene_integrator_create(tb_scene *scene, const tb_integrator_def *def,
                                            double t0, tb_integrator **out_integrator);

#ifdef __cplusplus
}
#endif

#endif
