/* libFuzzer target: the Wavefront OBJ reader. The input is an OBJ file; it is read by the
 * library's reader (src/io) and loaded as a mesh body of a scene file that names it, so the
 * mesh mass properties see whatever the reader accepts.
 *
 * Checked: a status with a message or a result, never a crash, leak or undefined behaviour;
 * when the reader accepts the file, it holds no NUL byte and the reader found exactly the
 * vertices and fan triangles that the file's lines hold (a line is the text up to a newline,
 * however long, a '#' starts a comment; "v x y z" is a vertex, "f a b c ..." gives count - 2
 * triangles), and every triangle index names a vertex; a loaded scene has a finite state. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "fuzz_input.h"

#include "io/scene_file_internal.h"
#include "tumble/tumble.h"

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void fail(const char *format, const char *value)
{
    fprintf(stderr, "fuzz_obj: ");
    fprintf(stderr, format, value);
    fputc('\n', stderr);
    abort();
}

/* The temporary folder the mesh file lives in, made once per process. */
static const char *work_folder(void)
{
    static char folder[64];
    if (folder[0] == '\0') {
        snprintf(folder, sizeof folder, "/tmp/tumble_fuzz_obj_XXXXXX");
        if (mkdtemp(folder) == NULL) {
            abort();
        }
    }
    return folder;
}

static int blank(uint8_t c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* What one line (without its newline) holds by the contract: text up to a '#' is the
 * statement; its first word is the keyword; a "v" is one vertex, an "f" with n corners gives
 * n - 2 triangles of a fan. */
static void count_line(const uint8_t *line, size_t length, size_t *vertices, size_t *triangles)
{
    const uint8_t *comment = memchr(line, '#', length);
    if (comment != NULL) {
        length = (size_t)(comment - line);
    }
    size_t i = 0;
    while (i < length && blank(line[i])) {
        ++i;
    }
    const size_t keyword = i;
    while (i < length && !blank(line[i])) {
        ++i;
    }
    if (i - keyword != 1 || (line[keyword] != 'v' && line[keyword] != 'f')) {
        return;
    }
    if (line[keyword] == 'v') {
        ++*vertices;
        return;
    }
    size_t words = 0;
    for (; i < length; ++i) {
        words += !blank(line[i]) && blank(line[i - 1]);
    }
    *triangles += words >= 2 ? words - 2 : 0;
}

/* What the file holds: lines end at a newline, however long. A NUL byte is never accepted
 * (checked by the caller), so none is counted here. */
static void count_statements(const uint8_t *data, size_t size, size_t *vertices, size_t *triangles)
{
    *vertices = *triangles = 0;
    for (size_t start = 0; start < size;) {
        const uint8_t *newline = memchr(data + start, '\n', size - start);
        const size_t end = newline != NULL ? (size_t)(newline - data) : size;
        count_line(data + start, end - start, vertices, triangles);
        start = end + 1;
    }
}

static void check_reader(const char *path, const uint8_t *data, size_t size)
{
    tb__mesh_buffers mesh;
    char detail[TB_DETAIL_SIZE] = "";
    const tb_status status = tb__obj_read_file(path, TB_SCENE_FILE_MAX_MESH_BYTES, &mesh, detail);
    const unsigned *triangles = mesh.triangles;
    const size_t vertex_count = mesh.vertex_count, triangle_count = mesh.triangle_count;
    if (status != TB_STATUS_OK) {
        if (detail[0] == '\0') {
            fail("%s: the reader failed without a message", tb_status_name(status));
        }
        return;
    }
    if (memchr(data, '\0', size) != NULL) {
        fail("%s", "accepted a file with a NUL byte (the rest of its line unread)");
    }
    size_t expected_vertices, expected_triangles;
    count_statements(data, size, &expected_vertices, &expected_triangles);
    if (vertex_count != expected_vertices || triangle_count != expected_triangles) {
        fprintf(stderr,
                "fuzz_obj: read %zu vertices and %zu triangles, the file's lines hold %zu "
                "and %zu\n",
                vertex_count, triangle_count, expected_vertices, expected_triangles);
        abort();
    }
    for (size_t i = 0; i < 3 * triangle_count; ++i) {
        if (triangles[i] >= vertex_count) {
            fail("%s", "a triangle index past the vertices");
        }
    }
    tb__mesh_buffers_free(&mesh);
}

static void check_loader(const char *folder)
{
    static const char *scene_text =
        "{\"bodies\": [{\"name\": \"m\", \"shape\": {\"type\": \"mesh\", \"file\": \"input.obj\"},"
        " \"density\": 1000}], \"output\": {\"duration\": 0.05, \"fps\": 20}}";
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    const tb_status status =
        tb_scene_load_string(scene_text, "fuzz.json", folder, &scene, &run, &error);
    if (status != TB_STATUS_OK) {
        if (scene != NULL || error.message[0] == '\0') {
            fail("%s: a failed load left a scene or no message", tb_status_name(status));
        }
        return;
    }
    const double *y = tb_scene_states_const(scene);
    for (size_t i = 0; i < tb_scene_state_size(scene); ++i) {
        if (!isfinite(y[i])) {
            fail("%s", "a loaded mesh body with a non-finite state");
        }
    }
    tb_scene_destroy(scene);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *folder = work_folder();
    char path[128];
    snprintf(path, sizeof path, "%s/input.obj", folder);
    FILE *file = fopen(path, "wb");
    if (file == NULL || fwrite(data, 1, size, file) != size || fclose(file) != 0) {
        abort();
    }
    check_reader(path, data, size);
    check_loader(folder);
    return 0;
}
