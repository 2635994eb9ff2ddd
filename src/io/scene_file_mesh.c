/* Scene files: mesh shapes, given inline ("vertices" and "triangles") or as a Wavefront OBJ
 * file ("file", relative to the scene file). */
#include "io/scene_file_internal.h"

#include "core/detail.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct mesh_buffers {
    double *vertices;
    size_t vertex_count, vertex_capacity;
    unsigned *triangles;
    size_t triangle_count, triangle_capacity;
} mesh_buffers;

static int grow(void **data, size_t *capacity, size_t needed, size_t item)
{
    if (needed <= *capacity) {
        return 1;
    }
    const size_t next = needed > 2 * *capacity ? needed : 2 * *capacity;
    void *grown = realloc(*data, next * item);
    if (grown == NULL) {
        return 0;
    }
    *data = grown;
    *capacity = next;
    return 1;
}

static int push_vertex(mesh_buffers *m, const double v[3])
{
    if (!grow((void **)&m->vertices, &m->vertex_capacity, m->vertex_count + 1,
              3 * sizeof(double))) {
        return 0;
    }
    memcpy(m->vertices + 3 * m->vertex_count++, v, 3 * sizeof(double));
    return 1;
}

static int push_triangle(mesh_buffers *m, unsigned a, unsigned b, unsigned c)
{
    if (!grow((void **)&m->triangles, &m->triangle_capacity, m->triangle_count + 1,
              3 * sizeof(unsigned))) {
        return 0;
    }
    unsigned *t = m->triangles + 3 * m->triangle_count++;
    t[0] = a, t[1] = b, t[2] = c;
    return 1;
}

/* One OBJ face index ("7", "7/2", "7/2/5", "-1/..."), 1-based or negative from the end. */
static int face_index(const char *token, size_t vertex_count, unsigned *out)
{
    char *end;
    errno = 0;
    const long index = strtol(token, &end, 10);
    if (end == token || errno != 0 || (*end != '\0' && *end != '/')) {
        return 0;
    }
    const long resolved = index > 0 ? index - 1 : (long)vertex_count + index;
    if (index == 0 || resolved < 0 || (size_t)resolved >= vertex_count ||
        resolved > (long)UINT_MAX) {
        return 0;
    }
    *out = (unsigned)resolved;
    return 1;
}

/* "f a b c d ...": fanned into triangles (a b c), (a c d), ... */
static int obj_face(mesh_buffers *m, char *rest)
{
    unsigned first = 0, previous = 0, index;
    int count = 0;
    for (char *token = strtok(rest, " \t\r\n"); token != NULL; token = strtok(NULL, " \t\r\n")) {
        if (!face_index(token, m->vertex_count, &index)) {
            return 0;
        }
        if (count == 0) {
            first = index;
        } else if (count >= 2 && !push_triangle(m, first, previous, index)) {
            return 0;
        }
        previous = index;
        ++count;
    }
    return count >= 3;
}

tb_status tb__read_obj(const char *path, double **out_vertices, size_t *out_vertex_count,
                       unsigned **out_triangles, size_t *out_triangle_count, char *detail)
{
    FILE *file = fopen(path, "r");
    if (file == NULL) {
        return tb__set_detail(detail, TB_STATUS_IO_ERROR, "cannot read %s: %s", path,
                              strerror(errno));
    }
    mesh_buffers m = {0};
    char line[1024];
    long number = 0;
    tb_status status = TB_STATUS_OK;
    while (status == TB_STATUS_OK && fgets(line, sizeof line, file) != NULL) {
        ++number;
        double v[3];
        int ok = 1;
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            ok = sscanf(line + 2, "%lf %lf %lf", &v[0], &v[1], &v[2]) == 3 && push_vertex(&m, v);
        } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
            ok = obj_face(&m, line + 2);
        }
        if (!ok) {
            status = tb__set_detail(detail, TB_STATUS_BAD_SCENE,
                                    "%s:%ld: not a vertex (v x y z) or face (f i j k ...) with "
                                    "indices of earlier vertices",
                                    path, number);
        }
    }
    fclose(file);
    if (status != TB_STATUS_OK) {
        free(m.vertices);
        free(m.triangles);
        return status;
    }
    *out_vertices = m.vertices;
    *out_vertex_count = m.vertex_count;
    *out_triangles = m.triangles;
    *out_triangle_count = m.triangle_count;
    return TB_STATUS_OK;
}

/* Inline: "vertices": [[x, y, z], ...], "triangles": [[i, j, k], ...] (0-based). */
static tb_status inline_mesh(tb__loader *ld, const json_t *shape, const char *path, mesh_buffers *m)
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
        if (status == TB_STATUS_OK && !push_vertex(m, v)) {
            status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, item, "no memory");
        }
    }
    for (size_t k = 0; k < json_array_size(triangles) && status == TB_STATUS_OK; ++k) {
        char item[176];
        double t[3];
        tb__path_index(item, sizeof item, path, "triangles", k);
        status = tb__json_numbers(ld, json_array_get(triangles, k), item, 3, t);
        for (int i = 0; i < 3 && status == TB_STATUS_OK; ++i) {
            if (t[i] < 0 || t[i] != (double)(unsigned)t[i] || t[i] >= (double)m->vertex_count) {
                status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, item,
                                       "vertex indices must be whole numbers from 0 to %zu, got %g",
                                       m->vertex_count - 1, t[i]);
            }
        }
        if (status == TB_STATUS_OK &&
            !push_triangle(m, (unsigned)t[0], (unsigned)t[1], (unsigned)t[2])) {
            status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, item, "no memory");
        }
    }
    return status;
}

static tb_status file_mesh(tb__loader *ld, const json_t *shape, const char *path, mesh_buffers *m)
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
    char full[2048];
    snprintf(full, sizeof full, "%s%s", file[0] == '/' ? "" : ld->directory, file);
    char detail[TB_DETAIL_SIZE];
    status = tb__read_obj(full, &m->vertices, &m->vertex_count, &m->triangles, &m->triangle_count,
                          detail);
    return status == TB_STATUS_OK ? status : tb__load_fail(ld, status, path, "file: %s", detail);
}

tb_status tb__load_mesh_shape(tb__loader *ld, const json_t *shape, const char *path,
                              tb_mass_mode mode, double value, tb_mass_properties *mass,
                              double **vertices, size_t *vertex_count, tb_error *error)
{
    mesh_buffers m = {0};
    tb_status status = json_object_get(shape, "file") != NULL ? file_mesh(ld, shape, path, &m)
                                                              : inline_mesh(ld, shape, path, &m);
    if (status == TB_STATUS_OK) {
        status = tb_mass_from_mesh(mode, value, m.vertices, m.vertex_count, m.triangles,
                                   m.triangle_count, mass, error);
    }
    free(m.triangles);
    if (status != TB_STATUS_OK) {
        free(m.vertices);
        return status;
    }
    *vertices = m.vertices;
    *vertex_count = m.vertex_count;
    return TB_STATUS_OK;
}
