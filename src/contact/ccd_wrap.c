/* libccd (Fiser; GJK, EPA and MPR on support functions, BSD-3): the one file that includes its
 * headers. Each shape is handed over as its support function, grown by the margin on A's side
 * so that pairs within margin are found. libccd gives the normal; the depth is then measured
 * along it from the shapes' own support points, (s_A(n) - s_B(-n)) . n, which is the exact
 * overlap of the two along n, continuous in the poses for a given normal. */
#include "contact/ccd_wrap.h"

#include "math/tb_math.h"

#include <ccd/ccd.h>

/* Support evaluations one query may make. libccd caps MPR's penetration search at
 * max_iterations, but not its portal discovery and refinement: on a hull with a vertex 2^64 m
 * out they cycled forever (F23), the derivative never returning. The most seen in a million
 * random near-degenerate pairs was 212. */
#define SUPPORT_BUDGET 2000

typedef struct ccd_object {
    const tb__collision_shape *shape;
    const double *pose;
    double grow;     /* m added along every direction */
    long *remaining; /* the query's support budget, shared by both objects */
} ccd_object;

static void support(const void *object, const ccd_vec3_t *direction, ccd_vec3_t *out)
{
    const ccd_object *o = object;
    const double d[3] = {direction->v[0], direction->v[1], direction->v[2]};
    if (--*o->remaining < 0) {
        /* -d / |d| from each object makes the Minkowski point -2 d / |d|, behind every
         * direction libccd asks for: each of its loops then ends (origin outside) */
        const double length = tb__v3_norm(d);
        const double scale = length > 0.0 ? -1.0 / length : NAN;
        ccdVec3Set(out, scale * d[0], scale * d[1], scale * d[2]);
        return;
    }
    double p[3];
    tb__collision_shape_support(o->shape, o->pose, d, p);
    const double length = tb__v3_norm(d);
    if (o->grow > 0.0 && length > 0.0) {
        tb__v3_axpy(p, o->grow / length, d);
    }
    ccdVec3Set(out, p[0], p[1], p[2]);
}

/* A point inside the shape: its pose origin, or the centre of its vertices' box. */
static void center(const void *object, ccd_vec3_t *out)
{
    const ccd_object *o = object;
    const tb__collision_shape *s = o->shape;
    double local[3] = {0.0, 0.0, 0.0}, world[3];
    if (s->type == TB_SHAPE_CONVEX || s->type == TB_SHAPE_POINTS) {
        for (int k = 0; k < 3; ++k) {
            local[k] = 0.5 * (s->local_min[k] + s->local_max[k]);
        }
    }
    tb__q_rotate(world, o->pose + 3, local);
    ccdVec3Set(out, world[0] + o->pose[0], world[1] + o->pose[1], world[2] + o->pose[2]);
}

int tb__ccd_collide(const tb__collision_shape *a, const double pose_a[TB__POSE_SIZE],
                    const tb__collision_shape *b, const double pose_b[TB__POSE_SIZE], double margin,
                    tb__ccd_method method, tb__contact_manifold *out)
{
    long remaining = SUPPORT_BUDGET;
    const ccd_object object_a = {a, pose_a, margin, &remaining},
                     object_b = {b, pose_b, 0.0, &remaining};
    ccd_t ccd;
    CCD_INIT(&ccd);
    ccd.support1 = support;
    ccd.support2 = support;
    ccd.center1 = center;
    ccd.center2 = center;
    ccd.max_iterations = 100;
    ccd.mpr_tolerance = 1e-12;
    ccd.epa_tolerance = 1e-12;
    ccd_real_t depth = 0.0;
    ccd_vec3_t direction, position;
    out->count = 0;
    const int result =
        method == TB__CCD_MPR
            ? ccdMPRPenetration(&object_a, &object_b, &ccd, &depth, &direction, &position)
            : ccdGJKPenetration(&object_a, &object_b, &ccd, &depth, &direction, &position);
    if (remaining < 0) {
        return -1; /* the budget ran out: no answer, so no contact */
    }
    if (result != 0) {
        return result == -1 ? 0 : -1; /* -1: apart; -2: EPA's allocation failed */
    }
    double n[3] = {direction.v[0], direction.v[1], direction.v[2]};
    const double length = tb__v3_norm(n);
    if (!(length > 0.0)) {
        tb__v3_set(n, 0.0, 0.0, 1.0);
    } else {
        tb__v3_set(n, n[0] / length, n[1] / length, n[2] / length);
    }
    double p_a[3], p_b[3];
    const double minus_n[3] = {-n[0], -n[1], -n[2]};
    tb__collision_shape_support(a, pose_a, n, p_a);
    tb__collision_shape_support(b, pose_b, minus_n, p_b);
    const double d[3] = {p_a[0] - p_b[0], p_a[1] - p_b[1], p_a[2] - p_b[2]};
    tb__v3_copy(out->normal, n);
    const double overlap = tb__v3_dot(d, n);
    if (overlap > -margin) {
        out->count = 1;
        out->points[0].depth = overlap;
        /* Across the normal, libccd's point (the support points may be any corners of two
         * touching faces); along it, halfway between the two surfaces. */
        const double mid[3] = {0.5 * (p_a[0] + p_b[0]), 0.5 * (p_a[1] + p_b[1]),
                               0.5 * (p_a[2] + p_b[2])};
        const double at[3] = {position.v[0], position.v[1], position.v[2]};
        const double along = tb__v3_dot(mid, n) - tb__v3_dot(at, n);
        tb__v3_copy(out->points[0].position, at);
        tb__v3_axpy(out->points[0].position, along, n);
    }
    return out->count;
}
