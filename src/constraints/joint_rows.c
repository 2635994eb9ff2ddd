/* The rows of each joint type: for a row, C (its position error), J (C's rate is J u, with u
 * each body's velocity and angular velocity, world) and dJ/dt u (the part of C's second
 * derivative that the velocities give, so that d^2C/dt^2 = J du/dt + dJ/dt u). With p = x + r
 * an anchor point (r = R r_body), n the axis in body a, t vectors across it:
 *
 *   ball (3):       C = p_a - p_b;               dJ/dt u = w_a x (w_a x r_a) - w_b x (w_b x r_b)
 *   axis (2):       C = n_a . t_b (the sine of the tilt); J: (w_a - w_b) . (n_a x t_b)
 *   rotation (3):   C = 2 vec(q_a q0^* q_b^*) (the relative rotation's angle, small); J: w_a - w_b
 *   travel (2):     C = (p_a - p_b) . t_a; J: v_a + w_a x (p_b - x_a) - v_b - w_b x r_b along t_a
 *
 * hinge = ball + axis, slider = rotation + travel, fixed = ball + rotation. */
#include "constraints/joints_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <string.h>

int tb__joint_row_count(tb_joint_type type)
{
    static const int rows[TB_JOINT_TYPE_COUNT] = {
        [TB_JOINT_BALL] = 3, [TB_JOINT_HINGE] = 5, [TB_JOINT_SLIDER] = 5, [TB_JOINT_FIXED] = 6};
    return rows[type];
}

/* Where a joint's rows are evaluated: both bodies' motions, arms, points. */
typedef struct frame {
    const tb__motion *m[2];
    double r[2][3]; /* anchor arms, world */
    double p[2][3]; /* anchor points, world */
} frame;

/* w x (w x a) */
static void centripetal(const double w[3], const double a[3], double out[3])
{
    double wa[3];
    tb__v3_cross(wa, w, a);
    tb__v3_cross(out, w, wa);
}

static void ball_rows(const frame *f, tb__joint_row *J, double *bias, double *C)
{
    double ca[3], cb[3];
    centripetal(f->m[0]->omega, f->r[0], ca);
    centripetal(f->m[1]->omega, f->r[1], cb);
    for (int k = 0; k < 3; ++k) {
        double e[3] = {0.0, 0.0, 0.0};
        e[k] = 1.0;
        tb__v3_copy(J[k].v[0], e);
        tb__v3_cross(J[k].w[0], f->r[0], e);
        tb__v3_set(J[k].v[1], -e[0], -e[1], -e[2]);
        tb__v3_cross(J[k].w[1], e, f->r[1]);
        bias[k] = ca[k] - cb[k];
        C[k] = f->p[0][k] - f->p[1][k];
    }
}

static void axis_rows(const tb__joint *joint, const frame *f, tb__joint_row *J, double *bias,
                      double *C)
{
    const double *wa = f->m[0]->omega, *wb = f->m[1]->omega;
    double n[3], dn[3], relative[3];
    tb__q_rotate(n, f->m[0]->q, joint->axis_a);
    tb__v3_cross(dn, wa, n);
    tb__v3_set(relative, wa[0] - wb[0], wa[1] - wb[1], wa[2] - wb[2]);
    for (int k = 0; k < 2; ++k) {
        double t[3], dt[3], w[3], a[3], b[3];
        tb__q_rotate(t, f->m[1]->q, joint->across_b[k]);
        tb__v3_cross(dt, wb, t);
        tb__v3_cross(w, n, t);
        memset(&J[k], 0, sizeof J[k]);
        tb__v3_copy(J[k].w[0], w);
        tb__v3_set(J[k].w[1], -w[0], -w[1], -w[2]);
        tb__v3_cross(a, dn, t); /* d(n x t)/dt = dn x t + n x dt */
        tb__v3_cross(b, n, dt);
        tb__v3_axpy(a, 1.0, b);
        bias[k] = tb__v3_dot(relative, a);
        C[k] = tb__v3_dot(n, t);
    }
}

static void rotation_rows(const tb__joint *joint, const frame *f, tb__joint_row *J, double *bias,
                          double *C)
{
    double held[4], error[4], conj_b[4];
    const double *qb = f->m[1]->q, *q0 = joint->relative;
    const double conj_q0[4] = {q0[0], -q0[1], -q0[2], -q0[3]};
    tb__v3_set(conj_b + 1, -qb[1], -qb[2], -qb[3]);
    conj_b[0] = qb[0];
    tb__q_mul(held, f->m[0]->q, conj_q0);
    tb__q_mul(error, held, conj_b);
    const double sign = error[0] < 0.0 ? -2.0 : 2.0;
    for (int k = 0; k < 3; ++k) {
        memset(&J[k], 0, sizeof J[k]);
        J[k].w[0][k] = 1.0;
        J[k].w[1][k] = -1.0;
        bias[k] = 0.0;
        C[k] = sign * error[1 + k];
    }
}

/* The travel row along dir, a unit vector fixed in body a given in a's frame. */
static void travel_row(const frame *f, const double dir_a[3], tb__joint_row *J, double *bias,
                       double *C)
{
    const tb__motion *ma = f->m[0], *mb = f->m[1];
    double d[3], pa_dot[3], pb_dot[3], d_dot[3], arm[3], ca[3], cb[3], c[3];
    tb__v3_set(d, f->p[0][0] - f->p[1][0], f->p[0][1] - f->p[1][1], f->p[0][2] - f->p[1][2]);
    tb__point_velocity(ma, f->r[0], pa_dot);
    tb__point_velocity(mb, f->r[1], pb_dot);
    tb__v3_set(d_dot, pa_dot[0] - pb_dot[0], pa_dot[1] - pb_dot[1], pa_dot[2] - pb_dot[2]);
    tb__v3_set(arm, f->p[1][0] - ma->x[0], f->p[1][1] - ma->x[1], f->p[1][2] - ma->x[2]);
    centripetal(ma->omega, f->r[0], ca);
    centripetal(mb->omega, f->r[1], cb);
    tb__v3_set(c, ca[0] - cb[0], ca[1] - cb[1], ca[2] - cb[2]);
    double t[3], dt[3], tt[3];
    tb__q_rotate(t, ma->q, dir_a);
    tb__v3_cross(dt, ma->omega, t);
    centripetal(ma->omega, t, tt);
    tb__v3_copy(J->v[0], t);
    tb__v3_cross(J->w[0], arm, t);
    tb__v3_set(J->v[1], -t[0], -t[1], -t[2]);
    tb__v3_cross(J->w[1], t, f->r[1]);
    *bias = tb__v3_dot(c, t) + 2.0 * tb__v3_dot(d_dot, dt) + tb__v3_dot(d, tt);
    *C = tb__v3_dot(d, t);
}

static void travel_rows(const tb__joint *joint, const frame *f, tb__joint_row *J, double *bias,
                        double *C)
{
    for (int k = 0; k < 2; ++k) {
        travel_row(f, joint->across_a[k], &J[k], &bias[k], &C[k]);
    }
}

/* The hinge's angle of a about n relative to b: t1 (fixed in a) against t1, t2 (fixed in b). */
static double hinge_angle(const tb__joint *joint, const tb__motion *ma, const tb__motion *mb)
{
    double t1a[3], t1b[3], t2b[3];
    tb__q_rotate(t1a, ma->q, joint->across_a[0]);
    tb__q_rotate(t1b, mb->q, joint->across_b[0]);
    tb__q_rotate(t2b, mb->q, joint->across_b[1]);
    return atan2(tb__v3_dot(t1a, t2b), tb__v3_dot(t1a, t1b));
}

/* The axial row: a hinge's angle (J u = (w_a - w_b) . n, n = R_a axis turning with a, so
 * dJ/dt u = (w_a - w_b) . (w_a x n)), a slider's travel along its axis (a travel row). C is the
 * coordinate less axial_zero. */
static void axial_row(const tb__joint *joint, const frame *f, tb__joint_row *J, double *bias,
                      double *C)
{
    if (joint->def.type == TB_JOINT_SLIDER) {
        travel_row(f, joint->axis_a, J, bias, C);
        *C -= joint->axial_zero;
        return;
    }
    const double *wa = f->m[0]->omega, *wb = f->m[1]->omega;
    double n[3], dn[3];
    tb__q_rotate(n, f->m[0]->q, joint->axis_a);
    tb__v3_cross(dn, wa, n);
    memset(J, 0, sizeof *J);
    tb__v3_copy(J->w[0], n);
    tb__v3_set(J->w[1], -n[0], -n[1], -n[2]);
    *bias = (wa[0] - wb[0]) * dn[0] + (wa[1] - wb[1]) * dn[1] + (wa[2] - wb[2]) * dn[2];
    *C = hinge_angle(joint, f->m[0], f->m[1]) - joint->axial_zero;
}

double tb__joint_axial_coordinate(const tb__joint *joint, const tb__motion *ma,
                                  const tb__motion *mb)
{
    if (joint->def.type == TB_JOINT_HINGE) {
        return hinge_angle(joint, ma, mb);
    }
    frame f = {.m = {ma, mb}};
    for (int s = 0; s < 2; ++s) {
        tb__point_arm(f.m[s], joint->anchor[s], f.r[s]);
        for (int k = 0; k < 3; ++k) {
            f.p[s][k] = f.m[s]->x[k] + f.r[s][k];
        }
    }
    double d[3], n[3];
    tb__v3_set(d, f.p[0][0] - f.p[1][0], f.p[0][1] - f.p[1][1], f.p[0][2] - f.p[1][2]);
    tb__q_rotate(n, ma->q, joint->axis_a);
    return tb__v3_dot(d, n);
}

/* M^-1 J^T: each row's v-part over the mass, its w-part through the world inverse inertia
 * R diag(I_body^-1) R^T (made once per side); zero for a body that cannot move. */
static void inverse_mass_rows(const tb__body *const inverse[2], const tb__motion *const m[2],
                              int rows, const tb__joint_row *J, tb__joint_row *W)
{
    for (int s = 0; s < 2; ++s) {
        const tb__body *body = inverse[s];
        double R[9], inverse_inertia[9];
        tb__q_to_matrix(R, m[s]->q);
        tb__m3_rotate_diagonal(inverse_inertia, R, body->inv_moments);
        for (int r = 0; r < rows; ++r) {
            for (int k = 0; k < 3; ++k) {
                W[r].v[s][k] = J[r].v[s][k] * body->inv_mass;
            }
            tb__m3_mul_v(W[r].w[s], inverse_inertia, J[r].w[s]);
        }
    }
}

void tb__joint_rows(const tb__joint *joint, const tb__motion *ma, const tb__motion *mb,
                    const tb__body *const inverse[2], tb__joint_eval *eval)
{
    frame f = {.m = {ma, mb}};
    for (int s = 0; s < 2; ++s) {
        tb__point_arm(f.m[s], joint->anchor[s], f.r[s]);
        for (int k = 0; k < 3; ++k) {
            f.p[s][k] = f.m[s]->x[k] + f.r[s][k];
        }
    }
    const int first = tb__joint_first_spring(joint); /* the type's rows from here */
    tb__joint_row *J = eval->J + first;
    double *bias = eval->bias + first, *C = eval->C + first;
    switch (joint->def.type) {
    case TB_JOINT_BALL:
        ball_rows(&f, J, bias, C);
        break;
    case TB_JOINT_HINGE:
        ball_rows(&f, J, bias, C);
        axis_rows(joint, &f, J + 3, bias + 3, C + 3);
        break;
    case TB_JOINT_SLIDER:
        rotation_rows(joint, &f, J, bias, C);
        travel_rows(joint, &f, J + 3, bias + 3, C + 3);
        break;
    default: /* fixed */
        ball_rows(&f, J, bias, C);
        rotation_rows(joint, &f, J + 3, bias + 3, C + 3);
        break;
    }
    if (joint->rows > joint->base_rows) { /* a stop or a motor: the axial row */
        const int r = joint->axial_row;
        axial_row(joint, &f, eval->J + r, eval->bias + r, eval->C + r);
    }
    inverse_mass_rows(inverse, f.m, joint->rows, eval->J, eval->W);
}

void tb__joint_row_velocities(const tb__joint *joint, const tb__joint_eval *eval,
                              const tb__motion *ma, const tb__motion *mb, double out[])
{
    const tb__motion *m[2] = {ma, mb};
    for (int r = 0; r < joint->rows; ++r) {
        double sum = 0.0;
        for (int s = 0; s < 2; ++s) {
            sum += tb__v3_dot(eval->J[r].v[s], m[s]->v) + tb__v3_dot(eval->J[r].w[s], m[s]->omega);
        }
        out[r] = sum;
    }
}

/* Two unit vectors across the unit n: n x e for the basis vector e least along n, then n x t1. */
static void across(const double n[3], double t1[3], double t2[3])
{
    const double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    double e[3] = {0.0, 0.0, 0.0};
    e[ax <= ay && ax <= az ? 0 : (ay <= az ? 1 : 2)] = 1.0;
    tb__v3_cross(t1, n, e);
    const double length = tb__v3_norm(t1);
    tb__v3_set(t1, t1[0] / length, t1[1] / length, t1[2] / length);
    tb__v3_cross(t2, n, t1);
}

void tb__joint_frames(tb__joint *joint, const tb__motion *ma, const tb__motion *mb)
{
    const tb__motion *m[2] = {ma, mb};
    const tb_joint_def *def = &joint->def;
    for (int s = 0; s < 2; ++s) {
        const double from_center[3] = {def->anchor[0] - m[s]->x[0], def->anchor[1] - m[s]->x[1],
                                       def->anchor[2] - m[s]->x[2]};
        tb__q_rotate_inverse(joint->anchor[s], m[s]->q, from_center);
    }
    double n[3], t[2][3];
    const double length = tb__v3_norm(def->axis);
    tb__v3_set(n, def->axis[0] / length, def->axis[1] / length, def->axis[2] / length);
    across(n, t[0], t[1]);
    tb__q_rotate_inverse(joint->axis_a, ma->q, n);
    for (int k = 0; k < 2; ++k) {
        tb__q_rotate_inverse(joint->across_a[k], ma->q, t[k]);
        tb__q_rotate_inverse(joint->across_b[k], mb->q, t[k]);
    }
    const double conj_b[4] = {mb->q[0], -mb->q[1], -mb->q[2], -mb->q[3]};
    tb__q_mul(joint->relative, conj_b, ma->q);
    joint->base_rows = tb__joint_row_count(def->type);
    joint->axial_first =
        def->soft_frequency > 0.0 && (def->has_limits || def->motor != TB_MOTOR_OFF);
    joint->axial_row = joint->axial_first ? 0 : joint->base_rows;
    joint->rows = joint->base_rows + (joint->axial_first ? 1 : 0);
    tb__joint_solve_rows_as_made(joint);
}
