/* Collision shapes: checking a tb_shape, making its private form (a convex shape's hull
 * computed here), and the two questions the phases ask of a shape at a pose: its world bounds
 * and its support point. */
#include "contact/collision_shape.h"

#include "contact/convex_hull.h"
#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIZE_MAX_M 1e100 /* m: squares of sizes and their sums stay finite */
#define VERTEX_COUNT_MAX 1000000

static tb_status check_size(char *detail, double value, const char *what, bool zero_ok)
{
    if (!isfinite(value)) {
        return tb__set_detail(detail, TB_STATUS_NOT_FINITE, "%s: must be finite, got %g", what,
                              value);
    }
    if (value > SIZE_MAX_M || value < 0.0 || (!zero_ok && value == 0.0)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "%s: must be %s and <= 1e100 m, got %g", what,
                              zero_ok ? ">= 0" : "> 0", value);
    }
    return TB_STATUS_OK;
}

static tb_status check_sizes(char *detail, const double *values, int n, const char *what)
{
    tb_status status = TB_STATUS_OK;
    for (int i = 0; i < n && status == TB_STATUS_OK; ++i) {
        char item[48];
        snprintf(item, sizeof item, n > 1 ? "%s[%d]" : "%s", what, i);
        status = check_size(detail, values[i], item, false);
    }
    return status;
}

static tb_status check_vertices(char *detail, const tb_shape *shape, size_t least)
{
    if (shape->vertices == NULL) {
        return tb__set_detail(detail, TB_STATUS_NULL_POINTER, "vertices is NULL");
    }
    if (shape->vertex_count < least || shape->vertex_count > VERTEX_COUNT_MAX) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "vertex_count: must be in [%zu, %d], got %zu", least,
                              VERTEX_COUNT_MAX, shape->vertex_count);
    }
    for (size_t i = 0; i < 3 * shape->vertex_count; ++i) {
        const double v = shape->vertices[i];
        if (!isfinite(v) || fabs(v) > SIZE_MAX_M) {
            return tb__set_detail(
                detail, isfinite(v) ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_NOT_FINITE,
                "vertices[%zu][%zu]: must be finite and within 1e100 m, got %g", i / 3, i % 3, v);
        }
    }
    for (size_t i = 0; shape->radii != NULL && i < shape->vertex_count; ++i) {
        char item[48];
        snprintf(item, sizeof item, "radii[%zu]", i);
        tb_status status = check_size(detail, shape->radii[i], item, true);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    return TB_STATUS_OK;
}

static tb_status check_shape(const tb_shape *shape, char *detail)
{
    switch (shape->type) {
    case TB_SHAPE_SPHERE:
        return check_sizes(detail, &shape->radius, 1, "radius");
    case TB_SHAPE_BOX:
        return check_sizes(detail, shape->size, 3, "size");
    case TB_SHAPE_CAPSULE:
    case TB_SHAPE_CYLINDER: {
        tb_status status = check_sizes(detail, &shape->radius, 1, "radius");
        return status == TB_STATUS_OK ? check_sizes(detail, &shape->length, 1, "length") : status;
    }
    case TB_SHAPE_ELLIPSOID:
        return check_sizes(detail, shape->semi_axes, 3, "semi_axes");
    case TB_SHAPE_CONVEX:
        return check_vertices(detail, shape, 4);
    case TB_SHAPE_POINTS:
        return check_vertices(detail, shape, 1);
    default:
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT, "type: %d is not a tb_shape_type",
                              (int)shape->type);
    }
}

static void local_bounds(tb__collision_shape *c)
{
    for (int k = 0; k < 3; ++k) {
        c->local_min[k] = INFINITY;
        c->local_max[k] = -INFINITY;
    }
    for (size_t i = 0; i < c->vertex_count; ++i) {
        const double r = c->radii != NULL ? c->radii[i] : 0.0;
        for (int k = 0; k < 3; ++k) {
            c->local_min[k] = fmin(c->local_min[k], c->vertices[3 * i + k] - r);
            c->local_max[k] = fmax(c->local_max[k], c->vertices[3 * i + k] + r);
        }
    }
}

/* The hull's vertices (convex) or all points, into one block after the header. */
static tb__collision_shape *with_vertices(const tb_shape *shape, char *detail, tb_status *status)
{
    const size_t n = shape->vertex_count;
    unsigned char *on_hull = NULL;
    size_t kept = n;
    if (shape->type == TB_SHAPE_CONVEX) {
        on_hull = malloc(n);
        *status = on_hull == NULL ? tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                                                   "convex hull of %zu vertices", n)
                                  : tb__convex_hull(shape->vertices, n, on_hull, detail);
        kept = 0;
        for (size_t i = 0; *status == TB_STATUS_OK && i < n; ++i) {
            kept += on_hull[i];
        }
    }
    const bool points = shape->type == TB_SHAPE_POINTS;
    tb__collision_shape *c = NULL;
    if (*status == TB_STATUS_OK) {
        size_t bytes = 0;
        c = tb__size_product(kept, (points ? 4 : 3) * sizeof(double), &bytes) &&
                    bytes <= (size_t)-1 - sizeof *c
                ? calloc(1, sizeof *c + bytes)
                : NULL;
        *status = c != NULL ? TB_STATUS_OK
                            : tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "%zu vertices", n);
    }
    if (c != NULL) {
        c->vertex_count = kept;
        c->vertices = c->data;
        c->radii = points ? c->data + 3 * kept : NULL;
        for (size_t i = 0, w = 0; i < n; ++i) {
            if (on_hull == NULL || on_hull[i]) {
                memcpy(c->vertices + 3 * w, shape->vertices + 3 * i, 3 * sizeof(double));
                if (points) {
                    c->radii[w] = shape->radii != NULL ? shape->radii[i] : 0.0;
                }
                ++w;
            }
        }
        local_bounds(c);
    }
    free(on_hull);
    return c;
}

tb__collision_shape *tb__collision_shape_make(const tb_shape *shape, char *detail,
                                              tb_status *out_status)
{
    *out_status = check_shape(shape, detail);
    if (*out_status != TB_STATUS_OK) {
        return NULL;
    }
    tb__collision_shape *c = NULL;
    if (shape->type == TB_SHAPE_CONVEX || shape->type == TB_SHAPE_POINTS) {
        c = with_vertices(shape, detail, out_status);
    } else {
        c = calloc(1, sizeof *c);
        *out_status =
            c != NULL ? TB_STATUS_OK : tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "shape");
    }
    if (c == NULL) {
        return NULL;
    }
    c->type = shape->type;
    c->radius = shape->radius;
    const bool capsule = shape->type == TB_SHAPE_CAPSULE,
               cylinder = shape->type == TB_SHAPE_CYLINDER;
    c->half_length = capsule || cylinder ? 0.5 * shape->length : 0.0;
    for (int k = 0; k < 3; ++k) {
        c->half[k] = shape->type == TB_SHAPE_BOX         ? 0.5 * shape->size[k]
                     : shape->type == TB_SHAPE_ELLIPSOID ? shape->semi_axes[k]
                                                         : 0.0;
    }
    return c;
}

/* World half-extents of a shape-frame box of half-extents h: sum_j |R_ij| h_j. */
static void rotated_extent(const double R[9], const double h[3], double out[3])
{
    for (int i = 0; i < 3; ++i) {
        out[i] = fabs(R[3 * i]) * h[0] + fabs(R[3 * i + 1]) * h[1] + fabs(R[3 * i + 2]) * h[2];
    }
}

/* Centre (world) and half-extents of the shape's world box. */
static void world_extent(const tb__collision_shape *s, const double R[9], const double *p,
                         double center[3], double e[3])
{
    tb__v3_copy(center, p);
    for (int i = 0; i < 3; ++i) {
        const double a = R[3 * i + 2]; /* the shape's z axis, component i */
        switch (s->type) {
        case TB_SHAPE_SPHERE:
            e[i] = s->radius;
            break;
        case TB_SHAPE_CAPSULE:
            e[i] = fabs(a) * s->half_length + s->radius;
            break;
        case TB_SHAPE_CYLINDER: /* the rim circle's extent is r sqrt(1 - a_i^2) */
            e[i] = fabs(a) * s->half_length + s->radius * sqrt(fmax(0.0, 1.0 - a * a));
            break;
        case TB_SHAPE_ELLIPSOID: /* max of e_i . x over x^T A^-2 x = 1: |A R^T e_i| */
            e[i] = hypot(hypot(R[3 * i] * s->half[0], R[3 * i + 1] * s->half[1]), a * s->half[2]);
            break;
        default:
            break;
        }
    }
    if (s->type == TB_SHAPE_BOX) {
        rotated_extent(R, s->half, e);
    } else if (s->type == TB_SHAPE_CONVEX || s->type == TB_SHAPE_POINTS ||
               s->type == TB_SHAPE_COMPOUND) {
        double c[3], h[3], offset[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = 0.5 * (s->local_min[k] + s->local_max[k]);
            h[k] = 0.5 * (s->local_max[k] - s->local_min[k]);
        }
        tb__m3_mul_v(offset, R, c);
        tb__v3_axpy(center, 1.0, offset);
        rotated_extent(R, h, e);
    }
}

void tb__collision_shape_bounds(const tb__collision_shape *shape, const double pose[TB__POSE_SIZE],
                                double out_min[3], double out_max[3])
{
    double R[9], center[3], e[3];
    tb__q_to_matrix(R, pose + 3);
    world_extent(shape, R, pose, center, e);
    for (int i = 0; i < 3; ++i) {
        out_min[i] = center[i] - e[i];
        out_max[i] = center[i] + e[i];
    }
}

static double sign_of(double x)
{
    return x < 0.0 ? -1.0 : 1.0;
}

/* Support in the shape frame along the local direction d (non-zero). */
static void local_support(const tb__collision_shape *s, const double d[3], double out[3])
{
    const double length = tb__v3_norm(d);
    const double u[3] = {d[0] / length, d[1] / length, d[2] / length};
    switch (s->type) {
    case TB_SHAPE_SPHERE:
        tb__v3_set(out, s->radius * u[0], s->radius * u[1], s->radius * u[2]);
        return;
    case TB_SHAPE_BOX:
        tb__v3_set(out, sign_of(d[0]) * s->half[0], sign_of(d[1]) * s->half[1],
                   sign_of(d[2]) * s->half[2]);
        return;
    case TB_SHAPE_CAPSULE:
        tb__v3_set(out, s->radius * u[0], s->radius * u[1],
                   s->radius * u[2] + sign_of(d[2]) * s->half_length);
        return;
    case TB_SHAPE_CYLINDER: {
        const double rho = hypot(d[0], d[1]);
        const double scale = rho > 0.0 ? s->radius / rho : 0.0;
        tb__v3_set(out, scale * d[0], scale * d[1], sign_of(d[2]) * s->half_length);
        return;
    }
    case TB_SHAPE_ELLIPSOID: { /* x = A^2 u / |A u| maximises u . x on x^T A^-2 x = 1 */
        const double *a = s->half;
        const double au[3] = {a[0] * u[0], a[1] * u[1], a[2] * u[2]};
        const double norm = tb__v3_norm(au);
        tb__v3_set(out, a[0] * au[0] / norm, a[1] * au[1] / norm, a[2] * au[2] / norm);
        return;
    }
    default:
        break;
    }
    size_t best = 0;
    double best_score = -INFINITY;
    for (size_t i = 0; i < s->vertex_count; ++i) {
        const double score =
            tb__v3_dot(s->vertices + 3 * i, u) + (s->radii != NULL ? s->radii[i] : 0.0);
        if (score > best_score) {
            best_score = score;
            best = i;
        }
    }
    const double r = s->radii != NULL ? s->radii[best] : 0.0;
    const double *v = s->vertices + 3 * best;
    tb__v3_set(out, v[0] + r * u[0], v[1] + r * u[1], v[2] + r * u[2]);
}

void tb__collision_shape_support(const tb__collision_shape *shape, const double pose[TB__POSE_SIZE],
                                 const double d[3], double out[3])
{
    if (shape->type == TB_SHAPE_COMPOUND) { /* the union's: the farthest piece's */
        double best = -INFINITY, piece_pose[TB__POSE_SIZE], point[3];
        for (size_t k = 0; k < shape->piece_count; ++k) {
            tb__collision_shape_support(tb__collision_shape_piece(shape, k, pose, piece_pose),
                                        piece_pose, d, point);
            if (tb__v3_dot(point, d) > best) {
                best = tb__v3_dot(point, d);
                tb__v3_copy(out, point);
            }
        }
        return;
    }
    double local_d[3], local[3];
    tb__q_rotate_inverse(local_d, pose + 3, d);
    local_support(shape, local_d, local);
    tb__q_rotate(out, pose + 3, local);
    tb__v3_axpy(out, 1.0, pose);
}
