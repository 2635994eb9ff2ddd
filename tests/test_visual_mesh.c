/* The scene owns the visual meshes and the writers draw from it: a mesh given through the C
 * API, a visual mesh set on a piece, and an OBJ file of several groups are written to the .glb
 * with exactly the triangles the test gave (count and vertex positions), not their hulls.
 * The .glb is read back with jansson and the test's own arrays are the expected values. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DIRECTORY TUMBLE_TEST_BUILD_DIR "/"

/* An L-shaped prism, 0.1 m thick: the L (0, 0) (0.2, 0) (0.2, 0.1) (0.1, 0.1) (0.1, 0.3)
 * (0, 0.3) at z = 0 (vertices 0-5) and z = 0.1 (6-11). Not convex: its hull leaves out the
 * inner corner (0.1, 0.1), so the hull has 10 vertices and 16 triangles, the L 12 and 20. */
static const double l_vertices[36] = {0,   0,   0,   0.2, 0,   0,   0.2, 0.1, 0,   0.1, 0.1, 0,
                                      0.1, 0.3, 0,   0,   0.3, 0,   0,   0,   0.1, 0.2, 0,   0.1,
                                      0.2, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.3, 0.1, 0,   0.3, 0.1};
#define L_TRIANGLES 20
static unsigned l_triangles[3 * L_TRIANGLES];

/* The caps fanned from the corner at the origin (counter-clockwise seen from outside), then
 * each side a quad (bottom i, bottom j, top j, top i) cut in two. */
static void make_l_triangles(void)
{
    unsigned *t = l_triangles;
    for (unsigned k = 0; k < 4; ++k) {
        const unsigned top[3] = {6, 7 + k, 8 + k}, bottom[3] = {0, 2 + k, 1 + k};
        memcpy(t, top, sizeof top);
        memcpy(t + 3, bottom, sizeof bottom);
        t += 6;
    }
    for (unsigned i = 0; i < 6; ++i) {
        const unsigned j = (i + 1) % 6;
        const unsigned side[6] = {i, j, 6 + j, i, 6 + j, 6 + i};
        memcpy(t, side, sizeof side);
        t += 6;
    }
}

/* A tetrahedron with its right-angled corner at (0.4, 0, 0), edges 0.1 m. */
static const double tetra_vertices[12] = {0.4, 0, 0, 0.5, 0, 0, 0.4, 0.1, 0, 0.4, 0, 0.1};
static const unsigned tetra_triangles[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

/* A body's triangles as the .glb holds them: float positions, 9 a triangle. */
typedef struct drawn {
    float *corners;
    size_t triangle_count;
} drawn;

static unsigned char *read_all(const char *path, size_t *size)
{
    FILE *file = fopen(path, "rb");
    assert_non_null(file);
    fseek(file, 0, SEEK_END);
    *size = (size_t)ftell(file);
    fseek(file, 0, SEEK_SET);
    unsigned char *data = malloc(*size + 1);
    assert_int_equal(fread(data, 1, *size, file), *size);
    fclose(file);
    return data;
}

static uint32_t read32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Where accessor index's data starts in the binary chunk, and its count. */
static const unsigned char *accessor_data(json_t *root, const unsigned char *bin, json_int_t index,
                                          size_t *count)
{
    json_t *accessor = json_array_get(json_object_get(root, "accessors"), (size_t)index);
    json_t *view =
        json_array_get(json_object_get(root, "bufferViews"),
                       (size_t)json_integer_value(json_object_get(accessor, "bufferView")));
    *count = (size_t)json_integer_value(json_object_get(accessor, "count"));
    return bin + json_integer_value(json_object_get(view, "byteOffset")) +
           json_integer_value(json_object_get(accessor, "byteOffset"));
}

/* The mesh named name in the .glb at path, its triangles' corners (glTF's little-endian floats
 * and 32-bit indices, read byte by byte). */
static drawn read_drawn(const char *path, const char *name)
{
    size_t size = 0;
    unsigned char *data = read_all(path, &size);
    assert_memory_equal(data, "glTF", 4);
    const uint32_t json_length = read32(data + 12);
    const unsigned char *bin = data + 20 + json_length + 8;
    json_error_t error;
    json_t *root = json_loadb((const char *)data + 20, json_length, 0, &error);
    assert_non_null(root);
    json_t *meshes = json_object_get(root, "meshes"), *primitive = NULL;
    for (size_t k = 0; k < json_array_size(meshes); ++k) {
        json_t *mesh = json_array_get(meshes, k);
        if (strcmp(json_string_value(json_object_get(mesh, "name")), name) == 0) {
            primitive = json_array_get(json_object_get(mesh, "primitives"), 0);
        }
    }
    assert_non_null(primitive);
    json_t *attributes = json_object_get(primitive, "attributes");
    size_t vertex_count = 0, index_count = 0;
    const unsigned char *positions = accessor_data(
        root, bin, json_integer_value(json_object_get(attributes, "POSITION")), &vertex_count);
    const unsigned char *indices = accessor_data(
        root, bin, json_integer_value(json_object_get(primitive, "indices")), &index_count);
    drawn d = {malloc(3 * index_count * sizeof(float) + 1), index_count / 3};
    for (size_t k = 0; k < index_count; ++k) {
        const uint32_t v = read32(indices + 4 * k);
        assert_true(v < vertex_count);
        for (int i = 0; i < 3; ++i) {
            const uint32_t bits = read32(positions + 12 * v + 4 * i);
            memcpy(&d.corners[3 * k + i], &bits, sizeof bits);
        }
    }
    json_decref(root);
    free(data);
    return d;
}

/* Triangles [first, first + count) of d are the mesh's, in order, each corner the float
 * nearest the given double (glTF stores floats: the writer rounds once), exactly. Moved by a
 * piece's pose (q, t), the test's double arithmetic may differ from the writer's in the last
 * bits, which can tip the rounding to the next float (6e-8 m near 0.5 m): within 1e-6 m,
 * while a wrong vertex or pose is off by centimetres. */
static void assert_drawn_as(const drawn *d, size_t first, const double *vertices,
                            const unsigned *triangles, size_t count, const double q[4],
                            const double t[3])
{
    assert_true(first + count <= d->triangle_count);
    for (size_t k = 0; k < 3 * count; ++k) {
        const double *v = vertices + 3 * triangles[k];
        double p[3] = {v[0], v[1], v[2]};
        if (q != NULL) { /* p = R(q) v + t: v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z) */
            const double *u = q + 1, c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                             u[0] * v[1] - u[1] * v[0]};
            const double cc[3] = {u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2],
                                  u[0] * c[1] - u[1] * c[0]};
            for (int i = 0; i < 3; ++i) {
                p[i] = v[i] + 2.0 * q[0] * c[i] + 2.0 * cc[i] + t[i];
            }
        }
        for (int i = 0; i < 3; ++i) {
            const float got = d->corners[9 * first + 3 * k + i];
            if (q == NULL) {
                assert_true(got == (float)p[i]);
            } else {
                assert_true(fabs((double)got - p[i]) < 1e-6);
            }
        }
    }
}

static tb_scene *empty_scene(void)
{
    tb_scene *scene = NULL;
    const tb_scene_def def = tb_scene_def_default();
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    return scene;
}

static size_t add_body(tb_scene *scene, const char *name)
{
    tb_body_def body = tb_body_def_default();
    body.name = name;
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 1.0, (double[3]){0.1, 0.1, 0.1}, &body.mass, NULL),
        TB_STATUS_OK);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
    return id;
}

/* A short run of the scene into a .glb at path. */
static void export_glb(tb_scene *scene, const char *path)
{
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_GLB;
    tb_run_def run = tb_run_def_default();
    run.duration = 0.1;
    run.fps = 10;
    tb_writer *writer = NULL;
    tb_error error;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error), TB_STATUS_OK);
    assert_int_equal(tb_scene_run(scene, &run, tb_writer_on_frame, writer, NULL, NULL),
                     TB_STATUS_OK);
    assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_OK);
}

/* A convex shape given with its triangles (a mesh) collides as its hull and is drawn as itself:
 * the L's 20 triangles, not the hull's 16. No scene file is involved. */
static void test_a_mesh_shape_given_in_c_is_drawn_with_its_own_triangles(void **state)
{
    (void)state;
    tb_scene *scene = empty_scene();
    const size_t id = add_body(scene, "letter");
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_CONVEX;
    shape.vertices = l_vertices;
    shape.vertex_count = 12;
    shape.triangles = l_triangles;
    shape.triangle_count = L_TRIANGLES;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    tb_shape_piece piece;
    assert_int_equal(tb_scene_body_piece(scene, id, 0, &piece), TB_STATUS_OK);
    assert_int_equal(piece.shape.vertex_count, 10); /* collides as the hull */
    tb_visual_mesh visual;
    assert_int_equal(tb_scene_body_visual_mesh(scene, id, 0, &visual), TB_STATUS_OK);
    assert_int_equal(visual.vertex_count, 12);
    assert_int_equal(visual.triangle_count, L_TRIANGLES);
    assert_true(visual.vertices != l_vertices); /* copied */
    assert_memory_equal(visual.vertices, l_vertices, sizeof l_vertices);
    assert_memory_equal(visual.triangles, l_triangles, sizeof l_triangles);

    const char *path = DIRECTORY "visual_mesh_c.glb";
    export_glb(scene, path);
    drawn d = read_drawn(path, "letter");
    assert_int_equal(d.triangle_count, L_TRIANGLES);
    assert_drawn_as(&d, 0, l_vertices, l_triangles, L_TRIANGLES, NULL, NULL);
    free(d.corners);

    /* setting the shape again replaces the visual meshes: a sphere is drawn as a sphere */
    shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = 0.1;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_visual_mesh(scene, id, 0, &visual), TB_STATUS_OK);
    assert_int_equal(visual.triangle_count, 0);
    assert_null(visual.vertices);
    tb_scene_destroy(scene);
}

/* tb_scene_set_body_visual_mesh on piece 1 of a compound: the box piece is drawn as a box (12
 * triangles), the sphere piece as the tetrahedron, placed by the piece's pose; on a body
 * without a shape, the mesh replaces the inertia ellipsoid. */
static void test_a_visual_mesh_set_on_a_piece_is_drawn_at_the_piece(void **state)
{
    (void)state;
    tb_scene *scene = empty_scene();
    const size_t id = add_body(scene, "compound"), bare = add_body(scene, "bare");
    tb_shape_piece pieces[2] = {tb_shape_piece_default(), tb_shape_piece_default()};
    pieces[0].shape.type = TB_SHAPE_BOX;
    pieces[0].shape.size[0] = pieces[0].shape.size[1] = pieces[0].shape.size[2] = 0.1;
    pieces[1].shape.type = TB_SHAPE_SPHERE;
    pieces[1].shape.radius = 0.05;
    const double q[4] = {sqrt(0.5), 0, 0, sqrt(0.5)}, t[3] = {0.3, -0.1, 0.2}; /* 90 deg about z */
    memcpy(pieces[1].orientation, q, sizeof q);
    memcpy(pieces[1].position, t, sizeof t);
    assert_int_equal(tb_scene_set_body_pieces(scene, id, pieces, 2), TB_STATUS_OK);
    assert_int_equal(
        tb_scene_set_body_visual_mesh(scene, id, 1, tetra_vertices, 4, tetra_triangles, 4),
        TB_STATUS_OK);
    assert_int_equal(
        tb_scene_set_body_visual_mesh(scene, bare, 0, tetra_vertices, 4, tetra_triangles, 4),
        TB_STATUS_OK);

    const char *path = DIRECTORY "visual_mesh_piece.glb";
    export_glb(scene, path);
    drawn d = read_drawn(path, "compound");
    assert_int_equal(d.triangle_count, 12 + 4);
    assert_drawn_as(&d, 12, tetra_vertices, tetra_triangles, 4, q, t);
    free(d.corners);
    d = read_drawn(path, "bare");
    assert_int_equal(d.triangle_count, 4);
    assert_drawn_as(&d, 0, tetra_vertices, tetra_triangles, 4, NULL, NULL);
    free(d.corners);

    /* counts 0 remove it: the piece is drawn as its sphere again */
    assert_int_equal(tb_scene_set_body_visual_mesh(scene, id, 1, NULL, 0, NULL, 0), TB_STATUS_OK);
    tb_visual_mesh visual;
    assert_int_equal(tb_scene_body_visual_mesh(scene, id, 1, &visual), TB_STATUS_OK);
    assert_int_equal(visual.triangle_count, 0);
    tb_scene_destroy(scene);
}

/* An OBJ file of two groups (the L, then the tetrahedron), written here from the arrays above,
 * loaded from a scene file: one convex piece a group, each drawn with its group's triangles
 * (20 and 4, against the hulls' 16 and 4). */
static void test_an_obj_of_several_groups_is_drawn_group_by_group(void **state)
{
    (void)state;
    FILE *obj = fopen(DIRECTORY "visual_mesh_groups.obj", "w");
    assert_non_null(obj);
    for (size_t v = 0; v < 12; ++v) {
        fprintf(obj, "v %.17g %.17g %.17g\n", l_vertices[3 * v], l_vertices[3 * v + 1],
                l_vertices[3 * v + 2]);
    }
    for (size_t v = 0; v < 4; ++v) {
        fprintf(obj, "v %.17g %.17g %.17g\n", tetra_vertices[3 * v], tetra_vertices[3 * v + 1],
                tetra_vertices[3 * v + 2]);
    }
    fprintf(obj, "g letter\n");
    for (size_t k = 0; k < L_TRIANGLES; ++k) { /* OBJ counts from 1 */
        fprintf(obj, "f %u %u %u\n", l_triangles[3 * k] + 1, l_triangles[3 * k + 1] + 1,
                l_triangles[3 * k + 2] + 1);
    }
    fprintf(obj, "g tetrahedron\n");
    for (size_t k = 0; k < 4; ++k) {
        fprintf(obj, "f %u %u %u\n", tetra_triangles[3 * k] + 13, tetra_triangles[3 * k + 1] + 13,
                tetra_triangles[3 * k + 2] + 13);
    }
    fclose(obj);
    FILE *json = fopen(DIRECTORY "visual_mesh_groups.json", "w");
    assert_non_null(json);
    fprintf(json, "{\"bodies\": [{\"name\": \"groups\", \"density\": 500, \"shape\": "
                  "{\"type\": \"mesh\", \"file\": \"visual_mesh_groups.obj\"}}]}\n");
    fclose(json);
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_file(DIRECTORY "visual_mesh_groups.json", &scene, &run, &error),
                     TB_STATUS_OK);
    size_t count = 0;
    assert_int_equal(tb_scene_body_piece_count(scene, 0, &count), TB_STATUS_OK);
    assert_int_equal(count, 2);

    const char *path = DIRECTORY "visual_mesh_groups.glb";
    export_glb(scene, path);
    drawn d = read_drawn(path, "groups");
    assert_int_equal(d.triangle_count, L_TRIANGLES + 4);
    assert_drawn_as(&d, 0, l_vertices, l_triangles, L_TRIANGLES, NULL, NULL);
    assert_drawn_as(&d, L_TRIANGLES, tetra_vertices, tetra_triangles, 4, NULL, NULL);
    free(d.corners);
    tb_scene_destroy(scene);
}

int main(void)
{
    make_l_triangles();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_mesh_shape_given_in_c_is_drawn_with_its_own_triangles),
        cmocka_unit_test(test_a_visual_mesh_set_on_a_piece_is_drawn_at_the_piece),
        cmocka_unit_test(test_an_obj_of_several_groups_is_drawn_group_by_group),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
