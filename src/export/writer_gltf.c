/* Writers: animated glTF 2.0 (.glb, or .gltf with the buffer embedded as base64). One node a
 * body, named as in the scene, with its shape as a mesh in the shape frame, under one root
 * node that turns tumble's z-up world into glTF's y-up one; ground planes as large squares.
 * Per body a translation channel (LINEAR) and a rotation channel: CUBICSPLINE with tangents
 * dq/dt = 1/2 (0, omega) q, or LINEAR. The glTF 2.0 specification, Appendix C, defines the
 * spline: p(s) = (2s^3 - 3s^2 + 1) v_k + t_d (s^3 - 2s^2 + s) b_k + (-2s^3 + 3s^2) v_k+1
 * + t_d (s^3 - s^2) a_k+1 with t_d the key interval, so the tangents a, b are stored per
 * second: the derivative itself. Each joint is a small dark sphere at its anchor, a child of
 * its first body's node (so it rides with that body), its extras naming the joint. */
#include "export/writer_gltf_internal.h"

#include "core/detail.h"
#include "math/tb_math.h"
#include "tumble/effects.h" /* TB_WORLD */

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Colours that tell neighbouring bodies apart (linear RGB). */
static const double palette[][3] = {{0.80, 0.22, 0.12}, {0.10, 0.38, 0.80}, {0.95, 0.65, 0.05},
                                    {0.20, 0.62, 0.25}, {0.55, 0.25, 0.70}, {0.05, 0.65, 0.70},
                                    {0.85, 0.40, 0.60}, {0.45, 0.45, 0.45}};
#define TB__PALETTE (sizeof palette / sizeof palette[0])

static json_t *vector_json(const double *v, size_t n)
{
    json_t *array = json_array();
    for (size_t k = 0; k < n; ++k) {
        json_array_append_new(array, json_real(v[k]));
    }
    return array;
}

/* One material per colour the bodies use, then the ground's (index body_materials(w)). */
static size_t body_materials(const tb_writer *w)
{
    return w->body_count < TB__PALETTE ? w->body_count : TB__PALETTE;
}

static void add_materials(tb__gltf *g, const tb_writer *w)
{
    const size_t count = body_materials(w) + (w->looks.ground_count > 0);
    for (size_t k = 0; k < count; ++k) {
        const bool ground = k == body_materials(w);
        const double grey[3] = {0.62, 0.62, 0.58};
        const double *rgb = ground ? grey : palette[k];
        const double color[4] = {rgb[0], rgb[1], rgb[2], 1.0};
        char name[32];
        snprintf(name, sizeof name, ground ? "ground" : "body colour %zu", k + 1);
        json_array_append_new(g->materials, json_pack("{s:s, s:{s:o, s:f, s:f}, s:b}", "name", name,
                                                      "pbrMetallicRoughness", "baseColorFactor",
                                                      vector_json(color, 4), "metallicFactor", 0.0,
                                                      "roughnessFactor", ground ? 0.9 : 0.5,
                                                      "doubleSided", ground));
    }
}

/* A mesh from the triangles; returns its index, or -1 when it has none. */
static long add_mesh(tb__gltf *g, const tb__mesh *m, const char *name, size_t material)
{
    if (m->index_count == 0) {
        return -1;
    }
    double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t k = 0; k < 3 * m->vertex_count; ++k) {
        low[k % 3] = fmin(low[k % 3], m->positions[k]);
        high[k % 3] = fmax(high[k % 3], m->positions[k]);
    }
    const size_t n = m->vertex_count;
    const long position =
        tb__gltf_accessor(g, m->positions, n, TB__GLTF_VEC3, TB__GLTF_VERTICES, low, high);
    const long normal =
        tb__gltf_accessor(g, m->normals, n, TB__GLTF_VEC3, TB__GLTF_VERTICES, NULL, NULL);
    const long indices = tb__gltf_accessor(g, m->indices, m->index_count, TB__GLTF_INDEX,
                                           TB__GLTF_INDICES, NULL, NULL);
    json_t *primitive = json_pack("{s:{s:i, s:i}, s:i, s:i, s:i}", "attributes", "POSITION",
                                  (json_int_t)position, "NORMAL", (json_int_t)normal, "indices",
                                  (json_int_t)indices, "material", (json_int_t)material, "mode", 4);
    json_array_append_new(g->meshes,
                          json_pack("{s:s, s:[o]}", "name", name, "primitives", primitive));
    return (long)json_array_size(g->meshes) - 1;
}

static json_t *body_node(tb__gltf *g, const tb_writer *w, size_t id)
{
    tb__mesh mesh = {0};
    tb__mesh_of_body(&mesh, &w->looks.bodies[id]);
    const long index = mesh.failed ? -1 : add_mesh(g, &mesh, w->names[id], id % TB__PALETTE);
    g->failed |= mesh.failed;
    tb__mesh_free(&mesh);
    json_t *node = json_pack("{s:s}", "name", w->names[id]);
    if (index >= 0) {
        json_object_set_new(node, "mesh", json_integer(index));
    }
    if (w->frames.count > 0) {
        /* the first key's pose, as the float the animation holds; glTF wants each component
         * in [-1, 1], which a unit quaternion's rounding can pass by an ulp */
        const double *q = w->frames.orientation + 4 * id;
        double xyzw[4] = {q[1], q[2], q[3], q[0]};
        for (int i = 0; i < 4; ++i) {
            xyzw[i] = fmax(-1.0, fmin(1.0, (double)(float)xyzw[i]));
        }
        json_object_set_new(node, "translation", vector_json(w->frames.position + 3 * id, 3));
        json_object_set_new(node, "rotation", vector_json(xyzw, 4));
    }
    return node;
}

static json_t *ground_node(tb__gltf *g, const tb_writer *w, size_t k)
{
    double center[3], half_size;
    tb__ground_extent(&w->frames, center, &half_size);
    tb__mesh mesh = {0};
    tb__mesh_of_ground(&mesh, &w->looks.grounds[k], center, half_size);
    char name[32];
    snprintf(name, sizeof name, "ground %zu", k + 1);
    const long index = mesh.failed ? -1 : add_mesh(g, &mesh, name, body_materials(w));
    g->failed |= mesh.failed;
    tb__mesh_free(&mesh);
    return json_pack("{s:s, s:i}", "name", name, "mesh", (json_int_t)index);
}

/* A marker node for joint j, its index in the nodes, made a child of body_a's node (node 1 +
 * body_a: the bodies follow the root in order). */
static void add_joint_node(tb__gltf *g, const tb_writer *w, size_t j, size_t material)
{
    const tb__joint_mark *mark = &w->looks.joints[j];
    const tb__shape sphere = {.kind = TB__SHAPE_SPHERE, .size = {mark->radius, 0, 0}};
    tb__mesh mesh = {0};
    tb__mesh_of_shape(&mesh, &sphere);
    char name[48];
    snprintf(name, sizeof name, "joint %zu (%s)", j, mark->type);
    const long index = mesh.failed ? -1 : add_mesh(g, &mesh, name, material);
    g->failed |= mesh.failed || index < 0;
    tb__mesh_free(&mesh);
    const char *other = mark->body_b == TB_WORLD ? "world" : w->names[mark->body_b];
    json_t *node = json_pack("{s:s, s:i, s:o, s:{s:{s:i, s:s, s:[s, s]}}}", "name", name, "mesh",
                             (json_int_t)index, "translation", vector_json(mark->anchor, 3),
                             "extras", "tumble_joint", "index", (json_int_t)j, "type", mark->type,
                             "bodies", w->names[mark->body_a], other);
    json_t *parent = json_array_get(g->nodes, 1 + mark->body_a);
    json_t *children = json_object_get(parent, "children");
    if (children == NULL) {
        children = json_array();
        json_object_set_new(parent, "children", children);
    }
    json_array_append_new(children, json_integer((json_int_t)json_array_size(g->nodes)));
    json_array_append_new(g->nodes, node);
}

/* The joints' markers, with a material of their own after the others. */
static void add_joints(tb__gltf *g, const tb_writer *w)
{
    if (w->looks.joint_count == 0) {
        return;
    }
    const size_t material = json_array_size(g->materials);
    const double color[4] = {0.08, 0.08, 0.08, 1.0};
    json_array_append_new(g->materials, json_pack("{s:s, s:{s:o, s:f, s:f}}", "name", "joint",
                                                  "pbrMetallicRoughness", "baseColorFactor",
                                                  vector_json(color, 4), "metallicFactor", 0.8,
                                                  "roughnessFactor", 0.3));
    for (size_t j = 0; j < w->looks.joint_count; ++j) {
        add_joint_node(g, w, j, material);
    }
}

/* The root: tumble's world is z up, glTF's y up. Turning -90 degrees about x takes z to y
 * and y to -z: q = (x, y, z, w) = (-sin 45, 0, 0, cos 45). */
static void add_nodes(tb__gltf *g, const tb_writer *w)
{
    json_t *children = json_array();
    const double root_rotation[4] = {-sqrt(0.5), 0.0, 0.0, sqrt(0.5)};
    json_array_append_new(g->nodes,
                          json_pack("{s:s, s:o, s:o, s:{s:s, s:s}}", "name", "tumble world (z up)",
                                    "rotation", vector_json(root_rotation, 4), "children", children,
                                    "extras", "up_axis",
                                    "tumble's world is z up; this node turns it to glTF's y up",
                                    "units", "SI: m, s, rad"));
    for (size_t id = 0; id < w->body_count; ++id) {
        json_array_append_new(children, json_integer((json_int_t)json_array_size(g->nodes)));
        json_array_append_new(g->nodes, body_node(g, w, id));
    }
    for (size_t k = 0; k < w->looks.ground_count; ++k) {
        json_array_append_new(children, json_integer((json_int_t)json_array_size(g->nodes)));
        json_array_append_new(g->nodes, ground_node(g, w, k));
    }
}

static json_t *document(tb__gltf *g, const tb_writer *w)
{
    add_materials(g, w);
    add_nodes(g, w);
    add_joints(g, w);
    tb__gltf_add_animation(g, w);
    char generator[64];
    snprintf(generator, sizeof generator, "tumble %s", tb_version());
    json_t *root =
        json_pack("{s:{s:s, s:s}, s:i, s:[{s:s, s:[i]}]}", "asset", "version", "2.0", "generator",
                  generator, "scene", 0, "scenes", "name", "tumble run", "nodes", 0);
    json_object_set(root, "nodes", g->nodes);
    json_object_set(root, "meshes", g->meshes);
    json_object_set(root, "materials", g->materials);
    if (json_array_size(g->animations) > 0) {
        json_object_set(root, "animations", g->animations);
    }
    json_t *events = tb__events_json(w, &g->failed);
    if (events != NULL) {
        json_object_set_new(json_array_get(json_object_get(root, "scenes"), 0), "extras",
                            json_pack("{s:o}", "tumble_events", events));
    }
    json_object_set(root, "accessors", g->accessors);
    json_object_set(root, "bufferViews", g->views);
    return root;
}

tb_status tb__gltf_write(tb_writer *w)
{
    tb__gltf g;
    tb__gltf_init(&g);
    json_t *root = document(&g, w);
    tb_status status = TB_STATUS_OK;
    if (g.failed || root == NULL) {
        status = tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: glTF of %zu frames",
                                w->path, w->frames.count);
    } else {
        status = w->format == TB_OUTPUT_GLB ? tb__gltf_write_glb(&g, root, w)
                                            : tb__gltf_write_text(&g, root, w);
    }
    json_decref(root);
    tb__gltf_free(&g);
    return status;
}
