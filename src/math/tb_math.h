/* Private inline math: 3-vectors, quaternions (w, x, y, z), row-major 3x3 matrices.
 * No allocation, no dependencies beyond libm. */
#ifndef TUMBLE_MATH_H
#define TUMBLE_MATH_H

#include <math.h>
#include <stdbool.h>

static inline void tb__v3_set(double out[3], double x, double y, double z)
{
    out[0] = x;
    out[1] = y;
    out[2] = z;
}

static inline void tb__v3_copy(double out[3], const double a[3])
{
    tb__v3_set(out, a[0], a[1], a[2]);
}

static inline double tb__v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double tb__v3_norm(const double a[3])
{
    return sqrt(tb__v3_dot(a, a));
}

/* a / |a| for any finite nonzero a, scaled by its largest component first so that |a|^2
 * neither underflows nor overflows ((0, 0, 1e-300) and (1e300, 1e300, 1e300) are directions
 * too); false, out untouched, for a zero or non-finite a. */
static inline bool tb__v3_direction(const double a[3], double out[3])
{
    const double scale = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
    if (!(scale > 0.0 && isfinite(scale))) {
        return false;
    }
    const double s[3] = {a[0] / scale, a[1] / scale, a[2] / scale};
    const double length = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    tb__v3_set(out, s[0] / length, s[1] / length, s[2] / length);
    return true;
}

/* |a| without the overflow of its squares (|a| = 1e300 is a number; tb__v3_norm gives inf):
 * slower, for checks and estimates outside the hot loop. */
static inline double tb__v3_hypot(const double a[3])
{
    return hypot(hypot(a[0], a[1]), a[2]);
}

/* out = a x b; out may alias neither input. */
static inline void tb__v3_cross(double out[3], const double a[3], const double b[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* out += s * a */
static inline void tb__v3_axpy(double out[3], double s, const double a[3])
{
    out[0] += s * a[0];
    out[1] += s * a[1];
    out[2] += s * a[2];
}

static inline bool tb__all_finite(const double *a, int n)
{
    for (int i = 0; i < n; ++i) {
        if (!isfinite(a[i])) {
            return false;
        }
    }
    return true;
}

static inline double tb__q_norm(const double q[4])
{
    return sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}

/* out = a (x) b (Hamilton product); out may alias neither input. */
static inline void tb__q_mul(double out[4], const double a[4], const double b[4])
{
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

/* Rotates v by the unit quaternion q: out = q v q*, using
 * v' = v + 2w (u x v) + 2 u x (u x v) with q = (w, u). out may alias v. */
static inline void tb__q_rotate(double out[3], const double q[4], const double v[3])
{
    const double *u = q + 1;
    double t[3], ut[3];
    tb__v3_cross(t, u, v);
    tb__v3_set(t, 2.0 * t[0], 2.0 * t[1], 2.0 * t[2]);
    tb__v3_cross(ut, u, t);
    tb__v3_set(out, v[0] + q[0] * t[0] + ut[0], v[1] + q[0] * t[1] + ut[1],
               v[2] + q[0] * t[2] + ut[2]);
}

/* Rotates v by the inverse of the unit quaternion q: out = q* v q. out may alias v. */
static inline void tb__q_rotate_inverse(double out[3], const double q[4], const double v[3])
{
    const double conjugate[4] = {q[0], -q[1], -q[2], -q[3]};
    tb__q_rotate(out, conjugate, v);
}

/* Row-major matrix I + (s/2) * 2 (w [u]x + [u]x^2) for q = (w, u): the rotation of q when
 * s = 2 and |q| = 1, and the rotation of q/|q| for any nonzero q when s = 2/|q|^2. */
static inline void tb__q_matrix_scaled(double R[9], const double q[4], double s)
{
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    R[0] = 1 - s * (y * y + z * z);
    R[1] = s * (x * y - w * z);
    R[2] = s * (x * z + w * y);
    R[3] = s * (x * y + w * z);
    R[4] = 1 - s * (x * x + z * z);
    R[5] = s * (y * z - w * x);
    R[6] = s * (x * z - w * y);
    R[7] = s * (y * z + w * x);
    R[8] = 1 - s * (x * x + y * y);
}

/* Row-major rotation matrix of the unit quaternion q (body -> world). */
static inline void tb__q_to_matrix(double R[9], const double q[4])
{
    tb__q_matrix_scaled(R, q, 2.0);
}

/* Row-major rotation matrix of q/|q| for any nonzero q, without a square root. */
static inline void tb__q_to_matrix_any(double R[9], const double q[4])
{
    tb__q_matrix_scaled(R, q, 2.0 / (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]));
}

/* Unit quaternion of a proper rotation matrix (row-major), by Shepperd's method: pick the
 * largest of w^2, x^2, y^2, z^2 to divide by, so no branch loses precision. w >= 0. */
static inline void tb__matrix_to_q(double q[4], const double R[9])
{
    const double trace = R[0] + R[4] + R[8];
    if (trace >= R[0] && trace >= R[4] && trace >= R[8]) {
        const double s = 2.0 * sqrt(1.0 + trace);
        q[0] = 0.25 * s;
        q[1] = (R[7] - R[5]) / s;
        q[2] = (R[2] - R[6]) / s;
        q[3] = (R[3] - R[1]) / s;
    } else if (R[0] >= R[4] && R[0] >= R[8]) {
        const double s = 2.0 * sqrt(1.0 + R[0] - R[4] - R[8]);
        q[0] = (R[7] - R[5]) / s;
        q[1] = 0.25 * s;
        q[2] = (R[1] + R[3]) / s;
        q[3] = (R[2] + R[6]) / s;
    } else if (R[4] >= R[8]) {
        const double s = 2.0 * sqrt(1.0 + R[4] - R[0] - R[8]);
        q[0] = (R[2] - R[6]) / s;
        q[1] = (R[1] + R[3]) / s;
        q[2] = 0.25 * s;
        q[3] = (R[5] + R[7]) / s;
    } else {
        const double s = 2.0 * sqrt(1.0 + R[8] - R[0] - R[4]);
        q[0] = (R[3] - R[1]) / s;
        q[1] = (R[2] + R[6]) / s;
        q[2] = (R[5] + R[7]) / s;
        q[3] = 0.25 * s;
    }
    if (q[0] < 0) {
        for (int i = 0; i < 4; ++i) {
            q[i] = -q[i];
        }
    }
}

/* out = A v (row-major A). out may not alias v. */
static inline void tb__m3_mul_v(double out[3], const double A[9], const double v[3])
{
    for (int i = 0; i < 3; ++i) {
        out[i] = A[3 * i] * v[0] + A[3 * i + 1] * v[1] + A[3 * i + 2] * v[2];
    }
}

/* out = A B (row-major). out may alias neither input. */
static inline void tb__m3_mul(double out[9], const double A[9], const double B[9])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
        }
    }
}

static inline void tb__m3_transpose(double out[9], const double A[9])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out[3 * j + i] = A[3 * i + j];
        }
    }
}

/* Rotates a symmetric tensor: out = R D R^T with D = diag(d). */
static inline void tb__m3_rotate_diagonal(double out[9], const double R[9], const double d[3])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            out[3 * i + j] = R[3 * i] * d[0] * R[3 * j] + R[3 * i + 1] * d[1] * R[3 * j + 1] +
                             R[3 * i + 2] * d[2] * R[3 * j + 2];
        }
    }
}

#endif
