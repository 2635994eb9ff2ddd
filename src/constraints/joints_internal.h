/* Private: the joints the scene holds through its constraint row (scene_internal.h's
 * tb__constraint_ops): each joint's frames in its bodies, its rows of the constraint Jacobian
 * (joint_rows.c), the block-sparse solve of J M^-1 J^T lambda = b (joint_solver.c), the stage
 * and projection (joint_stage.c) and the public calls (joints.c). */
#ifndef TUMBLE_JOINTS_INTERNAL_H
#define TUMBLE_JOINTS_INTERNAL_H

#include "tumble/joints.h"

#include "scene/scene_internal.h"

/* A joint has at most 6 rows (fixed); its blocks of J M^-1 J^T are stored 6 x 6, row-major. */
#define TB__JOINT_ROWS 6
#define TB__BLOCK (TB__JOINT_ROWS * TB__JOINT_ROWS)

/* One row of J: its coefficients on each body's velocity v (m/s) and angular velocity omega
 * (rad/s, world); side 0 is body_a, side 1 body_b. The row's force on a body is lambda v-part
 * (N) and its torque about the centre of mass lambda w-part (N m). */
typedef struct tb__joint_row {
    double v[2][3];
    double w[2][3];
} tb__joint_row;

/* A joint as made: its def and its frames in each body's principal frame (the world's frame
 * for TB_WORLD). */
typedef struct tb__joint {
    tb_joint_def def;
    size_t body[2];        /* body_a, body_b (TB_WORLD) */
    int rows;              /* 3, 5, 5, 6 */
    int solved_rows;       /* rows in the exact solve: rows, or 0 for a soft joint */
    double anchor[2][3];   /* the anchor from each centre of mass, m */
    double axis_a[3];      /* the axis, unit, in a's frame */
    double across_a[2][3]; /* two unit vectors across the axis, in a's frame (slider rows) */
    double across_b[2][3]; /* the same, in b's frame (hinge rows) */
    double relative[4];    /* q_b^* q_a when made: the held relative rotation (slider, fixed) */
    double soft_mass[TB__JOINT_ROWS]; /* a soft joint's spring masses per row, kg or kg m^2
                                         (joint_soft.c) */
    bool broken;        /* its reaction passed break_force or break_torque: rows dropped */
    double broken_time; /* s: the step boundary where it broke */
    /* Limits and motors (joint_limits.c): the axial row (row base_rows, the hinge's angle or
     * the slider's travel) in the solve while a stop holds the joint or a motor drives it. */
    int base_rows;      /* the type's rows (tb__joint_row_count) */
    int axial_row;      /* the axial row's index: base_rows, or 0 where axial_first */
    bool axial_first;   /* a soft joint with limits or a motor: its axial row first (an exact
                           row, in the solve while a stop holds or its motor drives), its springs
                           after it (rows 1 .. base_rows); always base_rows + 1 rows */
    int stop;           /* TB__STOP_NONE, or the stop that holds the joint (lower, upper) */
    double axial_zero;  /* the axial row's C is its coordinate minus this (the stop's bound) */
    double impact_rate; /* the axial rate the next momenta projection sets (an impact), */
    double impact_back; /* and how far from the bound the position projection puts it, */
    bool impact;        /* while impact is true */
    bool leaving;       /* an event's impact that leaves the joint free, its rate unchanged */
    int motor_state;    /* TB__MOTOR_ROW (in the solve), TB__MOTOR_CAPPED, ... or none */
    double motor_load;  /* TB__MOTOR_LOAD: the capped motor's lambda on the axial row */
    double stop_push;   /* the held stop's push at the last derivative (N or N m, > 0 while it
                           pushes; with a motor, what it would push with the motor as it acts) */
    double held_push;   /* a motor at a stop: the push the stop needs without the motor */
    /* An adaptive method's event switched the stop at switched_at from stop_before: an output
     * interpolated before that time (the event was past it) undoes the switch. */
    bool switched;
    int stop_before;
    double switched_at;
    /* Padding to 576 bytes, 9 x 64: the solve's loops index joints[] by a run-time index, and
     * at 544 bytes each index cost three instructions (bench_joints: 1% of a chain's step);
     * shorten it when adding a field (the assertion below keeps the size a multiple of 64). */
    double pad_[3];
} tb__joint;
_Static_assert(sizeof(tb__joint) % 64 == 0, "tb__joint: adjust pad_ to a multiple of 64 bytes");

/* joint.stop */
#define TB__STOP_NONE 0
#define TB__STOP_LOWER 1
#define TB__STOP_UPPER 2
/* joint.motor_state */
#define TB__MOTOR_NONE 0
#define TB__MOTOR_ROW 1
#define TB__MOTOR_CAPPED 2
/* A motor on a joint its stop holds (joint_limits.c, Motors at a stop): first not in the solve
 * (AT_STOP, the stop's row solved alone), then driving into the stop (LOAD: fixed at its cap
 * beside the stop's row, eval.motor_load) or away from it (AWAY: the motor's row instead of the
 * stop's, capped like a free motor's). */
#define TB__MOTOR_AT_STOP 3
#define TB__MOTOR_LOAD 4
#define TB__MOTOR_AWAY 5

/* The rate (1/s) at which a motor drives its error out: a velocity motor's axial
 * acceleration is TB__JOINT_MOTOR_RATE (speed - rate) (a first-order approach, time constant
 * 50 ms), a position motor's TB__JOINT_MOTOR_RATE^2 (target - coordinate) - 2
 * TB__JOINT_MOTOR_RATE rate (critically damped); the stability guard sees it as a decay at this
 * rate, the same as the Baumgarte rate. */
#define TB__JOINT_MOTOR_RATE 20.0

/* One evaluation's scratch per joint: its rows at y, M^-1 J^T (the same shape), the part of
 * the rows' acceleration that the velocities give (dJ/dt u), the position error C, the
 * rows' rates J u where the projection reads them, the right-hand side and lambda of the
 * solve. */
typedef struct tb__joint_eval {
    tb__joint_row J[TB__JOINT_ROWS];
    tb__joint_row W[TB__JOINT_ROWS];
    double bias[TB__JOINT_ROWS];
    double C[TB__JOINT_ROWS];
    double rate[TB__JOINT_ROWS]; /* J u (the projection's) */
    double rhs[TB__JOINT_ROWS];
    double lambda[TB__JOINT_ROWS];
    double last_lambda[TB__JOINT_ROWS]; /* the last derivative's lambda (joint_rate.c reads it) */
} tb__joint_eval;

/* A contribution J_i,side_i M^-1 J_k,side_k^T of one shared body to the block (i, k) of
 * J M^-1 J^T, i after k in the elimination order (i == k: the diagonal block). */
typedef struct tb__joint_coupling {
    size_t row_joint, column_joint;
    int row_side, column_side;
    size_t block; /* index into the solver's blocks */
} tb__joint_coupling;

/* L(target) -= L(first) L(second)^T: one update of the right-looking block Cholesky. */
typedef struct tb__block_update {
    size_t first, second, target;
    size_t first_joint, second_joint; /* the row joints of first and second */
} tb__block_update;

/* The block-sparse Cholesky factor's pattern, made when a joint is added (joint_solver.c): the
 * elimination order (minimum degree: the leaves of a tree first, so a chain or tree makes no
 * fill), each column's blocks below the diagonal and the updates they make. Joint j's diagonal
 * block is blocks[j]; off-diagonal ones follow. */
typedef struct tb__joint_solver {
    size_t count;
    size_t *order;        /* position -> joint */
    size_t *column_start; /* count + 1, by position: the column's blocks in below */
    size_t *below;        /* off-diagonal block indices, by column */
    size_t *below_joint;  /* the row joint of each */
    size_t *update_start; /* count + 1, by position */
    tb__block_update *updates;
    tb__joint_coupling *couplings;
    size_t coupling_count;
    double *blocks; /* TB__BLOCK per block */
    size_t block_count;
    double *scale; /* TB__JOINT_ROWS per joint: each row's diagonal of J M^-1 J^T as assembled */
} tb__joint_solver;

/* The scene's joints (scene->constraints). */
typedef struct tb__joints {
    tb__joint *joints;
    size_t count;
    tb__joint_eval *evals; /* count */
    tb__joint_solver solver;
    size_t breakable; /* joints with a finite break_force or break_torque */
    size_t limited;   /* joints with limits (the only ones a stop holds) */
    double *scratch;  /* a derivative's worth (scratch_size doubles) for the breaking check */
    size_t scratch_size;
    bool has_last_lambda; /* a derivative has solved since the joints were made */
} tb__joints;

/* Joint j's force on body_a (N) and torque about its anchor (N m), world, from the last solve's
 * lambda and the derivative's motions (joint_breaking.c). */
void tb__joint_reaction(const tb_scene *scene, const tb__joints *js, size_t j, double force[3],
                        double torque[3]);
/* At a step boundary (the post-step hook, after the projection): the reactions at (t, y), and
 * the breakable joints whose reaction passed a limit break there (their rows leave the solve
 * for the rest of the run; the scene's right-hand side changes, so CVODE restarts). 0, or the
 * derivative's failure. */
int tb__joints_check_breaking(tb__joints *js, const tb_scene *scene, double t, double *y);
/* tb__constraint_ops.restart: a joint broken after t (by a run that went past t) is whole
 * again, its rows back in the solve; one broken at or before t stays broken. */
void tb__joints_restart(void *constraints, const tb_scene *scene, double t);

/* Room for a derivative of the scene's state in js->scratch: made once per layout (the first
 * boundary after a body or an effect's states were added), never per step; false when out of
 * memory (joint_breaking.c). */
bool tb__joints_reserve_scratch(tb__joints *js, size_t n);
/* The jointed bodies' fastest modes at y and the scene's time, for the stability guard
 * (tb__constraint_ops.rate, joint_rate.c): one derivative for the reactions. */
int tb__joints_rate(void *constraints, const tb_scene *scene, const double *y,
                    tb__effect_rate *out);

/* The Baumgarte rate (1/s) under CVODE Adams (joint_stage.c explains it). */
#define TB__JOINT_BAUMGARTE_RATE 20.0

/* The joint's rows, M^-1 J^T, bias and position error at the motions of its bodies (ma, mb);
 * inverse[s] the body constants of side s (zero inverse mass and inertia for a body that
 * cannot move). */
void tb__joint_rows(const tb__joint *joint, const tb__motion *ma, const tb__motion *mb,
                    const tb__body *const inverse[2], tb__joint_eval *eval);
/* J u: each row's velocity at the motions. */
void tb__joint_row_velocities(const tb__joint *joint, const tb__joint_eval *eval,
                              const tb__motion *ma, const tb__motion *mb, double out[]);
/* The frames of a joint made from def at the motions of its bodies. */
void tb__joint_frames(tb__joint *joint, const tb__motion *ma, const tb__motion *mb);
/* Rows per type. */
int tb__joint_row_count(tb_joint_type type);
/* The axial coordinate of a hinge (the angle of a about the axis relative to b from the start,
 * rad, in (-pi, pi]) or a slider (the travel of a's anchor from b's along the axis, m). */
double tb__joint_axial_coordinate(const tb__joint *joint, const tb__motion *ma,
                                  const tb__motion *mb);

/* Limits and motors (joint_limits.c). The rows each joint has in the solve: its type's, plus
 * the axial row while a stop holds it, or (in the derivative, with_motors) while its motor
 * drives it uncapped. */
void tb__joints_configure_rows(tb__joints *js, bool with_motors);
/* The axial acceleration the motor of joint asks for at its rows' state (1/s^2 or m/s^2). */
double tb__joint_motor_acceleration(const tb__joint *joint, const tb__joint_eval *eval,
                                    double rate);
/* The derivative's motor caps: after a solve, each motor row whose |lambda| exceeds
 * motor_max_force is fixed at the cap (its load written into dydt) and left out; true when one
 * was, so that the stage solves again without it. */
bool tb__joints_cap_motors(tb__joints *js, const tb_scene *scene, double *dydt);
/* The derivative's motors on joints their stops hold, after a solve: each decides whether it
 * drives into its stop (fixed at its cap as a load, the stop's row kept) or away from it (its
 * row instead of the stop's, capped; the stop's row back if the capped motor cannot lift the
 * joint off). True when one changed, so that the stage solves again. */
bool tb__joints_motors_at_stops(tb__joints *js, const tb_scene *scene, double *dydt);
/* After the derivative's last solve: each held stop's push (joint.stop_push). */
void tb__joints_note_pushes(tb__joints *js);
/* An adaptive method's boundary: a held stop whose motor pulls the joint off it is released
 * (a motor set between advances); true when one was. 0 or the derivative's failure. */
int tb__joints_release_at_output(tb__joints *js, const tb_scene *scene, double t, double *y);
/* Step boundaries of fixed-step methods (the post-step hook, before the projection): a joint
 * past a stop engages it (an impact), a held one whose stop would pull is released. 0, or the
 * derivative's failure. */
int tb__joints_step_limits(tb__joints *js, const tb_scene *scene, double t, double *y);
/* Before a projection at t: the stops switched at an event after t (an output interpolated
 * before the event) are put back as they were; the event is found again. */
void tb__joints_undo_later_switches(tb__joints *js, double t);
/* After the momenta projection: a stop whose impact left the joint separating faster than
 * resting contact lets it go. */
void tb__joints_after_impacts(tb__joints *js);
/* The derivative at (t, y) into the joints' scratch, for the held stops' pushes; 0 or its
 * failure. */
int tb__joints_held_lambdas(tb__joints *js, const tb_scene *scene, double t, const double *y);
/* +1 at a lower stop (its push raises the coordinate), -1 at an upper one. */
static inline double tb__stop_sign(int stop)
{
    return stop == TB__STOP_UPPER ? -1.0 : 1.0;
}
/* Every row of the joint in the solve, as the joint is made (tb__joint_frames): none of a soft
 * joint's, whose springs act outside the solve. */
static inline void tb__joint_solve_rows_as_made(tb__joint *joint)
{
    joint->solved_rows = joint->def.soft_frequency > 0.0 ? 0 : joint->rows;
}
/* The axial row leaves the solve (a capped motor): rows = solved_rows = base_rows, or, where
 * axial_first, no row solved (the layout kept). */
static inline void tb__joint_drop_axial_row(tb__joint *joint)
{
    if (joint->axial_first) {
        joint->solved_rows = 0;
    } else {
        joint->rows = joint->solved_rows = joint->base_rows;
    }
}
/* Root functions under adaptive methods: one per joint with limits (the gap to the nearer
 * stop while free, the stop's push while held). */
size_t tb__joints_root_count(const void *constraints);
int tb__joints_roots(void *constraints, const tb_scene *scene, double t, const double *y,
                     double *g);
/* An adaptive method's event: the stops engage or release at (t, y), y receiving the impact;
 * the right-hand side's generation moves when one did. */
int tb__joints_at_event(void *constraints, const tb_scene *scene, double t, double *y);
/* Adds value times row r of joint j into dP, dL of its dynamic bodies at base. */
void tb__joint_add_row_load(const tb__joints *js, const tb_scene *scene, size_t j, int r,
                            double value, double *base);

/* The solver's pattern for the joints (replacing out's on success, out untouched on failure);
 * TB_STATUS_OUT_OF_MEMORY. */
tb_status tb__joint_solver_build(const tb_scene *scene, const tb__joint *joints, size_t count,
                                 tb__joint_solver *out);
void tb__joint_solver_free(tb__joint_solver *solver);
/* Assembles J M^-1 J^T from the evals, factors it and solves for every eval's lambda from its
 * rhs. A row that repeats others (its pivot at round-off of its diagonal: a door's second
 * hinge, a planar loop's out-of-plane rows) is dropped, its lambda 0, the others carrying its
 * load. 0, or 1 when a pivot is not a number (a non-finite state). */
int tb__joint_solve(tb__joint_solver *solver, const tb__joint *joints, tb__joint_eval *evals);

/* The motion of side s of a joint at (t, y): the accessor's, the world's at rest for
 * TB_WORLD; in the derivative the kinematics' (derivative = true). */
void tb__joint_motion(const tb_scene *scene, double t, const double *y, size_t body,
                      bool derivative, tb__motion *out);
/* The body constants of body (world: infinitely heavy). */
const tb__body *tb__joint_body_constants(const tb_scene *scene, size_t body);

/* Projects y at t onto the joints' rows: positions (Newton's method, a few iterations), then
 * momenta (J u = 0), as after each step, without the breaking check. 0, or 1 when the solve
 * fails or an error is not finite (joint_stage.c). */
int tb__joints_project(tb__joints *js, const tb_scene *scene, double t, double *y);

/* tb__constraint_ops.conserved (joint_projection.c): an ideal joint between two dynamic bodies
 * keeps momentum and energy; one to the world or a body without a state takes momentum; a
 * keyframed support, a motor, a soft joint or a stop with restitution below 1 does work. */
void tb__joints_conserved(const void *constraints, const tb_scene *scene, tb_conserved *c);

/* Whether a joint may have rows in the exact solve (the solver's pattern holds it). */
static inline bool tb__joint_in_pattern(const tb__joint *joint)
{
    return joint->solved_rows > 0 || joint->axial_first;
}

/* The first spring row of a soft joint (after an axial row kept first). */
static inline int tb__joint_first_spring(const tb__joint *joint)
{
    return joint->axial_first ? 1 : 0;
}

/* Whether a joint's side moves under the joint's loads: a dynamic body, not the world nor a
 * body without a state (static, keyframed). */
static inline bool tb__joint_side_moves(const tb_scene *scene, size_t body)
{
    return body != TB_WORLD && !tb__body_fixed(scene, body);
}

/* Soft joints (joint_soft.c): the constant spring masses of a soft joint's rows, from its rows at
 * the scene's states (when made); its rows' lambdas from eval's C and rate; the springs'
 * potential energy at y (J; tb__constraint_ops.potential_energy). */
void tb__joint_soft_masses(tb__joint *joint, const tb_scene *scene);
void tb__joint_soft_lambdas(const tb__joint *joint, tb__joint_eval *eval);
double tb__joints_potential_energy(const void *constraints, const tb_scene *scene, const double *y);

/* The ops row the scene holds the joints by (joint_stage.c). */
extern const tb__constraint_ops tb__joint_ops;

#endif
