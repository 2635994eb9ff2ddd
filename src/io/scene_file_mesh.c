/* Scene files: mesh shapes, given inline ("vertices" and "triangles") or as a Wavefront OBJ
 * file ("file", relative to the scene file and, unless the loader's options say otherwise,
 * inside the scene file's folder). */
#define _XOPEN_SOURCE 700 /* realpath */

#include "io/obj_reader.h"
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <errno.h>
#include <limits.h>
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
    return strncmp(root, resolved, n) == 0 &&
           (root[n - 1] == '/' || resolved[n] == '/' || resolved[n] == '\0');
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

#define UNUSED UINT_MAX /* a vertex no triangle of the run uses */

/* The vertices the triangles [first, end) use, renumbered in their order into to[vertex_count]
 * (UNUSED for the others); returns how many. */
static size_t number_used(const tb__mesh_buffers *m, size_t first, size_t end, unsigned *to)
{
    for (size_t v = 0; v < m->vertex_count; ++v) {
        to[v] = UNUSED;
    }
    for (size_t corner = 3 * first; corner < 3 * end; ++corner) {
        to[m->triangles[corner]] = 0;
    }
    unsigned count = 0; /* vertex_count fits an unsigned (the mesh code checks) */
    for (size_t v = 0; v < m->vertex_count; ++v) {
        to[v] = to[v] == UNUSED ? UNUSED : count++;
    }
    return count;
}

/* The mesh of the triangles [first, end) alone: the vertices they use (in their order) and the
 * triangles renumbered to them, in new arrays; false when memory runs out. */
static bool run_mesh(const tb__mesh_buffers *m, size_t first, size_t end, unsigned *to,
                     tb__mesh_buffers *out)
{
    memset(out, 0, sizeof *out);
    out->vertex_count = number_used(m, first, end, to);
    out->triangle_count = end - first;
    out->vertices = tb__malloc_array(out->vertex_count + 1, 3 * sizeof(double));
    out->triangles = tb__malloc_array(3 * out->triangle_count + 1, sizeof(unsigned));
    if (out->vertices == NULL || out->triangles == NULL) {
        tb__mesh_buffers_free(out);
        return false;
    }
    for (size_t v = 0; v < m->vertex_count; ++v) {
        if (to[v] != UNUSED) {
            memcpy(out->vertices + 3 * to[v], m->vertices + 3 * v, 3 * sizeof(double));
        }
    }
    for (size_t corner = 0; corner < 3 * out->triangle_count; ++corner) {
        out->triangles[corner] = to[m->triangles[3 * first + corner]];
    }
    return true;
}

/* A "mesh" shape's triangles, from its "file" (resolved and confined as ld->options say,
 * regular, bounded) or inline; *m starts empty, the caller frees it (emptied on failure). */
static tb_status load_mesh_buffers(tb__loader *ld, const json_t *shape, const char *path,
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

/* A convex piece of the triangles [first, end) of m: its vertices (those they use: a stray
 * vertex is no part of the solid and would make a wrong contact point) and the triangles it
 * is drawn with, into *vertices and *triangles (malloc'd). */
static bool convex_of_run(const tb__mesh_buffers *m, size_t first, size_t end, unsigned *to,
                          tb_shape *out, double **vertices, unsigned **triangles)
{
    tb__mesh_buffers run;
    if (!run_mesh(m, first, end, to, &run)) {
        return false;
    }
    *out = tb_shape_default();
    out->type = TB_SHAPE_CONVEX; /* a mesh collides as its convex hull */
    out->vertices = *vertices = run.vertices;
    out->vertex_count = run.vertex_count;
    out->triangles = *triangles = run.triangles;
    out->triangle_count = run.triangle_count;
    return true;
}

/* An OBJ of several objects or groups: one convex piece each (the hull of its vertices, drawn
 * with its own triangles), at the identity pose, into b's pieces. */
static tb_status group_pieces(tb__loader *ld, const char *path, const tb__mesh_buffers *m,
                              unsigned *to, tb__body_build *b)
{
    b->pieces = tb__malloc_array(m->group_count, sizeof *b->pieces);
    b->piece_vertices = calloc(m->group_count, sizeof *b->piece_vertices);
    b->piece_triangles = calloc(m->group_count, sizeof *b->piece_triangles);
    if (b->pieces == NULL || b->piece_vertices == NULL || b->piece_triangles == NULL) {
        return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu pieces", m->group_count);
    }
    b->piece_count = m->group_count;
    for (size_t k = 0; k < m->group_count; ++k) {
        const size_t end = k + 1 < m->group_count ? m->group_starts[k + 1] : m->triangle_count;
        b->pieces[k] = tb_shape_piece_default();
        if (!convex_of_run(m, m->group_starts[k], end, to, &b->pieces[k].shape,
                           &b->piece_vertices[k], &b->piece_triangles[k])) {
            return tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "piece %zu's mesh", k);
        }
    }
    return TB_STATUS_OK;
}

tb_status tb__load_mesh_shape(tb__loader *ld, const json_t *shape, const char *path,
                              tb_mass_mode mode, double value, tb__body_build *b, tb_error *error)
{
    tb__mesh_buffers m;
    tb_status status = load_mesh_buffers(ld, shape, path, &m);
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_mesh(mode, value, m.vertices, m.vertex_count, m.triangles,
                                   m.triangle_count, &b->def.mass, error);
    }
    unsigned *to = status == TB_STATUS_OK ? tb__malloc_array(m.vertex_count, sizeof *to) : NULL;
    if (status == TB_STATUS_OK && to == NULL) {
        status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu vertices", m.vertex_count);
    }
    if (status == TB_STATUS_OK && m.group_count >= 2 && !b->piece) {
        status = group_pieces(ld, path, &m, to, b);
    }
    if (status == TB_STATUS_OK && !convex_of_run(&m, 0, m.triangle_count, to, &b->shape,
                                                 &b->shape_vertices, &b->shape_triangles)) {
        status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, path, "%zu vertices", m.vertex_count);
    }
    free(to);
    tb__mesh_buffers_free(&m);
    return status;
}
