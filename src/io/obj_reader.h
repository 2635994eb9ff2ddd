/* Private: Wavefront OBJ meshes, from a memory buffer (what the fuzzer calls) or from a regular
 * file of bounded size. No jansson here, so the fuzz target needs only this header. */
#ifndef TUMBLE_OBJ_READER_H
#define TUMBLE_OBJ_READER_H

#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

/* For messages: path, or "..." and its last bytes when it is longer than fits, so that a long
 * path leaves room in a TB_DETAIL_SIZE message for what went wrong. */
#define TB__SHOWN_PATH_SIZE 80
void tb__shown_path(char out[TB__SHOWN_PATH_SIZE], const char *path);

/* Growable arrays of a triangle mesh: vertices[3 * vertex_count] (m), triangles[3 *
 * triangle_count] (0-based vertex indices). Start from all zeros; free with
 * tb__mesh_buffers_free. */
typedef struct tb__mesh_buffers {
    double *vertices;
    size_t vertex_count, vertex_capacity;
    unsigned *triangles;
    size_t triangle_count, triangle_capacity;
    /* OBJ objects and groups: group_starts[k] is the first triangle of the k-th run of faces that
     * an "o" or "g" statement begins (faces before any: the first run); group_count runs, 0 for
     * a mesh of no faces or one not read from OBJ */
    size_t *group_starts;
    size_t group_count, group_capacity;
} tb__mesh_buffers;

/* false when memory runs out (the buffers keep what they had). */
bool tb__mesh_push_vertex(tb__mesh_buffers *mesh, const double vertex[3]);
bool tb__mesh_push_triangle(tb__mesh_buffers *mesh, unsigned a, unsigned b, unsigned c);
void tb__mesh_buffers_free(tb__mesh_buffers *mesh);

/* Parses OBJ text of length bytes (need not end in NUL; a NUL inside is refused). Reads
 * "v x y z" (an optional "r g b" colour after it is ignored) and "f i j k ..." (1-based or
 * negative indices, "i/t/n" forms; polygons fanned into triangles (i j k), (i k l), ...).
 * "o" and "g" begin a new group of faces (group_starts); comments and the statements s,
 * usemtl, mtllib, vn and vt are ignored; any other
 * statement, a malformed number or index is refused with "name:line: ..." in detail
 * (TB_DETAIL_SIZE bytes, may be NULL) and TB_STATUS_BAD_SCENE. Lines may be any length. On
 * success *out holds the mesh (the caller frees it); on failure *out is all zeros. */
tb_status tb__obj_parse(const char *text, size_t length, const char *name, tb__mesh_buffers *out,
                        char *detail);

/* Reads and parses the OBJ file at path: only a regular file (not a device, pipe or
 * directory, which could be endless or block) of at most max_bytes bytes, else
 * TB_STATUS_IO_ERROR naming the path and the reason. */
tb_status tb__obj_read_file(const char *path, size_t max_bytes, tb__mesh_buffers *out,
                            char *detail);

#endif
