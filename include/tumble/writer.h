/* Writers: the frames of a run into a file, as CSV text, NumPy .npz arrays, an animated
 * glTF 2.0 scene (.glb binary or .gltf text) that Blender, three.js and other glTF viewers
 * open, or a USD ASCII layer (.usda) for usdview, Houdini and Omniverse. A writer is fed one frame
 * at a time (tb_writer_on_frame is a tb_frame_fn for tb_scene_run) and finished by tb_writer_close.
 * docs/export.md describes the formats.
 *
 * What a frame holds, per body, in tumble's world frame (z up) and SI units: the position of
 * the origin of the body's shape frame (m), the shape -> world unit quaternion (w, x, y, z),
 * the velocity of the shape origin (m/s) and the angular velocity (rad/s): the pose a model of
 * the shape is placed with (tb_body_def.orientation's frame, not the principal frame).
 *
 * Files appear whole or not at all: a writer writes into a new file of its own beside path
 * (".tumble-XXXXXXXX.partial" in path's folder, X's chosen so that no file there is taken
 * over) and renames it to path when tb_writer_close succeeds; a failed or abandoned writer
 * removes it and leaves an existing file at path as it was. (A path that names something
 * other than a regular file, such as /dev/null, is written directly.) */
#ifndef TUMBLE_WRITER_H
#define TUMBLE_WRITER_H

#include "tumble/export.h"

#include "tumble/contact_events.h"
#include "tumble/scene.h"
#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum tb_output_format {
    TB_OUTPUT_CSV = 0, /* text, a row per body per frame, numbers that read back exactly */
    TB_OUTPUT_NPZ,     /* NumPy .npz: t, position, orientation, velocity, angular_velocity */
    TB_OUTPUT_GLB,     /* binary glTF 2.0, one file */
    TB_OUTPUT_GLTF,    /* text glTF 2.0, its buffer embedded as base64 */
    TB_OUTPUT_USDA     /* USD ASCII layer: an Xform a body with translate and orient samples */
} tb_output_format;

/* How glTF rotation keys are interpolated between frames. */
typedef enum tb_rotation_keys {
    /* Cubic Hermite spline whose tangents are the simulated dq/dt = 1/2 (0, omega) q: a fast
     * spin stays on the simulated rotation between keys. Default. */
    TB_ROTATION_CUBICSPLINE = 0,
    TB_ROTATION_LINEAR /* spherical linear interpolation between the keys */
} tb_rotation_keys;

typedef struct tb_writer_def {
    tb_output_format format;        /* default CSV */
    tb_rotation_keys rotation_keys; /* glTF only; default TB_ROTATION_CUBICSPLINE */
    /* Deprecated and ignored (kept so that callers compile): the writers draw every body from
     * the scene alone (each piece as its visual mesh where it has one, tb_scene_body_visual_mesh,
     * else as its shape, tb_scene_body_piece; a body without either as the solid ellipsoid with
     * its mass and inertia) and the ground planes from the scene's. They once named the scene
     * file or JSON text (and the folder of its mesh files) to read a mesh's triangles from. */
    const char *scene_file;
    const char *scene_text;
    const char *base_directory;
    /* npz only: the number of frames that will come, if known (0, the default: not known). A
     * run of tb_scene_run makes 1 + the number tb_run_frame_count gives. Known, the frames are
     * not kept: they go to the file as they come, written by a thread of the writer while the
     * caller computes the next ones (the thread touches only the writer's copies of the frames
     * and the file, never the scene); one frame more is refused, fewer fail tb_writer_close
     * (TB_STATUS_INVALID_ARGUMENT both). Into a file that cannot seek (a pipe) they are kept. */
    size_t frame_count;
    /* USD only: frames per second, the layer's timeCodesPerSecond (frame k at t = k / fps is
     * time code k); 0 (the default): 1 / the interval between the first two frames, rounded to
     * a whole number within 1e-9 of one. Finite and >= 0. */
    double fps;
    /* USD only: how far (rad) USD's interpolation of the orientation samples may stray from the
     * spline TB_ROTATION_CUBICSPLINE draws through the frames. USD slerps between samples, which
     * cuts the corner where the spin axis moves and turns backwards past half a turn; where it
     * would stray further, samples from the spline are added between the frames (each frame
     * interval cut into up to 256 equal pieces). 0: samples at the frames only. Default
     * TB_WRITER_SAMPLE_TOLERANCE; else in [1e-6, 0.1]. */
    double sample_tolerance;
    int internal_cookie; /* set by tb_writer_def_default */
} tb_writer_def;

/* tb_writer_def.sample_tolerance's default, rad (0.05 degrees); docs/export.md measures it. */
#define TB_WRITER_SAMPLE_TOLERANCE 8.7266462599716477e-4

TB_API tb_writer_def tb_writer_def_default(void);

/* The format a file name asks for by its extension (.csv, .npz, .glb, .gltf, .usda, any case);
 * TB_STATUS_INVALID_ARGUMENT for another or no extension (.usd and .usdc too: tumble writes no
 * binary USD). */
TB_API tb_status tb_output_format_from_path(const char *path, tb_output_format *out_format);

/* The format called name ("csv", "npz", "glb", "gltf", "usda"); TB_STATUS_INVALID_ARGUMENT
 * else. */
TB_API tb_status tb_output_format_from_name(const char *name, tb_output_format *out_format);

/* Lower-case name of a format ("csv", ...), or "unknown". */
TB_API const char *tb_output_format_name(tb_output_format format);

typedef struct tb_writer tb_writer;

/* Opens a writer for the frames of scene (its bodies, names and, for glTF and USD, shapes are taken
 * now; the scene must keep its bodies while the writer is fed). On failure *out_writer is
 * NULL, no file is left behind and out_error (may be NULL) names the input or the file:
 * TB_STATUS_NULL_POINTER, TB_STATUS_INVALID_ARGUMENT (a def not from tb_writer_def_default,
 * an unknown format, scene_file and scene_text both given, fps or sample_tolerance out of
 * range), TB_STATUS_IO_ERROR (the file
 * cannot be created, the scene file cannot be read), TB_STATUS_PARSE_ERROR (scene_text is
 * not JSON), TB_STATUS_BAD_SCENE (a shape the scene description gets wrong). */
TB_API tb_status tb_writer_open(const char *path, const tb_writer_def *def, const tb_scene *scene,
                                tb_writer **out_writer, tb_error *out_error);

/* Adds the scene's current states as the frame at time t (s). Frames come in increasing t,
 * from a scene with the writer's body count, at most def.frame_count of them when it was given
 * (else TB_STATUS_INVALID_ARGUMENT, nothing added). A write that fails gives
 * TB_STATUS_IO_ERROR, and every later call the same (a streamed npz's thread reports its
 * failure to the call that hands it the next block of frames, or to tb_writer_close). */
TB_API tb_status tb_writer_frame(tb_writer *writer, double t, const tb_scene *scene);

/* Adds a frame from values the caller holds (a run recorded in memory, another simulator):
 * 13 doubles per body in the writer's body order, each the position (m), the shape -> world
 * unit quaternion (w, x, y, z), the velocity (m/s) and the angular velocity (rad/s), world
 * frame, as a frame above holds them. Refused, with nothing added: NULL values
 * (TB_STATUS_NULL_POINTER), a NaN or infinite value or t (TB_STATUS_NOT_FINITE, the detail
 * naming its index), t not after the previous frame's or a quaternion whose norm is off 1 by
 * more than 1e-6 (TB_STATUS_INVALID_ARGUMENT). */
TB_API tb_status tb_writer_frame_values(tb_writer *writer, double t, const double *values);

/* tb_frame_fn for tb_scene_run with the writer as ctx: tb_writer_frame, and non-zero (which
 * stops the run) when it fails; tb_writer_detail then says why. */
TB_API int tb_writer_on_frame(size_t frame, double t, const tb_scene *scene, void *writer);

/* Contact events for the file (include/tumble/contact_events.h), e.g. those a run's callback
 * kept: glTF (glb, gltf) writes them at close as scenes[0].extras.tumble_events, an array of
 * objects {t, kind, body_a, body_b (body names; "ground" for TB_WORLD), point, normal (tumble's
 * z-up world, m), speed (m/s), impulse (N s)}, for a sound designer to sync to; a later call
 * replaces them. Copies the array. Refused, nothing kept: NULL writer or events with count > 0
 * (TB_STATUS_NULL_POINTER), a format other than glTF, a body id past the writer's bodies
 * (TB_STATUS_INVALID_ARGUMENT), no memory (TB_STATUS_OUT_OF_MEMORY). */
TB_API tb_status tb_writer_set_contact_events(tb_writer *writer, const tb_contact_event *events,
                                              size_t count);

/* Detail of the writer's last failure ("" if none); owned by the writer. */
TB_API const char *tb_writer_detail(const tb_writer *writer);

/* Number of frames added so far. */
TB_API size_t tb_writer_frame_count(const tb_writer *writer);

/* Finishes the file (glTF, USD, and npz without a frame count, are written now from the frames kept
 * in memory; a streamed npz gets its last frames, headers and directory), puts it at its path
 * and frees the writer, also on failure (then no file is left behind and out_error, may be
 * NULL, says why). An earlier failed write makes close fail the same way; so do fewer frames
 * than def.frame_count announced (TB_STATUS_INVALID_ARGUMENT). */
TB_API tb_status tb_writer_close(tb_writer *writer, tb_error *out_error);

/* Frees the writer without finishing its file (which is removed); accepts NULL. */
TB_API void tb_writer_destroy(tb_writer *writer);

#ifdef __cplusplus
}
#endif

#endif
