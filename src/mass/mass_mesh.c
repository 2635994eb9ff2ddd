/* Mass properties of a closed triangle mesh by signed tetrahedra. Each triangle (a, b, c),
 * taken with a reference point o, spans a tetrahedron with signed volume det[a b c] / 6
 * (vectors relative to o). Over a solid tetrahedron with one vertex at o,
 *   integral of r dV     = V (a + b + c) / 4,
 *   integral of r r^T dV = V / 20 (a a^T + b b^T + c c^T + s s^T),  s = a + b + c,
 * (the covariance of the canonical tetrahedron mapped by [a b c]). Summed with signs over a
 * closed surface they give the solid's integrals; I = tr(C) Id - C from the covariance C. */
#include "tumble/mass.h"

#include "core/detail.h"
#include "core/validate.h"
#include "mass/mass_internal.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* Triangles with area below this fraction of the squared bounding-box diagonal are
 * degenerate. */
#define TB__DEGENERATE_AREA 1e-14

typedef struct mesh_view {
    const double *vertices;
    size_t vertex_count;
    const unsigned *triangles;
    size_t triangle_count;
} mesh_view;

static int compare_u64(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Over the triangles' corners only: a vertex no triangle uses is not part of the solid. */
static double bounding_diagonal_squared(const mesh_view *mesh)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t corner = 0; corner < 3 * mesh->triangle_count; ++corner) {
        const double *v = mesh->vertices + 3 * (size_t)mesh->triangles[corner];
        for (int i = 0; i < 3; ++i) {
            lo[i] = fmin(lo[i], v[i]);
            hi[i] = fmax(hi[i], v[i]);
        }
    }
    const double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    return tb__v3_dot(d, d);
}

static tb_status check_triangles(const mesh_view *mesh, tb_error *error)
{
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        if (!tb__all_finite(mesh->vertices + 3 * v, 3)) {
            return tb__set_error(error, TB_STATUS_NOT_FINITE,
                                 "vertices[%zu]: contains NaN or infinity", v);
        }
    }
    for (size_t corner = 0; corner < 3 * mesh->triangle_count; ++corner) {
        if (mesh->triangles[corner] >= mesh->vertex_count) {
            return tb__set_error(error, TB_STATUS_BAD_MESH,
                                 "triangles[%zu][%zu]: vertex index %u out of range (%zu "
                                 "vertices)",
                                 corner / 3, corner % 3, mesh->triangles[corner],
                                 mesh->vertex_count);
        }
    }
    const double min_area = TB__DEGENERATE_AREA * bounding_diagonal_squared(mesh);
    for (size_t t = 0; t < mesh->triangle_count; ++t) {
        const unsigned *tri = mesh->triangles + 3 * t;
        const double *a = mesh->vertices + 3 * tri[0], *b = mesh->vertices + 3 * tri[1],
                     *c = mesh->vertices + 3 * tri[2];
        const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3];
        tb__v3_cross(n, ab, ac);
        if (!(0.5 * tb__v3_norm(n) > min_area)) {
            return tb__set_error(error, TB_STATUS_BAD_MESH,
                                 "triangles[%zu]: degenerate (zero area, vertices %u %u %u)", t,
                                 tri[0], tri[1], tri[2]);
        }
    }
    return TB_STATUS_OK;
}

/* Closed and consistently oriented: every directed edge (a, b) occurs exactly once and its
 * reverse (b, a) occurs exactly once. */
static tb_status check_closed(const mesh_view *mesh, tb_error *error)
{
    const size_t edge_count = 3 * mesh->triangle_count;
    uint64_t *edges = tb__malloc_array(edge_count, sizeof *edges);
    if (edges == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "edge list of %zu entries",
                             edge_count);
    }
    for (size_t t = 0; t < mesh->triangle_count; ++t) {
        const unsigned *tri = mesh->triangles + 3 * t;
        for (int k = 0; k < 3; ++k) {
            edges[3 * t + k] = (uint64_t)tri[k] << 32 | tri[(k + 1) % 3];
        }
    }
    qsort(edges, edge_count, sizeof *edges, compare_u64);
    tb_status status = TB_STATUS_OK;
    for (size_t e = 0; e < edge_count && status == TB_STATUS_OK; ++e) {
        const unsigned from = (unsigned)(edges[e] >> 32), to = (unsigned)edges[e];
        const uint64_t reverse = (uint64_t)to << 32 | from;
        if (e + 1 < edge_count && edges[e + 1] == edges[e]) {
            status = tb__set_error(error, TB_STATUS_BAD_MESH,
                                   "edge %u->%u is used twice in the same direction: triangles "
                                   "are not consistently oriented (or the surface is not "
                                   "manifold)",
                                   from, to);
        } else if (bsearch(&reverse, edges, edge_count, sizeof *edges, compare_u64) == NULL) {
            status = tb__set_error(error, TB_STATUS_BAD_MESH,
                                   "edge %u->%u has no neighbouring triangle: the mesh is not "
                                   "closed",
                                   from, to);
        }
    }
    free(edges);
    return status;
}

/* Volume, first moment and covariance about o (unit density). */
static void integrate(const mesh_view *mesh, const double o[3], double *volume, double first[3],
                      double C[9])
{
    *volume = 0.0;
    tb__v3_set(first, 0, 0, 0);
    for (int i = 0; i < 9; ++i) {
        C[i] = 0.0;
    }
    for (size_t t = 0; t < mesh->triangle_count; ++t) {
        double p[3][3];
        for (int k = 0; k < 3; ++k) {
            const double *v = mesh->vertices + 3 * mesh->triangles[3 * t + k];
            tb__v3_set(p[k], v[0] - o[0], v[1] - o[1], v[2] - o[2]);
        }
        double bc[3];
        tb__v3_cross(bc, p[1], p[2]);
        const double tet_volume = tb__v3_dot(p[0], bc) / 6.0;
        const double s[3] = {p[0][0] + p[1][0] + p[2][0], p[0][1] + p[1][1] + p[2][1],
                             p[0][2] + p[1][2] + p[2][2]};
        *volume += tet_volume;
        tb__v3_axpy(first, tet_volume / 4.0, s);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                const double outer =
                    p[0][i] * p[0][j] + p[1][i] * p[1][j] + p[2][i] * p[2][j] + s[i] * s[j];
                C[3 * i + j] += tet_volume / 20.0 * outer;
            }
        }
    }
}

static tb_status check_inputs(const mesh_view *mesh, const tb_mass_properties *out, tb_error *error)
{
    /* The counts first: with too few, a NULL array (what an empty list gives) is not the
     * mistake to report. */
    if (mesh->vertex_count < 4 || mesh->triangle_count < 4) {
        return tb__set_error(error, TB_STATUS_BAD_MESH,
                             "%s: a closed mesh needs at least 4 vertices and 4 triangles, got "
                             "%zu and %zu",
                             mesh->vertex_count < 4 ? "vertex_count" : "triangle_count",
                             mesh->vertex_count, mesh->triangle_count);
    }
    if (mesh->vertices == NULL || mesh->triangles == NULL || out == NULL) {
        return tb__set_error(error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             mesh->vertices == NULL    ? "vertices"
                             : mesh->triangles == NULL ? "triangles"
                                                       : "out_props");
    }
    if (mesh->vertex_count > UINT32_MAX || mesh->triangle_count > SIZE_MAX / 24) {
        return tb__set_error(error, TB_STATUS_BAD_MESH, "mesh too large");
    }
    tb_status status = check_triangles(mesh, error);
    return status == TB_STATUS_OK ? check_closed(mesh, error) : status;
}

/* The integration origin: the centroid of the triangles' corners. Coordinates relative to it
 * stay as small as the solid, so a mesh far from the origin does not lose digits to
 * cancellation; a vertex no triangle uses does not move it (an unused vertex 1e5 m away moved
 * the old all-vertex centroid so far that the moments came out 230 times too large). */
static void corner_centroid(const mesh_view *mesh, double o[3])
{
    tb__v3_set(o, 0, 0, 0);
    const size_t corners = 3 * mesh->triangle_count;
    for (size_t corner = 0; corner < corners; ++corner) {
        tb__v3_axpy(o, 1.0 / (double)corners, mesh->vertices + 3 * (size_t)mesh->triangles[corner]);
    }
}

tb_status tb_mass_from_mesh(tb_mass_mode mode, double value, const double *vertices,
                            size_t vertex_count, const unsigned *triangles, size_t triangle_count,
                            tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    const mesh_view mesh = {vertices, vertex_count, triangles, triangle_count};
    tb_status status = check_inputs(&mesh, out_props, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    double o[3], volume, first[3], C[9];
    corner_centroid(&mesh, o);
    integrate(&mesh, o, &volume, first, C);
    if (!(volume > 0)) {
        return tb__set_error(out_error, TB_STATUS_BAD_MESH,
                             "enclosed volume is %g: triangles wind inward (clockwise seen from "
                             "outside); reverse them",
                             volume);
    }
    double mass;
    status = tb__resolve_mass(mode, value, volume, &mass, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double density = mode == TB_MASS_DENSITY ? value : mass / volume;
    const double d[3] = {first[0] / volume, first[1] / volume, first[2] / volume};
    double I[9];
    const double trace = C[0] + C[4] + C[8];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            /* Covariance about the centre of mass: C_o - V d d^T. */
            const double c = density * (C[3 * i + j] - volume * d[i] * d[j]);
            I[3 * i + j] = (i == j ? density * (trace - volume * tb__v3_dot(d, d)) : 0.0) - c;
        }
    }
    const double center[3] = {o[0] + d[0], o[1] + d[1], o[2] + d[2]};
    return tb_mass_from_tensor(mass, center, I, out_props, out_error);
}
