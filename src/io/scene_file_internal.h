/* Private: the scene-file loader's context and JSON helpers. Only the scene_file*.c sources
 * include jansson. */
#ifndef TUMBLE_SCENE_FILE_INTERNAL_H
#define TUMBLE_SCENE_FILE_INTERNAL_H

#include "tumble/effects.h"
#include "tumble/scene_file.h"

#include <jansson.h>

#include <stdbool.h>

typedef struct tb__loader {
    const char *name;      /* the file, for messages */
    const char *directory; /* where mesh files are looked for ("" for the current one) */
    tb_error *error;
    tb_scene *scene;
    tb_run_def run;
} tb__loader;

/* "name: path: message" into the loader's error; returns status. */
tb_status tb__load_fail(tb__loader *ld, tb_status status, const char *path, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* path must be an object with no keys outside allowed (NULL-terminated). */
tb_status tb__json_object(tb__loader *ld, const json_t *value, const char *path,
                          const char *const *allowed);

/* Optional members: a missing member leaves *out as it was and returns OK (or, if required,
 * fails naming it); a member of the wrong kind fails naming its path and what it is. */
tb_status tb__json_number(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          bool required, double *out);
/* n (<= 16) numbers from an array value at where. */
tb_status tb__json_numbers(tb__loader *ld, const json_t *value, const char *where, size_t n,
                           double *out);
tb_status tb__json_vector(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          size_t n, bool required, double *out);
tb_status tb__json_string(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          bool required, const char **out);
tb_status tb__json_count(tb__loader *ld, const json_t *object, const char *path, const char *key,
                         bool required, long *out);

/* A number > 0 (positive) or >= 0 (non-negative) at path.key, already read. */
tb_status tb__check_positive_at(tb__loader *ld, const char *path, const char *key, double value);
tb_status tb__check_non_negative_at(tb__loader *ld, const char *path, const char *key,
                                    double value);

/* "bodies[2]" style paths. */
void tb__path_index(char *out, size_t size, const char *path, const char *key, size_t index);

/* The sections. */
tb_status tb__load_bodies(tb__loader *ld, const json_t *bodies);
tb_status tb__load_effects(tb__loader *ld, const json_t *effects);

/* A "mesh" shape: mass properties, and its vertices (malloc'd, for contact points). */
tb_status tb__load_mesh_shape(tb__loader *ld, const json_t *shape, const char *path,
                              tb_mass_mode mode, double value, tb_mass_properties *mass,
                              double **vertices, size_t *vertex_count, tb_error *error);

/* Reads a Wavefront OBJ mesh (v and f lines; polygons are fanned into triangles). The
 * arrays are allocated with malloc; the caller frees them. */
tb_status tb__read_obj(const char *path, double **out_vertices, size_t *out_vertex_count,
                       unsigned **out_triangles, size_t *out_triangle_count, char *detail);

#endif
