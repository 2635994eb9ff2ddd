/* A contact scene as plain data, the same for every engine of bench_peer_contact and of
 * bench_peer_pybullet.py: boxes and spheres (size, mass, pose, velocity), ground planes, one
 * material, gravity. tumble builds its own scene (bench_scenes.h, examples/scenes/dice.json);
 * this description is read back from it (peer_world_from_scene), so MuJoCo's model and
 * PyBullet's world (from peer_world_write_json) start from the same bodies, bit for bit. The
 * figures are measured from poses alone, the same code for every engine:
 *   deepest penetration: the largest overlap of two bodies (boxes by the separating axis test:
 *     the least overlap over the 15 axes is the depth; spheres by their centres' distance) or of
 *     a body below a plane (m);
 *   fastest body: the largest speed of a centre of mass (m/s). */
#ifndef TUMBLE_BENCH_PEER_WORLD_H
#define TUMBLE_BENCH_PEER_WORLD_H

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PEER_MAX_PLANES 5

typedef struct peer_body {
    int sphere;        /* 1: a sphere of radius half[0]; 0: a box of half edges half */
    double half[3];    /* m */
    double mass;       /* kg, uniform density */
    double x[3];       /* centre, world, m */
    double q[4];       /* shape -> world, (w, x, y, z) */
    double v[3], w[3]; /* linear and angular velocity, world, m/s and rad/s */
} peer_body;

typedef struct peer_world {
    size_t count;
    peer_body *bodies;
    size_t planes;
    double normal[PEER_MAX_PLANES][3], offset[PEER_MAX_PLANES]; /* inside: n . x >= offset */
    double gravity;                                             /* along z, m/s^2 */
    double restitution;                                         /* the material's e */
    double friction; /* one coefficient for the peers: tumble's kinetic mu_k */
} peer_world;

/* Rotation matrix (row-major) of a unit quaternion (w, x, y, z). */
static inline void peer_rotation(const double q[4], double R[9])
{
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    R[0] = 1 - 2 * (y * y + z * z), R[1] = 2 * (x * y - w * z), R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z), R[4] = 1 - 2 * (x * x + z * z), R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y), R[7] = 2 * (y * z + w * x), R[8] = 1 - 2 * (x * x + y * y);
}

/* The bodies of a tumble scene (every body a box or a sphere at its shape origin), read at its
 * current state; planes, gravity and material are the caller's. 0 on success. */
static inline int peer_world_from_scene(const tb_scene *scene, peer_world *out)
{
    const double *y = tb_scene_states_const(scene);
    out->count = tb_scene_body_count(scene);
    out->bodies = calloc(out->count > 0 ? out->count : 1, sizeof *out->bodies);
    for (size_t i = 0; out->bodies != NULL && i < out->count; ++i) {
        peer_body *b = &out->bodies[i];
        tb_shape_piece piece;
        tb_mass_properties mass;
        if (tb_scene_body_piece(scene, i, 0, &piece) != TB_STATUS_OK ||
            tb_scene_get_mass(scene, i, &mass) != TB_STATUS_OK) {
            return 1;
        }
        b->sphere = piece.shape.type == TB_SHAPE_SPHERE;
        for (int k = 0; k < 3; ++k) {
            b->half[k] = b->sphere ? piece.shape.radius : 0.5 * piece.shape.size[k];
        }
        b->mass = mass.mass;
        tb_scene_body_shape_pose(scene, y, i, b->x, b->q);
        tb_scene_body_shape_velocity(scene, y, i, b->v);
        tb_scene_body_angular_velocity(scene, y, i, b->w);
    }
    return out->bodies == NULL;
}

static inline void peer_world_free(peer_world *world)
{
    free(world->bodies);
    world->bodies = NULL;
}

static inline void peer_write_vector(FILE *out, const char *name, const double *v, int n)
{
    fprintf(out, "\"%s\": [", name);
    for (int k = 0; k < n; ++k) {
        fprintf(out, "%s%.17g", k > 0 ? ", " : "", v[k]);
    }
    fprintf(out, "]");
}

/* The world as one JSON object (what bench_peer_pybullet.py reads), with the case's name, the
 * span (s) and the interval between samples of the figures (s). */
static inline void peer_world_write_json(FILE *out, const char *name, double duration,
                                         double sample, const peer_world *w)
{
    fprintf(out,
            "{\"case\": \"%s\", \"duration\": %.17g, \"sample\": %.17g, \"gravity\": %.17g, "
            "\"restitution\": %.17g, \"friction\": %.17g,\n \"planes\": [",
            name, duration, sample, w->gravity, w->restitution, w->friction);
    for (size_t k = 0; k < w->planes; ++k) {
        fprintf(out, "%s{", k > 0 ? ", " : "");
        peer_write_vector(out, "normal", w->normal[k], 3);
        fprintf(out, ", \"offset\": %.17g}", w->offset[k]);
    }
    fprintf(out, "],\n \"bodies\": [");
    for (size_t i = 0; i < w->count; ++i) {
        const peer_body *b = &w->bodies[i];
        fprintf(out, "%s\n  {\"type\": \"%s\", \"mass\": %.17g, ", i > 0 ? "," : "",
                b->sphere ? "sphere" : "box", b->mass);
        peer_write_vector(out, "half", b->half, 3);
        fprintf(out, ", ");
        peer_write_vector(out, "x", b->x, 3);
        fprintf(out, ", ");
        peer_write_vector(out, "q", b->q, 4);
        fprintf(out, ", ");
        peer_write_vector(out, "v", b->v, 3);
        fprintf(out, ", ");
        peer_write_vector(out, "w", b->w, 3);
        fprintf(out, "}");
    }
    fprintf(out, "]}");
}

/* --- the figures from poses: x[3 i], R[9 i] (row-major, shape -> world) ------------------- */

static inline double peer_dot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Half the extent of box (half edges h, axes the columns of R) along unit axis L. */
static inline double peer_box_reach(const double *h, const double *R, const double *L)
{
    double reach = 0.0;
    for (int k = 0; k < 3; ++k) {
        reach += h[k] * fabs(R[k] * L[0] + R[3 + k] * L[1] + R[6 + k] * L[2]);
    }
    return reach;
}

/* Overlap of two boxes: the least overlap over the separating axis test's 15 axes (each box's
 * 3 axes and their 9 cross products), <= 0 when apart. */
static inline double peer_box_overlap(const double *ha, const double *xa, const double *Ra,
                                      const double *hb, const double *xb, const double *Rb)
{
    const double d[3] = {xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]};
    double least = INFINITY;
    for (int a = 0; a < 15; ++a) {
        double L[3];
        if (a < 6) {
            const double *R = a < 3 ? Ra : Rb;
            L[0] = R[a % 3], L[1] = R[3 + a % 3], L[2] = R[6 + a % 3];
        } else {
            const int i = (a - 6) / 3, j = (a - 6) % 3;
            const double u[3] = {Ra[i], Ra[3 + i], Ra[6 + i]}, v[3] = {Rb[j], Rb[3 + j], Rb[6 + j]};
            L[0] = u[1] * v[2] - u[2] * v[1], L[1] = u[2] * v[0] - u[0] * v[2];
            L[2] = u[0] * v[1] - u[1] * v[0];
            const double n = sqrt(peer_dot(L, L));
            if (n < 1e-9) { /* parallel edges: the face axes decide */
                continue;
            }
            L[0] /= n, L[1] /= n, L[2] /= n;
        }
        const double overlap =
            peer_box_reach(ha, Ra, L) + peer_box_reach(hb, Rb, L) - fabs(peer_dot(d, L));
        least = fmin(least, overlap);
    }
    return least;
}

/* Depth of body i below plane k (<= 0 above it). */
static inline double peer_plane_depth(const peer_world *w, size_t i, size_t k, const double *x,
                                      const double *R)
{
    const peer_body *b = &w->bodies[i];
    const double *n = w->normal[k];
    const double reach = b->sphere ? b->half[0] : peer_box_reach(b->half, R, n);
    return w->offset[k] - (peer_dot(n, x) - reach);
}

/* The deepest penetration at one pose of every body: pairs (bounding spheres first) and planes. */
static inline double peer_deepest(const peer_world *w, const double *x, const double *R)
{
    double deepest = 0.0;
    for (size_t i = 0; i < w->count; ++i) {
        const peer_body *a = &w->bodies[i];
        for (size_t k = 0; k < w->planes; ++k) {
            deepest = fmax(deepest, peer_plane_depth(w, i, k, x + 3 * i, R + 9 * i));
        }
        const double ra = a->sphere ? a->half[0] : sqrt(peer_dot(a->half, a->half));
        for (size_t j = i + 1; j < w->count; ++j) {
            const peer_body *b = &w->bodies[j];
            const double rb = b->sphere ? b->half[0] : sqrt(peer_dot(b->half, b->half));
            const double d[3] = {x[3 * j] - x[3 * i], x[3 * j + 1] - x[3 * i + 1],
                                 x[3 * j + 2] - x[3 * i + 2]};
            const double distance = sqrt(peer_dot(d, d));
            if (distance >= ra + rb) {
                continue;
            }
            if (a->sphere && b->sphere) {
                deepest = fmax(deepest, ra + rb - distance);
            } else if (!a->sphere && !b->sphere) {
                deepest = fmax(deepest, peer_box_overlap(a->half, x + 3 * i, R + 9 * i, b->half,
                                                         x + 3 * j, R + 9 * j));
            } /* a sphere against a box: none in these scenes */
        }
    }
    return deepest;
}

/* The fastest of count speeds v[3 i] (m/s). */
static inline double peer_fastest(size_t count, const double *v)
{
    double fastest = 0.0;
    for (size_t i = 0; i < count; ++i) {
        fastest = fmax(fastest, sqrt(peer_dot(v + 3 * i, v + 3 * i)));
    }
    return fastest;
}

/* What the samples of one run found: the deepest penetration over them, the fastest body over
 * those in the last second of the span (the last sample's when the span is under 2 s), the
 * ball's impact (most negative v_z) and the fastest rise after it. */
typedef struct peer_track {
    double deepest, fastest, impact, rebound;
} peer_track;

static inline peer_track peer_track_start(void)
{
    return (peer_track){0.0, 0.0, 0.0, 0.0};
}

/* One sample at time t of a span `duration`: poses x, R, speeds v of every body. */
static inline void peer_track_sample(peer_track *track, const peer_world *w, double t,
                                     double duration, const double *x, const double *R,
                                     const double *v)
{
    track->deepest = fmax(track->deepest, peer_deepest(w, x, R));
    const double window = duration >= 2.0 ? 1.0 : 0.0;
    if (t >= duration - window - 1e-9) {
        track->fastest = fmax(track->fastest, peer_fastest(w->count, v));
    }
    if (v[2] < track->impact) { /* body 0's vertical velocity: the ball's bounce */
        track->impact = v[2];
        track->rebound = 0.0;
    }
    track->rebound = fmax(track->rebound, v[2]);
}

#endif
