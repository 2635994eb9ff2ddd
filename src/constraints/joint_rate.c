/* The jointed bodies' fastest modes, for the stability guard (tb__constraint_ops.rate). The
 * exact solve adds no stiffness of its own (its rows' accelerations are held at zero, C'' = 0),
 * but the joints' forces do: a body pulled at an anchor by a force F at arm r from its centre
 * of mass resists a turn dtheta with the torque change (dtheta x r) x F, a stiffness
 * K = (F . r) 1 - r F^T, |F| |r| across r when F pulls along it (a link of a chain under the
 * tension of a heavy weight: the string's transverse sway). Each body's modes are bounded
 * alone, its neighbours held: omega^2 <= sum over its joints of |F| |r| lambda_max(P I^-1 P),
 * P the projection across r (the eigenvalue of a sum is at most the sum of the eigenvalues),
 * and the same with |tau| across tau for a joint's reaction torque. On a uniform chain that is
 * its alternating mode, sqrt(12 T / (m l)); with the neighbours' inertia the true highest mode
 * lies below it (the heavy chain's: 669 rad/s against 767, tests/test_joints_guard.c). The
 * forces are the reactions of the last derivative's solve (at most a step old: the guard runs
 * before every step, and a derivative there would cost a fifth of a chain's step), or of one
 * derivative at the state before the first. The arm's direction is read in the body's frame,
 * where the anchor is fixed, and a ball joint's reaction torque about its anchor, which is
 * round-off, is left out. Soft joints add their springs:
 * w = 2 pi frequency and damping ratio zeta per row; motors their servo, a real decay at
 * TB__JOINT_MOTOR_RATE (20/s: an explicit step beyond real_limit / 20, 0.139 s for RK4, 0.1 s
 * for Euler and midpoint, makes the servo itself unstable). Baumgarte's rate (20/s) acts only under
 * CVODE Adams, which the guard does not limit (error control chooses its steps). */
#include "constraints/joints_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <string.h>

/* The largest eigenvalue (1/(kg m^2)) of the inverse inertia across the unit vector w of the
 * body's principal frame: of I^-1 restricted to the plane perpendicular to w. */
static double inverse_inertia_across_body(const tb__body *body, const double w[3])
{
    double e1[3], e2[3];
    int k = 0; /* the principal axis least along u, crossed with u: a vector across it */
    for (int i = 1; i < 3; ++i) {
        k = fabs(w[i]) < fabs(w[k]) ? i : k;
    }
    const double axis[3] = {k == 0 ? 1.0 : 0.0, k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0};
    tb__v3_cross(e1, w, axis);
    const double length = tb__v3_norm(e1);
    for (int i = 0; i < 3; ++i) {
        e1[i] /= length;
    }
    tb__v3_cross(e2, w, e1);
    const double *d = body->inv_moments;
    double a11 = 0.0, a22 = 0.0, a12 = 0.0;
    for (int i = 0; i < 3; ++i) {
        a11 += d[i] * e1[i] * e1[i];
        a22 += d[i] * e2[i] * e2[i];
        a12 += d[i] * e1[i] * e2[i];
    }
    const double half = 0.5 * (a11 - a22);
    return 0.5 * (a11 + a22) + sqrt(half * half + a12 * a12);
}

/* The same across the unit world vector u, the body turned by q. */
static double inverse_inertia_across(const tb__body *body, const double q[4], const double u[3])
{
    double w[3];
    tb__q_rotate_inverse(w, q, u);
    return inverse_inertia_across_body(body, w);
}

/* |F| |r| lambda_max(P I^-1 P) + |tau| lambda_max(P_tau I^-1 P_tau) for one side of a joint
 * (1/s^2), F and tau its reaction on that side. */
static double side_stiffness(const tb_scene *scene, const tb__joint *joint, int side,
                             const double force[3], const double torque[3])
{
    const size_t body = joint->body[side];
    if (!tb__joint_side_moves(scene, body)) {
        return 0.0;
    }
    const tb__body *constants = tb__body_constants(scene, body);
    /* the arm r is the anchor, fixed in the body: its direction read there, not turned out to
     * the world and back */
    const double *arm = joint->anchor[side];
    double u[3], sum = 0.0;
    const double arm_length = tb__v3_norm(arm), f = tb__v3_norm(force);
    if (arm_length > 0.0 && f > 0.0) {
        for (int i = 0; i < 3; ++i) {
            u[i] = arm[i] / arm_length;
        }
        sum += f * arm_length * inverse_inertia_across_body(constants, u);
    }
    /* a ball joint puts no torque about its anchor: its reaction's is round-off, 1e-16 N m */
    const double t = joint->def.type == TB_JOINT_BALL ? 0.0 : tb__v3_norm(torque);
    if (t > 0.0) {
        for (int i = 0; i < 3; ++i) {
            u[i] = torque[i] / t;
        }
        sum += t * inverse_inertia_across(constants, tb__derivative_motion(scene, body)->q, u);
    }
    return sum;
}

/* Each dynamic body's omega^2 summed over its joints into acc (13 doubles per slot: the first
 * of its slot's). */
static void sum_stiffness(const tb__joints *js, const tb_scene *scene, double *acc)
{
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        if (joint->solved_rows == 0 || joint->def.soft_frequency > 0.0) { /* springs below */
            continue;
        }
        double force[2][3], torque[2][3];
        tb__joint_reaction(scene, js, j, force[0], torque[0]);
        for (int i = 0; i < 3; ++i) {
            force[1][i] = -force[0][i];
            torque[1][i] = -torque[0][i];
        }
        for (int s = 0; s < 2; ++s) {
            const double k = side_stiffness(scene, joint, s, force[s], torque[s]);
            if (k > 0.0) {
                acc[TB_STATE_SIZE * tb__body_slot(scene, joint->body[s])] += k;
            }
        }
    }
}

/* The fastest body's rate into out, from the reactions of the evals' lambda (scratch: its room
 * sums the bodies, the derivative in it read out). */
static void sum_stiffness_into(tb__joints *js, const tb_scene *scene, size_t n,
                               tb__effect_rate *out)
{
    for (size_t k = 0; k < n; ++k) {
        js->scratch[k] = 0.0;
    }
    sum_stiffness(js, scene, js->scratch);
    for (size_t slot = 0; slot < scene->slot_count; ++slot) {
        const double rate = sqrt(js->scratch[TB_STATE_SIZE * slot]);
        if (rate > out->oscillation || isnan(rate)) {
            out->oscillation = rate;
            out->oscillation_body = scene->slot_ids[slot];
        }
    }
}

int tb__joints_rate(void *constraints, const tb_scene *scene, const double *y, tb__effect_rate *out)
{
    tb__joints *js = constraints;
    *out = (tb__effect_rate){0.0, 0, 0.0, 0, 0.0};
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        if (joint->def.soft_frequency > 0.0 && !joint->broken) {
            tb__effect_rate_add_damped_mode(
                out, 2.0 * 3.14159265358979323846 * joint->def.soft_frequency,
                joint->def.soft_damping_ratio, joint->def.body_a);
        }
        if (joint->def.motor != TB_MOTOR_OFF && !joint->broken) {
            /* a motor's servo: d(error)/dt = -K error (velocity), or a double root at -K
             * (position, critically damped): a real decay at K either way, even while capped */
            const size_t body =
                tb__joint_side_moves(scene, joint->body[0]) ? joint->body[0] : joint->body[1];
            tb__effect_rate_add_decay(out, TB__JOINT_MOTOR_RATE, body);
        }
    }
    const size_t n = tb_scene_state_size(scene);
    if (!tb__joints_reserve_scratch(js, n)) {
        return -1;
    }
    if (js->has_last_lambda) { /* the rows are the projection's, at y: the last solve's lambda */
        for (size_t j = 0; j < js->count; ++j) {
            memcpy(js->evals[j].lambda, js->evals[j].last_lambda, sizeof js->evals[j].lambda);
        }
        sum_stiffness_into(js, scene, n, out);
        return 0;
    }
    /* busy while it runs, as in a step: a user effect's call that would change the scene is
     * refused there too */
    tb_scene *held = (tb_scene *)scene;
    const bool busy = held->busy;
    held->busy = true;
    const int rc = tb_scene_derivative(scene->time, y, js->scratch, held);
    held->busy = busy;
    if (rc != 0) {
        return rc;
    }
    sum_stiffness_into(js, scene, n, out);
    return 0;
}
