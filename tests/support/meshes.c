#include "meshes.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

static void put_triangle(test_mesh *mesh, unsigned a, unsigned b, unsigned c)
{
    unsigned *t = mesh->triangles + 3 * mesh->triangle_count++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

test_mesh test_mesh_box(const double size[3])
{
    test_mesh mesh = {malloc(24 * sizeof(double)), malloc(36 * sizeof(unsigned)), 8, 0};
    for (unsigned c = 0; c < 8; ++c) { /* corner c has sign bits x = c&1, y = c&2, z = c&4 */
        for (int i = 0; i < 3; ++i) {
            mesh.vertices[3 * c + i] = ((c >> i) & 1 ? 0.5 : -0.5) * size[i];
        }
    }
    /* Each face as a quad of corners in cyclic order; wound outward below by checking the
     * normal against the direction from the centre (the box is convex). */
    static const unsigned quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                         {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; ++f) {
        const double *a = mesh.vertices + 3 * quads[f][0], *b = mesh.vertices + 3 * quads[f][1],
                     *c = mesh.vertices + 3 * quads[f][2];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                             u[0] * v[1] - u[1] * v[0]};
        const double outward = n[0] * (a[0] + c[0]) + n[1] * (a[1] + c[1]) + n[2] * (a[2] + c[2]);
        const unsigned *q = quads[f];
        if (outward > 0) {
            put_triangle(&mesh, q[0], q[1], q[2]);
            put_triangle(&mesh, q[0], q[2], q[3]);
        } else {
            put_triangle(&mesh, q[0], q[2], q[1]);
            put_triangle(&mesh, q[0], q[3], q[2]);
        }
    }
    return mesh;
}

test_mesh test_mesh_revolution(const double *r, const double *z, size_t count, size_t slices)
{
    const size_t rings = count - 2;
    test_mesh mesh;
    mesh.vertex_count = 2 + rings * slices;
    mesh.vertices = malloc(3 * mesh.vertex_count * sizeof(double));
    mesh.triangles = malloc(3 * 2 * rings * slices * sizeof(unsigned));
    mesh.triangle_count = 0;
    const unsigned bottom = 0, top = (unsigned)(mesh.vertex_count - 1);
    double *v = mesh.vertices;
    v[0] = v[1] = 0.0;
    v[2] = z[0];
    for (size_t k = 0; k < rings; ++k) {
        for (size_t j = 0; j < slices; ++j) {
            const double phi = 2.0 * PI * (double)j / (double)slices;
            double *p = v + 3 * (1 + k * slices + j);
            p[0] = r[k + 1] * cos(phi);
            p[1] = r[k + 1] * sin(phi);
            p[2] = z[k + 1];
        }
    }
    v[3 * top] = v[3 * top + 1] = 0.0;
    v[3 * top + 2] = z[count - 1];
#define RING(k, j) ((unsigned)(1 + (k)*slices + (j) % slices))
    for (size_t j = 0; j < slices; ++j) {
        put_triangle(&mesh, bottom, RING(0, j + 1), RING(0, j));
        for (size_t k = 0; k + 1 < rings; ++k) {
            put_triangle(&mesh, RING(k, j), RING(k, j + 1), RING(k + 1, j + 1));
            put_triangle(&mesh, RING(k, j), RING(k + 1, j + 1), RING(k + 1, j));
        }
        put_triangle(&mesh, top, RING(rings - 1, j), RING(rings - 1, j + 1));
    }
#undef RING
    return mesh;
}

test_mesh test_mesh_sphere(double radius, size_t stacks, size_t slices)
{
    double *r = malloc((stacks + 1) * sizeof(double)), *z = malloc((stacks + 1) * sizeof(double));
    for (size_t k = 0; k <= stacks; ++k) {
        const double theta = PI * (double)k / (double)stacks; /* from the south pole */
        r[k] = k == 0 || k == stacks ? 0.0 : radius * sin(theta);
        z[k] = -radius * cos(theta);
    }
    test_mesh mesh = test_mesh_revolution(r, z, stacks + 1, slices);
    free(r);
    free(z);
    return mesh;
}

test_mesh test_mesh_cylinder(double radius, double length, size_t slices)
{
    const double r[4] = {0, radius, radius, 0};
    const double z[4] = {-length / 2, -length / 2, length / 2, length / 2};
    return test_mesh_revolution(r, z, 4, slices);
}

test_mesh test_mesh_capsule(double radius, double length, size_t rings, size_t slices)
{
    const size_t count = 2 * rings + 2;
    double *r = malloc(count * sizeof(double)), *z = malloc(count * sizeof(double));
    for (size_t k = 0; k <= rings; ++k) { /* bottom cap from the pole to the equator */
        const double theta = 0.5 * PI * (double)k / (double)rings;
        r[k] = k == 0 ? 0.0 : radius * sin(theta);
        z[k] = -length / 2 - radius * cos(theta);
        r[count - 1 - k] = r[k];
        z[count - 1 - k] = -z[k];
    }
    test_mesh mesh = test_mesh_revolution(r, z, count, slices);
    free(r);
    free(z);
    return mesh;
}

void test_mesh_transform(test_mesh *mesh, const double q[4], const double t[3])
{
    const double w = q[0], x = q[1], y = q[2], zq = q[3];
    const double R[9] = {
        1 - 2 * (y * y + zq * zq), 2 * (x * y - w * zq),      2 * (x * zq + w * y),
        2 * (x * y + w * zq),      1 - 2 * (x * x + zq * zq), 2 * (y * zq - w * x),
        2 * (x * zq - w * y),      2 * (y * zq + w * x),      1 - 2 * (x * x + y * y)};
    for (size_t v = 0; v < mesh->vertex_count; ++v) {
        double *p = mesh->vertices + 3 * v;
        const double o[3] = {p[0], p[1], p[2]};
        for (int i = 0; i < 3; ++i) {
            p[i] = R[3 * i] * o[0] + R[3 * i + 1] * o[1] + R[3 * i + 2] * o[2] + t[i];
        }
    }
}

void test_mesh_flip(test_mesh *mesh)
{
    for (size_t t = 0; t < mesh->triangle_count; ++t) {
        unsigned swap = mesh->triangles[3 * t + 1];
        mesh->triangles[3 * t + 1] = mesh->triangles[3 * t + 2];
        mesh->triangles[3 * t + 2] = swap;
    }
}

void test_mesh_free(test_mesh *mesh)
{
    free(mesh->vertices);
    free(mesh->triangles);
    mesh->vertices = NULL;
    mesh->triangles = NULL;
}
