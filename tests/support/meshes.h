/* Closed triangle meshes for tests, built independently of tumble's mass code. */
#ifndef TUMBLE_TEST_MESHES_H
#define TUMBLE_TEST_MESHES_H

#include <stddef.h>

typedef struct test_mesh {
    double *vertices;    /* 3 * vertex_count */
    unsigned *triangles; /* 3 * triangle_count, outward winding */
    size_t vertex_count;
    size_t triangle_count;
} test_mesh;

/* Axis-aligned box centred at the origin with full edge lengths size[3]: 8 vertices,
 * 12 triangles. */
test_mesh test_mesh_box(const double size[3]);

/* Solid of revolution about z: the profile is count points (r, z), r = 0 at the first and
 * last (the poles), z increasing; slices segments around the axis. */
test_mesh test_mesh_revolution(const double *profile_r, const double *profile_z, size_t count,
                               size_t slices);

/* Sphere of radius r: stacks latitude bands, slices longitude segments. */
test_mesh test_mesh_sphere(double radius, size_t stacks, size_t slices);

/* Cylinder (radius, length along z, centred) and capsule (cylinder of that length plus
 * hemispherical caps of rings bands each). */
test_mesh test_mesh_cylinder(double radius, double length, size_t slices);
test_mesh test_mesh_capsule(double radius, double length, size_t rings, size_t slices);

/* v <- R(q) v + t for every vertex, q = (w, x, y, z) unit. */
void test_mesh_transform(test_mesh *mesh, const double q[4], const double t[3]);

/* Reverses every triangle's winding. */
void test_mesh_flip(test_mesh *mesh);

void test_mesh_free(test_mesh *mesh);

#endif
