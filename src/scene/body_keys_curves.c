/* Keyframe curves between two keys: position by a cubic Hermite (or linear) curve in R^3,
 * orientation by the same curve in the rotation vector of the rotation from the segment's first
 * key, q(t) = exp(phi(t)) (x) q_k, with the exact derivatives of the exponential map.
 *
 * Why the rotation vector and not a Hermite curve in R^4 normalised: a turn at a constant rate
 * about a fixed axis is phi(t) = omega (t - t_k), a straight line, which both the linear and the
 * cubic curve reproduce exactly (the end tangent J_l(phi_1)^-1 omega equals omega along the
 * axis); a normalised R^4 curve bends the angle's rate between keys. Linear interpolation is
 * then slerp: phi(t) = s phi_1, a constant angular velocity phi_1 / h about a fixed axis. */
#include "scene/body_keys_internal.h"

#include "math/tb_math.h"

#include <math.h>

/* --- the Hermite curve ------------------------------------------------------------------- */

/* The cubic Hermite basis on s in [0, 1] (e.g. Farin, Curves and Surfaces for CAGD, ch. 7):
 * x(s) = h00 x0 + h10 h m0 + h01 x1 + h11 h m1 for tangents m (per unit of t) over a segment
 * of length h; written as x0 + h01 (x1 - x0) + h (h10 m0 + h11 m1), since h00 = 1 - h01, so
 * that s = 0 gives x0 to the bit. d* and dd* are the first and second derivatives by s.
 * Linear interpolation is the same form with h01 = s and no tangent terms. */
typedef struct basis {
    double h10, h01, h11;
    double d10, d01, d11;
    double dd10, dd01, dd11;
} basis;

static basis hermite_basis(double s, tb_interpolation interpolation)
{
    if (interpolation != TB_INTERPOLATION_CUBIC) {
        return (basis){.h01 = s, .d01 = 1.0};
    }
    return (basis){
        .h10 = s * (s - 1.0) * (s - 1.0),
        .h01 = s * s * (3.0 - 2.0 * s),
        .h11 = s * s * (s - 1.0),
        .d10 = (s - 1.0) * (3.0 * s - 1.0),
        .d01 = 6.0 * s * (1.0 - s),
        .d11 = s * (3.0 * s - 2.0),
        .dd10 = 6.0 * s - 4.0,
        .dd01 = 6.0 - 12.0 * s,
        .dd11 = 6.0 * s - 2.0,
    };
}

/* value, its t-derivative and second t-derivative of the curve from x0 by delta = x1 - x0 with
 * tangents m0, m1 (per second) over a segment of h seconds. */
static void hermite(const basis *b, double h, const double x0[3], const double delta[3],
                    const double m0[3], const double m1[3], double value[3], double rate[3],
                    double acceleration[3])
{
    for (int i = 0; i < 3; ++i) {
        value[i] = x0[i] + b->h01 * delta[i] + h * (b->h10 * m0[i] + b->h11 * m1[i]);
        rate[i] = b->d01 * delta[i] / h + b->d10 * m0[i] + b->d11 * m1[i];
        /* divided by h twice, so a linear curve's 0 stays 0 however short h is */
        acceleration[i] = (b->dd01 * delta[i] / h + b->dd10 * m0[i] + b->dd11 * m1[i]) / h;
    }
}

/* --- the exponential map of rotations ---------------------------------------------------- */

/* exp(phi) = (cos(theta/2), sin(theta/2) phi/theta), theta = |phi|. */
void tb__rotation_exp(double q[4], const double phi[3])
{
    const double theta = tb__v3_norm(phi);
    /* sin(theta/2)/theta = 1/2 - theta^2/48 + ...: below 1e-8 the next term is under 1e-17 */
    const double k = theta < 1e-8 ? 0.5 - theta * theta / 48.0 : sin(0.5 * theta) / theta;
    q[0] = cos(0.5 * theta);
    q[1] = k * phi[0];
    q[2] = k * phi[1];
    q[3] = k * phi[2];
}

void tb__rotation_log(double phi[3], const double q[4])
{
    const double s = tb__v3_norm(q + 1), w = q[0];
    /* theta/s = 2 atan2(s, w)/s = (2/w)(1 - s^2/(3 w^2) + ...) for small s (w near 1) */
    const double k = s < 1e-8 ? 2.0 / w * (1.0 - s * s / (3.0 * w * w)) : 2.0 * atan2(s, w) / s;
    tb__v3_set(phi, k * q[1], k * q[2], k * q[3]);
}

/* The left Jacobian of SO(3), J_l(phi) = I + a [phi]x + b [phi]x^2 with
 * a = (1 - cos theta)/theta^2 and b = (theta - sin theta)/theta^3, maps the rotation vector's
 * rate to the world angular velocity of exp(phi): omega = J_l(phi) dphi/dt (Barfoot, State
 * Estimation for Robotics, 2017, section 7.1; Bullo and Murray 1995). Its inverse is
 * J_l^-1 = I - 1/2 [phi]x + c [phi]x^2, c = (1 - (theta/2) cot(theta/2))/theta^2, finite for
 * theta < 2 pi. a1 = (da/dtheta)/theta and b1 = (db/dtheta)/theta give the rates of a and b:
 * da/dt = a1 (phi . dphi/dt). */
typedef struct jacobian {
    double a, b, a1, b1;
} jacobian;

/* Below theta = 0.5 the closed forms lose up to eps/theta^4 to cancellation (b1), so the
 * Taylor series, whose terms (-1)^n x^n / (2n+2)! etc. (x = theta^2) follow from those of
 * cos and sin; ten terms leave under 1e-20. */
static jacobian jacobian_series(double x)
{
    jacobian j = {0.0, 0.0, 0.0, 0.0};
    double fa = 0.5, fb = 1.0 / 6.0, ga = -1.0 / 24.0, gb = -1.0 / 120.0;
    for (int n = 0; n < 10; ++n) {
        j.a += fa, j.b += fb;
        j.a1 += 2.0 * (n + 1) * ga, j.b1 += 2.0 * (n + 1) * gb;
        fa *= -x / ((2.0 * n + 3.0) * (2.0 * n + 4.0));
        fb *= -x / ((2.0 * n + 4.0) * (2.0 * n + 5.0));
        ga *= -x / ((2.0 * n + 5.0) * (2.0 * n + 6.0));
        gb *= -x / ((2.0 * n + 6.0) * (2.0 * n + 7.0));
    }
    return j;
}

static jacobian jacobian_of(double theta)
{
    if (theta < 0.5) {
        return jacobian_series(theta * theta);
    }
    const double half_sine = sin(0.5 * theta), sine = sin(theta);
    const double versine = 2.0 * half_sine * half_sine; /* 1 - cos theta, without cancellation */
    const double t2 = theta * theta, t3 = t2 * theta;
    return (jacobian){
        .a = versine / t2,
        .b = (theta - sine) / t3,
        .a1 = (theta * sine - 2.0 * versine) / (t2 * t2),
        .b1 = (theta * versine - 3.0 * (theta - sine)) / (t3 * t2),
    };
}

/* out = v + a phi x v + b phi x (phi x v) */
static void jacobian_apply(double out[3], const double phi[3], double a, double b,
                           const double v[3])
{
    double pv[3], ppv[3];
    tb__v3_cross(pv, phi, v);
    tb__v3_cross(ppv, phi, pv);
    for (int i = 0; i < 3; ++i) {
        out[i] = v[i] + a * pv[i] + b * ppv[i];
    }
}

void tb__rotation_rate_of(double out[3], const double phi[3], const double w[3])
{
    const double theta = tb__v3_norm(phi), half = 0.5 * theta;
    /* c = 1/12 + theta^2/720 + theta^4/30240 + theta^6/1209600 + ... (from x cot x's series);
     * below 0.1 the next term is under 1e-19, above it the closed form loses under 1e-13 */
    const double x = theta * theta;
    const double c = theta < 0.1
                         ? 1.0 / 12.0 + x * (1.0 / 720.0 + x * (1.0 / 30240.0 + x / 1209600.0))
                         : (1.0 - half * cos(half) / sin(half)) / x;
    jacobian_apply(out, phi, -0.5, c, w);
}

/* omega = J_l(phi) dphi and its time derivative
 * alpha = J_l(phi) ddphi + (da/dt) phi x dphi + (db/dt) phi x (phi x dphi)
 *         + b dphi x (phi x dphi),
 * the product rule on omega = dphi + a phi x dphi + b phi x (phi x dphi) (the terms
 * a dphi x dphi and b phi x (dphi x dphi) vanish). */
static void rotation_rates(const double phi[3], const double dphi[3], const double ddphi[3],
                           double omega[3], double alpha[3])
{
    const jacobian j = jacobian_of(tb__v3_norm(phi));
    jacobian_apply(omega, phi, j.a, j.b, dphi);
    const double along = tb__v3_dot(phi, dphi); /* theta dtheta/dt */
    double pd[3], ppd[3], dpd[3];
    tb__v3_cross(pd, phi, dphi);
    tb__v3_cross(ppd, phi, pd);
    tb__v3_cross(dpd, dphi, pd);
    jacobian_apply(alpha, phi, j.a, j.b, ddphi);
    tb__v3_axpy(alpha, j.a1 * along, pd);
    tb__v3_axpy(alpha, j.b1 * along, ppd);
    tb__v3_axpy(alpha, j.b, dpd);
}

/* --- a segment --------------------------------------------------------------------------- */

void tb__keys_segment_sample(const tb_keyframes *keyframes, size_t k, double t,
                             tb_body_motion_sample *out)
{
    const double h = keyframes->times[k + 1] - keyframes->times[k];
    const double s = (t - keyframes->times[k]) / h;
    const basis b = hermite_basis(s, keyframes->interpolation);
    const tb__key_node *from = &keyframes->nodes[k], *to = &keyframes->nodes[k + 1];
    const tb__key_segment *segment = &keyframes->segments[k];
    double delta[3];
    for (int i = 0; i < 3; ++i) {
        delta[i] = to->position[i] - from->position[i];
    }
    hermite(&b, h, from->position, delta, from->velocity, to->velocity, out->position,
            out->velocity, out->acceleration);
    const double zero[3] = {0.0, 0.0, 0.0};
    double phi[3], dphi[3], ddphi[3], turn[4];
    hermite(&b, h, zero, segment->rotation, from->angular_velocity, segment->end_rate, phi, dphi,
            ddphi);
    tb__rotation_exp(turn, phi);
    tb__q_mul(out->orientation, turn, from->orientation);
    if (keyframes->interpolation == TB_INTERPOLATION_CUBIC) {
        rotation_rates(phi, dphi, ddphi, out->angular_velocity, out->angular_acceleration);
    } else { /* slerp: phi parallel to dphi, J_l(phi) dphi = dphi, and no acceleration */
        tb__v3_copy(out->angular_velocity, dphi);
        tb__v3_set(out->angular_acceleration, 0.0, 0.0, 0.0);
    }
}
