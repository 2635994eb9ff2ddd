/* Private: the scene-file loader's context and JSON helpers. Only the scene_file*.c sources
 * include jansson. */
#ifndef TUMBLE_SCENE_FILE_INTERNAL_H
#define TUMBLE_SCENE_FILE_INTERNAL_H

#include "io/obj_reader.h"
#include "tumble/effects.h"
#include "tumble/keys.h"
#include "tumble/scene_file.h"
#include "tumble/shape.h"

#include <jansson.h>

#include <stdbool.h>

typedef struct tb__loader {
    const char *name;              /* the file, for messages (shortened when long) */
    char shown_name[80];           /* a long file name's shortened form (TB__SHOWN_PATH_SIZE) */
    const char *directory;         /* where mesh files are looked for ("" for the current one) */
    tb_scene_file_options options; /* from tb_scene_file_options_default() at least */
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

/* "an object", "a number", ...: what a JSON value is, for messages. */
const char *tb__json_kind(const json_t *value);

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

/* Contact points a shape brings by default, and how many of them carry it at rest. */
#define TB__SHAPE_POINTS_MAX 32
typedef struct tb__shape_contacts {
    tb_contact_point points[TB__SHAPE_POINTS_MAX];
    size_t count;
    size_t support;
    tb_contact_point *many; /* meshes and point sets: allocated, else NULL */
} tb__shape_contacts;

typedef struct tb__body_build {
    tb_body_def def;
    tb__shape_contacts contacts;
    bool has_contacts;
    tb_shape shape;            /* its collision shape (type TB_SHAPE_NONE without "shape") */
    double *shape_vertices;    /* mesh and points shapes: malloc'd, shape.vertices points here */
    unsigned *shape_triangles; /* mesh: malloc'd, shape.triangles points here (drawn) */
    /* a list as "shape" or an OBJ's groups: its pieces (malloc'd, piece_count), each mesh
     * piece's vertices and triangles in piece_vertices[k] and piece_triangles[k] (malloc'd, else
     * NULL); NULL and 0 for one shape */
    tb_shape_piece *pieces;
    double **piece_vertices;
    unsigned **piece_triangles;
    size_t piece_count;
    bool piece; /* this is one piece of a list: a mesh file's groups are not split again */
} tb__body_build;

/* A mass-property refusal from the library (its message names the mass, density or inertia)
 * as BAD_SCENE prefixed with the body's path; OK passes through. */
tb_status tb__mass_result(tb__loader *ld, tb_status status, const char *path,
                          const tb_error *error);

/* body.shape into b: mass properties (with the body's mass or density) and contact points. */
tb_status tb__load_shape(tb__loader *ld, const json_t *body, const char *path, tb__body_build *b);
/* The body's "mass" or "density" (exactly one, > 0). */
tb_status tb__load_mass_mode(tb__loader *ld, const json_t *body, const char *path,
                             tb_mass_mode *mode, double *value);
/* The same for body b, except that a body with no state (static, keyframed) needs neither: then
 * any density will do (its mass is not used). */
tb_status tb__load_body_mass_mode(tb__loader *ld, const json_t *body, const char *path,
                                  const tb__body_build *b, tb_mass_mode *mode, double *value);
/* A shape object's keys checked (piece: its "position" and "orientation" allowed) and its type. */
tb_status tb__load_shape_object(tb__loader *ld, const json_t *shape, const char *shape_path,
                                bool piece, const char **out_type);
/* A shape object of type (not "points") into b: b->def.mass (mass refusals named at mass_path),
 * b->shape, b->contacts. */
tb_status tb__load_shape_mass(tb__loader *ld, const json_t *shape, const char *shape_path,
                              const char *mass_path, const char *type, tb_mass_mode mode,
                              double value, tb__body_build *b);
/* body.shape as a list of pieces (scene_file_pieces.c): b->pieces, the combined mass properties
 * in b->def.mass, and the pieces' contact points in the body's frame. */
tb_status tb__load_pieces(tb__loader *ld, const json_t *body, const char *path, tb__body_build *b);
/* Frees b's pieces. */
void tb__free_pieces(tb__body_build *b);

/* The sections. */
tb_status tb__load_bodies(tb__loader *ld, const json_t *bodies);
tb_status tb__load_effects(tb__loader *ld, const json_t *effects);
tb_status tb__load_joints(tb__loader *ld, const json_t *joints); /* scene_file_joints.c */
tb_status tb__load_integrator(tb__loader *ld, const json_t *integrator);
tb_status tb__load_output(tb__loader *ld, const json_t *output);

/* A keyframed body's "keys" (required, a non-empty array of {t, position, orientation,
 * velocity, angular_velocity}) and "interpolation" ("linear", "cubic" (default) or "step"),
 * checked as tb_keyframes_create checks them; a refusal names path.keys[k].field. On success
 * *out_keys is malloc'd (the caller frees it) with *out_count keys; on failure the outputs are
 * untouched. (scene_file_keys.c) */
tb_status tb__load_keys(tb__loader *ld, const json_t *body, const char *path,
                        tb_body_key **out_keys, size_t *out_count,
                        tb_interpolation *out_interpolation);

/* The folder part of path, up to and including its last '/' ("" if none); malloc'd, as long
 * as the path is. NULL when memory runs out. */
char *tb__folder_of(const char *path);

/* A "mesh" shape: mass properties (into b->def.mass), and b->shape a convex shape of its
 * vertices (those its triangles use) and triangles (b->shape_vertices, b->shape_triangles): it
 * collides as its hull and is drawn as itself. An OBJ file of two or more objects or groups
 * also gives b one convex piece per group with the group's triangles (b->pieces, at the
 * identity pose), unless b->piece. */
tb_status tb__load_mesh_shape(tb__loader *ld, const json_t *shape, const char *path,
                              tb_mass_mode mode, double value, tb__body_build *b, tb_error *error);

#endif
