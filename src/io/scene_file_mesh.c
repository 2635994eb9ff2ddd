/* Scene files: mesh shapes, given inline ("vertices" and "triangles") or as a Wavefront OBJ
 * file ("file", relative to the scene file and, unless the loader's options say otherwise,
 * inside the scene file's folder). */
#define _XOPEN_SOURCE 700 /* realpath */

#include "io/obj_reader.h"
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Inline: "vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...] (0-based). */
static tb_status inline_mesh(tb__loader *ld, const json_t *shape, const char *path,
                             tb__mesh_buffers *m)
{
    const json_t *vertices = json_object_get(shape, "vertices");
    const json_t *triangles = json_object_get(shape, "triangles");
    if (!json_is_array(vertices) || !json_is_array(triangles)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "a mesh needs \"file\", or \"vertices\" and \"triangles\" arrays");
    }
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < json_array_size(vertices) && status == TB_STATUS_OK; ++k) {
        char item[176];
        double v[3];
        tb__path_index(item, sizeof item, path, "vertices", k);
        status = tb__json_numbers(ld, json_array_get(vertices, k), item, 3, v);
        if (status == TB_STATUS_OK && !tb__mesh_push_vertex(m, v)) {
            status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, item, "no memory");
        }
    }
    for (size_t k = 0; k < json_array_size(triangles) && status == TB_STATUS_OK; ++k) {
        char item[176];
        double t[3];
        tb__path_index(item, sizeof item, path, "triangles", k);
        status = tb__json_numbers(ld, json_array_get(triangles, k), item, 3, t);
        for (int i = 0; i < 3 && status == TB_STATUS_OK; ++i) {
            /* The range is checked on the double: casting 1e10 to an integer first would be
             * undefined behaviour. vertex_count fits an unsigned (the mesh code checks). */
            if (!(t[i] >= 0 && t[i] < (double)m->vertex_count && t[i] == floor(t[i]))) {
                status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, item,
                                       "vertex indices must be whole numbers from 0 to the number "
                                       "of vertices less one (%zu vertices), got %g",
                                       m->vertex_count, t[i]);
            }
        }
        if (status == TB_STATUS_OK &&
            !tb__mesh_push_triangle(m, (unsigned)t[0], (unsigned)t[1], (unsigned)t[2])) {
            status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, item, "no memory");
        }
    }
    return status;
}

/* directory/file, or file alone when it is absolute or there is no directory; malloc'd, no
 * length limit. */
static char *join_path(const char *directory, const char *file)
{
    const bool relative = file[0] != '/' && directory[0] != '\0';
    const char *prefix = relative ? directory : "";
    const char *slash = relative && prefix[strlen(prefix) - 1] != '/' ? "/" : "";
    const size_t size = strlen(prefix) + strlen(slash) + strlen(file) + 1;
    char *joined = malloc(size);
    if (joined != NULL) {
        snprintf(joined, size, "%s%s%s", prefix, slash, file);
    }
    return joined;
}

/* The resolved folder mesh files must be inside (malloc'd): the options' mesh_root, else the
 * scene file's folder. */
static tb_status resolve_root(tb__loader *ld, const char *path, char **out)
{
    const char *folder = ld->options.mesh_root != NULL ? ld->options.mesh_root
                         : ld->directory[0] != '\0'    ? ld->directory
                                                       : ".";
    *out = realpath(folder, NULL);
    if (*out == NULL) {
        const int reason = errno;
        char shown[TB__SHOWN_PATH_SIZE];
        tb__shown_path(shown, folder);
        return tb__load_fail(ld, TB_STATUS_IO_ERROR, path,
                             "file: cannot resolve the folder mesh files must be in, %s: %s", shown,
                             strerror(reason));
    }
    return TB_STATUS_OK;
}

/* resolved is root itself or below it (both without symbolic links or "..", from realpath). */
static bool inside(const char *root, const char *resolved)
{
    const size_t n = strlen(root);
    return strncmp(root, resolved, n) == 0 && (root[n - 1] == '/' || resolved[n] == '/');
}

/* The path to read file from: joined to the scene's folder and, unless the options allow any
 * path, resolved and checked to be inside the root. */
static tb_status resolve_mesh_file(tb__loader *ld, const char *file, const char *path, char **out)
{
    char *joined = join_path(ld->directory, file);
    if (joined == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "file: a path of %zu bytes",
                             strlen(file));
    }
    if (ld->options.allow_paths_outside) {
        *out = joined;
        return TB_STATUS_OK;
    }
    char *root = NULL;
    tb_status status = resolve_root(ld, path, &root);
    char *resolved = status == TB_STATUS_OK ? realpath(joined, NULL) : NULL;
    const int reason = errno;
    char shown[TB__SHOWN_PATH_SIZE], shown_root[TB__SHOWN_PATH_SIZE];
    tb__shown_path(shown, resolved != NULL ? resolved : joined);
    if (status == TB_STATUS_OK && resolved == NULL) {
        status = tb__load_fail(ld, TB_STATUS_IO_ERROR, path, "file: cannot read %s: %s", shown,
                               strerror(reason));
    }
    if (status == TB_STATUS_OK && !inside(root, resolved)) {
        tb__shown_path(shown_root, root);
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                               "file: outside the folder mesh files must be in (the loader's "
                               "allow_paths_outside or mesh_root widens it): %s is not in %s",
                               shown, shown_root);
    }
    free(joined);
    free(root);
    if (status != TB_STATUS_OK) {
        free(resolved);
        return status;
    }
    *out = resolved;
    return TB_STATUS_OK;
}

static tb_status file_mesh(tb__loader *ld, const json_t *shape, const char *path,
                           tb__mesh_buffers *m)
{
    const char *file = NULL;
    tb_status status = tb__json_string(ld, shape, path, "file", true, &file);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (json_object_get(shape, "vertices") || json_object_get(shape, "triangles")) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path,
                             "give \"file\" or \"vertices\" and \"triangles\", not both");
    }
    char *full = NULL;
    status = resolve_mesh_file(ld, file, path, &full);
    if (status != TB_STATUS_OK) {
        return status;
    }
    char detail[TB_DETAIL_SIZE];
    status = tb__obj_read_file(full, ld->options.max_mesh_file_bytes, m, detail);
    free(full);
    return status == TB_STATUS_OK ? status : tb__load_fail(ld, status, path, "file: %s", detail);
}

/* Keeps the vertices some triangle uses, in their order (a stray vertex is no part of the
 * solid and would make a wrong contact point). */
static tb_status keep_used_vertices(tb__loader *ld, const char *path, tb__mesh_buffers *m)
{
    bool *used = calloc(m->vertex_count, sizeof *used);
    if (used == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu vertices", m->vertex_count);
    }
    for (size_t corner = 0; corner < 3 * m->triangle_count; ++corner) {
        used[m->triangles[corner]] = true;
    }
    size_t kept = 0;
    for (size_t v = 0; v < m->vertex_count; ++v) {
        if (used[v]) {
            memmove(m->vertices + 3 * kept++, m->vertices + 3 * v, 3 * sizeof(double));
        }
    }
    free(used);
    m->vertex_count = kept;
    return TB_STATUS_OK;
}

tb_status tb__load_mesh_buffers(tb__loader *ld, const json_t *shape, const char *path,
                                tb__mesh_buffers *m)
{
    memset(m, 0, sizeof *m);
    tb_status status = json_object_get(shape, "file") != NULL ? file_mesh(ld, shape, path, m)
                                                              : inline_mesh(ld, shape, path, m);
    if (status != TB_STATUS_OK) {
        tb__mesh_buffers_free(m);
    }
    return status;
}

/* Group k's vertices (those its triangles use, once each, in order) into a new array. */
static double *group_vertices(const tb__mesh_buffers *m, size_t k, bool *seen, size_t *out_count)
{
    const size_t first = m->group_starts[k];
    const size_t end = k + 1 < m->group_count ? m->group_starts[k + 1] : m->triangle_count;
    memset(seen, 0, m->vertex_count * sizeof *seen);
    size_t count = 0;
    for (size_t corner = 3 * first; corner < 3 * end; ++corner) {
        count += !seen[m->triangles[corner]];
        seen[m->triangles[corner]] = true;
    }
    double *out = tb__malloc_array(count > 0 ? count : 1, 3 * sizeof(double));
    size_t w = 0;
    for (size_t v = 0; out != NULL && v < m->vertex_count; ++v) {
        if (seen[v]) {
            memcpy(out + 3 * w++, m->vertices + 3 * v, 3 * sizeof(double));
        }
    }
    *out_count = count;
    return out;
}

/* An OBJ of several objects or groups: one convex piece each (the hull of its vertices), at
 * the identity pose, into b's pieces. */
static tb_status group_pieces(tb__loader *ld, const char *path, const tb__mesh_buffers *m,
                              tb__body_build *b)
{
    bool *seen = tb__malloc_array(m->vertex_count, sizeof *seen);
    b->pieces = tb__malloc_array(m->group_count, sizeof *b->pieces);
    b->piece_vertices = calloc(m->group_count, sizeof *b->piece_vertices);
    if (seen == NULL || b->pieces == NULL || b->piece_vertices == NULL) {
        free(seen);
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu pieces", m->group_count);
    }
    b->piece_count = m->group_count;
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < m->group_count && status == TB_STATUS_OK; ++k) {
        tb_shape_piece *piece = &b->pieces[k];
        *piece = tb_shape_piece_default();
        piece->shape.type = TB_SHAPE_CONVEX;
        b->piece_vertices[k] = group_vertices(m, k, seen, &piece->shape.vertex_count);
        piece->shape.vertices = b->piece_vertices[k];
        if (b->piece_vertices[k] == NULL) {
            status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "piece %zu's vertices", k);
        }
    }
    free(seen);
    return status;
}

tb_status tb__load_mesh_shape(tb__loader *ld, const json_t *shape, const char *path,
                              tb_mass_mode mode, double value, tb__body_build *b, double **vertices,
                              size_t *vertex_count, tb_error *error)
{
    tb__mesh_buffers m;
    tb_status status = tb__load_mesh_buffers(ld, shape, path, &m);
    tb_mass_properties *mass = &b->def.mass;
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_mesh(mode, value, m.vertices, m.vertex_count, m.triangles,
                                   m.triangle_count, mass, error);
    }
    if (status == TB_STATUS_OK && m.group_count >= 2 && !b->piece) {
        status = group_pieces(ld, path, &m, b); /* before the vertices are compacted */
    }
    if (status == TB_STATUS_OK) {
        status = keep_used_vertices(ld, path, &m); /* after the mesh is known valid */
    }
    if (status != TB_STATUS_OK) {
        tb__mesh_buffers_free(&m);
        return status;
    }
    *vertex_count = m.vertex_count;
    *vertices = m.vertices;
    free(m.triangles);
    free(m.group_starts);
    return TB_STATUS_OK;
}
