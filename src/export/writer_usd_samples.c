/* Writers: USD time samples of a body's pose. Time codes are frames: t fps, so frame k is time
 * code k. Translations are the frames' (USD interpolates them linearly). Orientations are the
 * frames', and samples between two frames where USD's interpolation would stray from the turn.
 * USD interpolates quatd samples by slerp the short way round: exact for a spin about a fixed
 * axis, but it cuts the corner where the axis moves (precession, a contact) and turns backwards
 * past half a turn between samples. Between frames where the body coasting from one frame
 * (Euler's equations, from its inertia and the frame's omega) arrives at the next, the turn is
 * taken to be that torque-free one, from each end, blended so that both frames are met: the
 * simulated motion itself, whatever the spin. Elsewhere (a torque acts) it is the curve glTF's
 * CUBICSPLINE keys draw (the cubic Hermite spline with tangents dq/dt = 1/2 (0, omega) (x) q). A
 * frame interval is cut into 2, 4, ... equal pieces until the slerp of each piece meets the turn at
 * the piece's middle within the writer's sample_tolerance. docs/export.md has the measured distance
 * from the simulation. Values are printed with 17 significant digits, which read back as the
 * doubles printed. */
#include "export/writer_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <string.h>

/* Pieces of a frame interval at most (docs/export.md's fastest spin, 6.7 rad a frame, needs
 * 64). */
#define TB__USD_MAX_PIECES 256

double tb__usd_time_code(double t, double fps)
{
    const double code = t * fps, whole = round(code);
    return fabs(code - whole) <= 1e-9 * fmax(1.0, fabs(whole)) ? whole : code;
}

static double dot4(const double a[4], const double b[4])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
}

/* The angle (rad) of the turn from one unit quaternion's rotation to the other's. */
static double turn_angle(const double a[4], const double b[4])
{
    return 2.0 * acos(fmin(1.0, fabs(dot4(a, b))));
}

typedef struct key {
    double t, q[4], dq[4], omega[3];
} key;

static void key_of(const tb__frames *f, size_t k, size_t id, key *out)
{
    const size_t at = k * f->body_count + id;
    out->t = f->t[k];
    for (int i = 0; i < 4; ++i) {
        out->q[i] = f->orientation[4 * at + i];
    }
    for (int i = 0; i < 3; ++i) {
        out->omega[i] = f->angular_velocity[3 * at + i];
    }
    const double half_omega[4] = {0.0, 0.5 * out->omega[0], 0.5 * out->omega[1],
                                  0.5 * out->omega[2]};
    tb__q_mul(out->dq, half_omega, out->q);
}

/* b's sign (q and -q are one rotation) that the spin leads to from a: the one nearer a turned
 * by the mean angular velocity for the interval, which for a small turn is a's hemisphere. */
static void follow(const key *a, key *b)
{
    double omega[3], predicted[4];
    for (int i = 0; i < 3; ++i) {
        omega[i] = 0.5 * (a->omega[i] + b->omega[i]);
    }
    const double rate = tb__v3_norm(omega), half = 0.5 * rate * (b->t - a->t);
    const double s = rate > 0 ? sin(half) / rate : 0.0;
    tb__q_mul(predicted, (double[4]){cos(half), s * omega[0], s * omega[1], s * omega[2]}, a->q);
    const double sign = dot4(predicted, b->q) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        b->q[i] *= sign;
        b->dq[i] *= sign;
    }
}

/* The spline's unit quaternion at s in [0, 1] of the interval from a to b. */
static void spline(const key *a, const key *b, double s, double q[4])
{
    const double dt = b->t - a->t, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2,
                 h11 = s3 - s2;
    for (int i = 0; i < 4; ++i) {
        q[i] = h00 * a->q[i] + h10 * dt * a->dq[i] + h01 * b->q[i] + h11 * dt * b->dq[i];
    }
    const double norm = tb__q_norm(q);
    for (int i = 0; i < 4; ++i) {
        q[i] /= norm;
    }
}

/* Two frames of a body and how it turns between them. */
typedef struct interval {
    key a, b;
    const tb_mass_properties *mass; /* NULL: no usable inertia, the spline alone */
} interval;

/* d/dt of the principal frame's quaternion p turning freely with world angular momentum L:
 * omega = R(p) I^-1 R(p)^T L, dp/dt = 1/2 (0, omega) (x) p. */
static void free_turn_rate(const double p[4], const double L[3], const double moments[3],
                           double dp[4])
{
    double body[3], omega[3];
    tb__q_rotate_inverse(body, p, L);
    for (int i = 0; i < 3; ++i) {
        body[i] /= moments[i];
    }
    tb__q_rotate(omega, p, body);
    tb__q_mul(dp, (double[4]){0.0, 0.5 * omega[0], 0.5 * omega[1], 0.5 * omega[2]}, p);
}

/* The shape frame's quaternion tau s from key k (tau < 0: before it), turning free of torque:
 * the principal frame p = q (x) rotation keeps the world angular momentum the key's omega gives
 * (Euler's equations), integrated by RK4 in steps of at most 0.01 rad. */
static void coast(const key *k, const tb_mass_properties *mass, double tau, double out[4])
{
    double p[4], L[3], body[3];
    tb__q_mul(p, k->q, mass->rotation);
    tb__q_rotate_inverse(body, p, k->omega);
    for (int i = 0; i < 3; ++i) {
        body[i] *= mass->moments[i];
    }
    tb__q_rotate(L, p, body);
    const double turn = tb__v3_norm(k->omega) * fabs(tau) / 0.01;
    const int steps = turn < 1.0 ? 1 : turn > 4096.0 ? 4096 : (int)ceil(turn);
    const double h = tau / steps;
    for (int n = 0; n < steps; ++n) {
        double k1[4], k2[4], k3[4], k4[4], stage[4];
        free_turn_rate(p, L, mass->moments, k1);
        for (int i = 0; i < 4; ++i) {
            stage[i] = p[i] + 0.5 * h * k1[i];
        }
        free_turn_rate(stage, L, mass->moments, k2);
        for (int i = 0; i < 4; ++i) {
            stage[i] = p[i] + 0.5 * h * k2[i];
        }
        free_turn_rate(stage, L, mass->moments, k3);
        for (int i = 0; i < 4; ++i) {
            stage[i] = p[i] + h * k3[i];
        }
        free_turn_rate(stage, L, mass->moments, k4);
        for (int i = 0; i < 4; ++i) {
            p[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        const double norm = tb__q_norm(p);
        for (int i = 0; i < 4; ++i) {
            p[i] /= norm;
        }
    }
    const double *r = mass->rotation;
    tb__q_mul(out, p, (double[4]){r[0], -r[1], -r[2], -r[3]});
}

/* The turn at s in [0, 1] of the interval: with inertia, the torque-free turn from each end,
 * blended (s from a, 1 - s from b, normalised), which is the motion itself for a body free of
 * torque and meets both frames exactly; without, the spline. */
static void turn_at(const interval *v, double s, double q[4])
{
    if (v->mass == NULL) {
        spline(&v->a, &v->b, s, q);
        return;
    }
    double from_a[4], from_b[4];
    const double dt = v->b.t - v->a.t;
    coast(&v->a, v->mass, s * dt, from_a);
    coast(&v->b, v->mass, -(1.0 - s) * dt, from_b);
    const double sign = dot4(from_a, from_b) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        q[i] = (1.0 - s) * from_a[i] + s * sign * from_b[i];
    }
    const double norm = tb__q_norm(q);
    for (int i = 0; i < 4; ++i) {
        q[i] /= norm;
    }
}

/* The inertia for the free turn when it fits the interval: positive, finite moments, and the
 * body coasting from a arrives at b's orientation within tolerance (rad), as it does when no
 * torque acts; else NULL, and the spline is drawn (a torque turns the axis, which the spline's
 * tangents at both ends see and the coast from one end does not). */
static const tb_mass_properties *free_inertia(const tb_mass_properties *mass, const key *a,
                                              const key *b, double tolerance)
{
    for (int i = 0; i < 3; ++i) {
        if (!(mass->moments[i] > 0) || !isfinite(mass->moments[i])) {
            return NULL;
        }
    }
    double arrival[4];
    coast(a, mass, b->t - a->t, arrival);
    return turn_angle(arrival, b->q) <= tolerance ? mass : NULL;
}

static void put_quaternion(FILE *file, double code, const double *q)
{
    fprintf(file, "            %.17g: (%.17g, %.17g, %.17g, %.17g),\n", code, q[0], q[1], q[2],
            q[3]);
}

/* The middle of USD's slerp from a to b (the short way round), normalised. */
static void slerp_middle(const double a[4], const double b[4], double out[4])
{
    const double sign = dot4(a, b) < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        out[i] = a[i] + sign * b[i];
    }
    const double norm = tb__q_norm(out);
    for (int i = 0; i < 4; ++i) {
        out[i] /= norm;
    }
}

/* Whether slerp over each of count equal pieces meets the turn at the piece's middle. */
static bool pieces_follow(const interval *v, int count, double tolerance)
{
    double start[4], end[4], on[4], middle[4];
    memcpy(start, v->a.q, sizeof start);
    for (int j = 0; j < count; ++j) {
        turn_at(v, (j + 1.0) / count, end);
        turn_at(v, (j + 0.5) / count, on);
        slerp_middle(start, end, middle);
        if (turn_angle(on, middle) > tolerance) {
            return false;
        }
        memcpy(start, end, sizeof start);
    }
    return true;
}

/* The samples between frames k and k + 1 that USD's slerp needs to follow the spline. */
static void samples_between(const tb_writer *w, size_t k, size_t id)
{
    interval v;
    key_of(&w->frames, k, id, &v.a);
    key_of(&w->frames, k + 1, id, &v.b);
    follow(&v.a, &v.b);
    v.mass = free_inertia(&w->looks.bodies[id].mass, &v.a, &v.b, w->sample_tolerance);
    int count = 1;
    while (count < TB__USD_MAX_PIECES && !pieces_follow(&v, count, w->sample_tolerance)) {
        count *= 2;
    }
    const double first = tb__usd_time_code(v.a.t, w->fps), last = tb__usd_time_code(v.b.t, w->fps);
    for (int j = 1; j < count; ++j) {
        double q[4];
        turn_at(&v, (double)j / count, q);
        put_quaternion(w->file, first + (last - first) * j / count, q);
    }
}

void tb__usd_put_pose_samples(const tb_writer *w, size_t id)
{
    const tb__frames *f = &w->frames;
    FILE *file = w->file;
    fputs("        double3 xformOp:translate.timeSamples = {\n", file);
    for (size_t k = 0; k < f->count; ++k) {
        const double *x = f->position + 3 * (k * f->body_count + id);
        fprintf(file, "            %.17g: (%.17g, %.17g, %.17g),\n",
                tb__usd_time_code(f->t[k], w->fps), x[0], x[1], x[2]);
    }
    fputs("        }\n        quatd xformOp:orient.timeSamples = {\n", file);
    for (size_t k = 0; k < f->count; ++k) {
        put_quaternion(file, tb__usd_time_code(f->t[k], w->fps),
                       f->orientation + 4 * (k * f->body_count + id));
        if (k + 1 < f->count && w->sample_tolerance > 0) {
            samples_between(w, k, id);
        }
    }
    fputs("        }\n", file);
}
