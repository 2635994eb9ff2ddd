/* Writers: triangle meshes of the shapes for glTF, in the shape frame (m), with outward
 * normals and counter-clockwise triangles seen from outside (glTF's front faces). */
#include "export/writer_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TB__PI 3.14159265358979323846
#define TB__SEGMENTS 32 /* around a round shape's axis */
#define TB__RINGS 16    /* from pole to pole */

/* Adds a vertex; returns its index. The normal is normalised here. */
static uint32_t vertex(tb__mesh *m, const double p[3], const double n[3])
{
    size_t capacity = m->vertex_capacity;
    if (!tb__grow_array((void **)&m->positions, &capacity, m->vertex_count + 1,
                        3 * sizeof(float)) ||
        !tb__grow_array((void **)&m->normals, &m->vertex_capacity, m->vertex_count + 1,
                        3 * sizeof(float))) {
        m->failed = true;
        return 0;
    }
    const double length = tb__v3_norm(n);
    for (int i = 0; i < 3; ++i) {
        m->positions[3 * m->vertex_count + i] = (float)p[i];
        m->normals[3 * m->vertex_count + i] = (float)(length > 0 ? n[i] / length : i == 2);
    }
    return (uint32_t)m->vertex_count++;
}

static void triangle(tb__mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->failed || !tb__grow_array((void **)&m->indices, &m->index_capacity, m->index_count + 3,
                                     sizeof(uint32_t))) {
        m->failed = true;
        return;
    }
    m->indices[m->index_count++] = a;
    m->indices[m->index_count++] = b;
    m->indices[m->index_count++] = c;
}

/* A box of edges size centred at the origin: 4 vertices a face, so each face is flat. */
static void box(tb__mesh *m, const double size[3])
{
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2, sign = face % 2 ? -1 : 1;
        /* u x v = sign * e_axis, so the corners below run counter-clockwise about the normal */
        const int u = (axis + (sign > 0 ? 1 : 2)) % 3, v = (axis + (sign > 0 ? 2 : 1)) % 3;
        double n[3] = {0, 0, 0}, p[3];
        n[axis] = sign;
        static const int corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        const uint32_t first = (uint32_t)m->vertex_count;
        for (int k = 0; k < 4; ++k) {
            p[axis] = 0.5 * sign * size[axis];
            p[u] = 0.5 * corners[k][0] * size[u];
            p[v] = 0.5 * corners[k][1] * size[v];
            vertex(m, p, n);
        }
        triangle(m, first, first + 1, first + 2);
        triangle(m, first, first + 2, first + 3);
    }
}

/* A round surface: the ellipsoid of semi-axes a about center, turned by q (w, x, y, z); with
 * stretch > 0 its halves move apart along z by stretch / 2 each (a capsule). */
typedef struct round_shape {
    double a[3], center[3], q[4], stretch;
} round_shape;

static uint32_t round_vertex(tb__mesh *m, const round_shape *r, int ring, int segment)
{
    /* two equator rings when stretched: ring TB__RINGS / 2 belongs to the lower half */
    const int half = TB__RINGS / 2;
    const int latitude_ring = ring <= half ? ring : ring - (r->stretch > 0);
    const double phi = -0.5 * TB__PI + TB__PI * latitude_ring / TB__RINGS;
    const double theta = 2.0 * TB__PI * (segment % TB__SEGMENTS) / TB__SEGMENTS;
    const double d[3] = {cos(phi) * cos(theta), cos(phi) * sin(theta), sin(phi)};
    double local[3], normal[3], p[3], n[3];
    for (int i = 0; i < 3; ++i) {
        local[i] = r->a[i] * d[i];
        normal[i] = d[i] / r->a[i]; /* gradient of the ellipsoid's equation */
    }
    local[2] += r->stretch > 0 ? (ring <= half ? -0.5 : 0.5) * r->stretch : 0.0;
    tb__q_rotate(p, r->q, local);
    tb__q_rotate(n, r->q, normal);
    tb__v3_axpy(p, 1.0, r->center);
    return vertex(m, p, n);
}

static void round_surface(tb__mesh *m, const round_shape *r)
{
    const int rings = TB__RINGS + (r->stretch > 0); /* index of the last ring */
    const uint32_t first = (uint32_t)m->vertex_count;
    for (int ring = 0; ring <= rings; ++ring) {
        for (int segment = 0; segment <= TB__SEGMENTS; ++segment) {
            round_vertex(m, r, ring, segment);
        }
    }
    const uint32_t row = TB__SEGMENTS + 1;
    for (uint32_t ring = 0; ring < (uint32_t)rings; ++ring) {
        for (uint32_t s = 0; s < TB__SEGMENTS; ++s) {
            const uint32_t a = first + ring * row + s, b = a + 1, c = b + row, d = a + row;
            if (ring > 0) { /* at the south pole a and b are one point */
                triangle(m, a, b, c);
            }
            if (ring + 1 < (uint32_t)rings) { /* at the north pole c and d are one point */
                triangle(m, a, c, d);
            }
        }
    }
}

/* Cylinder of radius r and length h along z: a side with radial normals and two flat caps. */
static void cylinder(tb__mesh *m, double radius, double length)
{
    const uint32_t side = (uint32_t)m->vertex_count;
    for (int end = 0; end < 2; ++end) {
        for (int s = 0; s <= TB__SEGMENTS; ++s) {
            const double theta = 2.0 * TB__PI * (s % TB__SEGMENTS) / TB__SEGMENTS;
            const double n[3] = {cos(theta), sin(theta), 0};
            const double p[3] = {radius * n[0], radius * n[1], (end - 0.5) * length};
            vertex(m, p, n);
        }
    }
    for (uint32_t s = 0; s < TB__SEGMENTS; ++s) {
        const uint32_t a = side + s, d = a + TB__SEGMENTS + 1;
        triangle(m, a, a + 1, d + 1);
        triangle(m, a, d + 1, d);
    }
    for (int end = 0; end < 2; ++end) {
        const double n[3] = {0, 0, end ? 1 : -1}, middle[3] = {0, 0, (end - 0.5) * length};
        const uint32_t centre = vertex(m, middle, n);
        for (int s = 0; s <= TB__SEGMENTS; ++s) {
            const double theta = 2.0 * TB__PI * (s % TB__SEGMENTS) / TB__SEGMENTS;
            const double p[3] = {radius * cos(theta), radius * sin(theta), middle[2]};
            vertex(m, p, n);
        }
        for (uint32_t s = 0; s < TB__SEGMENTS; ++s) {
            const uint32_t a = centre + 1 + s;
            triangle(m, centre, end ? a : a + 1, end ? a + 1 : a);
        }
    }
}

/* Flat-shaded triangles (each its own three vertices and face normal); degenerate ones,
 * which have no normal, are left out. */
static void triangles(tb__mesh *m, const double *v, const unsigned *t, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        const double *a = v + 3 * t[3 * k], *b = v + 3 * t[3 * k + 1], *c = v + 3 * t[3 * k + 2];
        double ab[3], ac[3], n[3];
        tb__v3_set(ab, b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        tb__v3_set(ac, c[0] - a[0], c[1] - a[1], c[2] - a[2]);
        tb__v3_cross(n, ab, ac);
        if (!((float)tb__v3_norm(n) > 0.0f)) {
            continue;
        }
        const uint32_t first = vertex(m, a, n);
        vertex(m, b, n);
        vertex(m, c, n);
        triangle(m, first, first + 1, first + 2);
    }
}

/* Point masses as spheres of a size that shows them: 8% of the points' bounding box. */
static void points(tb__mesh *m, const double *p, size_t count)
{
    double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < 3 * count; ++k) {
        low[k % 3] = fmin(low[k % 3], p[k]);
        high[k % 3] = fmax(high[k % 3], p[k]);
    }
    const double extent[3] = {high[0] - low[0], high[1] - low[1], high[2] - low[2]};
    const double radius = tb__v3_norm(extent) > 0 ? 0.08 * tb__v3_norm(extent) : 0.05;
    for (size_t k = 0; k < count; ++k) {
        round_shape r = {
            {radius, radius, radius}, {p[3 * k], p[3 * k + 1], p[3 * k + 2]}, {1, 0, 0, 0}, 0.0};
        round_surface(m, &r);
    }
}

/* The solid ellipsoid with the body's mass and principal moments (I_1 = M (a_2^2 + a_3^2) / 5,
 * ...), at its centre of mass and turned to its principal axes. A moment sum that gives no
 * positive square (a rod) keeps a sliver of 1% of the largest semi-axis. */
static void inertia_ellipsoid(tb__mesh *m, const tb_mass_properties *mass)
{
    const double *I = mass->moments;
    round_shape r = {{0}, {0}, {0}, 0.0};
    double largest = 0;
    for (int i = 0; i < 3; ++i) {
        const double square = 2.5 / mass->mass * (I[(i + 1) % 3] + I[(i + 2) % 3] - I[i]);
        r.a[i] = square > 0 ? sqrt(square) : 0.0;
        largest = fmax(largest, r.a[i]);
    }
    for (int i = 0; i < 3; ++i) {
        r.a[i] = fmax(r.a[i], 0.01 * (largest > 0 ? largest : 1.0));
    }
    memcpy(r.center, mass->center, sizeof r.center);
    memcpy(r.q, mass->rotation, sizeof r.q);
    round_surface(m, &r);
}

void tb__mesh_of_shape(tb__mesh *m, const tb__shape *s)
{
    const double r = s->size[0];
    round_shape sphere = {{r, r, r}, {0, 0, 0}, {1, 0, 0, 0}, 0.0};
    switch (s->kind) {
    case TB__SHAPE_BOX:
        box(m, s->size);
        break;
    case TB__SHAPE_CAPSULE:
        sphere.stretch = s->size[1];
        round_surface(m, &sphere);
        break;
    case TB__SHAPE_ELLIPSOID:
        memcpy(sphere.a, s->size, sizeof sphere.a);
        round_surface(m, &sphere);
        break;
    case TB__SHAPE_SPHERE:
        round_surface(m, &sphere);
        break;
    case TB__SHAPE_CYLINDER:
        cylinder(m, s->size[0], s->size[1]);
        break;
    case TB__SHAPE_MESH:
        triangles(m, s->vertices, s->triangles, s->triangle_count);
        break;
    case TB__SHAPE_POINTS:
        points(m, s->vertices, s->vertex_count);
        break;
    default:
        inertia_ellipsoid(m, &s->mass);
        break;
    }
}

void tb__mesh_of_ground(tb__mesh *m, const tb__ground *g, const double center[3], double half_size)
{
    /* the plane's own axes u, v with u x v = normal, from the world axis least along it */
    const double *n = g->normal;
    const int least = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0
                      : fabs(n[1]) <= fabs(n[2])                           ? 1
                                                                           : 2;
    double axis[3] = {0, 0, 0}, u[3], v[3], base[3];
    axis[least] = 1;
    tb__v3_cross(u, n, axis);
    const double length = tb__v3_norm(u);
    tb__v3_set(u, u[0] / length, u[1] / length, u[2] / length);
    tb__v3_cross(v, n, u);
    /* the point of the plane nearest center */
    const double height = tb__v3_dot(n, center) - g->offset;
    tb__v3_set(base, center[0] - height * n[0], center[1] - height * n[1],
               center[2] - height * n[2]);
    static const int corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    const uint32_t first = (uint32_t)m->vertex_count;
    for (int k = 0; k < 4; ++k) {
        double p[3];
        tb__v3_copy(p, base);
        tb__v3_axpy(p, corners[k][0] * half_size, u);
        tb__v3_axpy(p, corners[k][1] * half_size, v);
        vertex(m, p, n);
    }
    triangle(m, first, first + 1, first + 2);
    triangle(m, first, first + 2, first + 3);
}

void tb__ground_extent(const tb__frames *f, double center[3], double *half_size)
{
    tb__v3_set(center, 0, 0, 0);
    const size_t n = f->count > 0 ? f->body_count : 0;
    for (size_t id = 0; id < n; ++id) {
        tb__v3_axpy(center, 1.0 / (double)n, f->position + 3 * id);
    }
    double spread = 0;
    for (size_t k = 0; k < f->count * n; ++k) {
        const double *p = f->position + 3 * k;
        double d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
        spread = fmax(spread, tb__v3_norm(d));
    }
    *half_size = fmax(10.0, 2.0 * spread);
}

void tb__mesh_free(tb__mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->indices);
    memset(m, 0, sizeof *m);
}
