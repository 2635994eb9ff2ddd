/* Pairs without a closed form (a cylinder, ellipsoid, convex hull or point set against anything
 * but a plane and a sphere-swept shape's closed forms): libccd's MPR gives the normal and the
 * overlap along it; then each shape's support feature along the normal (narrow_features.c: the
 * points within the overlap plus the margin of its farthest one) is found, and where one of them
 * is a face (a box's, a hull's, a cylinder's end, a point set's), the other's feature (a face, a
 * segment or a point) is clipped to it as the box pairs clip their faces: every point that
 * remains is a contact whose depth is measured from that face's plane, with the face's normal.
 * Features are fixed in the bodies and enter at the margin, where they push with no force, so the
 * manifold of a can standing on a can, or a hull on a hull, moves continuously with the poses.
 * Without a face (an edge across an edge, round shapes): MPR's single point. */
#include "contact/narrow_internal.h"

#include "contact/ccd_wrap.h"
#include "math/tb_math.h"

/* Points a clipped polygon can hold: the incident feature plus one per reference edge. */
#define CLIP_MAX (2 * TB__FEATURE_MAX + 2)

/* Two unit vectors spanning the plane normal to unit m. */
static void plane_basis(const double m[3], double u[3], double v[3])
{
    const double *helper = fabs(m[0]) < 0.6 ? (const double[]){1, 0, 0} : (const double[]){0, 1, 0};
    tb__v3_cross(u, m, helper);
    const double length = tb__v3_norm(u);
    tb__v3_set(u, u[0] / length, u[1] / length, u[2] / length);
    tb__v3_cross(v, m, u);
}

/* The feature's points in counter-clockwise order about m (viewed from m's tip) as their
 * convex hull in the plane normal to m (gift wrapping); returns the hull's count. */
static int ordered_hull(const tb__feature *f, const double m[3], double out[][3])
{
    double u[3], v[3], x[TB__FEATURE_MAX], y[TB__FEATURE_MAX];
    plane_basis(m, u, v);
    int start = 0;
    for (int k = 0; k < f->count; ++k) {
        x[k] = tb__v3_dot(f->points[k], u);
        y[k] = tb__v3_dot(f->points[k], v);
        start = x[k] < x[start] || (x[k] == x[start] && y[k] < y[start]) ? k : start;
    }
    int count = 0, current = start;
    do {
        tb__v3_copy(out[count++], f->points[current]);
        int next = current == 0 ? 1 : 0;
        for (int k = 0; k < f->count; ++k) {
            const double cross = (x[next] - x[current]) * (y[k] - y[current]) -
                                 (y[next] - y[current]) * (x[k] - x[current]);
            const double along = (x[k] - x[current]) * (x[k] - x[current]) +
                                 (y[k] - y[current]) * (y[k] - y[current]);
            const double next_along = (x[next] - x[current]) * (x[next] - x[current]) +
                                      (y[next] - y[current]) * (y[next] - y[current]);
            if (k != current && (cross < 0.0 || (cross == 0.0 && along > next_along))) {
                next = k; /* k lies clockwise of next: wrap tighter */
            }
        }
        current = next;
    } while (current != start && count < f->count);
    return count;
}

/* Keeps the part of polygon poly (count points; 2: a segment, 1: a point) on the inner side
 * of the plane through o with inward normal w; returns the new count. */
static int clip_half(double poly[][3], int count, const double o[3], const double w[3])
{
    double out[CLIP_MAX][3];
    int kept = 0;
    const int edges = count == 2 ? 1 : count;
    for (int i = 0; i < edges || (count == 1 && i == 0); ++i) {
        const double *p = poly[i], *q = poly[(i + 1) % count];
        const double dp = tb__v3_dot(w, p) - tb__v3_dot(w, o);
        const double dq = tb__v3_dot(w, q) - tb__v3_dot(w, o);
        if (dp >= 0.0 && kept < CLIP_MAX) {
            tb__v3_copy(out[kept++], p);
        }
        if (((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) && kept < CLIP_MAX) {
            const double s = dp / (dp - dq);
            tb__v3_set(out[kept++], p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]),
                       p[2] + s * (q[2] - p[2]));
        }
        if (count == 2 && dq >= 0.0 && kept < CLIP_MAX) {
            tb__v3_copy(out[kept++], q); /* a segment's far end */
        }
    }
    for (int i = 0; i < kept; ++i) {
        tb__v3_copy(poly[i], out[i]);
    }
    return kept;
}

/* The incident feature clipped to the reference face, each point a candidate of depth measured
 * from the face's plane; ref_is_a says which shape the face is A's. */
static void clip_to_face(const tb__feature *ref, const tb__feature *inc, bool ref_is_a,
                         double margin, tb__candidates *out, double n[3])
{
    double face[TB__FEATURE_MAX][3], poly[CLIP_MAX][3];
    const int sides = ordered_hull(ref, ref->normal, face);
    int count = inc->count;
    if (inc->face) {
        count = ordered_hull(inc, inc->normal, poly);
    } else {
        for (int k = 0; k < count; ++k) {
            tb__v3_copy(poly[k], inc->points[k]);
        }
    }
    for (int i = 0; i < sides && count > 0; ++i) {
        const double *p = face[i], *q = face[(i + 1) % sides];
        const double edge[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double inward[3];
        tb__v3_cross(inward, ref->normal, edge);
        count = clip_half(poly, count, p, inward);
    }
    const double sign = ref_is_a ? 1.0 : -1.0;
    tb__v3_set(n, sign * ref->normal[0], sign * ref->normal[1], sign * ref->normal[2]);
    for (int k = 0; k < count; ++k) {
        const double depth = ref->offset - tb__v3_dot(ref->normal, poly[k]);
        double p_a[3];
        tb__v3_copy(p_a, poly[k]);
        if (ref_is_a) {
            tb__v3_axpy(p_a, depth, n); /* B's point lifted onto A's face */
        }
        tb__candidate_add(out, n, p_a, depth, margin);
    }
}

int tb__general_collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                        const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                        double margin, tb__contact_manifold *out)
{
    if (tb__ccd_collide(a, pose_a, b, pose_b, margin, TB__CCD_MPR, out) <= 0) {
        out->count = 0;
        return 0;
    }
    const double *n = out->normal, minus_n[3] = {-n[0], -n[1], -n[2]};
    const double band = out->points[0].depth + margin; /* > 0: the depth exceeds -margin */
    tb__feature fa, fb;
    tb__support_feature(a, pose_a, n, band, &fa);
    tb__support_feature(b, pose_b, minus_n, band, &fb);
    if (!fa.face && !fb.face) {
        return out->count; /* MPR's point */
    }
    /* the reference: the face nearer to facing along the normal */
    const bool ref_is_a =
        fa.face && (!fb.face || tb__v3_dot(fa.normal, n) >= tb__v3_dot(fb.normal, minus_n));
    tb__candidates c = {0};
    double normal[3];
    clip_to_face(ref_is_a ? &fa : &fb, ref_is_a ? &fb : &fa, ref_is_a, margin, &c, normal);
    if (c.count == 0) {
        return out->count; /* the features do not overlap across the normal: MPR's point */
    }
    return tb__reduce_candidates(&c, normal, out);
}
