/* The friction laws' local derivatives (friction_jacobian.h), differentiated by hand from
 * effect_ground.c's bristles() and effect_contact_friction.c's anchor_friction() and
 * slip_friction(); checked against difference quotients by test_contact_jacobian. */
#include "effects/friction_jacobian.h"

#include "contact/contact_law.h"
#include "math/tb_math.h"

#include <math.h>
#include <string.h>

/* mu at slip speed w and d mu / dw: from mu_s at rest to mu_k (Stribeck). */
static double stribeck(const tb__friction_law *law, double slip, double *slope)
{
    const double ratio = slip / law->stribeck_velocity, fall = exp(-ratio * ratio);
    const double drop = law->static_friction - law->kinetic_friction;
    *slope = drop * fall * (-2.0 * ratio) / law->stribeck_velocity;
    return law->kinetic_friction + drop * fall;
}

/* The capped force's derivatives: friction = mu N trial / |trial| beyond the cap. Q =
 * (mu N / |trial|)(1 - t t^T) turns d trial into d friction; mu and N scale it along t. */
static void capped(double muN, const double trial[3], double magnitude, double Q[3][3])
{
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            const double t = trial[a] * trial[b] / (magnitude * magnitude);
            Q[a][b] = muN / magnitude * ((a == b ? 1.0 : 0.0) - t);
        }
    }
}

void tb__anchor_jacobian(const tb__friction_law *law, double k, double c, double N,
                         const double n[3], const double v_t[3], const double z[3],
                         tb__friction_jacobian *out)
{
    memset(out, 0, sizeof *out);
    const double along = tb__v3_dot(z, n);
    double P[3][3], z_t[3], trial[3], unit[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < 3; ++a) {
        z_t[a] = z[a] - along * n[a];
        for (int b = 0; b < 3; ++b) {
            P[a][b] = (a == b ? 1.0 : 0.0) - n[a] * n[b];
        }
    }
    const double deflection = tb__v3_norm(z_t), cone = law->static_friction * N / k;
    const double excess = deflection > cone ? deflection - cone : 0.0;
    double slope;
    const double mu = stribeck(law, TB__BRISTLE_MAX_RATE * excess, &slope);
    slope *= TB__BRISTLE_MAX_RATE; /* d mu / d excess */
    for (int a = 0; a < 3; ++a) {
        trial[a] = -(k * z_t[a] + c * v_t[a]);
        unit[a] = excess > 0.0 ? z_t[a] / deflection : 0.0;
    }
    /* d excess = unit . dz - (mu_s / k) dN beyond the cone */
    const double excess_N = excess > 0.0 ? -law->static_friction / k : 0.0;
    const double magnitude = tb__v3_norm(trial);
    const bool cap = magnitude > mu * N;
    double Q[3][3];
    if (cap) {
        capped(mu * N, trial, magnitude, Q);
    }
    for (int a = 0; a < 3; ++a) {
        const double t = cap ? trial[a] / magnitude : 0.0;
        out->force_N[a] = cap ? t * (mu + N * slope * excess_N) : 0.0;
        out->rate_N[a] = -TB__BRISTLE_MAX_RATE * unit[a] * excess_N;
        for (int b = 0; b < 3; ++b) {
            /* d trial = -k P dz - c dv */
            double dz = 0.0;
            for (int m = 0; m < 3; ++m) {
                dz += (cap ? Q[a][m] : (a == m ? 1.0 : 0.0)) * -k * P[m][b];
            }
            out->force_z[a][b] = dz + (cap ? t * N * slope * unit[b] : 0.0);
            out->force_v[a][b] = cap ? -c * Q[a][b] : (a == b ? -c : 0.0);
            out->rate_v[a][b] = a == b ? 1.0 : 0.0;
            /* d (excess z_t / |z_t|) = unit d excess + excess / |z_t| (1 - unit unit^T) P dz */
            const double plastic =
                excess > 0.0
                    ? unit[a] * unit[b] + excess / deflection * (P[a][b] - unit[a] * unit[b])
                    : 0.0;
            out->rate_z[a][b] =
                -TB__BRISTLE_RELEASE_RATE * n[a] * n[b] - TB__BRISTLE_MAX_RATE * plastic;
        }
        out->rate[a] = v_t[a] - TB__BRISTLE_RELEASE_RATE * along * n[a] -
                       TB__BRISTLE_MAX_RATE * excess * unit[a];
    }
}

/* [a]x */
static void cross_matrix(const double a[3], double out[3][3])
{
    const double m[3][3] = {{0.0, -a[2], a[1]}, {a[2], 0.0, -a[0]}, {-a[1], a[0], 0.0}};
    memcpy(out, m, sizeof m);
}

void tb__anchor_turn_rows(const tb__friction_jacobian *fr, const double *R, const double z[3],
                          tb__point_jacobian *p)
{
    double zx[3][3], dzx[3][3], rate[3][3];
    cross_matrix(z, zx);
    cross_matrix(fr->rate, dzx);
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            double force = 0.0, moved = 0.0;
            for (int m = 0; m < 3; ++m) {
                force -= fr->force_z[a][m] * zx[m][b];
                moved -= fr->rate_z[a][m] * zx[m][b];
            }
            p->force_turn_a[a][b] = force;
            rate[a][b] = dzx[a][b] + moved;
        }
    }
    for (int k = 0; k < 3; ++k) { /* R^T rate */
        for (int b = 0; b < 3; ++b) {
            p->rate_turn_a[k][b] =
                R[k] * rate[0][b] + R[3 + k] * rate[1][b] + R[6 + k] * rate[2][b];
        }
    }
}

void tb__slip_jacobian(const tb__friction_law *law, double N, const double v_t[3],
                       tb__friction_jacobian *out)
{
    memset(out, 0, sizeof *out);
    const double speed = tb__v3_norm(v_t);
    const double S = sqrt(speed * speed + law->slip_velocity * law->slip_velocity);
    double slope;
    const double mu = stribeck(law, speed, &slope);
    for (int a = 0; a < 3; ++a) {
        out->force_N[a] = -mu * v_t[a] / S;
        for (int b = 0; b < 3; ++b) {
            /* d (mu / S) = (mu' v^ / S - mu v / S^3) dv */
            const double d_ratio =
                (speed > 0.0 ? slope * v_t[b] / speed : 0.0) / S - mu * v_t[b] / (S * S * S);
            out->force_v[a][b] = -N * ((a == b ? mu / S : 0.0) + v_t[a] * d_ratio);
        }
    }
}

void tb__contact_point_rows(const double n[3], double dN_dd, double dN_ddr,
                            const tb__friction_jacobian *fr, const double *T, size_t count,
                            tb__point_jacobian *p)
{
    double along[3], Fv[3][3], Rv[3][3], Fz[3][3], Rz[3][3];
    for (int a = 0; a < 3; ++a) {
        along[a] = n[a] + (fr != NULL ? fr->force_N[a] : 0.0); /* df / dN */
        for (int b = 0; b < 3; ++b) {
            Fv[a][b] = Rv[a][b] = 0.0;
            for (int m = 0; m < 3 && fr != NULL; ++m) { /* v_t = (1 - n n^T) w */
                const double P = (m == b ? 1.0 : 0.0) - n[m] * n[b];
                Fv[a][b] += fr->force_v[a][m] * P;
                Rv[a][b] += fr->rate_v[a][m] * P;
            }
            p->force_u[a][b] = -along[a] * dN_dd * n[b];
            p->force_w[a][b] = -along[a] * dN_ddr * n[b] + Fv[a][b];
        }
    }
    p->state_count = fr != NULL ? count : 0;
    for (size_t k = 0; k < p->state_count; ++k) { /* d/ds = (d/dz) T, ds = T^T dz */
        for (int a = 0; a < 3; ++a) {
            Fz[a][k] = Rz[a][k] = 0.0;
            for (int m = 0; m < 3; ++m) {
                Fz[a][k] += fr->force_z[a][m] * T[3 * m + k];
                Rz[a][k] += fr->rate_z[a][m] * T[3 * m + k];
            }
            p->force_s[a][k] = Fz[a][k];
        }
    }
    for (size_t k = 0; k < p->state_count; ++k) {
        for (int b = 0; b < 3; ++b) {
            double u = 0.0, w = 0.0;
            for (int m = 0; m < 3; ++m) {
                u += T[3 * m + k] * fr->rate_N[m] * -dN_dd * n[b];
                w += T[3 * m + k] * (fr->rate_N[m] * -dN_ddr * n[b] + Rv[m][b]);
            }
            p->rate_u[k][b] = u;
            p->rate_w[k][b] = w;
        }
        for (size_t i = 0; i < count; ++i) {
            double s = 0.0;
            for (int m = 0; m < 3; ++m) {
                s += T[3 * m + k] * Rz[m][i];
            }
            p->rate_s[k][i] = s;
        }
    }
}
