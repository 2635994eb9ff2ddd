/* The joints' stage of the derivative and their projection after each step.
 *
 * The stage runs after the applied loads. With u each body's (v, omega) and M its mass and
 * world inertia, the loads alone give du/dt = a_free: a = F / M and alpha = I^-1 (tau -
 * omega x L) (the state holds L, so d omega/dt carries the gyroscopic term). The joint forces
 * J^T lambda make the rows' accelerations J du/dt + dJ/dt u vanish:
 *
 *     J M^-1 J^T lambda = -(J a_free + dJ/dt u)      (joint_solver.c, exact)
 *
 * and add lambda v-parts to dP, lambda w-parts to dL. A body without a state (static,
 * keyframed) has M^-1 = 0 and its known acceleration in a_free.
 *
 * That keeps C'' = 0, so C and C' drift at the integrator's error. After each step (the scene's
 * post-step hook: every fixed step, CVODE BDF's projection, every CVODE output) positions are
 * projected by Newton's method on C = 0 with the correction M^-1 J^T mu, J M^-1 J^T mu = -C
 * (the mass-weighted least change), then momenta by dP, dL = J^T mu with J M^-1 J^T mu = -J u,
 * which leaves J u = 0 exactly.
 *
 * CVODE Adams (SUNDIALS 6) has no projection: its steps use Baumgarte's terms instead,
 * -(2 b J u + b^2 C) added to the right-hand side, so that errors decay as (1 + b t) e^(-b t).
 * b = TB__JOINT_BAUMGARTE_RATE = 20/s: a drift is halved within about 80 ms (a few frames),
 * while the added modes (rate b, critically damped) are far slower than what sets Adams's
 * steps at useful tolerances (a pendulum's rtol-1e-8 steps are ~1 ms: h b ~ 0.02), so they
 * cost no steps; the outputs are projected as every method's are. */
#include "constraints/joints_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The projection's Newton iterations: at most this many, stopping when the largest |C| is
 * below the tolerance (m, or rad) or stops halving (round-off). One iteration from a step's
 * drift (1e-10 m at RK4's 1/240 s) lands near round-off; 1e-13 m keeps a second one for the
 * rare step that does not, within the 1e-12 m the tests ask. */
#define TB__PROJECTION_ITERATIONS 5
#define TB__PROJECTION_TOLERANCE 1e-13

static const tb__body world_constants = {INFINITY, 0.0, {0.0, 0.0, 0.0}};

const tb__body *tb__joint_body_constants(const tb_scene *scene, size_t body)
{
    return body == TB_WORLD ? &world_constants : tb__body_constants(scene, body);
}

void tb__joint_motion(const tb_scene *scene, double t, const double *y, size_t body,
                      bool derivative, tb__motion *out)
{
    if (body == TB_WORLD) {
        *out = (tb__motion){.q = {1.0, 0.0, 0.0, 0.0}};
    } else if (derivative) {
        *out = *tb__derivative_motion(scene, body);
    } else {
        (void)tb__body_motion_at(scene, t, y, body, out); /* a failure holds the rest pose */
    }
}

/* The acceleration and angular acceleration of a body under the applied loads in dydt. */
static void free_acceleration(const tb_scene *scene, double t, const double *y, const double *dydt,
                              size_t body, const tb__motion *m, double a[3], double alpha[3])
{
    const size_t slot = body == TB_WORLD ? TB_NO_SLOT : tb__body_slot(scene, body);
    if (body == TB_WORLD) {
        tb__v3_set(a, 0.0, 0.0, 0.0);
        tb__v3_set(alpha, 0.0, 0.0, 0.0);
        return;
    }
    if (slot == TB_NO_SLOT) {
        tb__fixed_body_acceleration_at(scene, t, body, a, alpha);
        return;
    }
    const tb__body *constants = &scene->bodies[slot];
    const double *d = dydt + TB_STATE_SIZE * slot, *L = y + TB_STATE_SIZE * slot + TB_STATE_L;
    double gyroscopic[3], torque[3], principal[3];
    tb__v3_cross(gyroscopic, m->omega, L);
    for (int k = 0; k < 3; ++k) {
        a[k] = d[TB_STATE_P + k] * constants->inv_mass;
        torque[k] = d[TB_STATE_L + k] - gyroscopic[k];
    }
    tb__q_rotate_inverse(principal, m->q, torque);
    for (int k = 0; k < 3; ++k) {
        principal[k] *= constants->inv_moments[k];
    }
    tb__q_rotate(alpha, m->q, principal);
}

/* Joint j's rows at (t, y), its motions in m: the kinematics' own in the derivative (a dynamic
 * body's, not copied), else made in store. */
static void evaluate(const tb__joints *js, const tb_scene *scene, double t, const double *y,
                     bool derivative, size_t j, const tb__motion *m[2], tb__motion store[2])
{
    const tb__joint *joint = &js->joints[j];
    const tb__body *constants[2];
    for (int s = 0; s < 2; ++s) {
        const size_t body = joint->body[s];
        if (derivative && body != TB_WORLD) {
            m[s] = tb__derivative_motion(scene, body);
        } else {
            tb__joint_motion(scene, t, y, body, derivative, &store[s]);
            m[s] = &store[s];
        }
        constants[s] = tb__joint_body_constants(scene, body);
    }
    tb__joint_rows(joint, m[0], m[1], constants, &js->evals[j]);
}

/* The right-hand side -(J a_free + dJ/dt u), with Baumgarte's terms when stabilising. */
static void stage_rhs(const tb__joints *js, const tb_scene *scene, double t, const double *y,
                      const double *dydt, size_t j)
{
    const tb__joint *joint = &js->joints[j];
    tb__joint_eval *eval = &js->evals[j];
    const tb__motion *m[2];
    tb__motion store[2];
    evaluate(js, scene, t, y, true, j, m, store);
    double a[2][3], alpha[2][3], velocity[TB__JOINT_ROWS];
    for (int s = 0; s < 2; ++s) {
        free_acceleration(scene, t, y, dydt, joint->body[s], m[s], a[s], alpha[s]);
    }
    tb__joint_row_velocities(joint, eval, m[0], m[1], velocity);
    const double b = scene->stabilise_constraints ? TB__JOINT_BAUMGARTE_RATE : 0.0;
    for (int r = 0; r < joint->rows; ++r) {
        double free = eval->bias[r];
        for (int s = 0; s < 2; ++s) {
            free += tb__v3_dot(eval->J[r].v[s], a[s]) + tb__v3_dot(eval->J[r].w[s], alpha[s]);
        }
        const bool motor =
            joint->motor_state == TB__MOTOR_ROW || joint->motor_state == TB__MOTOR_AWAY;
        eval->rate[r] = velocity[r]; /* a motor at a stop reads it (joint_motor_stops.c) */
        eval->rhs[r] = motor && r == joint->axial_row
                           ? -free + tb__joint_motor_acceleration(joint, eval, velocity[r])
                           : -free - 2.0 * b * velocity[r] - b * b * eval->C[r];
    }
}

void tb__joint_add_row_load(const tb__joints *js, const tb_scene *scene, size_t j, int r,
                            double value, double *base)
{
    const tb__joint *joint = &js->joints[j];
    const tb__joint_eval *eval = &js->evals[j];
    for (int s = 0; s < 2; ++s) {
        const size_t body = joint->body[s];
        if (tb__joint_side_moves(scene, body)) {
            double *state = base + TB_STATE_SIZE * tb__body_slot(scene, body);
            tb__v3_axpy(state + TB_STATE_P, value, eval->J[r].v[s]);
            tb__v3_axpy(state + TB_STATE_L, value, eval->J[r].w[s]);
        }
    }
}

/* Adds J^T lambda (or, for momenta, the impulse J^T mu) of joint j's solved rows into the P and
 * L of the dynamic bodies at base (dydt or y). */
static void add_row_loads(const tb__joints *js, const tb_scene *scene, size_t j, double *base,
                          bool skip_asleep)
{
    const tb__joint *joint = &js->joints[j];
    const tb__joint_eval *eval = &js->evals[j];
    for (int s = 0; s < 2; ++s) {
        const size_t body = joint->body[s];
        if (body == TB_WORLD || (skip_asleep && tb__body_asleep(scene, body))) {
            continue;
        }
        const bool fixed = tb__body_fixed(scene, body);
        if (fixed && (skip_asleep || scene->reactions == NULL)) {
            continue;
        }
        /* a body without a state: its reaction, while tb_scene_body_reaction reads it */
        double *force = fixed ? scene->reactions + 6 * body
                              : base + TB_STATE_SIZE * tb__body_slot(scene, body) + TB_STATE_P;
        double *torque = fixed ? force + 3 : force + (TB_STATE_L - TB_STATE_P);
        for (int r = 0; r < joint->solved_rows; ++r) {
            tb__v3_axpy(force, eval->lambda[r], eval->J[r].v[s]);
            tb__v3_axpy(torque, eval->lambda[r], eval->J[r].w[s]);
        }
    }
}

/* A soft joint's springs' loads (its rows after an axial row kept first) into dydt; a body
 * without a state gets its reaction, while tb_scene_body_reaction reads it. */
static void add_spring_loads(const tb__joints *js, const tb_scene *scene, size_t j, double *dydt)
{
    const tb__joint *joint = &js->joints[j];
    const tb__joint_eval *eval = &js->evals[j];
    for (int s = 0; s < 2; ++s) {
        const size_t body = joint->body[s];
        const bool fixed = body != TB_WORLD && tb__body_fixed(scene, body);
        if (body == TB_WORLD || (fixed && scene->reactions == NULL)) {
            continue;
        }
        double *force = fixed ? scene->reactions + 6 * body
                              : dydt + TB_STATE_SIZE * tb__body_slot(scene, body) + TB_STATE_P;
        double *torque = fixed ? force + 3 : force + (TB_STATE_L - TB_STATE_P);
        for (int r = tb__joint_first_spring(joint); r < joint->rows; ++r) {
            tb__v3_axpy(force, eval->lambda[r], eval->J[r].v[s]);
            tb__v3_axpy(torque, eval->lambda[r], eval->J[r].w[s]);
        }
    }
}

/* A soft joint's rows as springs with dampers (joint_soft.c). */
static void soft_loads(const tb__joints *js, const tb_scene *scene, double t, const double *y,
                       size_t j)
{
    tb__joint_eval *eval = &js->evals[j];
    const tb__motion *m[2];
    tb__motion store[2];
    evaluate(js, scene, t, y, true, j, m, store);
    tb__joint_row_velocities(&js->joints[j], eval, m[0], m[1], eval->rate);
    tb__joint_soft_lambdas(&js->joints[j], eval);
}

static int apply_joints(void *constraints, const tb_scene *scene, double t, const double *y,
                        double *dydt)
{
    tb__joints *js = constraints;
    for (size_t j = 0; j < js->count; ++j) { /* soft joints first: loads the solve sees */
        const tb__joint *joint = &js->joints[j];
        if (joint->def.soft_frequency > 0.0 && !joint->broken) {
            soft_loads(js, scene, t, y, j);
            add_spring_loads(js, scene, j, dydt);
        }
    }
    /* a motor past its cap is fixed there and the rest solved again (joint_limits.c) */
    tb__joints_configure_rows(js, true);
    do {
        for (size_t j = 0; j < js->count; ++j) {
            if (js->joints[j].solved_rows > 0) {
                stage_rhs(js, scene, t, y, dydt, j);
            }
        }
        if (tb__joint_solve(&js->solver, js->joints, js->evals) != 0) {
            return 1; /* rows that repeat one another: recoverable, a smaller step may pass */
        }
    } while (tb__joints_cap_motors(js, scene, dydt) ||
             (js->limited > 0 && tb__joints_motors_at_stops(js, scene, dydt)));
    if (js->limited > 0) {
        tb__joints_note_pushes(js);
    }
    for (size_t j = 0; j < js->count; ++j) {
        if (js->joints[j].solved_rows > 0) {
            add_row_loads(js, scene, j, dydt, false);
            memcpy(js->evals[j].last_lambda, js->evals[j].lambda, sizeof js->evals[j].lambda);
        }
    }
    js->has_last_lambda = true;
    return 0;
}

/* Every joint's rows and rates at (t, y) with rhs = -C; the largest |C|. */
static double position_rhs(const tb__joints *js, const tb_scene *scene, double t, const double *y)
{
    double worst = 0.0;
    const tb__motion *m[2];
    tb__motion store[2];
    for (size_t j = 0; j < js->count; ++j) {
        evaluate(js, scene, t, y, false, j, m, store);
        tb__joint_eval *eval = &js->evals[j];
        tb__joint_row_velocities(&js->joints[j], eval, m[0], m[1], eval->rate);
        for (int r = 0; r < js->joints[j].solved_rows; ++r) { /* soft joints: not projected */
            eval->rhs[r] = -eval->C[r];
            worst = fmax(worst, fabs(eval->C[r]));
        }
    }
    return worst;
}

/* x += M^-1 J^T mu (the W rows), q turned by M^-1 J^T mu's angular part, for the dynamic awake
 * bodies of joint j. */
static void move_bodies(const tb__joints *js, const tb_scene *scene, size_t j, double *y)
{
    const tb__joint *joint = &js->joints[j];
    const tb__joint_eval *eval = &js->evals[j];
    for (int s = 0; s < 2 && joint->solved_rows > 0; ++s) {
        const size_t body = joint->body[s];
        if (!tb__joint_side_moves(scene, body) || tb__body_asleep(scene, body)) {
            continue;
        }
        double *state = y + TB_STATE_SIZE * tb__body_slot(scene, body);
        double turn[3] = {0.0, 0.0, 0.0};
        for (int r = 0; r < joint->solved_rows; ++r) {
            tb__v3_axpy(state + TB_STATE_X, eval->lambda[r], eval->W[r].v[s]);
            tb__v3_axpy(turn, eval->lambda[r], eval->W[r].w[s]);
        }
        double *q = state + TB_STATE_Q, dq[4];
        const double half_turn[4] = {0.0, 0.5 * turn[0], 0.5 * turn[1], 0.5 * turn[2]};
        tb__q_mul(dq, half_turn, q);
        for (int k = 0; k < 4; ++k) {
            q[k] += dq[k];
        }
    }
}

static void normalise_joint_bodies(const tb__joints *js, const tb_scene *scene, double *y)
{
    for (size_t j = 0; j < js->count; ++j) {
        for (int s = 0; s < 2; ++s) {
            const size_t body = js->joints[j].body[s];
            if (tb__joint_side_moves(scene, body) && !tb__body_asleep(scene, body)) {
                double *q = y + TB_STATE_SIZE * tb__body_slot(scene, body) + TB_STATE_Q;
                const double inverse = 1.0 / tb__q_norm(q);
                for (int k = 0; k < 4; ++k) {
                    q[k] *= inverse;
                }
            }
        }
    }
}

/* Newton's iterations; *current tells whether the evals hold the rows at the final y. */
static int project_positions(tb__joints *js, const tb_scene *scene, double t, double *y,
                             bool *current)
{
    double last = INFINITY;
    *current = false;
    for (int iteration = 0; iteration < TB__PROJECTION_ITERATIONS; ++iteration) {
        const double worst = position_rhs(js, scene, t, y);
        *current = true;
        if (!isfinite(worst)) {
            return 1;
        }
        if (worst <= TB__PROJECTION_TOLERANCE || worst > 0.5 * last) {
            break;
        }
        last = worst;
        if (tb__joint_solve(&js->solver, js->joints, js->evals) != 0) {
            return 1;
        }
        for (size_t j = 0; j < js->count; ++j) {
            move_bodies(js, scene, j, y);
        }
        normalise_joint_bodies(js, scene, y);
        *current = false;
    }
    return 0;
}

/* J u = 0 with the rows at the projected positions (those of the last iteration when it
 * evaluated them there). */
static int project_momenta(tb__joints *js, const tb_scene *scene, double t, double *y, bool current)
{
    if (!current) {
        position_rhs(js, scene, t, y);
    }
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        for (int r = 0; r < joint->solved_rows; ++r) { /* an impact sets its stop's rate */
            const bool impact = joint->impact && r == joint->axial_row;
            js->evals[j].rhs[r] = (impact ? joint->impact_rate : 0.0) - js->evals[j].rate[r];
        }
    }
    if (tb__joint_solve(&js->solver, js->joints, js->evals) != 0) {
        return 1;
    }
    for (size_t j = 0; j < js->count; ++j) {
        if (js->joints[j].solved_rows > 0) {
            add_row_loads(js, scene, j, y, true);
        }
    }
    return 0;
}

int tb__joints_project(tb__joints *js, const tb_scene *scene, double t, double *y)
{
    bool current = false;
    tb__joints_undo_later_switches(js, t);
    tb__joints_configure_rows(js, false);
    int rc = project_positions(js, scene, t, y, &current);
    rc = rc != 0 ? rc : project_momenta(js, scene, t, y, current);
    tb__joints_after_impacts(js);
    return rc;
}

static int project_joints(void *constraints, const tb_scene *scene, double t, double *y)
{
    /* an adaptive method's projections run on trial steps too: its stops switch at events
     * (tb__joints_at_event), its joints break at outputs */
    const bool fixed = !tb_method_is_adaptive(scene->guard_method);
    int rc = fixed ? tb__joints_step_limits(constraints, scene, t, y) : 0;
    rc = rc != 0 ? rc : tb__joints_project(constraints, scene, t, y);
    return rc != 0 || !fixed ? rc : tb__joints_check_breaking(constraints, scene, t, y);
}

static void link_joints(const void *constraints, const tb_scene *scene)
{
    const tb__joints *js = constraints;
    for (size_t j = 0; j < js->count; ++j) {
        if (js->joints[j].body[1] != TB_WORLD && !js->joints[j].broken) {
            tb__scene_sleep_link(scene, js->joints[j].body[0], js->joints[j].body[1]);
        }
    }
}

static void destroy_joints(void *constraints)
{
    tb__joints *js = constraints;
    if (js != NULL) {
        tb__joint_solver_free(&js->solver);
        free(js->scratch);
        free(js->joints);
        free(js->evals);
        free(js);
    }
}

static int joints_at_output(void *constraints, const tb_scene *scene, double t, double *y)
{
    const int rc = tb__joints_release_at_output(constraints, scene, t, y);
    return rc != 0 ? rc : tb__joints_check_breaking(constraints, scene, t, y);
}

const tb__constraint_ops tb__joint_ops = {
    .apply = apply_joints,
    .project = project_joints,
    .link_islands = link_joints,
    .destroy = destroy_joints,
    .at_output = joints_at_output,
    .rate = tb__joints_rate,
    .root_count = tb__joints_root_count,
    .roots = tb__joints_roots,
    .at_event = tb__joints_at_event,
    .conserved = tb__joints_conserved,
    .potential_energy = tb__joints_potential_energy,
    .restart = tb__joints_restart, /* joint_breaking.c */
};
