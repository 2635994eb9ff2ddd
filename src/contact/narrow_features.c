/* A shape's support feature along a direction: the points of the shape within a band of its
 * farthest point along d, as the general pairs' manifold (narrow_general.c) clips them. Points
 * fixed in the body (a box's corners, a hull's vertices, a point set's spheres, a cylinder's 16
 * rim points at fixed angles) enter and leave the band continuously as the body turns, so the
 * manifold built from them does not jump; a face is three or more of them in one plane facing d,
 * a segment two (a capsule's or a lying cylinder's side), a point one (round shapes: the support
 * point itself). */
#include "contact/narrow_internal.h"

#include "math/tb_math.h"

/* Points of a face lie within this fraction of its size of one plane. */
#define COPLANAR 1e-9
/* A face is used when its normal is within about 8 degrees of d. */
#define FACE_ALIGNMENT 0.99

static void add_point(tb__feature *f, const double p[3], const double d[3])
{
    const double height = tb__v3_dot(p, d);
    int slot = f->count;
    if (slot == TB__FEATURE_MAX) { /* full: replace the lowest, if p is higher */
        slot = 0;
        for (int k = 1; k < TB__FEATURE_MAX; ++k) {
            slot = tb__v3_dot(f->points[k], d) < tb__v3_dot(f->points[slot], d) ? k : slot;
        }
        if (!(height > tb__v3_dot(f->points[slot], d))) {
            return;
        }
    } else {
        ++f->count;
    }
    tb__v3_copy(f->points[slot], p);
}

/* p = pose applied to local, plus lift along d; added if within band of the top. */
static void offer(tb__feature *f, const double pose[TB__POSE_SIZE], const double local[3],
                  double lift, const double d[3], double floor_height)
{
    double p[3];
    tb__q_rotate(p, pose + 3, local);
    tb__v3_axpy(p, 1.0, pose);
    tb__v3_axpy(p, lift, d);
    if (tb__v3_dot(p, d) >= floor_height) {
        add_point(f, p, d);
    }
}

/* The cylinder's fixed rim points (8 a circle, 45 degrees apart from shape x) in the band; when
 * fewer than 3, its side instead: the farthest point of each end circle in the band. */
static void cylinder_feature(const tb__collision_shape *s, const double pose[TB__POSE_SIZE],
                             const double d[3], double floor_height, tb__feature *f)
{
    for (int k = 0; k < 16; ++k) {
        const double angle = 0.78539816339744831 * (k % 8);
        const double local[3] = {s->radius * cos(angle), s->radius * sin(angle),
                                 (k < 8 ? -1.0 : 1.0) * s->half_length};
        offer(f, pose, local, 0.0, d, floor_height);
    }
    if (f->count >= 3) {
        return;
    }
    f->count = 0;
    double rim[8][3];
    tb__cylinder_rim_points(s, pose, d, rim);
    for (int k = 0; k < 8; k += 4) {
        if (tb__v3_dot(rim[k], d) >= floor_height) {
            add_point(f, rim[k], d);
        }
    }
}

static void gather(const tb__collision_shape *s, const double pose[TB__POSE_SIZE],
                   const double d[3], double floor_height, tb__feature *f)
{
    switch (s->type) {
    case TB_SHAPE_BOX:
        for (int k = 0; k < 8; ++k) {
            const double local[3] = {k & 1 ? s->half[0] : -s->half[0],
                                     k & 2 ? s->half[1] : -s->half[1],
                                     k & 4 ? s->half[2] : -s->half[2]};
            offer(f, pose, local, 0.0, d, floor_height);
        }
        break;
    case TB_SHAPE_CONVEX:
    case TB_SHAPE_POINTS:
        for (size_t i = 0; i < s->vertex_count; ++i) {
            offer(f, pose, s->vertices + 3 * i, s->radii != NULL ? s->radii[i] : 0.0, d,
                  floor_height);
        }
        break;
    case TB_SHAPE_CAPSULE:
        for (int k = 0; k < 2; ++k) {
            const double local[3] = {0.0, 0.0, (k ? 1.0 : -1.0) * s->half_length};
            offer(f, pose, local, s->radius, d, floor_height);
        }
        break;
    case TB_SHAPE_CYLINDER:
        cylinder_feature(s, pose, d, floor_height, f);
        break;
    default: /* round: the support point alone */
        break;
    }
    if (f->count == 0) {
        tb__collision_shape_support(s, pose, d, f->points[0]);
        f->count = 1;
    }
}

/* Whether the points span a plane: its unit normal (towards d) and offset. */
static bool plane_of(tb__feature *f, const double d[3])
{
    const double *p0 = f->points[0];
    int i1 = 0, i2 = 0;
    double far = 0.0, area = 0.0, e1[3] = {0, 0, 0};
    for (int k = 1; k < f->count; ++k) {
        const double e[3] = {f->points[k][0] - p0[0], f->points[k][1] - p0[1],
                             f->points[k][2] - p0[2]};
        if (tb__v3_dot(e, e) > far) {
            far = tb__v3_dot(e, e);
            i1 = k;
            tb__v3_copy(e1, e);
        }
    }
    for (int k = 1; k < f->count; ++k) {
        const double e[3] = {f->points[k][0] - p0[0], f->points[k][1] - p0[1],
                             f->points[k][2] - p0[2]};
        double c[3];
        tb__v3_cross(c, e1, e);
        if (tb__v3_norm(c) > area) {
            area = tb__v3_norm(c);
            i2 = k;
            tb__v3_copy(f->normal, c);
        }
    }
    if (i1 == 0 || i2 == 0 || !(area > 1e-6 * far)) {
        return false; /* collinear: a segment at most */
    }
    const double sign = tb__v3_dot(f->normal, d) < 0.0 ? -1.0 : 1.0;
    tb__v3_set(f->normal, sign * f->normal[0] / area, sign * f->normal[1] / area,
               sign * f->normal[2] / area);
    f->offset = tb__v3_dot(f->normal, p0);
    for (int k = 0; k < f->count; ++k) {
        if (fabs(tb__v3_dot(f->normal, f->points[k]) - f->offset) > COPLANAR * sqrt(far)) {
            return false;
        }
    }
    return true;
}

void tb__support_feature(const tb__collision_shape *s, const double pose[TB__POSE_SIZE],
                         const double d[3], double band, tb__feature *out)
{
    double top[3];
    tb__collision_shape_support(s, pose, d, top);
    out->count = 0;
    gather(s, pose, d, tb__v3_dot(top, d) - band, out);
    out->planar = out->count >= 3 && plane_of(out, d);
    out->face = out->planar && tb__v3_dot(out->normal, d) >= FACE_ALIGNMENT;
    if (!out->face && out->count > 2) {
        out->count = 0; /* neither a face nor a segment: the support point alone */
        tb__v3_copy(out->points[0], top);
        out->count = 1;
    }
}
