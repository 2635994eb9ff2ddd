/* Runs a scene file and writes its motion with a tb_writer: CSV, NumPy .npz, animated glTF
 * (.glb / .gltf) for Blender or a browser, or USD (.usda), the format chosen by the output's
 * extension.
 *
 *   export_scene SCENE.json OUT.(csv|npz|glb|gltf|usda) [FPS] [linear]
 *
 * FPS (absent or 0: the scene's) is the rate of the frames, and so of the glTF keys and USD
 * time codes; "linear" asks for LINEAR glTF rotation keys instead of cubic-spline ones, and for
 * USD orientation samples at the frames only (USD slerps between them). Exit 0 when the file was
 * written, 1 when it was not (the reason on standard error). */
#include "tumble/tumble.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, "export_scene: %s: %s\n", what, detail);
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr,
                "usage: export_scene SCENE.json OUT.(csv|npz|glb|gltf|usda) [FPS] [linear]\n");
        return 1;
    }
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_file(argv[1], &scene, &run, &error) != TB_STATUS_OK) {
        return fail(argv[1], error.message);
    }
    if (argc > 3 && atof(argv[3]) != 0.0) {
        run.fps = atof(argv[3]); /* the run checks it */
    }
    tb_writer_def def = tb_writer_def_default();
    const bool linear = argc > 4 && strcmp(argv[4], "linear") == 0;
    def.rotation_keys = linear ? TB_ROTATION_LINEAR : TB_ROTATION_CUBICSPLINE;
    def.sample_tolerance = linear ? 0.0 : def.sample_tolerance;
    def.fps = run.fps; /* USD: frame k is time code k */
    if (tb_output_format_from_path(argv[2], &def.format) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return fail(argv[2], "extension must be .csv, .npz, .glb, .gltf or .usda");
    }
    /* the number of frames, known before the run: the .npz writer then streams them */
    size_t last_frame = 0;
    if (tb_run_frame_count(run.duration, run.fps, &last_frame, &error) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return fail(argv[1], error.message);
    }
    def.frame_count = last_frame + 1;
    tb_writer *writer = NULL;
    if (tb_writer_open(argv[2], &def, scene, &writer, &error) != TB_STATUS_OK) {
        tb_scene_destroy(scene);
        return fail(argv[2], error.message);
    }
    /* the writer is the run's frame callback: every frame, t = 0 included, goes to the file */
    tb_status status = tb_scene_run(scene, &run, tb_writer_on_frame, writer, NULL, &error);
    if (status != TB_STATUS_OK) {
        fail(argv[1], tb_writer_detail(writer)[0] ? tb_writer_detail(writer) : error.message);
        tb_writer_destroy(writer);
        tb_scene_destroy(scene);
        return 1;
    }
    const size_t frames = tb_writer_frame_count(writer);
    status = tb_writer_close(writer, &error);
    tb_scene_destroy(scene);
    if (status != TB_STATUS_OK) {
        return fail(argv[2], error.message);
    }
    printf("%s: %zu frames at %g fps\n", argv[2], frames, run.fps);
    return 0;
}
