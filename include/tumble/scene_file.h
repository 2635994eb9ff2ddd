/* Scene files: JSON descriptions of bodies, effects, integrator and output, documented with an
 * example of every field in docs/scene-format.md. */
#ifndef TUMBLE_SCENE_FILE_H
#define TUMBLE_SCENE_FILE_H

#include "tumble/export.h"

#include "tumble/run.h"
#include "tumble/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Loads a scene file into a new scene and the run it asks for. Mesh files are found relative
 * to the scene file's directory. On failure *out_scene is NULL, out_run is untouched, and
 * out_error (may be NULL) names the place:
 *   "scene.json:12:7: end of file expected near ']'"             (JSON syntax, line:column)
 *   "scene.json: bodies[2].mass: must be > 0, got -1"            (meaning, JSON path) */
TB_API tb_status tb_scene_load_file(const char *path, tb_scene **out_scene, tb_run_def *out_run,
                                    tb_error *out_error);

/* The same from a string. name stands for the file in messages; base_directory (may be NULL
 * for the current directory) is where mesh files are looked for. */
TB_API tb_status tb_scene_load_string(const char *json, const char *name,
                                      const char *base_directory, tb_scene **out_scene,
                                      tb_run_def *out_run, tb_error *out_error);

#ifdef __cplusplus
}
#endif

#endif
