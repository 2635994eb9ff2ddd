/* The narrow phase's dispatch, the sphere-swept pairs (sphere and capsule: a point or a segment
 * grown by a radius, so every pair is two spheres at the closest points of their cores) and the
 * helpers the pair routines share. Pairs are solved in a canonical order (by type, then by
 * pose and size), so swapping A and B gives exactly the negated normal and the same points. */
#include "contact/narrow_internal.h"

#include "math/tb_math.h"

#include <string.h>

void tb__candidate_add(tb__candidates *c, const double n[3], const double p_a[3], double depth,
                       double margin)
{
    if (depth > -margin && c->count < TB__CANDIDATES_MAX) {
        tb__contact_point *p = &c->points[c->count++];
        tb__v3_copy(p->position, p_a);
        tb__v3_axpy(p->position, -0.5 * depth, n);
        p->depth = depth;
    }
}

static double distance2(const double a[3], const double b[3])
{
    const double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return tb__v3_dot(d, d);
}

/* Twice the area of the triangle a, b, c projected on the plane of n, signed by n. */
static double signed_area(const double a[3], const double b[3], const double c[3],
                          const double n[3])
{
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double cross[3];
    tb__v3_cross(cross, ab, ac);
    return tb__v3_dot(cross, n);
}

/* The index maximising score among candidates not yet taken (-1 if none). */
static int pick(const tb__candidates *c, const bool *taken, const int *chosen, const double n[3],
                int rule)
{
    int best = -1;
    double best_score = -INFINITY;
    for (int i = 0; i < c->count; ++i) {
        const double *p = c->points[i].position;
        const double score = rule == 0   ? c->points[i].depth
                             : rule == 1 ? distance2(p, c->points[chosen[0]].position)
                                         : (rule == 2 ? 1.0 : -1.0) *
                                               signed_area(c->points[chosen[0]].position,
                                                           c->points[chosen[1]].position, p, n);
        if (!taken[i] && (score > best_score || best < 0)) { /* NaN scores: the first */
            best_score = score;
            best = i;
        }
    }
    return best;
}

int tb__reduce_candidates(const tb__candidates *c, const double n[3], tb__contact_manifold *out)
{
    tb__v3_copy(out->normal, n);
    if (c->count <= TB__MANIFOLD_POINTS) {
        memcpy(out->points, c->points, (size_t)c->count * sizeof c->points[0]);
        out->count = c->count;
        return out->count;
    }
    bool taken[TB__CANDIDATES_MAX] = {false};
    int chosen[TB__MANIFOLD_POINTS];
    for (int k = 0; k < TB__MANIFOLD_POINTS; ++k) {
        chosen[k] = pick(c, taken, chosen, n, k);
        taken[chosen[k]] = true;
        out->points[k] = c->points[chosen[k]];
    }
    out->count = TB__MANIFOLD_POINTS;
    return out->count;
}

int tb__spheres(const double c_a[3], double r_a, const double c_b[3], double r_b,
                const double fallback[3], double margin, tb__contact_manifold *out)
{
    double n[3] = {c_b[0] - c_a[0], c_b[1] - c_a[1], c_b[2] - c_a[2]};
    const double reach = r_a + r_b + margin, distance2 = tb__v3_dot(n, n);
    if (distance2 > reach * reach * (1.0 + 1e-12)) {
        /* farther apart than the margin by more than round-off (the depth computed below would
         * be at most -margin): no point, and the normal, unspecified then, is not worked out */
        out->count = 0;
        return 0;
    }
    const double distance = sqrt(distance2);
    if (distance > 0.0) {
        tb__v3_set(n, n[0] / distance, n[1] / distance, n[2] / distance);
    } else {
        tb__v3_copy(n, fallback);
    }
    tb__candidates c;
    c.count = 0;
    double p_a[3];
    tb__v3_copy(p_a, c_a);
    tb__v3_axpy(p_a, r_a, n);
    tb__candidate_add(&c, n, p_a, r_a + r_b - distance, margin);
    return tb__reduce_candidates(&c, n, out);
}

void tb__segments_closest(const double p0[3], const double p1[3], const double q0[3],
                          const double q1[3], double *out_s, double *out_t)
{
    /* Minimises |p0 + s d1 - q0 - t d2|^2 over the unit square (Ericson, Real-Time Collision
     * Detection, 5.1.9): the unconstrained s for t's line, clamped, then t, clamped, then s. */
    const double d1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    const double d2[3] = {q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]};
    const double r[3] = {p0[0] - q0[0], p0[1] - q0[1], p0[2] - q0[2]};
    const double a = tb__v3_dot(d1, d1), e = tb__v3_dot(d2, d2), f = tb__v3_dot(d2, r);
    const double c = tb__v3_dot(d1, r), b = tb__v3_dot(d1, d2);
    const double denominator = a * e - b * b; /* >= 0; 0 when parallel */
    double s = 0.0, t = 0.0;
    if (a > 0.0 && e > 0.0) {
        s = denominator > 1e-12 * a * e
                ? fmin(fmax((b * f - c * e) / denominator, 0.0), 1.0)
                : 0.5 * (fmin(fmax(-c / a, 0.0), 1.0) + fmin(fmax((b - c) / a, 0.0), 1.0));
        t = (b * s + f) / e;
        if (t < 0.0 || t > 1.0) {
            t = fmin(fmax(t, 0.0), 1.0);
            s = fmin(fmax((b * t - c) / a, 0.0), 1.0);
        }
    } else if (a > 0.0) {
        s = fmin(fmax(-c / a, 0.0), 1.0);
    } else if (e > 0.0) {
        t = fmin(fmax(f / e, 0.0), 1.0);
    }
    *out_s = s;
    *out_t = t;
}

void tb__capsule_ends(const tb__collision_shape *capsule, const double pose[TB__POSE_SIZE],
                      double out_p0[3], double out_p1[3])
{
    double axis[3];
    tb__q_rotate(axis, pose + 3, (const double[]){0.0, 0.0, capsule->half_length});
    tb__v3_copy(out_p0, pose);
    tb__v3_axpy(out_p0, -1.0, axis);
    tb__v3_copy(out_p1, pose);
    tb__v3_axpy(out_p1, 1.0, axis);
}

static void lerp(double out[3], const double a[3], const double b[3], double s)
{
    tb__v3_set(out, a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]));
}

static const double world_up[3] = {0.0, 0.0, 1.0};

static int sphere_capsule(const double c[3], double r, const tb__collision_shape *capsule,
                          const double pose[TB__POSE_SIZE], double margin,
                          tb__contact_manifold *out)
{
    double p0[3], p1[3], s, t, closest[3];
    tb__capsule_ends(capsule, pose, p0, p1);
    tb__segments_closest(c, c, p0, p1, &s, &t);
    lerp(closest, p0, p1, t);
    return tb__spheres(c, r, closest, capsule->radius, world_up, margin, out);
}

/* Capsules lying side by side rest along their length: each segment end (ends[0..2) B's,
 * [2..4) A's) against the other segment is a candidate too, with the closest pair's normal. An
 * end enters at depth -margin, so crossing capsules keep one point and parallel ones gain the
 * ends of their overlap continuously. */
static int capsule_ends(const double *ends[4], double radii, double radius_a, double margin,
                        tb__contact_manifold *out)
{
    tb__candidates c;
    c.count = 1;
    c.points[0] = out->points[0];
    const double *n = out->normal, *p0 = ends[2], *p1 = ends[3], *q0 = ends[0], *q1 = ends[1];
    for (int e = 0; e < 4; ++e) {
        const double *end = ends[e];
        double s, t, on_a[3], on_b[3];
        e < 2 ? tb__segments_closest(p0, p1, end, end, &s, &t)
              : tb__segments_closest(end, end, q0, q1, &s, &t);
        lerp(on_a, e < 2 ? p0 : end, e < 2 ? p1 : end, s);
        lerp(on_b, e < 2 ? end : q0, e < 2 ? end : q1, t);
        double p_a[3], gap[3] = {on_b[0] - on_a[0], on_b[1] - on_a[1], on_b[2] - on_a[2]};
        tb__v3_copy(p_a, on_a);
        tb__v3_axpy(p_a, radius_a, n);
        const double depth = radii - tb__v3_norm(gap);
        double position[3];
        tb__v3_copy(position, p_a);
        tb__v3_axpy(position, -0.5 * depth, n);
        bool known = false;
        for (int k = 0; k < c.count; ++k) {
            known |= distance2(position, c.points[k].position) <= 1e-18 * radii * radii;
        }
        if (!known) {
            tb__candidate_add(&c, n, p_a, depth, margin);
        }
    }
    return tb__reduce_candidates(&c, n, out);
}

static int capsule_capsule(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                           const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                           double margin, tb__contact_manifold *out)
{
    double p0[3], p1[3], q0[3], q1[3], s, t, ca[3], cb[3];
    tb__capsule_ends(a, pose_a, p0, p1);
    tb__capsule_ends(b, pose_b, q0, q1);
    tb__segments_closest(p0, p1, q0, q1, &s, &t);
    lerp(ca, p0, p1, s);
    lerp(cb, q0, q1, t);
    /* Crossing segments: the common perpendicular of the axes, pointing from A to B. */
    double axis_a[3], axis_b[3], fallback[3];
    tb__q_rotate(axis_a, pose_a + 3, world_up);
    tb__q_rotate(axis_b, pose_b + 3, world_up);
    tb__v3_cross(fallback, axis_a, axis_b);
    const double length = tb__v3_norm(fallback);
    const double toward[3] = {pose_b[0] - pose_a[0], pose_b[1] - pose_a[1], pose_b[2] - pose_a[2]};
    const double sign = tb__v3_dot(fallback, toward) < 0.0 ? -1.0 : 1.0;
    if (length > 0.0) {
        tb__v3_set(fallback, sign * fallback[0] / length, sign * fallback[1] / length,
                   sign * fallback[2] / length);
    } else {
        tb__v3_copy(fallback, world_up);
    }
    if (tb__spheres(ca, a->radius, cb, b->radius, fallback, margin, out) == 0) {
        return 0;
    }
    const double *ends[4] = {q0, q1, p0, p1};
    return capsule_ends(ends, a->radius + b->radius, a->radius, margin, out);
}

void tb__cylinder_rim_points(const tb__collision_shape *cylinder, const double pose[TB__POSE_SIZE],
                             const double d[3], double out[8][3])
{
    double local_d[3], far[3], side[3];
    tb__q_rotate_inverse(local_d, pose + 3, d);
    const double rho = hypot(local_d[0], local_d[1]);
    tb__v3_set(far, rho > 1e-12 ? local_d[0] / rho : 1.0, rho > 1e-12 ? local_d[1] / rho : 0.0,
               0.0);
    tb__v3_set(side, -far[1], far[0], 0.0); /* 90 degrees on */
    for (int k = 0; k < 8; ++k) {
        const double c = k % 4 == 0 ? 1.0 : k % 4 == 2 ? -1.0 : 0.0;
        const double s = k % 4 == 1 ? 1.0 : k % 4 == 3 ? -1.0 : 0.0;
        double local[3];
        for (int i = 0; i < 2; ++i) {
            local[i] = cylinder->radius * (c * far[i] + s * side[i]);
        }
        local[2] = (k < 4 ? -1.0 : 1.0) * cylinder->half_length;
        tb__q_rotate(out[k], pose + 3, local);
        tb__v3_axpy(out[k], 1.0, pose);
    }
}

/* Solving order: sphere, capsule, box, then the libccd types by their enum value. */
static int rank(tb_shape_type type)
{
    return type == TB_SHAPE_SPHERE    ? 0
           : type == TB_SHAPE_CAPSULE ? 1
           : type == TB_SHAPE_BOX     ? 2
                                      : 3 + (int)type;
}

static bool solve_swapped(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                          const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE])
{
    if (rank(a->type) != rank(b->type)) {
        return rank(a->type) > rank(b->type);
    }
    for (int k = 0; k < TB__POSE_SIZE; ++k) { /* by value: the order changes only when the */
        if (pose_a[k] != pose_b[k]) {         /* shapes' x (then y, ...) cross */
            return pose_a[k] > pose_b[k];
        }
    }
    const double sizes_a[5] = {a->radius, a->half_length, a->half[0], a->half[1], a->half[2]};
    const double sizes_b[5] = {b->radius, b->half_length, b->half[0], b->half[1], b->half[2]};
    for (int k = 0; k < 5; ++k) {
        if (sizes_a[k] != sizes_b[k]) {
            return sizes_a[k] > sizes_b[k];
        }
    }
    return false; /* the same shape at the same pose: either order */
}

/* The pair routines, each for A ranked before B (rank()): normal from A to B. */
typedef int (*pair_function)(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                             const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                             double margin, tb__contact_manifold *out);

static int sphere_sphere(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                         const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                         double margin, tb__contact_manifold *out)
{
    return tb__spheres(pose_a, a->radius, pose_b, b->radius, world_up, margin, out);
}

static int sphere_capsule_pair(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                               const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                               double margin, tb__contact_manifold *out)
{
    return sphere_capsule(pose_a, a->radius, b, pose_b, margin, out);
}

static void flip(tb__contact_manifold *out)
{
    tb__v3_set(out->normal, -out->normal[0], -out->normal[1], -out->normal[2]);
}

/* The box routines take the box as A: solved so, then the normal turned round. */
static int sphere_box(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                      double margin, tb__contact_manifold *out)
{
    const int count = tb__box_sphere(b, pose_b, pose_a, a->radius, margin, out);
    flip(out);
    return count;
}

static int capsule_box(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                       double margin, tb__contact_manifold *out)
{
    const int count = tb__box_capsule(b, pose_b, a, pose_a, margin, out);
    flip(out);
    return count;
}

#define GENERAL tb__general_collide
/* Every pair of shape types, as MuJoCo's mjCOLLISIONFUNC: row A, column B, A ranked before B
 * (the other half is never read). Closed forms for spheres, capsules and boxes among
 * themselves; libccd's normal with clipped support features for the rest (narrow_general.c). */
static const pair_function pair_table[TB_SHAPE_POINTS + 1][TB_SHAPE_POINTS + 1] = {
    [TB_SHAPE_SPHERE] = {[TB_SHAPE_SPHERE] = sphere_sphere,
                         [TB_SHAPE_BOX] = sphere_box,
                         [TB_SHAPE_CAPSULE] = sphere_capsule_pair,
                         [TB_SHAPE_CYLINDER] = GENERAL,
                         [TB_SHAPE_ELLIPSOID] = GENERAL,
                         [TB_SHAPE_CONVEX] = GENERAL,
                         [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_CAPSULE] = {[TB_SHAPE_BOX] = capsule_box,
                          [TB_SHAPE_CAPSULE] = capsule_capsule,
                          [TB_SHAPE_CYLINDER] = GENERAL,
                          [TB_SHAPE_ELLIPSOID] = GENERAL,
                          [TB_SHAPE_CONVEX] = GENERAL,
                          [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_BOX] = {[TB_SHAPE_BOX] = tb__box_box,
                      [TB_SHAPE_CYLINDER] = GENERAL,
                      [TB_SHAPE_ELLIPSOID] = GENERAL,
                      [TB_SHAPE_CONVEX] = GENERAL,
                      [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_CYLINDER] = {[TB_SHAPE_CYLINDER] = GENERAL,
                           [TB_SHAPE_ELLIPSOID] = GENERAL,
                           [TB_SHAPE_CONVEX] = GENERAL,
                           [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_ELLIPSOID] =
        {[TB_SHAPE_ELLIPSOID] = GENERAL, [TB_SHAPE_CONVEX] = GENERAL, [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_CONVEX] = {[TB_SHAPE_CONVEX] = GENERAL, [TB_SHAPE_POINTS] = GENERAL},
    [TB_SHAPE_POINTS] = {[TB_SHAPE_POINTS] = GENERAL},
};
#undef GENERAL

static int ordered(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                   const tb__box_frame *frame_a, const tb__collision_shape *b,
                   const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b, double margin,
                   tb__contact_manifold *out)
{
    const bool known = a->type > TB_SHAPE_NONE && a->type <= TB_SHAPE_POINTS &&
                       b->type > TB_SHAPE_NONE && b->type <= TB_SHAPE_POINTS;
    const pair_function solve = known ? pair_table[a->type][b->type] : NULL;
    if (solve == NULL) {
        out->count = 0; /* no shape: nothing touches */
        return 0;
    }
    if (solve == tb__box_box) { /* the frames given, if any */
        return tb__box_box_framed(a, pose_a, frame_a, b, pose_b, frame_b, margin, out);
    }
    return solve(a, pose_a, b, pose_b, margin, out);
}

int tb__collide_framed(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       double margin, tb__contact_manifold *out)
{
    if (!solve_swapped(a, pose_a, b, pose_b)) {
        return ordered(a, pose_a, frame_a, b, pose_b, frame_b, margin, out);
    }
    const int count = ordered(b, pose_b, frame_b, a, pose_a, frame_a, margin, out);
    tb__v3_set(out->normal, -out->normal[0], -out->normal[1], -out->normal[2]);
    return count;
}

int tb__collide_below(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__box_frame *frame_a, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                      double level, double margin, tb__contact_manifold *out)
{
    if (a->type != TB_SHAPE_BOX || b->type != TB_SHAPE_BOX) {
        return tb__collide_framed(a, pose_a, frame_a, b, pose_b, frame_b, margin, out);
    }
    if (!solve_swapped(a, pose_a, b, pose_b)) { /* the order tb__collide_framed solves in */
        return tb__box_box_below(a, pose_a, frame_a, b, pose_b, frame_b, level, margin, out);
    }
    const int count = tb__box_box_below(b, pose_b, frame_b, a, pose_a, frame_a, level, margin, out);
    tb__v3_set(out->normal, -out->normal[0], -out->normal[1], -out->normal[2]);
    return count;
}

int tb__collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                tb__contact_manifold *out)
{
    return tb__collide_framed(a, pose_a, NULL, b, pose_b, NULL, margin, out);
}
