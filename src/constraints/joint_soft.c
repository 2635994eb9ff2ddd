/* Soft joints: each of the joint's row groups a linear spring-damper instead of an exact
 * constraint (for animators' wobbly rigs). The rows come in groups: ball (3, the anchors' gap
 * p_a - p_b), axis (2, a hinge's tilt), rotation (3, the relative rotation 2 vec(e)), travel (2, a
 * slider's sideways gap). Each group g has one mass m_g = n_g / trace(J_g M^-1 J_g^T), its rows'
 * mean effective mass when the joint was made, and pulls with
 *
 *     lambda_r = -m_g (w^2 C_r + 2 zeta w J_r u),     w = 2 pi soft_frequency,
 *
 * so a row alone rings at soft_frequency with damping ratio zeta (exactly for a body whose rows'
 * effective masses are equal, as a ball held at its centre). Why constants, and one per group:
 * a spring whose stiffness changes with the pose (the effective mass turns with the body) is
 * not conservative, and one whose stiffness differs between world axes (the ball and rotation
 * rows are along world axes) turns the pair it joins: with one constant stiffness per group the
 * spring has the potential V = sum_g m_g w^2 |C_g|^2 / 2 (tb_scene_potential_energy counts it),
 * and it is isotropic, a function of the bodies' relative pose only, so momentum and angular
 * momentum are kept between two dynamic bodies.
 *
 * The rotation rows' C = 2 vec(e) (e the error rotation, e0 >= 0, angle theta: |C| = 2 sin
 * theta/2) has the rate (e0 I - [vec(e) x]) (w_a - w_b), not the rows' w_a - w_b: the exact
 * gradient of V is e0 m w^2 C (the cross term vanishes on C, the stiffness isotropic), so their
 * spring's lambda carries the factor e0 = sqrt(1 - |C|^2 / 4): torque m w^2 sin theta, V = m w^2
 * (1 - cos theta). Every other row's J is its C's exact gradient (joint_rows.c). */
#include "constraints/joints_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <string.h>

#define TB__TWO_PI (2.0 * 3.14159265358979323846)

/* Rows per group of each type; rotation_group the index of the rotation rows' group (or -1). */
static void groups(tb_joint_type type, int rows[2], int *rotation_group)
{
    static const int counts[TB_JOINT_TYPE_COUNT][2] = {[TB_JOINT_BALL] = {3, 0},
                                                       [TB_JOINT_HINGE] = {3, 2},
                                                       [TB_JOINT_SLIDER] = {3, 2},
                                                       [TB_JOINT_FIXED] = {3, 3}};
    rows[0] = counts[type][0];
    rows[1] = counts[type][1];
    *rotation_group = type == TB_JOINT_SLIDER ? 0 : type == TB_JOINT_FIXED ? 1 : -1;
}

void tb__joint_soft_masses(tb__joint *joint, const tb_scene *scene)
{
    if (!(joint->def.soft_frequency > 0.0)) {
        return;
    }
    tb__motion m[2];
    const tb__body *constants[2];
    for (int s = 0; s < 2; ++s) {
        tb__joint_motion(scene, scene->time, scene->states, joint->body[s], false, &m[s]);
        constants[s] = tb__joint_body_constants(scene, joint->body[s]);
    }
    tb__joint_eval eval;
    tb__joint_rows(joint, &m[0], &m[1], constants, &eval);
    int rows[2], rotation_group = -1, first = tb__joint_first_spring(joint);
    groups(joint->def.type, rows, &rotation_group);
    joint->soft_mass[0] = 0.0; /* an axial row kept first: not a spring */
    for (int g = 0; g < 2; ++g) {
        double trace = 0.0;
        for (int r = first; r < first + rows[g]; ++r) {
            for (int s = 0; s < 2; ++s) {
                trace += tb__v3_dot(eval.J[r].v[s], eval.W[r].v[s]) +
                         tb__v3_dot(eval.J[r].w[s], eval.W[r].w[s]);
            }
        }
        for (int r = first; r < first + rows[g]; ++r) {
            joint->soft_mass[r] = trace > 0.0 ? rows[g] / trace : 0.0;
        }
        first += rows[g];
    }
}

/* e0 of the rotation rows' error (their C = 2 vec(e)), 1 for the other groups' rows. */
static void spring_factors(const tb__joint *joint, const double *C, double factor[])
{
    int rows[2], rotation_group = -1;
    groups(joint->def.type, rows, &rotation_group);
    for (int r = 0; r < joint->rows; ++r) {
        factor[r] = 1.0;
    }
    if (rotation_group >= 0) {
        const int first = tb__joint_first_spring(joint) + (rotation_group == 0 ? 0 : rows[0]);
        const double *c = C + first;
        const double e0 = sqrt(fmax(0.0, 1.0 - 0.25 * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2])));
        for (int r = first; r < first + 3; ++r) {
            factor[r] = e0;
        }
    }
}

void tb__joint_soft_lambdas(const tb__joint *joint, tb__joint_eval *eval)
{
    const double w = TB__TWO_PI * joint->def.soft_frequency;
    const double zeta = joint->def.soft_damping_ratio;
    double factor[TB__JOINT_ROWS];
    spring_factors(joint, eval->C, factor);
    eval->lambda[0] = joint->axial_first ? 0.0 : eval->lambda[0]; /* its axial row: solved */
    for (int r = tb__joint_first_spring(joint); r < joint->rows; ++r) {
        const double mass = joint->soft_mass[r];
        eval->lambda[r] = -mass * (w * w * factor[r] * eval->C[r] + 2.0 * zeta * w * eval->rate[r]);
    }
}

double tb__joints_potential_energy(const void *constraints, const tb_scene *scene, const double *y)
{
    const tb__joints *js = constraints;
    double energy = 0.0;
    for (size_t j = 0; j < js->count; ++j) {
        const tb__joint *joint = &js->joints[j];
        if (!(joint->def.soft_frequency > 0.0) || joint->broken) {
            continue;
        }
        tb__motion m[2];
        const tb__body *constants[2];
        for (int s = 0; s < 2; ++s) {
            tb__joint_motion(scene, scene->time, y, joint->body[s], false, &m[s]);
            constants[s] = tb__joint_body_constants(scene, joint->body[s]);
        }
        tb__joint_eval eval;
        tb__joint_rows(joint, &m[0], &m[1], constants, &eval);
        const double w = TB__TWO_PI * joint->def.soft_frequency;
        for (int r = tb__joint_first_spring(joint); r < joint->rows; ++r) {
            energy += 0.5 * joint->soft_mass[r] * w * w * eval.C[r] * eval.C[r];
        }
    }
    return energy;
}
