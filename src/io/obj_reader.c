/* Wavefront OBJ meshes: a line-by-line parser over a memory buffer, and a reader that takes
 * only regular files of bounded size (a device such as /dev/zero never ends, and opening a
 * FIFO waits for a writer). */
#define _POSIX_C_SOURCE 200809L

#include "io/obj_reader.h"

#include "core/detail.h"
#include "core/validate.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void tb__shown_path(char out[TB__SHOWN_PATH_SIZE], const char *path)
{
    const size_t length = strlen(path);
    if (length < TB__SHOWN_PATH_SIZE) {
        memcpy(out, path, length + 1);
    } else {
        const size_t kept = TB__SHOWN_PATH_SIZE - 4;
        memcpy(out, "...", 3);
        memcpy(out + 3, path + length - kept, kept + 1);
    }
}

bool tb__mesh_push_vertex(tb__mesh_buffers *mesh, const double vertex[3])
{
    if (!tb__grow_array((void **)&mesh->vertices, &mesh->vertex_capacity, mesh->vertex_count + 1,
                        3 * sizeof(double))) {
        return false;
    }
    memcpy(mesh->vertices + 3 * mesh->vertex_count++, vertex, 3 * sizeof(double));
    return true;
}

bool tb__mesh_push_triangle(tb__mesh_buffers *mesh, unsigned a, unsigned b, unsigned c)
{
    if (!tb__grow_array((void **)&mesh->triangles, &mesh->triangle_capacity,
                        mesh->triangle_count + 1, 3 * sizeof(unsigned))) {
        return false;
    }
    unsigned *t = mesh->triangles + 3 * mesh->triangle_count++;
    t[0] = a, t[1] = b, t[2] = c;
    return true;
}

void tb__mesh_buffers_free(tb__mesh_buffers *mesh)
{
    free(mesh->vertices);
    free(mesh->triangles);
    free(mesh->group_starts);
    memset(mesh, 0, sizeof *mesh);
}

/* --- parsing ------------------------------------------------------------------------------ */

typedef struct obj_parser {
    const char *name; /* for messages */
    size_t line;      /* 1-based number of the line being parsed */
    char *detail;
    tb__mesh_buffers mesh;
    char *copy; /* the current line, NUL-terminated */
    size_t copy_capacity;
    bool group_pending; /* an "o" or "g" (or the file's start) since the last face */
} obj_parser;

/* A new group begins at the next triangle if an "o" or "g" came since the last face. */
static bool begin_group(obj_parser *p)
{
    tb__mesh_buffers *m = &p->mesh;
    if (!p->group_pending) {
        return true;
    }
    if (!tb__grow_array((void **)&m->group_starts, &m->group_capacity, m->group_count + 1,
                        sizeof *m->group_starts)) {
        return false;
    }
    m->group_starts[m->group_count++] = m->triangle_count;
    p->group_pending = false;
    return true;
}

static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

static char *skip_blanks(char *s)
{
    while (is_blank(*s)) {
        ++s;
    }
    return s;
}

/* One coordinate: a finite number ending at a blank or the end of the line. */
static bool coordinate(char **cursor, double *out)
{
    char *end;
    *out = strtod(*cursor, &end);
    if (end == *cursor || !(*end == '\0' || is_blank(*end)) || !isfinite(*out)) {
        return false;
    }
    *cursor = skip_blanks(end);
    return true;
}

/* "v x y z", optionally followed by an "r g b" colour (ignored). */
static tb_status vertex_line(obj_parser *p, char *rest)
{
    double values[6];
    int count = 0;
    for (rest = skip_blanks(rest); *rest != '\0' && count < 6; ++count) {
        if (!coordinate(&rest, &values[count])) {
            return tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                                  "%s:%zu: v: coordinate %d is not a finite number", p->name,
                                  p->line, count + 1);
        }
    }
    if ((count != 3 && count != 6) || *rest != '\0') {
        return tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                              "%s:%zu: v needs 3 coordinates (x y z, optionally followed by an "
                              "r g b colour), got %s",
                              p->name, p->line, *rest != '\0' ? "more than 6" : "another count");
    }
    return tb__mesh_push_vertex(&p->mesh, values)
               ? TB_STATUS_OK
               : tb__set_detail(p->detail, TB_STATUS_OUT_OF_MEMORY, "%s:%zu: %zu vertices", p->name,
                                p->line, p->mesh.vertex_count + 1);
}

/* An optional integer after a '/' of "i/t/n": digits or nothing. */
static bool optional_integer(char **cursor)
{
    if (**cursor == '\0' || **cursor == '/' || is_blank(**cursor)) {
        return true;
    }
    char *end;
    errno = 0;
    (void)strtol(*cursor, &end, 10);
    if (end == *cursor || errno != 0) {
        return false;
    }
    *cursor = end;
    return true;
}

/* One face corner "i", "i/t", "i//n" or "i/t/n": the vertex index i, 1-based or negative
 * (counted back from the latest vertex), resolved to 0-based. */
static bool face_corner(char **cursor, size_t vertex_count, unsigned *out)
{
    char *end;
    errno = 0;
    const long index = strtol(*cursor, &end, 10);
    if (end == *cursor || errno != 0) {
        return false;
    }
    for (int part = 0; part < 2 && *end == '/'; ++part) {
        ++end;
        if (!optional_integer(&end)) {
            return false;
        }
    }
    if (!(*end == '\0' || is_blank(*end))) {
        return false;
    }
    *cursor = skip_blanks(end);
    /* vertex_count <= UINT_MAX - 1 (checked when vertices are added), so no overflow here */
    if (index > 0 && (size_t)index <= vertex_count) {
        *out = (unsigned)(index - 1);
        return true;
    }
    if (index < 0 && (size_t)(-(index + 1)) < vertex_count) {
        *out = (unsigned)(vertex_count - (size_t)(-(index + 1)) - 1);
        return true;
    }
    return false;
}

/* "f a b c d ...": fanned into triangles (a b c), (a c d), ... */
static tb_status face_line(obj_parser *p, char *rest)
{
    unsigned first = 0, previous = 0, index;
    size_t count = 0;
    for (rest = skip_blanks(rest); *rest != '\0'; ++count) {
        if (!face_corner(&rest, p->mesh.vertex_count, &index)) {
            return tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                                  "%s:%zu: f: corner %zu is not the index of an earlier vertex "
                                  "(1 to %zu, or -1 for the latest; forms i, i/t, i//n, i/t/n)",
                                  p->name, p->line, count + 1, p->mesh.vertex_count);
        }
        if (count == 0) {
            first = index;
        } else if (count >= 2 &&
                   (!begin_group(p) || !tb__mesh_push_triangle(&p->mesh, first, previous, index))) {
            return tb__set_detail(p->detail, TB_STATUS_OUT_OF_MEMORY, "%s:%zu: %zu triangles",
                                  p->name, p->line, p->mesh.triangle_count + 1);
        }
        previous = index;
    }
    return count >= 3 ? TB_STATUS_OK
                      : tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                                       "%s:%zu: f needs at least 3 corners, got %zu", p->name,
                                       p->line, count);
}

/* Statements that carry nothing a rigid body needs: smoothing, materials, normals and texture
 * coordinates. */
static bool ignored_statement(const char *keyword)
{
    static const char *const ignored[] = {"s", "usemtl", "mtllib", "vn", "vt", NULL};
    for (size_t k = 0; ignored[k] != NULL; ++k) {
        if (strcmp(keyword, ignored[k]) == 0) {
            return true;
        }
    }
    return false;
}

/* One line, NUL-terminated in p->copy. */
static tb_status parse_statement(obj_parser *p)
{
    char *comment = strchr(p->copy, '#');
    if (comment != NULL) {
        *comment = '\0';
    }
    char *keyword = skip_blanks(p->copy);
    char *rest = keyword;
    while (*rest != '\0' && !is_blank(*rest)) {
        ++rest;
    }
    if (rest == keyword) {
        return TB_STATUS_OK; /* blank or a comment */
    }
    const char after = *rest;
    *rest = '\0';
    if (strcmp(keyword, "v") == 0) {
        return after == '\0' ? vertex_line(p, rest) : vertex_line(p, rest + 1);
    }
    if (strcmp(keyword, "f") == 0) {
        return after == '\0' ? face_line(p, rest) : face_line(p, rest + 1);
    }
    if (strcmp(keyword, "o") == 0 || strcmp(keyword, "g") == 0) {
        p->group_pending = true; /* its name is not kept */
        return TB_STATUS_OK;
    }
    if (ignored_statement(keyword)) {
        return TB_STATUS_OK;
    }
    return tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                          "%s:%zu: \"%.32s\" statements are not supported (tumble reads v and f; "
                          "o and g begin pieces; s, usemtl, mtllib, vn and vt are ignored)",
                          p->name, p->line, keyword);
}

/* Copies the line [start, start + length) into p->copy and parses it. */
static tb_status parse_line(obj_parser *p, const char *start, size_t length)
{
    if (memchr(start, '\0', length) != NULL) {
        return tb__set_detail(p->detail, TB_STATUS_BAD_SCENE,
                              "%s:%zu: a NUL byte: not an OBJ text file", p->name, p->line);
    }
    if (length == SIZE_MAX ||
        !tb__grow_array((void **)&p->copy, &p->copy_capacity, length + 1, 1)) {
        return tb__set_detail(p->detail, TB_STATUS_OUT_OF_MEMORY, "%s:%zu: a line of %zu bytes",
                              p->name, p->line, length);
    }
    memcpy(p->copy, start, length);
    p->copy[length] = '\0';
    return parse_statement(p);
}

tb_status tb__obj_parse(const char *text, size_t length, const char *name, tb__mesh_buffers *out,
                        char *detail)
{
    memset(out, 0, sizeof *out);
    obj_parser p = {.name = name != NULL ? name : "<obj>", .detail = detail, .group_pending = true};
    tb_status status = TB_STATUS_OK;
    const char *end = text + (text != NULL ? length : 0);
    for (const char *line = text; line != NULL && line < end && status == TB_STATUS_OK;) {
        const char *newline = memchr(line, '\n', (size_t)(end - line));
        const char *stop = newline != NULL ? newline : end;
        ++p.line;
        status = parse_line(&p, line, (size_t)(stop - line));
        line = newline != NULL ? newline + 1 : end;
        if (status == TB_STATUS_OK && p.mesh.vertex_count >= UINT_MAX) {
            status = tb__set_detail(detail, TB_STATUS_BAD_SCENE, "%s:%zu: more than %u vertices",
                                    p.name, p.line, UINT_MAX - 1);
        }
    }
    free(p.copy);
    if (status != TB_STATUS_OK) {
        tb__mesh_buffers_free(&p.mesh);
        return status;
    }
    *out = p.mesh;
    return TB_STATUS_OK;
}

/* --- files -------------------------------------------------------------------------------- */

/* The whole of an open regular file of size bytes into a new buffer. */
/* path: as shown in messages. */
static tb_status read_all(int fd, const char *path, size_t size, char **out, char *detail)
{
    char *text = malloc(size + 1);
    if (text == NULL) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY, "%s: %zu bytes", path, size);
    }
    size_t total = 0;
    /* One byte more than the size: a file that grew while read is noticed, not cut short. */
    while (total < size + 1) {
        const ssize_t got = read(fd, text + total, size + 1 - total);
        if (got < 0 && errno == EINTR) {
            continue;
        }
        if (got < 0) {
            const int reason = errno;
            free(text);
            return tb__set_detail(detail, TB_STATUS_IO_ERROR, "cannot read %s: %s", path,
                                  strerror(reason));
        }
        if (got == 0) {
            break;
        }
        total += (size_t)got;
    }
    if (total != size) {
        free(text);
        return tb__set_detail(detail, TB_STATUS_IO_ERROR, "%s changed size while it was read",
                              path);
    }
    *out = text;
    return TB_STATUS_OK;
}

/* A regular file of at most max_bytes: opened without waiting (O_NONBLOCK: a FIFO would
 * otherwise block the open until a writer comes), then checked by its descriptor. */
static tb_status open_regular(const char *path, const char *shown, size_t max_bytes, int *out_fd,
                              size_t *out_size, char *detail)
{
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        return tb__set_detail(detail, TB_STATUS_IO_ERROR, "cannot read %s: %s", shown,
                              strerror(errno));
    }
    struct stat info;
    tb_status status = TB_STATUS_OK;
    if (fstat(fd, &info) != 0) {
        status = tb__set_detail(detail, TB_STATUS_IO_ERROR, "cannot read %s: %s", shown,
                                strerror(errno));
    } else if (!S_ISREG(info.st_mode)) {
        status = tb__set_detail(detail, TB_STATUS_IO_ERROR,
                                "cannot read %s: not a regular file (a directory, device or "
                                "pipe); mesh files must be regular files",
                                shown);
    } else if ((uintmax_t)info.st_size > (uintmax_t)max_bytes) {
        status = tb__set_detail(detail, TB_STATUS_IO_ERROR,
                                "cannot read %s: %jd bytes, more than the %zu bytes allowed for "
                                "a mesh file (max_mesh_file_bytes)",
                                shown, (intmax_t)info.st_size, max_bytes);
    }
    if (status != TB_STATUS_OK) {
        close(fd);
        return status;
    }
    *out_fd = fd;
    *out_size = (size_t)info.st_size;
    return TB_STATUS_OK;
}

tb_status tb__obj_read_file(const char *path, size_t max_bytes, tb__mesh_buffers *out, char *detail)
{
    memset(out, 0, sizeof *out);
    int fd = -1;
    size_t size = 0;
    char shown[TB__SHOWN_PATH_SIZE];
    tb__shown_path(shown, path);
    tb_status status = open_regular(path, shown, max_bytes, &fd, &size, detail);
    if (status != TB_STATUS_OK) {
        return status;
    }
    char *text = NULL;
    status = read_all(fd, shown, size, &text, detail);
    close(fd);
    if (status == TB_STATUS_OK) {
        status = tb__obj_parse(text, size, shown, out, detail);
    }
    free(text);
    return status;
}
