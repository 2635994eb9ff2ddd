/* Scene files: JSON descriptions of bodies, effects, integrator and output, documented with an
 * example of every field in docs/scene-format.md. */
#ifndef TUMBLE_SCENE_FILE_H
#define TUMBLE_SCENE_FILE_H

#include "tumble/export.h"

#include "tumble/run.h"
#include "tumble/scene.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* How a scene file may reach mesh files. A scene file is data that people share, so by
 * default its "file" meshes must lie inside the folder of the scene file (for
 * tb_scene_load_string: inside base_directory, or the current directory): both paths are
 * resolved with realpath(), so neither ".." nor a symbolic link can lead out of it, and an
 * absolute path outside it is refused (TB_STATUS_BAD_SCENE, naming the path and the folder).
 * Fill with tb_scene_file_options_default() and widen explicitly. */
typedef struct tb_scene_file_options {
    /* Mesh files may come from anywhere (absolute paths, ".."): only for scene files you
     * trust. Default false. */
    bool allow_paths_outside;
    /* With allow_paths_outside false: the folder mesh files must be inside instead of the
     * scene file's own (for example a project's root, so scenes in its subfolders can share
     * meshes). Default NULL. */
    const char *mesh_root;
    /* Largest mesh file read, bytes; a larger one is TB_STATUS_IO_ERROR. Default 256 MiB
     * (TB_SCENE_FILE_MAX_MESH_BYTES), a few million triangles of text. */
    size_t max_mesh_file_bytes;
    int internal_cookie;
} tb_scene_file_options;

#define TB_SCENE_FILE_MAX_MESH_BYTES ((size_t)256 << 20)

TB_API tb_scene_file_options tb_scene_file_options_default(void);

/* Loads a scene file into a new scene and the run it asks for, with the default options. Mesh
 * files are found relative to the scene file's directory and must lie inside it. On failure
 * *out_scene is NULL, out_run is untouched, and out_error (may be NULL) names the place:
 *   "scene.json:12:7: end of file expected near ']'"             (JSON syntax, line:column)
 *   "scene.json: bodies[2].mass: must be > 0, got -1"            (meaning, JSON path)
 * A path too long for the system (PATH_MAX) is TB_STATUS_IO_ERROR, never truncated. */
TB_API tb_status tb_scene_load_file(const char *path, tb_scene **out_scene, tb_run_def *out_run,
                                    tb_error *out_error);

/* The same with options (NULL for the defaults). */
TB_API tb_status tb_scene_load_file_with_options(const char *path,
                                                 const tb_scene_file_options *options,
                                                 tb_scene **out_scene, tb_run_def *out_run,
                                                 tb_error *out_error);

/* The same from a string. name stands for the file in messages; base_directory (may be NULL
 * for the current directory) is where mesh files are looked for, and the folder they must be
 * inside by default. */
TB_API tb_status tb_scene_load_string(const char *json, const char *name,
                                      const char *base_directory, tb_scene **out_scene,
                                      tb_run_def *out_run, tb_error *out_error);

TB_API tb_status tb_scene_load_string_with_options(const char *json, const char *name,
                                                   const char *base_directory,
                                                   const tb_scene_file_options *options,
                                                   tb_scene **out_scene, tb_run_def *out_run,
                                                   tb_error *out_error);

#ifdef __cplusplus
}
#endif

#endif
