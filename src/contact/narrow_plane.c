/* Every shape against a plane, in closed form: the shape's lowest features, each a point whose
 * depth is continuous in the pose (a box's corners, a capsule's two end spheres, a cylinder's
 * rim points, an ellipsoid's lowest point, a hull's vertices, a point set's spheres); up to 4
 * of them, spread over the lowest face. A feature enters the manifold when it comes within
 * margin of the plane, where a contact law's force is still zero. */
#include "contact/narrow_internal.h"

#include "math/tb_math.h"

typedef struct plane {
    const double *n;
    double offset;
    double margin;
} plane;

/* A sphere of radius r at world c: its lowest point's depth below the plane. */
static void sphere_point(const plane *g, const double c[3], double r, tb__candidates *out)
{
    const double height = tb__v3_dot(g->n, c) - g->offset;
    double on_plane[3]; /* A's (the plane's) point under c */
    tb__v3_copy(on_plane, c);
    tb__v3_axpy(on_plane, -height, g->n);
    tb__candidate_add(out, g->n, on_plane, r - height, g->margin);
}

static void local_point(const double pose[TB__POSE_SIZE], const double local[3], double out[3])
{
    tb__q_rotate(out, pose + 3, local);
    tb__v3_axpy(out, 1.0, pose);
}

static void box_corners(const plane *g, const tb__collision_shape *box,
                        const double pose[TB__POSE_SIZE], tb__candidates *out)
{
    for (unsigned corner = 0; corner < 8; ++corner) {
        double local[3], world[3];
        for (int k = 0; k < 3; ++k) {
            local[k] = (corner >> k & 1u ? 1.0 : -1.0) * box->half[k];
        }
        local_point(pose, local, world);
        sphere_point(g, world, 0.0, out);
    }
}

static void cylinder_rims(const plane *g, const tb__collision_shape *cylinder,
                          const double pose[TB__POSE_SIZE], tb__candidates *out)
{
    const double down[3] = {-g->n[0], -g->n[1], -g->n[2]};
    double rim[8][3];
    tb__cylinder_rim_points(cylinder, pose, down, rim);
    for (int k = 0; k < 8; ++k) {
        sphere_point(g, rim[k], 0.0, out);
    }
}

/* Adds one candidate, or when there is no room replaces the shallowest if it is deeper: a full
 * list keeps the deepest points. */
static void keep_deepest(tb__candidates *out, const tb__contact_point *point)
{
    if (out->count < TB__CANDIDATES_MAX) {
        out->points[out->count++] = *point;
        return;
    }
    int shallowest = 0;
    for (int k = 1; k < out->count; ++k) {
        shallowest = out->points[k].depth < out->points[shallowest].depth ? k : shallowest;
    }
    if (point->depth > out->points[shallowest].depth) {
        out->points[shallowest] = *point;
    }
}

static void vertices(const plane *g, const tb__collision_shape *s, const double pose[TB__POSE_SIZE],
                     tb__candidates *out)
{
    for (size_t i = 0; i < s->vertex_count; ++i) {
        double world[3];
        local_point(pose, s->vertices + 3 * i, world);
        const double r = s->radii != NULL ? s->radii[i] : 0.0;
        if (out->count == TB__CANDIDATES_MAX) {
            tb__candidates one;
            one.count = 0;
            sphere_point(g, world, r, &one);
            if (one.count == 1) {
                keep_deepest(out, &one.points[0]);
            }
        } else {
            sphere_point(g, world, r, out);
        }
    }
}

/* A convex shape's lowest points against the plane, by type, into c. */
static void plane_candidates(const plane *g, const tb__collision_shape *b,
                             const double pose_b[TB__POSE_SIZE], tb__candidates *c)
{
    const double *normal = g->n;
    switch (b->type) {
    case TB_SHAPE_SPHERE:
        sphere_point(g, pose_b, b->radius, c);
        break;
    case TB_SHAPE_CAPSULE: {
        double p0[3], p1[3];
        tb__capsule_ends(b, pose_b, p0, p1);
        sphere_point(g, p0, b->radius, c);
        sphere_point(g, p1, b->radius, c);
        break;
    }
    case TB_SHAPE_BOX:
        box_corners(g, b, pose_b, c);
        break;
    case TB_SHAPE_CYLINDER:
        cylinder_rims(g, b, pose_b, c);
        break;
    case TB_SHAPE_ELLIPSOID: {
        double lowest[3];
        const double down[3] = {-normal[0], -normal[1], -normal[2]};
        tb__collision_shape_support(b, pose_b, down, lowest);
        sphere_point(g, lowest, 0.0, c);
        break;
    }
    default:
        vertices(g, b, pose_b, c);
        break;
    }
}

int tb__collide_plane(const double normal[3], double offset, const tb__collision_shape *b,
                      const double pose_b[TB__POSE_SIZE], double margin, tb__contact_manifold *out)
{
    const plane g = {normal, offset, margin};
    tb__candidates c;
    c.count = 0;
    const size_t pieces = tb__collision_shape_piece_count(b);
    if (pieces == 1) {
        plane_candidates(&g, b, pose_b, &c);
        return tb__reduce_candidates(&c, normal, out);
    }
    /* a body of several pieces: each piece's own manifold, then the deepest of them all */
    for (size_t k = 0; k < pieces; ++k) {
        double pose[TB__POSE_SIZE];
        const tb__collision_shape *piece = tb__collision_shape_piece(b, k, pose_b, pose);
        tb__candidates own;
        own.count = 0;
        tb__contact_manifold lowest;
        plane_candidates(&g, piece, pose, &own);
        tb__reduce_candidates(&own, normal, &lowest);
        for (int i = 0; i < lowest.count; ++i) {
            keep_deepest(&c, &lowest.points[i]);
        }
    }
    return tb__reduce_candidates(&c, normal, out);
}
