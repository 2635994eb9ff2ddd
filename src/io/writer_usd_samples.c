/* Writers: USD time samples of a body's pose. Time codes are frames: t fps, so frame k is time
 * code k. Translations are the frames' (USD interpolates them linearly). Orientations are the
 * frames', and samples between two frames where USD's interpolation would stray from the
 * simulated turn. USD interpolates quatd samples by slerp the short way round: exact for a spin
 * about a fixed axis, but it cuts the corner where the axis moves (precession, a contact) and
 * turns backwards past half a turn between samples. Between frames the simulated turn is taken
 * to be the curve glTF's CUBICSPLINE keys draw: the cubic Hermite spline through the two
 * quaternions with tangents the simulated dq/dt = 1/2 (0, omega) (x) q, normalised (its distance
 * from the simulation is measured in docs/export.md). A frame interval is cut into 2, 4, ... equal
 * pieces until the slerp of each piece meets the spline at the piece's middle within the
 * writer's sample_tolerance. Values are printed with 17 significant digits, which read back as
 * the doubles printed. */
#include "io/writer_internal.h"

#include "math/tb_math.h"

#include <math.h>
#include <string.h>

/* Pieces of a frame interval at most: a spin this far past the frame rate is past what the
 * spline follows anyway (docs/export.md). */
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

/* Whether slerp over each of count equal pieces meets the spline at the piece's middle. */
static bool pieces_follow(const key *a, const key *b, int count, double tolerance)
{
    double start[4], end[4], on[4], middle[4];
    spline(a, b, 0.0, start);
    for (int j = 0; j < count; ++j) {
        spline(a, b, (j + 1.0) / count, end);
        spline(a, b, (j + 0.5) / count, on);
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
    key a, b;
    key_of(&w->frames, k, id, &a);
    key_of(&w->frames, k + 1, id, &b);
    follow(&a, &b);
    int count = 1;
    while (count < TB__USD_MAX_PIECES && !pieces_follow(&a, &b, count, w->sample_tolerance)) {
        count *= 2;
    }
    const double first = tb__usd_time_code(a.t, w->fps), last = tb__usd_time_code(b.t, w->fps);
    for (int j = 1; j < count; ++j) {
        double q[4];
        spline(&a, &b, (double)j / count, q);
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
