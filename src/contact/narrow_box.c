/* Box pairs in closed form: sphere-box (closest point, or the nearest face from inside),
 * capsule-box (the segment point of least signed distance, which is convex along the segment,
 * plus the segment's ends when they rest on the same face), and box-box by the separating axis
 * test over the 15 axes (Gottschalk, Lin and Manocha, OBBTree, SIGGRAPH 1996) with the
 * incident face clipped against the reference face's sides (Sutherland-Hodgman), so boxes
 * resting flat on each other touch at the corners of their overlap. */
#include "contact/narrow_internal.h"

#include "math/tb_math.h"

#include <string.h>

/* The edge axes' bound (edge_cannot_win) and the one-face floor (one_face_above) are on;
 * test_narrow_box_bound compiles this file with them off as the reference they must match. */
#ifndef TB__BOX_EDGE_BOUND
#define TB__BOX_EDGE_BOUND 1
#endif

/* Box axes at pose: axis[i] is shape axis i in the world. */
static void box_axes(const double pose[TB__POSE_SIZE], double axis[3][3])
{
    double R[9];
    tb__q_to_matrix(R, pose + 3);
    for (int i = 0; i < 3; ++i) {
        tb__v3_set(axis[i], R[i], R[3 + i], R[6 + i]);
    }
}

static double sign_of(double x)
{
    return x < 0.0 ? -1.0 : 1.0;
}

/* Signed distance of the local point c from the box of half-extents h (< 0 inside). */
static double box_signed_distance(const double h[3], const double c[3])
{
    double outside = 0.0, inside = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        const double q = fabs(c[k]) - h[k];
        outside += q > 0.0 ? q * q : 0.0;
        inside = fmax(inside, q);
    }
    return sqrt(outside) + fmin(inside, 0.0);
}

static void to_local(const double pose[TB__POSE_SIZE], const double p[3], double out[3])
{
    const double d[3] = {p[0] - pose[0], p[1] - pose[1], p[2] - pose[2]};
    tb__q_rotate_inverse(out, pose + 3, d);
}

/* The box's point nearest c (local) and the outward normal there (local); from inside, the
 * nearest face's. */
static void box_nearest(const double h[3], const double c[3], double q[3], double n[3])
{
    double distance2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        q[k] = fmin(fmax(c[k], -h[k]), h[k]);
        n[k] = c[k] - q[k];
        distance2 += n[k] * n[k];
    }
    if (distance2 > 0.0) {
        const double d = sqrt(distance2);
        tb__v3_set(n, n[0] / d, n[1] / d, n[2] / d);
        return;
    }
    int face = 0;
    for (int k = 1; k < 3; ++k) {
        face = h[k] - fabs(c[k]) < h[face] - fabs(c[face]) ? k : face;
    }
    tb__v3_set(n, 0.0, 0.0, 0.0);
    n[face] = sign_of(c[face]);
    q[face] = n[face] * h[face];
}

void tb__box_sphere_candidate(const tb__collision_shape *box, const double pose[TB__POSE_SIZE],
                              const double c[3], double r, double margin, tb__candidates *out,
                              double n[3])
{
    double local[3], q[3], n_local[3], p_a[3];
    to_local(pose, c, local);
    box_nearest(box->half, local, q, n_local);
    const double depth = r - tb__v3_dot(n_local, (const double[]){local[0] - q[0], local[1] - q[1],
                                                                  local[2] - q[2]});
    tb__q_rotate(n, pose + 3, n_local);
    tb__q_rotate(p_a, pose + 3, q);
    tb__v3_axpy(p_a, 1.0, pose);
    tb__candidate_add(out, n, p_a, depth, margin);
}

int tb__box_sphere(const tb__collision_shape *box, const double pose_box[TB__POSE_SIZE],
                   const double center[3], double radius, double margin, tb__contact_manifold *out)
{
    tb__candidates c;
    c.count = 0;
    double n[3];
    tb__box_sphere_candidate(box, pose_box, center, radius, margin, &c, n);
    return tb__reduce_candidates(&c, n, out);
}

/* The segment parameter in [0, 1] of least signed distance to the box: the signed distance of
 * a convex set is convex, so golden-section search converges to it (to 1e-12 of the segment). */
static double deepest_parameter(const double h[3], const double p0[3], const double p1[3])
{
    const double ratio = 0.5 * (sqrt(5.0) - 1.0);
    double low = 0.0, high = 1.0;
    while (high - low > 1e-12) {
        const double s1 = high - ratio * (high - low), s2 = low + ratio * (high - low);
        double x1[3], x2[3];
        for (int k = 0; k < 3; ++k) {
            x1[k] = p0[k] + s1 * (p1[k] - p0[k]);
            x2[k] = p0[k] + s2 * (p1[k] - p0[k]);
        }
        if (box_signed_distance(h, x1) <= box_signed_distance(h, x2)) {
            high = s2;
        } else {
            low = s1;
        }
    }
    return 0.5 * (low + high);
}

int tb__box_capsule(const tb__collision_shape *box, const double pose_box[TB__POSE_SIZE],
                    const tb__collision_shape *capsule, const double pose_capsule[TB__POSE_SIZE],
                    double margin, tb__contact_manifold *out)
{
    double p0[3], p1[3], l0[3], l1[3], deepest[3], n[3];
    tb__capsule_ends(capsule, pose_capsule, p0, p1);
    to_local(pose_box, p0, l0);
    to_local(pose_box, p1, l1);
    const double s = deepest_parameter(box->half, l0, l1);
    for (int k = 0; k < 3; ++k) {
        deepest[k] = p0[k] + s * (p1[k] - p0[k]);
    }
    tb__candidates c;
    c.count = 0;
    tb__box_sphere_candidate(box, pose_box, deepest, capsule->radius, margin, &c, n);
    /* A capsule lying on a face rests on both ends: add an end whose own contact has the same
     * normal, and drop the middle point when both ends carry it. */
    tb__candidates ends;
    ends.count = 0;
    for (int e = 0; e < 2 && c.count > 0; ++e) {
        const double t = e == 0 ? 0.0 : 1.0;
        tb__candidates one;
        one.count = 0;
        double n_end[3];
        tb__box_sphere_candidate(box, pose_box, e == 0 ? p0 : p1, capsule->radius, margin, &one,
                                 n_end);
        if (one.count == 1 && tb__v3_dot(n_end, n) > 1.0 - 1e-9 && fabs(t - s) > 1e-9) {
            ends.points[ends.count++] = one.points[0];
        }
    }
    if (ends.count == 2) {
        c = ends;
    } else if (ends.count == 1) {
        c.points[c.count++] = ends.points[0];
    }
    return tb__reduce_candidates(&c, n, out);
}

/* --- box-box ---------------------------------------------------------------------------- */

typedef struct box_pose {
    const double *center;
    double axis[3][3];
    const double *half;
    const tb__box_frame *frame; /* axis, with |a_k . a_l| and the defect (tb__box_frame_at) */
} box_pose;

static double projected_radius(const box_pose *b, const double L[3])
{
    return b->half[0] * fabs(tb__v3_dot(b->axis[0], L)) +
           b->half[1] * fabs(tb__v3_dot(b->axis[1], L)) +
           b->half[2] * fabs(tb__v3_dot(b->axis[2], L));
}

/* Separation of the boxes along unit L (< 0: overlap). */
static double separation(const box_pose *a, const box_pose *b, const double T[3], const double L[3])
{
    return fabs(tb__v3_dot(T, L)) - projected_radius(a, L) - projected_radius(b, L);
}

/* Clips the polygon (count points, room for 12) to u . (x - o) <= limit; returns the new count.
 * Each point's distance is computed once, as (u . p - u . o) - limit, the same bits whichever edge
 * asks (the clip was a sixth of a box pile's derivative when it recomputed them per edge). */
static int clip(double poly[][3], int count, const double o[3], const double u[3], double limit)
{
    double out[12][3], distance[12];
    const double uo = tb__v3_dot(u, o);
    bool inside = true;
    for (int i = 0; i < count; ++i) {
        distance[i] = tb__v3_dot(u, poly[i]) - uo - limit;
        inside = inside && distance[i] <= 0.0;
    }
    if (inside) {
        return count; /* every point kept, none added: the polygon as it was */
    }
    int w = 0;
    for (int i = 0; i < count; ++i) {
        const int next = i + 1 < count ? i + 1 : 0;
        const double *p = poly[i], *q = poly[next];
        const double dp = distance[i], dq = distance[next];
        if (dp <= 0.0) {
            tb__v3_copy(out[w++], p);
        }
        if ((dp < 0.0 && dq > 0.0) || (dp > 0.0 && dq < 0.0)) {
            const double s = dp / (dp - dq);
            tb__v3_set(out[w++], p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]),
                       p[2] + s * (q[2] - p[2]));
        }
    }
    for (int i = 0; i < w; ++i) {
        tb__v3_copy(poly[i], out[i]);
    }
    return w;
}

/* The incident box's face most against n (from the reference box), as 4 corners in order. */
static void incident_face(const box_pose *inc, const double n[3], double poly[][3])
{
    int j = 0;
    for (int k = 1; k < 3; ++k) {
        j = fabs(tb__v3_dot(inc->axis[k], n)) > fabs(tb__v3_dot(inc->axis[j], n)) ? k : j;
    }
    const double t = -sign_of(tb__v3_dot(inc->axis[j], n));
    const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
    static const double corners[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
    for (int c = 0; c < 4; ++c) {
        tb__v3_copy(poly[c], inc->center);
        tb__v3_axpy(poly[c], t * inc->half[j], inc->axis[j]);
        tb__v3_axpy(poly[c], corners[c][0] * inc->half[j1], inc->axis[j1]);
        tb__v3_axpy(poly[c], corners[c][1] * inc->half[j2], inc->axis[j2]);
    }
}

/* Face contact: face k of ref, normal n_ref (from ref toward inc); ref_is_a says which is A. */
static void face_contact(const box_pose *ref, const box_pose *inc, int k, const double n_ref[3],
                         bool ref_is_a, double margin, tb__candidates *out)
{
    double poly[12][3];
    incident_face(inc, n_ref, poly);
    int count = 4;
    for (int side = 1; side <= 2 && count > 0; ++side) {
        const double *u = ref->axis[(k + side) % 3];
        const double neg[3] = {-u[0], -u[1], -u[2]};
        count = clip(poly, count, ref->center, u, ref->half[(k + side) % 3]);
        count = count > 0 ? clip(poly, count, ref->center, neg, ref->half[(k + side) % 3]) : 0;
    }
    const double face_height = tb__v3_dot(ref->center, n_ref) + ref->half[k];
    const double n_a[3] = {ref_is_a ? n_ref[0] : -n_ref[0], ref_is_a ? n_ref[1] : -n_ref[1],
                           ref_is_a ? n_ref[2] : -n_ref[2]};
    for (int i = 0; i < count; ++i) {
        const double depth = face_height - tb__v3_dot(poly[i], n_ref);
        double p_a[3];
        tb__v3_copy(p_a, poly[i]);
        if (ref_is_a) {
            tb__v3_axpy(p_a, depth, n_ref); /* A's point: the vertex lifted onto A's face */
        }
        tb__candidate_add(out, n_a, p_a, depth, margin);
    }
}

/* The edge of b along axis i that lies farthest along L: its two ends. */
static void extreme_edge(const box_pose *b, int i, const double L[3], double e0[3], double e1[3])
{
    double c[3];
    tb__v3_copy(c, b->center);
    for (int k = 0; k < 3; ++k) {
        if (k != i) {
            tb__v3_axpy(c, sign_of(tb__v3_dot(b->axis[k], L)) * b->half[k], b->axis[k]);
        }
    }
    tb__v3_copy(e0, c);
    tb__v3_axpy(e0, -b->half[i], b->axis[i]);
    tb__v3_copy(e1, c);
    tb__v3_axpy(e1, b->half[i], b->axis[i]);
}

static void edge_contact(const box_pose *a, const box_pose *b, int i, int j, const double L[3],
                         double margin, tb__candidates *out)
{
    const double minus_L[3] = {-L[0], -L[1], -L[2]};
    double a0[3], a1[3], b0[3], b1[3], s, t, pa[3], pb[3];
    extreme_edge(a, i, L, a0, a1);
    extreme_edge(b, j, minus_L, b0, b1);
    tb__segments_closest(a0, a1, b0, b1, &s, &t);
    for (int k = 0; k < 3; ++k) {
        pa[k] = a0[k] + s * (a1[k] - a0[k]);
        pb[k] = b0[k] + t * (b1[k] - b0[k]);
    }
    const double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
    tb__candidate_add(out, L, pa, tb__v3_dot(d, L), margin);
}

/* The axis of largest separation among a's faces, b's faces (kind 0, 1; index) and the edge
 * pairs (kind 2; index 3 i + j), preferring faces: an edge axis must separate by more than
 * 1e-6 of the boxes' size beyond the best face's. */
typedef struct best_axis {
    double separation;
    int kind, index;
    double L[3];
} best_axis;

static void consider(best_axis *best, double separation, int kind, int index, const double L[3],
                     double bias)
{
    if (separation > best->separation + bias) {
        best->separation = separation;
        best->kind = kind;
        best->index = index;
        tb__v3_copy(best->L, L);
    }
}

/* What the face axes leave for the edge axes' bound: a_k . b_j, T . a_k, and how far the two
 * frames are from orthonormal and right-handed (the sums of |a_k . a_l - delta_kl| and
 * |b_k . b_l - delta_kl|, plus the round-off of those dots; infinite when either frame is
 * left-handed), which the bound's slack grows with. */
typedef struct pair_dots {
    double ab[3][3], t[3];
    double defect;
} pair_dots;

/* out's gram and defect from its axes. */
static void frame_from_axes(tb__box_frame *out)
{
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j <= k; ++j) {
            out->gram[k][j] = out->gram[j][k] = fabs(tb__v3_dot(out->axis[k], out->axis[j]));
        }
    }
    double cross[3];
    /* the sum of the off-identity entries bounds their largest (NaN stays NaN: no bound) */
    double(*g)[3] = out->gram;
    const double defect = 1e-15 + fabs(g[0][0] - 1.0) + fabs(g[1][1] - 1.0) + fabs(g[2][2] - 1.0) +
                          2.0 * (g[0][1] + g[0][2] + g[1][2]);
    tb__v3_cross(cross, out->axis[0], out->axis[1]);
    out->defect = tb__v3_dot(cross, out->axis[2]) > 0.5 ? defect : INFINITY;
}

void tb__box_frame_at(const double pose[TB__POSE_SIZE], tb__box_frame *out)
{
    box_axes(pose, out->axis);
    frame_from_axes(out);
}

/* separation() along each face axis, a's (out[0]) and b's (out[1]): the same bits, from the
 * 21 dot products among the six axes computed once (a_k . b_j and b_j . a_k multiply the same
 * numbers in the same order; a_k . a_l come with the frames) instead of 36. */
static void face_separations(const box_pose *a, const box_pose *b, const double T[3],
                             double out[2][3], pair_dots *dots)
{
    double ab[3][3];
    const double(*aa)[3] = a->frame->gram, (*bb)[3] = b->frame->gram;
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j) {
            dots->ab[k][j] = tb__v3_dot(a->axis[k], b->axis[j]);
            ab[k][j] = fabs(dots->ab[k][j]);
        }
    }
    const double *ha = a->half, *hb = b->half;
    for (int i = 0; i < 3; ++i) {
        dots->t[i] = tb__v3_dot(T, a->axis[i]);
        const double along_b = fabs(tb__v3_dot(T, b->axis[i]));
        out[0][i] = fabs(dots->t[i]) - (ha[0] * aa[0][i] + ha[1] * aa[1][i] + ha[2] * aa[2][i]) -
                    (hb[0] * ab[i][0] + hb[1] * ab[i][1] + hb[2] * ab[i][2]);
        out[1][i] = along_b - (ha[0] * ab[0][i] + ha[1] * ab[1][i] + ha[2] * ab[2][i]) -
                    (hb[0] * bb[0][i] + hb[1] * bb[1][i] + hb[2] * bb[2][i]);
    }
    dots->defect = a->frame->defect + b->frame->defect;
}

/* Whether edge axis a_i x b_j surely separates by no more than `threshold` (so consider() would
 * pass it over), from the closed form of orthonormal frames (Gottschalk et al.: with
 * R = a . b and t = T . a, |T . L| = |t_i2 R_i1j - t_i1 R_i2j|, r_A = h_i1 |R_i2j| + h_i2 |R_i1j|,
 * r_B = h_j1 |R_ij2| + h_j2 |R_ij1|, |a_i x b_j|^2 = 1 - R_ij^2) plus a slack a thousand times
 * the round-off and the frames' defect can make it differ from separation() by, which grows as
 * the axes turn parallel. Skipping an axis only when it cannot win keeps every result bit for
 * bit, and spares the square root, three divisions and seven dot products of an axis that
 * cannot win: most of a resting pair's cost. */
static bool edge_cannot_win(const box_pose *a, const box_pose *b, const pair_dots *d, double scale,
                            int i, int j, double threshold)
{
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
    const double length2 = 1.0 - d->ab[i][j] * d->ab[i][j];
    if (!(length2 > 1e-6)) {
        return false; /* nearly parallel: separation() decides */
    }
    const double along = fabs(d->t[i2] * d->ab[i1][j] - d->t[i1] * d->ab[i2][j]);
    const double r_a = a->half[i1] * fabs(d->ab[i2][j]) + a->half[i2] * fabs(d->ab[i1][j]);
    const double r_b = b->half[j1] * fabs(d->ab[i][j2]) + b->half[j2] * fabs(d->ab[i][j1]);
    /* (along - r_a - r_b) / sqrt(length2) + slack < threshold, without the square root */
    const double slack = 1e3 * d->defect * scale;
    const double x = along - r_a - r_b,
                 room = threshold - (length2 >= 0.25 ? 4.0 * slack : slack / length2);
    if (x <= 0.0 && room > 0.0) {
        return true;
    }
    const double x2 = x * x, room2 = room * room * length2;
    return x > 0.0 ? room > 0.0 && x2 < room2 * (1.0 - 1e-12)
                   : room <= 0.0 && x2 > room2 * (1.0 + 1e-12);
}

/* Stops after the face axes when one of them already parts the boxes by more than margin plus
 * twice the largest preference (each axis considered later is taken only beyond best + bias, so
 * best never falls): the pair is apart whatever the edge axes say, and only its normal, which
 * tb__collide leaves unspecified for a pair apart, could differ. Most candidate pairs of a pile
 * are apart along a face. */
static best_axis find_axis(const box_pose *a, const box_pose *b, const double T[3], double margin,
                           double faces[2][3], const pair_dots *dots)
{
    const double size = a->half[0] + a->half[1] + a->half[2] + b->half[0] + b->half[1] + b->half[2];
    best_axis best = {.separation = -INFINITY};
    for (int kind = 0; kind < 2; ++kind) {
        for (int i = 0; i < 3; ++i) {
            const double *L = (kind == 0 ? a : b)->axis[i];
            consider(&best, faces[kind][i], kind, i, L, kind == 0 ? 0.0 : 1e-9 * size);
        }
    }
    if (best.separation > margin + 2e-6 * size) {
        return best;
    }
    const double scale = fabs(T[0]) + fabs(T[1]) + fabs(T[2]) + 2.0 * size;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (TB__BOX_EDGE_BOUND &&
                edge_cannot_win(a, b, dots, scale, i, j, best.separation + 1e-6 * size)) {
                continue;
            }
            double L[3];
            tb__v3_cross(L, a->axis[i], b->axis[j]);
            const double length = tb__v3_norm(L);
            if (length > 1e-6) {
                tb__v3_set(L, L[0] / length, L[1] / length, L[2] / length);
                consider(&best, separation(a, b, T, L), 2, 3 * i + j, L, 1e-6 * size);
            }
        }
    }
    return best;
}

int tb__box_box(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                tb__contact_manifold *out)
{
    return tb__box_box_framed(a, pose_a, NULL, b, pose_b, NULL, margin, out);
}

/* The floor's slack, 1e3 times the frames' defect times the poses' scale (m). */
static double floor_slack(const box_pose *a, const box_pose *b, double defect)
{
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) {
        scale += 2.0 * (a->half[k] + b->half[k]) + fabs(a->center[k]) + fabs(b->center[k]);
    }
    return 1e3 * defect * scale;
}

/* The floor of tb__box_box_gap_floor from the pair's face separations. */
static double gap_floor(const box_pose *a, const box_pose *b, double faces[2][3],
                        const pair_dots *dots)
{
    double best = -INFINITY;
    for (int k = 0; k < 6; ++k) {
        best = faces[k / 3][k % 3] > best ? faces[k / 3][k % 3] : best;
    }
    const double floor = best - floor_slack(a, b, dots->defect);
    return isfinite(floor) ? floor : -INFINITY;
}

/* Whether gap_floor would be above level, seen from one face axis of a's (the one T reaches
 * farthest past a's half-width along): its separation as face_separations works it out (the
 * same arithmetic, so the same bits), less the same slack. The floor is the largest of the six
 * less that slack (rounding is monotone), so it is above level too. T is kept below 1e300, so no
 * face separation is +infinity (which makes the floor -infinity). A look-ahead pair apart is
 * passed over after one axis instead of six. */
static bool one_face_above(const box_pose *a, const box_pose *b, const double T[3], double level)
{
    if (!(fabs(T[0]) + fabs(T[1]) + fabs(T[2]) < 1e300)) {
        return false;
    }
    int i = 0;
    double reach = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        const double r = fabs(tb__v3_dot(T, a->axis[k])) - a->half[k];
        i = r > reach ? k : i;
        reach = r > reach ? r : reach;
    }
    const double(*aa)[3] = a->frame->gram;
    const double *ha = a->half, *hb = b->half;
    double ab[3];
    for (int j = 0; j < 3; ++j) {
        ab[j] = fabs(tb__v3_dot(a->axis[i], b->axis[j]));
    }
    const double separation = fabs(tb__v3_dot(T, a->axis[i])) -
                              (ha[0] * aa[0][i] + ha[1] * aa[1][i] + ha[2] * aa[2][i]) -
                              (hb[0] * ab[0] + hb[1] * ab[1] + hb[2] * ab[2]);
    const double floor = separation - floor_slack(a, b, a->frame->defect + b->frame->defect);
    return isfinite(floor) && floor > level;
}

/* The pair's boxes at their poses and frames (NULL: worked out into own), T from a to b, and
 * their face separations. */
static void pair_setup(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       tb__box_frame own[2], box_pose *A, box_pose *B, double T[3],
                       double faces[2][3], pair_dots *dots)
{
    if (frame_a == NULL) {
        tb__box_frame_at(pose_a, &own[0]);
        frame_a = &own[0];
    }
    if (frame_b == NULL) {
        tb__box_frame_at(pose_b, &own[1]);
        frame_b = &own[1];
    }
    *A = (box_pose){.center = pose_a, .half = a->half, .frame = frame_a};
    *B = (box_pose){.center = pose_b, .half = b->half, .frame = frame_b};
    memcpy(A->axis, frame_a->axis, sizeof A->axis);
    memcpy(B->axis, frame_b->axis, sizeof B->axis);
    tb__v3_set(T, pose_b[0] - pose_a[0], pose_b[1] - pose_a[1], pose_b[2] - pose_a[2]);
    face_separations(A, B, T, faces, dots);
}

double tb__box_box_gap_floor(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                             const tb__box_frame *frame_a, const tb__collision_shape *b,
                             const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b)
{
    tb__box_frame own[2];
    box_pose A, B;
    double T[3], faces[2][3];
    pair_dots dots;
    pair_setup(a, pose_a, frame_a, b, pose_b, frame_b, own, &A, &B, T, faces, &dots);
    return gap_floor(&A, &B, faces, &dots);
}

int tb__box_box_framed(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                       const tb__box_frame *frame_a, const tb__collision_shape *b,
                       const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                       double margin, tb__contact_manifold *out)
{
    return tb__box_box_below(a, pose_a, frame_a, b, pose_b, frame_b, INFINITY, margin, out);
}

int tb__box_box_below(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                      const tb__box_frame *frame_a, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], const tb__box_frame *frame_b,
                      double level, double margin, tb__contact_manifold *out)
{
    tb__box_frame own_a, own_b; /* pair_setup's work inline: this is the derivative's hot path */
    if (frame_a == NULL) {
        tb__box_frame_at(pose_a, &own_a);
        frame_a = &own_a;
    }
    if (frame_b == NULL) {
        tb__box_frame_at(pose_b, &own_b);
        frame_b = &own_b;
    }
    box_pose A = {.center = pose_a, .half = a->half, .frame = frame_a};
    box_pose B = {.center = pose_b, .half = b->half, .frame = frame_b};
    memcpy(A.axis, frame_a->axis, sizeof A.axis);
    memcpy(B.axis, frame_b->axis, sizeof B.axis);
    const double T[3] = {pose_b[0] - pose_a[0], pose_b[1] - pose_a[1], pose_b[2] - pose_a[2]};
    double faces[2][3];
    pair_dots dots;
    const bool above = TB__BOX_EDGE_BOUND && level < INFINITY && one_face_above(&A, &B, T, level);
    if (!above) {
        face_separations(&A, &B, T, faces, &dots);
    }
    if (above || (level < INFINITY && gap_floor(&A, &B, faces, &dots) > level)) {
        out->count = 0; /* its gap is above level: passed over */
        tb__v3_set(out->normal, 0.0, 0.0, 0.0);
        return 0;
    }
    best_axis best = find_axis(&A, &B, T, margin, faces, &dots);
    tb__candidates c;
    c.count = 0;
    double n[3];
    tb__v3_copy(n, best.L);
    if (tb__v3_dot(T, n) < 0.0) {
        tb__v3_set(n, -n[0], -n[1], -n[2]); /* from A to B */
    }
    if (!(best.separation < margin)) {
        out->count = 0;
        tb__v3_copy(out->normal, n);
        return 0;
    }
    if (best.kind == 0) {
        face_contact(&A, &B, best.index, n, true, margin, &c);
    } else if (best.kind == 1) {
        const double n_b[3] = {-n[0], -n[1], -n[2]};
        face_contact(&B, &A, best.index, n_b, false, margin, &c);
    } else {
        edge_contact(&A, &B, best.index / 3, best.index % 3, n, margin, &c);
    }
    return tb__reduce_candidates(&c, n, out);
}
