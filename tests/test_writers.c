/* Writers: CSV numbers read back as exactly the doubles in memory; files appear whole or not
 * at all; bad input is refused with the shared statuses and changes nothing; a failed write
 * is an error. The independent readers (NumPy, pygltflib, the Khronos validator) check the
 * .npz and glTF contents in tests/export. */
#define _POSIX_C_SOURCE 200809L /* opendir, mkdir */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#define DIRECTORY TUMBLE_TEST_BUILD_DIR "/"
/* A folder of this test's own, where no other test's side files come and go. */

/* A box thrown with a spin (its shape origin is its centre of mass, so the velocity written
 * is P / M exactly) and a sphere, under gravity; awkward decimals so no number is short. */
static const char scene_json[] =
    "{\"bodies\": [{\"name\": \"box\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.2, "
    "0.3]}, \"density\": 700, \"position\": [0.1, 0.2, 1.3], \"velocity\": [0.7, 0.3, 6.1], "
    "\"angular_velocity\": [0.3, 1.1, 7.7]}, {\"name\": \"ball\", \"shape\": {\"type\": "
    "\"sphere\", \"radius\": 0.1}, \"mass\": 1.1, \"position\": [1, 0, 2]}],"
    " \"effects\": [{\"type\": \"gravity\"}], \"output\": {\"fps\": 30, \"duration\": 0.5}}";

static tb_scene *load(tb_run_def *run)
{
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(scene_json, "writers.json", NULL, &scene, run, &error),
                     TB_STATUS_OK);
    return scene;
}

static long file_size(const char *path)
{
    FILE *file = fopen(path, "rb");
    if (file == NULL) {
        return -1;
    }
    fseek(file, 0, SEEK_END);
    const long size = ftell(file);
    fclose(file);
    return size;
}

/* Frames as the run saw them, for comparison with what the file says. */
typedef struct recorder {
    tb_writer *writer;
    size_t count;
    double rows[64][2][14]; /* t, position, q, v, omega */
} recorder;

static int record(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    recorder *r = ctx;
    const double *y = tb_scene_states_const(scene);
    for (size_t id = 0; id < 2 && r->count < 64; ++id) {
        double *row = r->rows[r->count][id];
        row[0] = t;
        tb_scene_body_shape_pose(scene, y, id, row + 1, row + 4);
        tb_scene_body_velocity(scene, y, id, row + 8);
        tb_scene_body_angular_velocity(scene, y, id, row + 11);
    }
    r->count++;
    return tb_writer_on_frame(frame, t, scene, r->writer);
}

/* Printed with 17 significant digits, every double reads back (strtod) as itself. */
static void test_csv_numbers_read_back_as_the_doubles_in_memory(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_exact.csv";
    tb_writer_def def = tb_writer_def_default();
    recorder *r = calloc(1, sizeof *r);
    assert_int_equal(tb_writer_open(path, &def, scene, &r->writer, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_run(scene, &run, record, r, NULL, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(r->writer, NULL), TB_STATUS_OK);
    FILE *file = fopen(path, "r");
    char line[1024], name[64];
    assert_non_null(fgets(line, sizeof line, file)); /* the header */
    assert_string_equal(line, "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
    size_t rows = 0;
    for (; fgets(line, sizeof line, file) != NULL; ++rows) {
        const double *expected = r->rows[rows / 2][rows % 2];
        char *p = line;
        for (int k = 0; k < 15; ++k) {
            if (k == 1) {
                const size_t length = strcspn(p, ",");
                memcpy(name, p, length);
                name[length] = '\0';
                assert_string_equal(name, rows % 2 ? "ball" : "box");
                p += length + 1;
                continue;
            }
            char *end;
            const double value = strtod(p, &end);
            /* exact: the same bits, not merely close */
            assert_memory_equal(&value, &expected[k == 0 ? 0 : k - 1], sizeof value);
            p = end + 1;
        }
    }
    fclose(file);
    assert_int_equal(rows, 2 * r->count);
    assert_true(r->count == 16); /* 0.5 s at 30 fps: frames 0 .. 15 */
    free(r);
    tb_scene_destroy(scene);
}

static void test_format_follows_the_extension_or_the_name(void **state)
{
    (void)state;
    tb_output_format format = TB_OUTPUT_CSV;
    assert_int_equal(tb_output_format_from_path("run/anim.GLB", &format), TB_STATUS_OK);
    assert_int_equal(format, TB_OUTPUT_GLB);
    assert_int_equal(tb_output_format_from_path("a.b/frames.npz", &format), TB_STATUS_OK);
    assert_int_equal(format, TB_OUTPUT_NPZ);
    assert_int_equal(tb_output_format_from_path("x.gltf", &format), TB_STATUS_OK);
    assert_int_equal(format, TB_OUTPUT_GLTF);
    assert_int_equal(tb_output_format_from_path("a.glb/frames", &format),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_output_format_from_path("frames.txt", &format), TB_STATUS_INVALID_ARGUMENT);
    /* binary USD has no writer: tumble writes the text form only */
    assert_int_equal(tb_output_format_from_path("stage.usd", &format), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_output_format_from_path("stage.usdc", &format), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(format, TB_OUTPUT_GLTF); /* unchanged by the failures */
    assert_int_equal(tb_output_format_from_path("shot/stage.USDA", &format), TB_STATUS_OK);
    assert_int_equal(format, TB_OUTPUT_USDA);
    assert_int_equal(tb_output_format_from_name("Csv", &format), TB_STATUS_OK);
    assert_int_equal(format, TB_OUTPUT_CSV);
    assert_int_equal(tb_output_format_from_name(NULL, &format), TB_STATUS_NULL_POINTER);
    assert_string_equal(tb_output_format_name(TB_OUTPUT_NPZ), "npz");
}

static void test_open_refuses_bad_input_and_leaves_no_file(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_refused.glb";
    remove(path);
    tb_writer_def def = tb_writer_def_default();
    tb_writer *writer = (tb_writer *)&def; /* must come back NULL */
    tb_error error;
    assert_int_equal(tb_writer_open(NULL, &def, scene, &writer, &error), TB_STATUS_NULL_POINTER);
    assert_null(writer);
    assert_non_null(strstr(error.message, "path"));
    tb_writer_def plain;
    memset(&plain, 0, sizeof plain);
    assert_int_equal(tb_writer_open(path, &plain, scene, &writer, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "tb_writer_def_default"));
    def.format = (tb_output_format)7;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.format"));
    def.format = TB_OUTPUT_USDA;
    def.fps = -24.0;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.fps"));
    def.fps = 24.0;
    const double tolerances[] = {NAN, -1e-3, 1e-7, 0.2};
    for (size_t k = 0; k < sizeof tolerances / sizeof tolerances[0]; ++k) {
        def.sample_tolerance = tolerances[k];
        assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error),
                         TB_STATUS_INVALID_ARGUMENT);
        assert_non_null(strstr(error.message, "def.sample_tolerance"));
    }
    def.sample_tolerance = TB_WRITER_SAMPLE_TOLERANCE;
    def.format = TB_OUTPUT_GLB;
    assert_int_equal(
        tb_writer_open(DIRECTORY "no_such_directory/a.glb", &def, scene, &writer, &error),
        TB_STATUS_IO_ERROR);
    assert_non_null(strstr(error.message, "no_such_directory/a.glb"));
    assert_null(writer);
    assert_int_equal(file_size(path), -1);
    tb_scene_destroy(scene);
}

static void test_a_bad_frame_is_refused_and_changes_nothing(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_frames.npz";
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_NPZ;
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, NAN, scene), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_writer_detail(writer), "t: must be finite"));
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_writer_detail(writer), "t: must be after"));
    assert_int_equal(tb_writer_frame(writer, 0.1, NULL), TB_STATUS_NULL_POINTER);
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *empty = NULL;
    tb_scene_create(&scene_def, &empty, NULL);
    assert_int_equal(tb_writer_frame(writer, 0.1, empty), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_writer_detail(writer), "scene: has 0 bodies"));
    assert_int_equal(tb_writer_frame_count(writer), 1);
    assert_int_equal(tb_writer_frame(writer, 0.1, scene), TB_STATUS_OK);
    assert_string_equal(tb_writer_detail(writer), "");
    assert_int_equal(tb_writer_frame_count(writer), 2);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    /* a stored zip: a local header first, and the end record counts the 10 arrays */
    FILE *file = fopen(path, "rb");
    unsigned char head[4], end[22];
    assert_int_equal(fread(head, 1, 4, file), 4);
    assert_memory_equal(head, "PK\3\4", 4);
    fseek(file, -22, SEEK_END);
    assert_int_equal(fread(end, 1, 22, file), 22);
    fclose(file);
    assert_memory_equal(end, "PK\5\6", 4);
    assert_int_equal(end[10], 10);
    tb_scene_destroy(empty);
    tb_scene_destroy(scene);
}

/* The disk is full: the failure comes back as IO_ERROR naming the file, at the latest from
 * close (CSV rows are buffered), and never as success. */
static void test_a_failed_write_is_an_error(void **state)
{
    (void)state;
    if (file_size("/dev/full") < 0) {
        skip();
    }
    tb_run_def run;
    tb_scene *scene = load(&run);
    for (int format = TB_OUTPUT_CSV; format <= TB_OUTPUT_USDA; ++format) {
        tb_writer_def def = tb_writer_def_default();
        def.format = (tb_output_format)format;
        tb_writer *writer = NULL;
        tb_error error;
        assert_int_equal(tb_writer_open("/dev/full", &def, scene, &writer, NULL), TB_STATUS_OK);
        tb_status status = TB_STATUS_OK;
        for (int k = 0; k < 2000 && status == TB_STATUS_OK; ++k) {
            status = tb_writer_frame(writer, 0.01 * k, scene);
        }
        assert_true(status == TB_STATUS_OK || status == TB_STATUS_IO_ERROR);
        assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_IO_ERROR);
        assert_non_null(strstr(error.message, "/dev/full"));
    }
    tb_scene_destroy(scene);
}

/* A path in this process's own side directory, writers_side_<pid>/ (name "" for the directory):
 * the ctests writers, memcheck_writers and helgrind_writers run this program at the same time,
 * and each empties its side directory. Four buffers in turn, for two paths in one call. */
static const char *side_path(const char *name)
{
    static char paths[4][512];
    static int next;
    char *out = paths[next++ % 4];
    snprintf(out, sizeof paths[0], "%swriters_side_%ld/%s", DIRECTORY, (long)getpid(), name);
    return out;
}

/* Files in the side directory whose name starts with prefix. */
static int files_named(const char *prefix)
{
    DIR *folder = opendir(side_path(""));
    assert_non_null(folder);
    int count = 0;
    for (struct dirent *entry = readdir(folder); entry != NULL; entry = readdir(folder)) {
        count += strncmp(entry->d_name, prefix, strlen(prefix)) == 0;
    }
    closedir(folder);
    return count;
}

static void empty_side_directory(void)
{
    mkdir(side_path(""), 0777);
    DIR *folder = opendir(side_path(""));
    assert_non_null(folder);
    char path[512];
    for (struct dirent *entry = readdir(folder); entry != NULL; entry = readdir(folder)) {
        snprintf(path, sizeof path, "%s", side_path(entry->d_name));
        remove(path); /* "." and ".." stay */
    }
    closedir(folder);
}

/* The group's teardown: the side directory goes with its process, so runs leave none behind. */
static int remove_side_directory(void **state)
{
    (void)state;
    empty_side_directory();
    return rmdir(side_path(""));
}

/* An abandoned or failed writer leaves the file that was there, and no partial file. */
static void test_an_unfinished_file_never_replaces_the_old_one(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    empty_side_directory();
    const char *path = side_path("writers_kept.csv");
    FILE *file = fopen(path, "w");
    fputs("old\n", file);
    fclose(file);
    tb_writer_def def = tb_writer_def_default();
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
    assert_int_equal(files_named(".tumble-"), 1); /* the side file it writes */
    tb_writer_destroy(writer);
    assert_int_equal(file_size(path), 4);
    assert_int_equal(files_named(".tumble-"), 0);
    tb_writer_destroy(NULL);
    assert_int_equal(tb_writer_close(NULL, NULL), TB_STATUS_NULL_POINTER);
    tb_scene_destroy(scene);
}

/* A file named as the side file once was ("<path>.partial") is another user's: a writer to path
 * leaves it as it was (it used to be overwritten, then renamed to path). */
static void test_a_file_named_like_a_side_file_is_left_alone(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    empty_side_directory();
    FILE *file = fopen(side_path("kept.glb.partial"), "w");
    fputs("mine\n", file);
    fclose(file);
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_GLB;
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(side_path("kept.glb"), &def, scene, &writer, NULL),
                     TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    assert_int_equal(file_size(side_path("kept.glb.partial")), 5);
    assert_true(file_size(side_path("kept.glb")) > 5);
    assert_int_equal(files_named(".tumble-"), 0);
    tb_scene_destroy(scene);
}

/* Names of 248 to 255 bytes (255: the longest a Linux file system takes) are written in every
 * format; "<name>.partial" had no room beside them. */
static void test_the_longest_file_names_are_written(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    empty_side_directory();
    static const char *const extensions[] = {"csv", "npz", "glb", "gltf", "usda"};
    for (size_t length = 248; length <= 255; length += 7) {
        for (size_t k = 0; k < sizeof extensions / sizeof extensions[0]; ++k) {
            char path[512];
            snprintf(path, sizeof path, "%s", side_path(""));
            const size_t folder = strlen(path), stem = length - 1 - strlen(extensions[k]);
            memset(path + folder, 'a', stem);
            snprintf(path + folder + stem, sizeof path - folder - stem, ".%s", extensions[k]);
            tb_writer_def def = tb_writer_def_default();
            assert_int_equal(tb_output_format_from_path(path, &def.format), TB_STATUS_OK);
            tb_writer *writer = NULL;
            tb_error error;
            assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error), TB_STATUS_OK);
            assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
            assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_OK);
            assert_true(file_size(path) > 0);
            remove(path);
        }
    }
    assert_int_equal(files_named(".tumble-"), 0);
    tb_scene_destroy(scene);
}

/* A name with a comma and a quote stays one field (RFC 4180: quoted, the quote doubled). */
static void test_csv_quotes_a_name_that_holds_a_comma(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_scene_create(&scene_def, &scene, NULL);
    tb_body_def body = tb_body_def_default();
    body.name = "die 1, \"red\"";
    tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &body.mass, NULL);
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    const char *path = DIRECTORY "writers_quoted.csv";
    tb_writer_def def = tb_writer_def_default();
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    FILE *file = fopen(path, "r");
    char line[512];
    assert_non_null(fgets(line, sizeof line, file));
    assert_non_null(fgets(line, sizeof line, file));
    fclose(file);
    assert_string_equal(line, "0,\"die 1, \"\"red\"\"\",0,0,0,1,0,0,0,0,0,0,0,0,0\n");
    tb_scene_destroy(scene);
}

/* Frames from the caller's own values: written as given, and checked like any input. */
static void test_frames_from_values_are_written_as_given(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_values.csv";
    tb_writer_def def = tb_writer_def_default();
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
    double values[26] = {0.1, 0.2, 0.3, 0.6, 0.8, 0, 0, 1, 2, 3, 4, 5, 6,
                         1,   2,   3,   0,   0,   1, 0, 0, 0, 0, 0, 0, 7};
    assert_int_equal(tb_writer_frame_values(writer, 0.25, NULL), TB_STATUS_NULL_POINTER);
    values[17] = NAN;
    assert_int_equal(tb_writer_frame_values(writer, 0.25, values), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_writer_detail(writer), "values[17] (body 1)"));
    values[17] = 0.5; /* |q| = sqrt(1.25) */
    assert_int_equal(tb_writer_frame_values(writer, 0.25, values), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_writer_detail(writer), "body 1's orientation"));
    assert_int_equal(tb_writer_frame_count(writer), 0);
    values[17] = 0.0;
    assert_int_equal(tb_writer_frame_values(writer, 0.25, values), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame_values(writer, 0.25, values), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    FILE *file = fopen(path, "r");
    char header[128], box[256], ball[256];
    assert_non_null(fgets(header, sizeof header, file));
    assert_non_null(fgets(box, sizeof box, file));
    assert_non_null(fgets(ball, sizeof ball, file));
    fclose(file);
    /* 0.1 and 0.2 print as their 17-digit expansions, which read back as themselves */
    assert_string_equal(box, "0.25,box,0.10000000000000001,0.20000000000000001,"
                             "0.29999999999999999,0.59999999999999998,0.80000000000000004,0,0,1,"
                             "2,3,4,5,6\n");
    assert_string_equal(ball, "0.25,ball,1,2,3,0,0,1,0,0,0,0,0,0,7\n");
    tb_scene_destroy(scene);
}

/* A run of one frame (duration 0) is a still: the nodes hold the pose and there is no
 * animation (glTF requires two keys for a cubic spline; one made the validator fail). */
static void test_one_frame_glb_is_a_still(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_still.glb";
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_GLB;
    tb_writer *writer = NULL;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.0, scene), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    FILE *file = fopen(path, "rb");
    char data[8192] = {0};
    const size_t size = fread(data, 1, sizeof data - 1, file);
    fclose(file);
    assert_true(size > 20);
    const char *json = data + 20;
    assert_null(strstr(json, "\"animations\""));
    assert_non_null(strstr(json, "\"translation\":["));
    tb_scene_destroy(scene);
}

static unsigned read32(const unsigned char *p)
{
    return p[0] | (unsigned)p[1] << 8 | (unsigned)p[2] << 16 | (unsigned)p[3] << 24;
}

/* GLB container (glTF 2.0 section 4.4): magic, version 2, the total length, a JSON chunk then
 * a BIN chunk; LINEAR rotation keys when asked for. */
static void test_glb_is_one_json_chunk_and_one_binary_chunk(void **state)
{
    (void)state;
    for (int linear = 0; linear < 2; ++linear) {
        tb_run_def run;
        tb_scene *scene = load(&run);
        const char *path = DIRECTORY "writers.glb";
        tb_writer_def def = tb_writer_def_default();
        def.format = TB_OUTPUT_GLB;
        def.rotation_keys = linear ? TB_ROTATION_LINEAR : TB_ROTATION_CUBICSPLINE;
        /* shapes and grounds are drawn from the scene: a ground added through the C API is */
        if (linear) {
            const tb_ground_def ground = tb_ground_def_default();
            assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        }
        tb_writer *writer = NULL;
        assert_int_equal(tb_writer_open(path, &def, scene, &writer, NULL), TB_STATUS_OK);
        assert_int_equal(tb_scene_run(scene, &run, tb_writer_on_frame, writer, NULL, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
        const long size = file_size(path);
        unsigned char *data = malloc((size_t)size + 1);
        FILE *file = fopen(path, "rb");
        assert_int_equal(fread(data, 1, (size_t)size, file), (size_t)size);
        fclose(file);
        assert_memory_equal(data, "glTF", 4);
        assert_int_equal(read32(data + 4), 2);
        assert_int_equal(read32(data + 8), (unsigned)size);
        const unsigned json_length = read32(data + 12);
        assert_memory_equal(data + 16, "JSON", 4);
        assert_int_equal(json_length % 4, 0);
        assert_memory_equal(data + 20 + json_length + 4, "BIN\0", 4);
        assert_int_equal(20 + json_length + 8 + read32(data + 20 + json_length), size);
        data[20 + json_length] = '\0';
        const char *json = (const char *)data + 20;
        assert_non_null(strstr(json, "\"name\":\"box\""));
        assert_non_null(strstr(json, "\"name\":\"ball\""));
        assert_true((strstr(json, "CUBICSPLINE") == NULL) == linear);
        assert_non_null(strstr(json, "\"meshes\""));
        assert_true((strstr(json, "\"ground 1\"") != NULL) == linear);
        free(data);
        tb_scene_destroy(scene);
    }
}

/* The whole of a file (NULL if it cannot be read); its size in *size. */
static unsigned char *read_all(const char *path, long *size)
{
    *size = file_size(path);
    FILE *file = fopen(path, "rb");
    unsigned char *data = *size >= 0 && file != NULL ? malloc((size_t)*size + 1) : NULL;
    if (data != NULL && fread(data, 1, (size_t)*size, file) != (size_t)*size) {
        free(data);
        data = NULL;
    }
    if (file != NULL) {
        fclose(file);
    }
    return data;
}

static void assert_same_file(const char *a, const char *b)
{
    long size_a = 0, size_b = 0;
    unsigned char *data_a = read_all(a, &size_a), *data_b = read_all(b, &size_b);
    assert_non_null(data_a);
    assert_non_null(data_b);
    assert_int_equal(size_a, size_b);
    assert_memory_equal(data_a, data_b, (size_t)size_a);
    free(data_a);
    free(data_b);
}

/* The writer draws from the scene alone: the deprecated scene_file, scene_text and
 * base_directory are ignored, so a .glb written with a missing file and broken text named in
 * them is the .glb written without, byte for byte. */
static void test_the_deprecated_scene_file_fields_are_ignored(void **state)
{
    (void)state;
    const char *paths[2] = {DIRECTORY "writers_plain.glb", DIRECTORY "writers_named.glb"};
    for (int named = 0; named < 2; ++named) {
        tb_run_def run;
        tb_scene *scene = load(&run);
        tb_writer_def def = tb_writer_def_default();
        def.format = TB_OUTPUT_GLB;
        if (named) {
            def.scene_file = DIRECTORY "no_such_scene.json";
            def.scene_text = "{\"bodies\": [";
            def.base_directory = DIRECTORY "no_such_directory";
        }
        tb_writer *writer = NULL;
        tb_error error;
        assert_int_equal(tb_writer_open(paths[named], &def, scene, &writer, &error), TB_STATUS_OK);
        assert_int_equal(tb_scene_run(scene, &run, tb_writer_on_frame, writer, NULL, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_OK);
        tb_scene_destroy(scene);
    }
    assert_same_file(paths[0], paths[1]);
}

/* Feeds two writers: one streaming (the frame count announced), one keeping the frames. */
typedef struct two_writers {
    tb_writer *streamed, *kept;
} two_writers;

static int feed_both(size_t frame, double t, const tb_scene *scene, void *ctx)
{
    two_writers *w = ctx;
    return tb_writer_on_frame(frame, t, scene, w->streamed) |
           tb_writer_on_frame(frame, t, scene, w->kept);
}

static void open_npz(const char *path, size_t frame_count, const tb_scene *scene, tb_writer **out)
{
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_NPZ;
    def.frame_count = frame_count;
    assert_int_equal(tb_writer_open(path, &def, scene, out, NULL), TB_STATUS_OK);
}

/* Frame k of the two bodies: values that differ in every frame, body and component, and a
 * unit quaternion turning about z. */
static void frame_values(size_t k, double values[26])
{
    for (size_t id = 0; id < 2; ++id) {
        double *s = values + 13 * id;
        const double angle = 0.01 * (double)k + 0.3 * (double)id;
        for (int c = 0; c < 13; ++c) {
            s[c] = 1.0 / (1.0 + (double)k) + 0.1 * c - (double)id;
        }
        s[3] = cos(angle), s[4] = 0, s[5] = 0, s[6] = sin(angle);
    }
}

/* Streamed by the writer's thread or kept in memory until close, the .npz is the same file
 * byte for byte (NumPy reads both back bit for bit: tests/export for the streamed files of
 * every example, the Python tests for kept ones). A run's frames (read out of the scene into
 * the stream's block), and 12 000 frames given as values, more than one block of the stream
 * holds (about 1 MiB, 4854 frames of 2 bodies), so blocks take turns and the last is partial. */
static void test_npz_streamed_is_the_npz_kept_byte_for_byte(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    size_t last = 0;
    assert_int_equal(tb_run_frame_count(run.duration, run.fps, &last, NULL), TB_STATUS_OK);
    two_writers w;
    open_npz(DIRECTORY "writers_streamed.npz", last + 1, scene, &w.streamed);
    open_npz(DIRECTORY "writers_kept.npz", 0, scene, &w.kept);
    assert_int_equal(tb_scene_run(scene, &run, feed_both, &w, NULL, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(w.streamed, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(w.kept, NULL), TB_STATUS_OK);
    assert_same_file(DIRECTORY "writers_streamed.npz", DIRECTORY "writers_kept.npz");

    const size_t frames = 12000;
    open_npz(DIRECTORY "writers_streamed.npz", frames, scene, &w.streamed);
    open_npz(DIRECTORY "writers_kept.npz", 0, scene, &w.kept);
    double values[26];
    for (size_t k = 0; k < frames; ++k) {
        frame_values(k, values);
        assert_int_equal(tb_writer_frame_values(w.streamed, 0.01 * (double)k, values), 0);
        assert_int_equal(tb_writer_frame_values(w.kept, 0.01 * (double)k, values), 0);
    }
    assert_int_equal(tb_writer_close(w.streamed, NULL), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(w.kept, NULL), TB_STATUS_OK);
    assert_same_file(DIRECTORY "writers_streamed.npz", DIRECTORY "writers_kept.npz");
    assert_true(file_size(DIRECTORY "writers_kept.npz") > (long)(frames * 26 * sizeof(double)));
    tb_scene_destroy(scene);
}

/* The announced frame count holds: one frame more is refused and changes nothing, fewer
 * frames fail close and leave no file; a count past what zip without zip64 holds is refused
 * at open. */
static void test_npz_frame_count_is_held_to(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load(&run);
    const char *path = DIRECTORY "writers_count.npz";
    remove(path);
    tb_writer *writer = NULL;
    tb_error error;
    double values[26];
    frame_values(0, values);
    open_npz(path, 2, scene, &writer);
    assert_int_equal(tb_writer_frame_values(writer, 0.0, values), TB_STATUS_OK);
    assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "announced 2 frames, 1 came"));
    assert_int_equal(file_size(path), -1);
    open_npz(path, 1, scene, &writer);
    assert_int_equal(tb_writer_frame_values(writer, 0.0, values), TB_STATUS_OK);
    assert_int_equal(tb_writer_frame(writer, 0.5, scene), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_writer_detail(writer), "one frame more than the 1"));
    assert_int_equal(tb_writer_frame_count(writer), 1);
    assert_int_equal(tb_writer_close(writer, NULL), TB_STATUS_OK);
    assert_true(file_size(path) > 0);
    tb_writer_def def = tb_writer_def_default();
    def.format = TB_OUTPUT_NPZ;
    def.frame_count = (size_t)UINT32_MAX + 1;
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error), TB_STATUS_UNSUPPORTED);
    assert_null(writer);
    def.frame_count = 40000000; /* 2 bodies: 8.3 GB */
    assert_int_equal(tb_writer_open(path, &def, scene, &writer, &error), TB_STATUS_UNSUPPORTED);
    assert_non_null(strstr(error.message, "zip64"));
    assert_null(writer);
    assert_true(file_size(path) > 0); /* the finished file before is left as it was */
    tb_scene_destroy(scene);
}

/* The disk fills while the writer's thread writes: the failure comes back as IO_ERROR with the
 * system's reason, from the frame that hands over the next block, from every call after it and
 * from close; never as success. */
static void test_a_failed_streamed_write_is_reported_with_its_reason(void **state)
{
    (void)state;
    if (file_size("/dev/full") < 0) {
        skip();
    }
    tb_run_def run;
    tb_scene *scene = load(&run);
    tb_writer *writer = NULL;
    tb_error error;
    open_npz("/dev/full", 12000, scene, &writer);
    double values[26];
    tb_status status = TB_STATUS_OK;
    size_t k = 0;
    for (; k < 12000 && status == TB_STATUS_OK; ++k) {
        frame_values(k, values);
        status = tb_writer_frame_values(writer, 0.01 * (double)k, values);
    }
    assert_int_equal(status, TB_STATUS_IO_ERROR);
    assert_true(k < 12000);
    assert_non_null(strstr(tb_writer_detail(writer), "/dev/full: write failed"));
    assert_non_null(strstr(tb_writer_detail(writer), strerror(ENOSPC)));
    assert_int_equal(tb_writer_frame_values(writer, 0.01 * (double)k, values), TB_STATUS_IO_ERROR);
    assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_IO_ERROR);
    assert_non_null(strstr(error.message, strerror(ENOSPC)));
    /* a short run, all in the first block: the failure shows at close */
    open_npz("/dev/full", 3, scene, &writer);
    for (k = 0; k < 3; ++k) {
        frame_values(k, values);
        assert_int_equal(tb_writer_frame_values(writer, 0.01 * (double)k, values), TB_STATUS_OK);
    }
    assert_int_equal(tb_writer_close(writer, &error), TB_STATUS_IO_ERROR);
    assert_non_null(strstr(error.message, strerror(ENOSPC)));
    /* abandoned while its thread may still be writing */
    open_npz("/dev/null", 12000, scene, &writer);
    for (k = 0; k < 6000; ++k) {
        frame_values(k, values);
        assert_int_equal(tb_writer_frame_values(writer, 0.01 * (double)k, values), TB_STATUS_OK);
    }
    tb_writer_destroy(writer);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_csv_numbers_read_back_as_the_doubles_in_memory),
        cmocka_unit_test(test_csv_quotes_a_name_that_holds_a_comma),
        cmocka_unit_test(test_frames_from_values_are_written_as_given),
        cmocka_unit_test(test_format_follows_the_extension_or_the_name),
        cmocka_unit_test(test_open_refuses_bad_input_and_leaves_no_file),
        cmocka_unit_test(test_the_deprecated_scene_file_fields_are_ignored),
        cmocka_unit_test(test_a_bad_frame_is_refused_and_changes_nothing),
        cmocka_unit_test(test_a_failed_write_is_an_error),
        cmocka_unit_test(test_an_unfinished_file_never_replaces_the_old_one),
        cmocka_unit_test(test_a_file_named_like_a_side_file_is_left_alone),
        cmocka_unit_test(test_the_longest_file_names_are_written),
        cmocka_unit_test(test_glb_is_one_json_chunk_and_one_binary_chunk),
        cmocka_unit_test(test_one_frame_glb_is_a_still),
        cmocka_unit_test(test_npz_streamed_is_the_npz_kept_byte_for_byte),
        cmocka_unit_test(test_npz_frame_count_is_held_to),
        cmocka_unit_test(test_a_failed_streamed_write_is_reported_with_its_reason),
    };
    return cmocka_run_group_tests(tests, NULL, remove_side_directory);
}
