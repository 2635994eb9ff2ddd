/* Writers: what the bodies and grounds look like in glTF, read from the scene file the scene
 * was loaded from (its "shape" of each body, matched by name, and its "ground" effects). The
 * scene file was already validated by the loader; what is read here is checked again only as
 * far as drawing needs. */
#include "io/scene_file_internal.h"
#include "io/writer_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

/* A mesh, file or inline, read and checked as the loader reads it (mesh files confined to
 * the scene file's folder by the loader's default options). */
static tb_status mesh_shape(tb__loader *ld, const json_t *shape, const char *path, tb__shape *s)
{
    s->kind = TB__SHAPE_MESH;
    tb__mesh_buffers mesh;
    const tb_status status = tb__load_mesh_buffers(ld, shape, path, &mesh);
    if (status == TB_STATUS_OK) {
        s->vertices = mesh.vertices;
        s->vertex_count = mesh.vertex_count;
        s->triangles = mesh.triangles;
        s->triangle_count = mesh.triangle_count;
    }
    return status;
}

static tb_status points_shape(tb__loader *ld, const json_t *shape, const char *path, tb__shape *s)
{
    const json_t *points = json_object_get(shape, "points");
    s->kind = TB__SHAPE_POINTS;
    s->vertex_count = json_array_size(points);
    s->vertices = tb__malloc_array(s->vertex_count + 1, 3 * sizeof(double));
    if (s->vertices == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu points", s->vertex_count);
    }
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < s->vertex_count && status == TB_STATUS_OK; ++k) {
        status = tb__json_vector(ld, json_array_get(points, k), path, "position", 3, true,
                                 s->vertices + 3 * k);
    }
    return status;
}

/* Primitive sizes: box edges, sphere radius, cylinder and capsule radius and length,
 * ellipsoid semi-axes. */
static tb_status primitive_shape(tb__loader *ld, const json_t *shape, const char *path,
                                 const char *type, tb__shape *s)
{
    static const struct {
        const char *type;
        tb__shape_kind kind;
    } kinds[] = {{"box", TB__SHAPE_BOX},
                 {"sphere", TB__SHAPE_SPHERE},
                 {"cylinder", TB__SHAPE_CYLINDER},
                 {"capsule", TB__SHAPE_CAPSULE},
                 {"ellipsoid", TB__SHAPE_ELLIPSOID}};
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k) {
        if (strcmp(type, kinds[k].type) == 0) {
            s->kind = kinds[k].kind;
        }
    }
    switch (s->kind) {
    case TB__SHAPE_BOX:
        return tb__json_vector(ld, shape, path, "size", 3, true, s->size);
    case TB__SHAPE_ELLIPSOID:
        return tb__json_vector(ld, shape, path, "semi_axes", 3, true, s->size);
    case TB__SHAPE_SPHERE:
        return tb__json_number(ld, shape, path, "radius", true, &s->size[0]);
    case TB__SHAPE_CYLINDER:
    case TB__SHAPE_CAPSULE: {
        tb_status status = tb__json_number(ld, shape, path, "radius", true, &s->size[0]);
        return status == TB_STATUS_OK
                   ? tb__json_number(ld, shape, path, "length", true, &s->size[1])
                   : status;
    }
    default:
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "type: \"%s\" cannot be drawn", type);
    }
}

static tb_status body_shape(tb__loader *ld, const json_t *body, const char *path, tb__shape *s)
{
    const json_t *shape = json_object_get(body, "shape");
    if (shape == NULL) {
        return TB_STATUS_OK; /* mass and inertia: drawn as the equivalent ellipsoid */
    }
    const char *type = NULL;
    tb_status status = tb__json_string(ld, shape, path, "type", true, &type);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (strcmp(type, "mesh") == 0) {
        return mesh_shape(ld, shape, path, s);
    }
    return strcmp(type, "points") == 0 ? points_shape(ld, shape, path, s)
                                       : primitive_shape(ld, shape, path, type, s);
}

static tb_status load_grounds(tb__loader *ld, const json_t *effects, tb__looks *looks)
{
    looks->grounds = tb__malloc_array(json_array_size(effects) + 1, sizeof *looks->grounds);
    if (looks->grounds == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, "effects", "ground planes");
    }
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < json_array_size(effects) && status == TB_STATUS_OK; ++k) {
        const json_t *e = json_array_get(effects, k);
        const char *type = json_string_value(json_object_get(e, "type"));
        if (type == NULL || strcmp(type, "ground") != 0) {
            continue;
        }
        char path[32];
        tb__path_index(path, sizeof path, "", "effects", k);
        tb__ground *g = &looks->grounds[looks->ground_count];
        tb__v3_set(g->normal, 0, 0, 1);
        g->offset = 0;
        status = tb__json_vector(ld, e, path, "normal", 3, false, g->normal);
        if (status == TB_STATUS_OK) {
            status = tb__json_number(ld, e, path, "offset", false, &g->offset);
        }
        const double length = tb__v3_norm(g->normal);
        if (status == TB_STATUS_OK && !(length > 0)) {
            status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "normal: must not be zero");
        }
        for (int i = 0; i < 3; ++i) {
            g->normal[i] /= length;
        }
        looks->ground_count += status == TB_STATUS_OK;
    }
    return status;
}

/* Each body of the scene drawn as the scene file's body of the same name describes it. */
static tb_status load_file(tb__loader *ld, const json_t *root, const tb_scene *scene,
                           tb__looks *looks)
{
    const json_t *bodies = json_object_get(root, "bodies");
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < json_array_size(bodies) && status == TB_STATUS_OK; ++k) {
        const json_t *body = json_array_get(bodies, k);
        const char *name = json_string_value(json_object_get(body, "name"));
        size_t id;
        if (name == NULL || tb_scene_find_body(scene, name, &id) != TB_STATUS_OK) {
            continue;
        }
        char path[32];
        tb__path_index(path, sizeof path, "", "bodies", k);
        status = body_shape(ld, body, path, &looks->shapes[id]);
    }
    return status == TB_STATUS_OK ? load_grounds(ld, json_object_get(root, "effects"), looks)
                                  : status;
}

/* The scene file, or the text with its base directory, as JSON; *directory (malloc'd, any
 * length) is where its mesh files are. */
static tb_status parse_scene(const tb_writer_def *def, json_t **out, char **directory,
                             tb_error *error)
{
    json_error_t json_error;
    json_t *root = def->scene_file != NULL ? json_load_file(def->scene_file, 0, &json_error)
                                           : json_loads(def->scene_text, 0, &json_error);
    *out = root;
    if (root == NULL) {
        return tb__set_error(error,
                             def->scene_file != NULL ? TB_STATUS_IO_ERROR : TB_STATUS_PARSE_ERROR,
                             "%s: %s%s%s", def->scene_file != NULL ? "scene_file" : "scene_text",
                             def->scene_file != NULL ? def->scene_file : "",
                             def->scene_file != NULL ? ": " : "", json_error.text);
    }
    if (def->scene_text != NULL && def->base_directory != NULL) {
        /* the loader joins a folder without a trailing '/' itself */
        *directory = malloc(strlen(def->base_directory) + 1);
        if (*directory != NULL) {
            strcpy(*directory, def->base_directory);
        }
    } else {
        *directory = tb__folder_of(def->scene_file != NULL ? def->scene_file : "");
    }
    if (*directory == NULL) {
        json_decref(root);
        *out = NULL;
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: the scene's folder name");
    }
    return TB_STATUS_OK;
}

tb_status tb__looks_load(tb__looks *looks, const tb_writer_def *def, const tb_scene *scene,
                         tb_error *error)
{
    const size_t n = tb_scene_body_count(scene);
    memset(looks, 0, sizeof *looks);
    looks->shapes = calloc(n > 0 ? n : 1, sizeof *looks->shapes);
    if (looks->shapes == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: shapes of %zu bodies", n);
    }
    for (size_t id = 0; id < n; ++id) {
        looks->shapes[id].kind = TB__SHAPE_INERTIA;
        tb_scene_get_mass(scene, id, &looks->shapes[id].mass);
    }
    if (def->scene_file == NULL && def->scene_text == NULL) {
        return TB_STATUS_OK;
    }
    char *directory = NULL;
    json_t *root = NULL;
    tb_status status = parse_scene(def, &root, &directory, error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__loader ld = {.name = def->scene_file != NULL ? def->scene_file : "scene_text",
                     .directory = directory,
                     .options = tb_scene_file_options_default(),
                     .error = error};
    status = load_file(&ld, root, scene, looks);
    json_decref(root);
    free(directory);
    return status;
}

void tb__looks_free(tb__looks *looks, size_t body_count)
{
    for (size_t id = 0; looks->shapes != NULL && id < body_count; ++id) {
        free(looks->shapes[id].vertices);
        free(looks->shapes[id].triangles);
    }
    free(looks->shapes);
    free(looks->grounds);
    memset(looks, 0, sizeof *looks);
}
