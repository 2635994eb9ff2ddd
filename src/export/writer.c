/* Writers: choosing a format, opening the file, taking frames, finishing the file whole. */
#define _POSIX_C_SOURCE 200809L /* stat, lseek, open, fdopen, getpid, clock_gettime */
#include "export/writer_npz_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define TB__WRITER_COOKIE 0x77726974
#define TB__PARTIAL_PATTERN ".tumble-XXXXXXXX.partial"

static const char *const format_names[] = {"csv", "npz", "glb", "gltf", "usda"};
#define TB__FORMATS (sizeof format_names / sizeof format_names[0])

tb_writer_def tb_writer_def_default(void)
{
    tb_writer_def def;
    memset(&def, 0, sizeof def);
    def.format = TB_OUTPUT_CSV;
    def.rotation_keys = TB_ROTATION_CUBICSPLINE;
    def.sample_tolerance = TB_WRITER_SAMPLE_TOLERANCE;
    def.internal_cookie = TB__WRITER_COOKIE;
    return def;
}

const char *tb_output_format_name(tb_output_format format)
{
    return (unsigned)format < TB__FORMATS ? format_names[format] : "unknown";
}

static bool same_name(const char *a, const char *b)
{
    for (; *a != '\0' && *b != '\0'; ++a, ++b) {
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) {
            return false;
        }
    }
    return *a == *b;
}

tb_status tb_output_format_from_name(const char *name, tb_output_format *out_format)
{
    if (name == NULL || out_format == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    for (unsigned k = 0; k < TB__FORMATS; ++k) {
        if (same_name(name, format_names[k])) {
            *out_format = (tb_output_format)k;
            return TB_STATUS_OK;
        }
    }
    return TB_STATUS_INVALID_ARGUMENT;
}

tb_status tb_output_format_from_path(const char *path, tb_output_format *out_format)
{
    if (path == NULL || out_format == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    if (dot == NULL || (slash != NULL && slash > dot)) {
        return TB_STATUS_INVALID_ARGUMENT;
    }
    return tb_output_format_from_name(dot + 1, out_format);
}

tb_status tb__writer_io_failure(tb_writer *writer, const char *what)
{
    writer->failed = TB_STATUS_IO_ERROR;
    return tb__set_detail(writer->detail, TB_STATUS_IO_ERROR, "%s: %s: %s", writer->path, what,
                          strerror(errno != 0 ? errno : EIO));
}

static tb_status check_def(const tb_writer_def *def, tb_error *error)
{
    if (def->internal_cookie != TB__WRITER_COOKIE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def: not initialised with tb_writer_def_default");
    }
    if ((unsigned)def->format >= TB__FORMATS) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.format: must be a tb_output_format, got %d", (int)def->format);
    }
    if ((unsigned)def->rotation_keys > TB_ROTATION_LINEAR) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.rotation_keys: must be a tb_rotation_keys, got %d",
                             (int)def->rotation_keys);
    }
    if (def->format == TB_OUTPUT_NPZ && def->frame_count > UINT32_MAX) {
        return tb__set_error(error, TB_STATUS_UNSUPPORTED,
                             "def.frame_count: %zu frames pass 4 GiB, which needs zip64",
                             def->frame_count);
    }
    if (!(def->fps >= 0) || !isfinite(def->fps)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.fps: must be finite and >= 0 (0: from the frames), got %g",
                             def->fps);
    }
    const double tolerance = def->sample_tolerance;
    if (!(tolerance == 0 || (tolerance >= 1e-6 && tolerance <= 0.1))) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "def.sample_tolerance: must be 0 (samples at the frames only) or in "
                             "[1e-6, 0.1] rad, got %g",
                             tolerance);
    }
    return TB_STATUS_OK;
}

/* Regular files (and paths not there yet) are written into a new file in the same folder and
 * renamed at the end; a device or a pipe is written directly. The new file's name is short
 * (".tumble-XXXXXXXX.partial", so a path whose name has the system's longest still has one
 * beside it) and made afresh, created exclusively: no file that was there is taken over. */
static tb_status choose_paths(tb_writer *w, const char *path)
{
    struct stat info;
    const bool direct = stat(path, &info) == 0 && !S_ISREG(info.st_mode);
    const size_t length = strlen(path);
    const char *slash = strrchr(path, '/');
    const size_t folder = slash != NULL ? (size_t)(slash - path) + 1 : 0;
    w->path = malloc(length + 1);
    w->written_path = malloc((direct ? length : folder + sizeof TB__PARTIAL_PATTERN) + 1);
    if (w->path == NULL || w->written_path == NULL) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    memcpy(w->path, path, length + 1);
    memcpy(w->written_path, path, direct ? length + 1 : folder);
    if (!direct) {
        memcpy(w->written_path + folder, TB__PARTIAL_PATTERN, sizeof TB__PARTIAL_PATTERN);
    }
    return TB_STATUS_OK;
}

/* A 32-bit mix (the finaliser of MurmurHash3) of what differs between writers and tries. */
static uint32_t mix(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    return (uint32_t)(x ^ (x >> 33));
}

/* Creates the side file: its X's replaced by hexadecimal digits until a name is free (the
 * writer's address, the process, the clock and the try pick them; no state is kept). */
static FILE *create_partial(tb_writer *w)
{
    char *x = strstr(w->written_path + strlen(w->written_path) - (sizeof TB__PARTIAL_PATTERN - 1),
                     "XXXXXXXX");
    struct timespec now;
    clock_gettime(CLOCK_REALTIME, &now);
    for (uint64_t attempt = 0; attempt < 100; ++attempt) {
        const uint32_t bits =
            mix((uint64_t)(uintptr_t)w ^ ((uint64_t)getpid() << 32) ^ (uint64_t)now.tv_nsec ^
                ((uint64_t)now.tv_sec << 20) ^ (attempt * 0x9e3779b97f4a7c15ULL));
        char digits[9];
        snprintf(digits, sizeof digits, "%08x", (unsigned)bits);
        memcpy(x, digits, 8);
        const int fd = open(w->written_path, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd >= 0) {
            FILE *file = fdopen(fd, "wb");
            if (file == NULL) {
                close(fd);
                remove(w->written_path);
            }
            return file;
        }
        if (errno != EEXIST) {
            return NULL;
        }
    }
    return NULL;
}

static tb_status take_scene(tb_writer *w, const tb_writer_def *def, const tb_scene *scene,
                            tb_error *error)
{
    w->body_count = tb_scene_body_count(scene);
    w->names = calloc(w->body_count > 0 ? w->body_count : 1, sizeof *w->names);
    w->values = tb__malloc_array(w->body_count > 0 ? w->body_count : 1, 13 * sizeof(double));
    if (w->names == NULL || w->values == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: %zu body names",
                             w->body_count);
    }
    for (size_t id = 0; id < w->body_count; ++id) {
        snprintf(w->names[id], TB_NAME_SIZE, "%s", tb_scene_body_name(scene, id));
    }
    tb__frames_init(&w->frames, w->body_count);
    if (def->format == TB_OUTPUT_GLB || def->format == TB_OUTPUT_GLTF ||
        def->format == TB_OUTPUT_USDA) {
        w->looks.bodies = NULL;
        return tb__looks_load(&w->looks, scene, error);
    }
    return TB_STATUS_OK;
}

static tb_status open_file(tb_writer *w, const char *path, tb_error *error)
{
    tb_status status = choose_paths(w, path);
    if (status != TB_STATUS_OK) {
        return tb__set_error(error, status, "path: %zu characters", strlen(path));
    }
    errno = 0;
    const bool direct = strcmp(w->written_path, w->path) == 0;
    w->file = direct ? fopen(w->written_path, "wb") : create_partial(w);
    if (w->file == NULL) {
        w->written_path[0] = '\0'; /* nothing of ours to remove */
        return tb__set_error(error, TB_STATUS_IO_ERROR, "%s: cannot open for writing: %s", w->path,
                             strerror(errno));
    }
    status = w->format == TB_OUTPUT_CSV ? tb__csv_header(w) : TB_STATUS_OK;
    /* npz of a known length into a file that can seek: streamed; else kept until close */
    if (status == TB_STATUS_OK && w->announced_frames > 0 &&
        lseek(fileno(w->file), 0, SEEK_CUR) != -1) {
        status = tb__npz_stream_open(w, w->announced_frames);
    }
    return status == TB_STATUS_OK ? status : tb__set_error(error, status, "%s", w->detail);
}

tb_status tb_writer_open(const char *path, const tb_writer_def *def, const tb_scene *scene,
                         tb_writer **out_writer, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (out_writer == NULL || path == NULL || def == NULL || scene == NULL) {
        if (out_writer != NULL) {
            *out_writer = NULL;
        }
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s: is NULL",
                             out_writer == NULL ? "out_writer"
                             : path == NULL     ? "path"
                             : def == NULL      ? "def"
                                                : "scene");
    }
    *out_writer = NULL;
    tb_status status = check_def(def, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb_writer *w = calloc(1, sizeof *w);
    if (w == NULL) {
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "writer");
    }
    w->format = def->format;
    w->rotation_keys = def->rotation_keys;
    w->fps = def->fps;
    w->sample_tolerance = def->sample_tolerance;
    w->last_t = -INFINITY;
    w->announced_frames = def->format == TB_OUTPUT_NPZ ? def->frame_count : 0;
    status = take_scene(w, def, scene, out_error);
    if (status == TB_STATUS_OK) {
        status = open_file(w, path, out_error);
    }
    if (status != TB_STATUS_OK) {
        tb_writer_destroy(w);
        return status;
    }
    *out_writer = w;
    return TB_STATUS_OK;
}

/* t after the last frame's, and room for one more frame than came (npz: of those announced). */
static tb_status check_time(tb_writer *w, double t)
{
    if (!isfinite(t)) {
        return tb__set_detail(w->detail, TB_STATUS_NOT_FINITE, "t: must be finite, got %g", t);
    }
    if (!(t > w->last_t)) {
        return tb__set_detail(w->detail, TB_STATUS_INVALID_ARGUMENT,
                              "t: must be after the previous frame's %.17g s, got %.17g", w->last_t,
                              t);
    }
    if (w->announced_frames > 0 && w->frame_count == w->announced_frames) {
        return tb__set_detail(w->detail, TB_STATUS_INVALID_ARGUMENT,
                              "t = %.17g s: one frame more than the %zu def.frame_count announced",
                              t, w->announced_frames);
    }
    return TB_STATUS_OK;
}

/* Where the next frame goes (npz, glTF): the stream's block, or the frames kept. */
static tb_status frame_slot(tb_writer *w, double **parts)
{
    if (w->stream != NULL) {
        return tb__npz_stream_slot(w, parts);
    }
    const tb_status status = tb__frames_slot(&w->frames, parts);
    if (status != TB_STATUS_OK) {
        tb__set_detail(w->detail, status, "frame %zu: no memory for %zu bodies", w->frame_count,
                       w->body_count);
    }
    return status;
}

static void frame_done(tb_writer *w, double t, double **parts)
{
    if (w->format != TB_OUTPUT_CSV) {
        parts[0][0] = t;
    }
    if (w->stream != NULL) {
        tb__npz_stream_commit(w);
    } else if (w->format != TB_OUTPUT_CSV) {
        w->frames.count++;
    }
    w->last_t = t;
    w->frame_count++;
}

/* A frame's values (13 doubles a body) into the file (CSV) or to their place (npz, glTF). */
static tb_status add_values(tb_writer *w, double t, const double *values)
{
    double *parts[TB__NPZ_FLOATS] = {w->values};
    tb_status status =
        w->format == TB_OUTPUT_CSV ? tb__csv_frame(w, t, values) : frame_slot(w, parts);
    if (status != TB_STATUS_OK || w->format == TB_OUTPUT_CSV) {
        if (status == TB_STATUS_OK) {
            frame_done(w, t, parts);
        }
        return status;
    }
    for (size_t id = 0; id < w->body_count; ++id) {
        const double *s = values + 13 * id;
        memcpy(parts[1] + 3 * id, s, 3 * sizeof(double));
        memcpy(parts[2] + 4 * id, s + 3, 4 * sizeof(double));
        memcpy(parts[3] + 3 * id, s + 7, 3 * sizeof(double));
        memcpy(parts[4] + 3 * id, s + 10, 3 * sizeof(double));
    }
    frame_done(w, t, parts);
    return TB_STATUS_OK;
}

tb_status tb_writer_frame(tb_writer *writer, double t, const tb_scene *scene)
{
    if (writer == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if (writer->failed != TB_STATUS_OK) {
        return writer->failed; /* the detail still says what failed */
    }
    writer->detail[0] = '\0';
    if (scene == NULL) {
        return tb__set_detail(writer->detail, TB_STATUS_NULL_POINTER, "scene: is NULL");
    }
    tb_status status = check_time(writer, t);
    if (status == TB_STATUS_OK && tb_scene_body_count(scene) != writer->body_count) {
        status = tb__set_detail(writer->detail, TB_STATUS_INVALID_ARGUMENT,
                                "scene: has %zu bodies, the writer was opened for %zu",
                                tb_scene_body_count(scene), writer->body_count);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* one library call reads the whole frame (shape-origin pose, velocity, omega) */
    tb_scene_frame_values(scene, tb_scene_states_const(scene), writer->values);
    return add_values(writer, t, writer->values);
}

/* Finite values, and unit quaternions (to 1e-6: what a double-precision run keeps). */
static tb_status check_values(tb_writer *w, const double *values)
{
    for (size_t k = 0; k < 13 * w->body_count; ++k) {
        if (!isfinite(values[k])) {
            return tb__set_detail(w->detail, TB_STATUS_NOT_FINITE,
                                  "values[%zu] (body %zu): must be finite, got %g", k, k / 13,
                                  values[k]);
        }
    }
    for (size_t id = 0; id < w->body_count; ++id) {
        const double norm = tb__q_norm(values + 13 * id + 3);
        if (fabs(norm - 1.0) > 1e-6) {
            return tb__set_detail(w->detail, TB_STATUS_INVALID_ARGUMENT,
                                  "values[%zu..%zu] (body %zu's orientation): must be a unit "
                                  "quaternion to 1e-6, got |q| = %.9g",
                                  13 * id + 3, 13 * id + 6, id, norm);
        }
    }
    return TB_STATUS_OK;
}

tb_status tb_writer_frame_values(tb_writer *writer, double t, const double *values)
{
    if (writer == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    if (writer->failed != TB_STATUS_OK) {
        return writer->failed;
    }
    writer->detail[0] = '\0';
    if (values == NULL) {
        return tb__set_detail(writer->detail, TB_STATUS_NULL_POINTER, "values: is NULL");
    }
    tb_status status = check_time(writer, t);
    if (status == TB_STATUS_OK) {
        status = check_values(writer, values);
    }
    return status == TB_STATUS_OK ? add_values(writer, t, values) : status;
}

int tb_writer_on_frame(size_t frame, double t, const tb_scene *scene, void *writer)
{
    (void)frame;
    return tb_writer_frame(writer, t, scene) == TB_STATUS_OK ? 0 : 1;
}

const char *tb_writer_detail(const tb_writer *writer)
{
    return writer != NULL ? writer->detail : "";
}

size_t tb_writer_frame_count(const tb_writer *writer)
{
    return writer != NULL ? writer->frame_count : 0;
}

static void release(tb_writer *w, bool remove_file)
{
    tb__npz_stream_free(w->stream); /* before the file closes: its thread may be writing */
    w->stream = NULL;
    if (w->file != NULL) {
        fclose(w->file);
    }
    if (remove_file && w->written_path != NULL && w->written_path[0] != '\0' &&
        strcmp(w->written_path, w->path) != 0) {
        remove(w->written_path);
    }
    tb__frames_free(&w->frames);
    tb__looks_free(&w->looks, w->body_count);
    free(w->names);
    free(w->events);
    free(w->values);
    free(w->path);
    free(w->written_path);
    free(w);
}

tb_status tb_writer_close(tb_writer *writer, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (writer == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "writer: is NULL");
    }
    tb_status status = writer->failed;
    if (status == TB_STATUS_OK && writer->frame_count != writer->announced_frames &&
        writer->announced_frames > 0) {
        status = tb__set_detail(writer->detail, TB_STATUS_INVALID_ARGUMENT,
                                "%s: def.frame_count announced %zu frames, %zu came", writer->path,
                                writer->announced_frames, writer->frame_count);
    } else if (status == TB_STATUS_OK && writer->stream != NULL) {
        status = tb__npz_stream_finish(writer);
    } else if (status == TB_STATUS_OK && writer->format == TB_OUTPUT_NPZ) {
        status = tb__npz_write(writer);
    } else if (status == TB_STATUS_OK && writer->format == TB_OUTPUT_USDA) {
        status = tb__usd_write(writer);
    } else if (status == TB_STATUS_OK && writer->format != TB_OUTPUT_CSV) {
        status = tb__gltf_write(writer);
    }
    if (status == TB_STATUS_OK && (fflush(writer->file) != 0 || ferror(writer->file))) {
        status = tb__writer_io_failure(writer, "write failed");
    }
    FILE *file = writer->file;
    writer->file = NULL;
    if (fclose(file) != 0 && status == TB_STATUS_OK) {
        status = tb__writer_io_failure(writer, "closing failed");
    }
    if (status == TB_STATUS_OK && strcmp(writer->written_path, writer->path) != 0 &&
        rename(writer->written_path, writer->path) != 0) {
        status = tb__writer_io_failure(writer, "renaming the finished file failed");
    }
    if (status != TB_STATUS_OK) {
        tb__set_error(out_error, status, "%s", writer->detail);
    }
    release(writer, status != TB_STATUS_OK);
    return status;
}

void tb_writer_destroy(tb_writer *writer)
{
    if (writer != NULL) {
        release(writer, true);
    }
}
