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

/* Two unit vectors spanning the reference face, fixed in its body (shape x projected on the
 * face, or shape y where x is within 45 degrees of the face's normal m), so that the rule's
 * points below turn with the body and not with the normal's round-off. */
static void face_basis(const double q[4], const double m[3], double u[3], double v[3])
{
    double axis[3];
    tb__q_rotate(axis, q, (const double[]){1.0, 0.0, 0.0});
    if (fabs(tb__v3_dot(axis, m)) > 0.7) {
        tb__q_rotate(axis, q, (const double[]){0.0, 1.0, 0.0});
    }
    tb__v3_copy(u, axis);
    tb__v3_axpy(u, -tb__v3_dot(axis, m), m);
    const double length = tb__v3_norm(u);
    tb__v3_set(u, u[0] / length, u[1] / length, u[2] / length);
    tb__v3_cross(v, m, u);
}

/* The region's points in the face's coordinates (x, y) and their depths. */
typedef struct region {
    int count;
    double x[CLIP_MAX], y[CLIP_MAX], depth[CLIP_MAX];
} region;

/* Centroid (cx, cy) and central second moments per area m[3] = (xx, xy, yy) of the region: a
 * polygon's exact ones; a segment's (uniform along it) when it has 2 points or no area. */
static void region_moments(const region *r, double c[2], double m[3])
{
    double area = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, syy = 0.0, extent = 0.0;
    int i0 = 0, i1 = 0;
    for (int i = 0; i < r->count; ++i) {
        const int j = (i + 1) % r->count;
        const double xi = r->x[i], yi = r->y[i], xj = r->x[j], yj = r->y[j];
        const double w = xi * yj - xj * yi;
        area += 0.5 * w;
        sx += (xi + xj) * w / 6.0;
        sy += (yi + yj) * w / 6.0;
        sxx += (xi * xi + xi * xj + xj * xj) * w / 12.0;
        syy += (yi * yi + yi * yj + yj * yj) * w / 12.0;
        sxy += (xi * yj + 2.0 * xi * yi + 2.0 * xj * yj + xj * yi) * w / 24.0;
        for (int k = 0; k < r->count; ++k) {
            const double d2 = (r->x[k] - xi) * (r->x[k] - xi) + (r->y[k] - yi) * (r->y[k] - yi);
            if (d2 > extent) {
                extent = d2, i0 = i, i1 = k;
            }
        }
    }
    if (r->count >= 3 && fabs(area) > 1e-9 * extent) {
        c[0] = sx / area, c[1] = sy / area;
        m[0] = sxx / area - c[0] * c[0];
        m[1] = sxy / area - c[0] * c[1];
        m[2] = syy / area - c[1] * c[1];
        return;
    }
    const double dx = r->x[i1] - r->x[i0], dy = r->y[i1] - r->y[i0];
    c[0] = 0.5 * (r->x[i0] + r->x[i1]), c[1] = 0.5 * (r->y[i0] + r->y[i1]);
    m[0] = dx * dx / 12.0, m[1] = dx * dy / 12.0, m[2] = dy * dy / 12.0;
}

/* The depth field a + g . (p - c) fitted to the region's points by least squares (exact for the
 * plane of an incident face or the line of an edge); along a segment, g across it is 0. */
static void depth_field(const region *r, const double c[2], double *a, double g[2])
{
    double s[3][4] = {{0}};
    for (int k = 0; k < r->count; ++k) {
        const double row[3] = {1.0, r->x[k] - c[0], r->y[k] - c[1]};
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                s[i][j] += row[i] * row[j];
            }
            s[i][3] += row[i] * r->depth[k];
        }
    }
    for (int i = 0; i < 3; ++i) { /* a small ridge keeps a segment's cross direction at 0 */
        s[i][i] += 1e-12 * (s[0][0] + s[1][1] + s[2][2]);
    }
    for (int i = 0; i < 3; ++i) { /* Gauss-Jordan on the positive definite 3 x 3 */
        for (int k = 0; k < 3; ++k) {
            const double f = k == i ? 0.0 : s[k][i] / s[i][i];
            for (int j = 0; j < 4; ++j) {
                s[k][j] -= k == i ? 0.0 : f * s[i][j];
            }
        }
    }
    *a = s[0][3] / s[0][0];
    g[0] = s[1][3] / s[1][1];
    g[1] = s[2][3] / s[2][2];
}

/* Keeps the part of the region pressed in (depth >= 0) when some of it is: the face pushes
 * only there. The depth is linear along every edge, so the cut is where it crosses 0. */
static void pressed_part(region *r)
{
    double deepest = -INFINITY, shallowest = INFINITY;
    for (int k = 0; k < r->count; ++k) {
        deepest = fmax(deepest, r->depth[k]);
        shallowest = fmin(shallowest, r->depth[k]);
    }
    if (!(deepest > 0.0) || shallowest >= 0.0) {
        return;
    }
    region kept = {0};
    const int edges = r->count == 2 ? 1 : r->count;
    for (int i = 0; i < edges; ++i) {
        const int j = (i + 1) % r->count;
        const double di = r->depth[i], dj = r->depth[j];
        if (di >= 0.0 && kept.count < CLIP_MAX) {
            kept.x[kept.count] = r->x[i], kept.y[kept.count] = r->y[i];
            kept.depth[kept.count++] = di;
        }
        if (((di < 0.0 && dj > 0.0) || (di > 0.0 && dj < 0.0)) && kept.count < CLIP_MAX) {
            const double s = di / (di - dj);
            kept.x[kept.count] = r->x[i] + s * (r->x[j] - r->x[i]);
            kept.y[kept.count] = r->y[i] + s * (r->y[j] - r->y[i]);
            kept.depth[kept.count++] = 0.0;
        }
        if (r->count == 2 && dj >= 0.0 && kept.count < CLIP_MAX) {
            kept.x[kept.count] = r->x[j], kept.y[kept.count] = r->y[j];
            kept.depth[kept.count++] = dj;
        }
    }
    *r = kept;
}

/* The 4-point rule of the region: its centroid c plus and minus the columns of sqrt(2 M) (M the
 * second moments per area), each of weight 1/4, which integrates a linear depth field and its
 * first moments exactly: the force and torque of a face pressed by its depth. Its points move
 * continuously with the region (sqrt is continuous on positive semidefinite 2 x 2 matrices). */
static void four_point_rule(region *r, double out_xy[4][2], double out_depth[4])
{
    double c[2], m[3], a, g[2];
    pressed_part(r);
    region_moments(r, c, m);
    depth_field(r, c, &a, g);
    /* round-off can leave a sliver's moments slightly indefinite: make them semidefinite */
    m[0] = fmax(m[0], 0.0), m[2] = fmax(m[2], 0.0);
    m[1] = fmin(fmax(m[1], -sqrt(m[0] * m[2])), sqrt(m[0] * m[2]));
    const double root_det = sqrt(fmax(m[0] * m[2] - m[1] * m[1], 0.0));
    const double trace = m[0] + m[2] + 2.0 * root_det;
    const double scale = trace > 0.0 ? sqrt(2.0 / trace) : 0.0;
    const double s[3] = {scale * (m[0] + root_det), scale * m[1], scale * (m[2] + root_det)};
    const double columns[2][2] = {{s[0], s[1]}, {s[1], s[2]}};
    for (int k = 0; k < 4; ++k) {
        const double sign = k < 2 ? 1.0 : -1.0;
        out_xy[k][0] = c[0] + sign * columns[k % 2][0];
        out_xy[k][1] = c[1] + sign * columns[k % 2][1];
        out_depth[k] = a + g[0] * (out_xy[k][0] - c[0]) + g[1] * (out_xy[k][1] - c[1]);
    }
}

/* The incident feature clipped to the reference face; its points' depths from the face's plane,
 * with the face's normal n (from A to B). One point: it alone; more: the 4-point rule. */
static int clip_to_face(const tb__feature *ref, const double ref_q[4], const tb__feature *inc,
                        bool ref_is_a, double margin, tb__contact_manifold *out)
{
    double face[TB__FEATURE_MAX][3], poly[CLIP_MAX][3], u[3], v[3];
    const int sides = ordered_hull(ref, ref->normal, face);
    int count = inc->face ? ordered_hull(inc, inc->normal, poly) : inc->count;
    for (int k = 0; !inc->face && k < count; ++k) {
        tb__v3_copy(poly[k], inc->points[k]);
    }
    for (int i = 0; i < sides && count > 0; ++i) {
        const double *p = face[i], *q = face[(i + 1) % sides];
        const double edge[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double inward[3];
        tb__v3_cross(inward, ref->normal, edge);
        count = clip_half(poly, count, p, inward);
    }
    face_basis(ref_q, ref->normal, u, v);
    return tb__pressed_face(poly, count, face[0], ref->normal, ref->offset, u, v, ref_is_a, margin,
                            out);
}

int tb__pressed_face(double poly[][3], int count, const double origin[3], const double m[3],
                     double offset, const double u[3], const double v[3], bool ref_is_a,
                     double margin, tb__contact_manifold *out)
{
    const double sign = ref_is_a ? 1.0 : -1.0;
    const double n[3] = {sign * m[0], sign * m[1], sign * m[2]};
    region r = {.count = count < CLIP_MAX ? count : CLIP_MAX};
    for (int k = 0; k < r.count; ++k) {
        r.x[k] = tb__v3_dot(poly[k], u) - tb__v3_dot(origin, u);
        r.y[k] = tb__v3_dot(poly[k], v) - tb__v3_dot(origin, v);
        r.depth[k] = offset - tb__v3_dot(m, poly[k]);
    }
    double xy[4][2], depth[4];
    if (r.count > 1) {
        four_point_rule(&r, xy, depth);
    } else if (r.count == 1) {
        xy[0][0] = r.x[0], xy[0][1] = r.y[0], depth[0] = r.depth[0];
    }
    const int points = r.count > 1 ? 4 : r.count;
    double deepest = -INFINITY;
    for (int k = 0; k < points; ++k) { /* on the face's plane, then halfway along n */
        tb__contact_point *p = &out->points[k];
        tb__v3_copy(p->position, origin);
        tb__v3_axpy(p->position, offset - tb__v3_dot(m, origin), m);
        tb__v3_axpy(p->position, xy[k][0], u);
        tb__v3_axpy(p->position, xy[k][1], v);
        tb__v3_axpy(p->position, -0.5 * sign * depth[k], n);
        p->depth = depth[k];
        deepest = fmax(deepest, depth[k]);
    }
    tb__v3_copy(out->normal, n);
    out->count = deepest > -margin ? points : 0;
    return out->count;
}

/* Overlap of a and b along unit n (from A to B), m: (s_A(n) - s_B(-n)) . n. */
static double overlap_along(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                            const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                            const double n[3])
{
    const double minus_n[3] = {-n[0], -n[1], -n[2]};
    double p_a[3], p_b[3];
    tb__collision_shape_support(a, pose_a, n, p_a);
    tb__collision_shape_support(b, pose_b, minus_n, p_b);
    return tb__v3_dot(p_a, n) - tb__v3_dot(p_b, n);
}

/* Both features along n (overlap `overlap` there); whether either is a face. */
static bool features_along(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                           const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                           const double n[3], double overlap, double margin, tb__feature *fa,
                           tb__feature *fb)
{
    const double minus_n[3] = {-n[0], -n[1], -n[2]};
    tb__support_feature(a, pose_a, n, overlap + margin, fa);
    tb__support_feature(b, pose_b, minus_n, overlap + margin, fb);
    return fa->face || fb->face;
}

/* A plane among the features (a face, else a plane within 25 degrees of facing along n) whose
 * normal, from A to B, is a candidate for the contact's: m. */
static bool candidate_normal(const tb__feature *fa, const tb__feature *fb, const double n[3],
                             double m[3])
{
    const double along_a = fa->planar ? tb__v3_dot(fa->normal, n) : -1.0;
    const double along_b = fb->planar ? -tb__v3_dot(fb->normal, n) : -1.0;
    if (fmax(along_a, along_b) < 0.9) {
        return false;
    }
    const double sign = along_a >= along_b ? 1.0 : -1.0;
    const double *normal = along_a >= along_b ? fa->normal : fb->normal;
    tb__v3_set(m, sign * normal[0], sign * normal[1], sign * normal[2]);
    return true;
}

/* MPR's normal bounds the least overlap from above and sometimes stops on a wrong face of the
 * Minkowski difference (4 to 10 degrees off for a can on a box or a hull on a hull): a face's own
 * normal that overlaps less is the better one, and the features are taken again along it (at
 * most 3 times). Returns the overlap along the normal n finally chosen. */
static double refine_normal(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                            const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                            double margin, double n[3], double overlap, tb__feature *fa,
                            tb__feature *fb)
{
    features_along(a, pose_a, b, pose_b, n, overlap, margin, fa, fb);
    for (int k = 0; k < 3; ++k) {
        double m[3];
        if (!candidate_normal(fa, fb, n, m) || (m[0] == n[0] && m[1] == n[1] && m[2] == n[2])) {
            break;
        }
        const double along = overlap_along(a, pose_a, b, pose_b, m);
        if (!(along < overlap && along > -margin)) {
            break;
        }
        overlap = along;
        tb__v3_copy(n, m);
        features_along(a, pose_a, b, pose_b, n, overlap, margin, fa, fb);
    }
    return overlap;
}

/* The support points along n as the one point of the manifold. */
static int support_point(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                         const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                         const double n[3], double margin, tb__contact_manifold *out)
{
    const double minus_n[3] = {-n[0], -n[1], -n[2]};
    double p_a[3], p_b[3];
    tb__collision_shape_support(a, pose_a, n, p_a);
    tb__collision_shape_support(b, pose_b, minus_n, p_b);
    tb__v3_copy(out->normal, n);
    out->points[0].depth = tb__v3_dot(p_a, n) - tb__v3_dot(p_b, n);
    tb__v3_set(out->points[0].position, 0.5 * (p_a[0] + p_b[0]), 0.5 * (p_a[1] + p_b[1]),
               0.5 * (p_a[2] + p_b[2]));
    out->count = out->points[0].depth > -margin ? 1 : 0;
    return out->count;
}

int tb__general_collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                        const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE],
                        double margin, tb__contact_manifold *out)
{
    if (tb__ccd_collide(a, pose_a, b, pose_b, margin, TB__CCD_MPR, out) <= 0) {
        out->count = 0;
        return 0;
    }
    double n[3];
    tb__v3_copy(n, out->normal);
    tb__feature fa, fb;
    refine_normal(a, pose_a, b, pose_b, margin, n, out->points[0].depth, &fa, &fb);
    const bool refined = n[0] != out->normal[0] || n[1] != out->normal[1] || n[2] != out->normal[2];
    tb__contact_manifold clipped;
    /* the reference: the face nearer to facing along the normal */
    const bool ref_is_a =
        fa.face && (!fb.face || tb__v3_dot(fa.normal, n) >= -tb__v3_dot(fb.normal, n));
    if ((fa.face || fb.face) &&
        clip_to_face(ref_is_a ? &fa : &fb, (ref_is_a ? pose_a : pose_b) + 3, ref_is_a ? &fb : &fa,
                     ref_is_a, margin, &clipped) > 0) {
        *out = clipped;
        return out->count;
    }
    /* no face, or the features do not overlap across it: one point, MPR's unless a face's
     * normal replaced its own */
    return refined ? support_point(a, pose_a, b, pose_b, n, margin, out) : out->count;
}
