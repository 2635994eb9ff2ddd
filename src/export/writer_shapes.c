/* Writers: the visual meshes of the scene file the scene was loaded from. The scene keeps a
 * "mesh" shape only as the convex hull it collides with; a body whose shape in the file is one
 * mesh is drawn with the mesh's own triangles, read from the file as the loader reads them
 * (matched by name). Everything else is drawn from the scene (writer_looks.c). */
#include "io/scene_file_internal.h"
#include "export/writer_internal.h"

#include "core/detail.h"
#include "core/validate.h"

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
        free(mesh.group_starts); /* drawn whole */
    }
    return status;
}

/* Each body of the scene whose file shape is one mesh and whose scene shape is one convex
 * piece at its origin (the loader's making) takes the mesh's triangles. */
static tb_status load_file(tb__loader *ld, const json_t *root, const tb_scene *scene,
                           tb__looks *looks)
{
    const json_t *bodies = json_object_get(root, "bodies");
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < json_array_size(bodies) && status == TB_STATUS_OK; ++k) {
        const json_t *body = json_array_get(bodies, k);
        const char *name = json_string_value(json_object_get(body, "name"));
        const json_t *shape = json_object_get(body, "shape");
        const char *type = json_string_value(json_object_get(shape, "type"));
        size_t id;
        if (name == NULL || type == NULL || strcmp(type, "mesh") != 0 ||
            tb_scene_find_body(scene, name, &id) != TB_STATUS_OK ||
            looks->bodies[id].piece_count != 1 ||
            looks->bodies[id].pieces[0].kind != TB__SHAPE_MESH) {
            continue;
        }
        char path[48];
        tb__path_index(path, sizeof path, "", "bodies", k);
        strcat(path, ".shape");
        tb__shape *s = &looks->bodies[id].pieces[0];
        free(s->vertices);
        free(s->triangles);
        s->vertices = NULL;
        s->triangles = NULL;
        s->vertex_count = s->triangle_count = 0;
        status = mesh_shape(ld, shape, path, s);
    }
    return status;
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

tb_status tb__looks_file_meshes(tb__looks *looks, const tb_writer_def *def, const tb_scene *scene,
                                tb_error *error)
{
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
