/* A box against the shapes without a closed form (cylinder, ellipsoid, convex hull, points).
 * libccd's MPR gives one point and a normal; a hull resting on a box face, or a cylinder
 * standing on one, needs its whole base. So the shape's own features (a hull's vertices, a
 * point set's spheres, a cylinder's rim points) are each met with the box in closed form, as a
 * sphere of their radius against the box; those that face the box along the same face as the
 * deepest of them (normals within 1e-9) form the manifold when there are two or more.
 * Otherwise, a vertex, an edge or a rounded surface on the box: MPR's single point. Features
 * enter at depth -margin, so the base's points appear continuously. */
#include "contact/narrow_internal.h"

#include "contact/ccd_wrap.h"
#include "math/tb_math.h"

#define SAME_FACE (1.0 - 1e-9)

typedef struct feature_set {
    tb__candidates points;
    double normals[TB__CANDIDATES_MAX][3];
} feature_set;

/* Adds feature c (radius r), keeping the deepest TB__CANDIDATES_MAX. */
static void add_feature(const tb__collision_shape *box, const double *pose_box, const double c[3],
                        double r, double margin, feature_set *f)
{
    tb__candidates one = {0};
    double n[3];
    tb__box_sphere_candidate(box, pose_box, c, r, margin, &one, n);
    if (one.count == 0) {
        return;
    }
    int slot = f->points.count;
    if (slot == TB__CANDIDATES_MAX) {
        slot = 0;
        for (int k = 1; k < TB__CANDIDATES_MAX; ++k) {
            slot = f->points.points[k].depth < f->points.points[slot].depth ? k : slot;
        }
        if (!(one.points[0].depth > f->points.points[slot].depth)) {
            return;
        }
    } else {
        ++f->points.count;
    }
    f->points.points[slot] = one.points[0];
    tb__v3_copy(f->normals[slot], n);
}

static void features(const tb__collision_shape *box, const double *pose_box,
                     const tb__collision_shape *other, const double *pose_other, const double n[3],
                     double margin, feature_set *f)
{
    if (other->type == TB_SHAPE_CYLINDER) {
        const double toward_box[3] = {-n[0], -n[1], -n[2]};
        double rim[8][3];
        tb__cylinder_rim_points(other, pose_other, toward_box, rim);
        for (int k = 0; k < 8; ++k) {
            add_feature(box, pose_box, rim[k], 0.0, margin, f);
        }
        return;
    }
    for (size_t i = 0; i < other->vertex_count; ++i) { /* none for an ellipsoid */
        double c[3];
        tb__q_rotate(c, pose_other + 3, other->vertices + 3 * i);
        tb__v3_axpy(c, 1.0, pose_other);
        add_feature(box, pose_box, c, other->radii != NULL ? other->radii[i] : 0.0, margin, f);
    }
}

int tb__box_general(const tb__collision_shape *box, const double pose_box[TB__POSE_SIZE],
                    const tb__collision_shape *other, const double pose_other[TB__POSE_SIZE],
                    double margin, tb__contact_manifold *out)
{
    if (tb__ccd_collide(box, pose_box, other, pose_other, margin, TB__CCD_MPR, out) <= 0) {
        out->count = 0;
        return 0;
    }
    feature_set f = {0};
    features(box, pose_box, other, pose_other, out->normal, margin, &f);
    int deepest = -1;
    for (int k = 0; k < f.points.count; ++k) {
        if (tb__v3_dot(f.normals[k], out->normal) > 0.99 &&
            (deepest < 0 || f.points.points[k].depth > f.points.points[deepest].depth)) {
            deepest = k;
        }
    }
    tb__candidates base = {0};
    for (int k = 0; deepest >= 0 && k < f.points.count; ++k) {
        if (tb__v3_dot(f.normals[k], f.normals[deepest]) > SAME_FACE) {
            base.points[base.count++] = f.points.points[k];
        }
    }
    if (base.count < 2) {
        return out->count;
    }
    return tb__reduce_candidates(&base, f.normals[deepest], out);
}
