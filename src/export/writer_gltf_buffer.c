/* Writers: glTF's binary buffer, its views and accessors, and the two containers: .glb (a
 * 12-byte header, a JSON chunk and a BIN chunk, each 4-byte aligned) and .gltf (JSON text
 * with the buffer as a base64 data URI). */
#include "export/writer_gltf_internal.h"

#include "core/detail.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

enum {
    GLTF_FLOAT = 5126,
    GLTF_UNSIGNED_INT = 5125,
    GLTF_ARRAY_BUFFER = 34962,
    GLTF_ELEMENT_ARRAY_BUFFER = 34963
};

void tb__gltf_init(tb__gltf *g)
{
    memset(g, 0, sizeof *g);
    g->nodes = json_array();
    g->meshes = json_array();
    g->materials = json_array();
    g->animations = json_array();
    g->accessors = json_array();
    g->views = json_array();
    g->failed =
        !g->nodes || !g->meshes || !g->materials || !g->animations || !g->accessors || !g->views;
}

void tb__gltf_free(tb__gltf *g)
{
    json_decref(g->nodes);
    json_decref(g->meshes);
    json_decref(g->materials);
    json_decref(g->animations);
    json_decref(g->accessors);
    json_decref(g->views);
    free(g->buffer);
    memset(g, 0, sizeof *g);
}

/* Appends size bytes at a 4-byte boundary; returns their offset. */
static size_t append(tb__gltf *g, const void *data, size_t size)
{
    const size_t offset = (g->size + 3) & ~(size_t)3;
    if (offset + size > g->capacity) {
        size_t capacity = g->capacity > 0 ? 2 * g->capacity : 4096;
        while (capacity < offset + size) {
            capacity *= 2;
        }
        unsigned char *grown = realloc(g->buffer, capacity);
        if (grown == NULL) {
            g->failed = true;
            return 0;
        }
        g->buffer = grown;
        g->capacity = capacity;
    }
    memset(g->buffer + g->size, 0, offset - g->size);
    memcpy(g->buffer + offset, data, size);
    g->size = offset + size;
    return offset;
}

static const char *type_name(tb__gltf_type type)
{
    return type == TB__GLTF_VEC3 ? "VEC3" : type == TB__GLTF_VEC4 ? "VEC4" : "SCALAR";
}

static size_t components(tb__gltf_type type)
{
    return type == TB__GLTF_VEC3 ? 3 : type == TB__GLTF_VEC4 ? 4 : 1;
}

long tb__gltf_accessor(tb__gltf *g, const void *data, size_t count, tb__gltf_type type,
                       tb__gltf_use use, const double *min, const double *max)
{
    const size_t size = count * components(type) * 4; /* float and uint32 are 4 bytes */
    const size_t offset = append(g, data, size);
    json_t *view = json_pack("{s:i, s:I, s:I}", "buffer", 0, "byteOffset", (json_int_t)offset,
                             "byteLength", (json_int_t)size);
    if (use != TB__GLTF_ANIMATION) {
        json_object_set_new(
            view, "target",
            json_integer(use == TB__GLTF_VERTICES ? GLTF_ARRAY_BUFFER : GLTF_ELEMENT_ARRAY_BUFFER));
    }
    json_array_append_new(g->views, view);
    json_t *accessor =
        json_pack("{s:I, s:i, s:I, s:s}", "bufferView", (json_int_t)json_array_size(g->views) - 1,
                  "componentType", type == TB__GLTF_INDEX ? GLTF_UNSIGNED_INT : GLTF_FLOAT, "count",
                  (json_int_t)count, "type", type_name(type));
    for (int k = 0; k < 2 && min != NULL && max != NULL; ++k) {
        json_t *bound = json_array();
        for (size_t i = 0; i < components(type); ++i) {
            json_array_append_new(bound, json_real(k == 0 ? min[i] : max[i]));
        }
        json_object_set_new(accessor, k == 0 ? "min" : "max", bound);
    }
    json_array_append_new(g->accessors, accessor);
    g->failed |= view == NULL || accessor == NULL;
    return (long)json_array_size(g->accessors) - 1;
}

static void put32(unsigned char *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k) {
        p[k] = (unsigned char)(v >> (8 * k));
    }
}

static tb_status write_all(tb_writer *w, const void *data, size_t size)
{
    errno = 0;
    return size == 0 || fwrite(data, 1, size, w->file) == size
               ? TB_STATUS_OK
               : tb__writer_io_failure(w, "write failed");
}

static tb_status too_big(tb_writer *w, size_t size)
{
    return tb__set_detail(w->detail, TB_STATUS_UNSUPPORTED,
                          "%s: %zu bytes is past glTF's 4 GiB; write fewer frames or bodies",
                          w->path, size);
}

tb_status tb__gltf_write_glb(tb__gltf *g, json_t *root, tb_writer *w)
{
    const size_t bin_size = (g->size + 3) & ~(size_t)3;
    json_object_set_new(root, "buffers", json_pack("[{s:I}]", "byteLength", (json_int_t)g->size));
    char *text = json_dumps(root, JSON_COMPACT);
    if (text == NULL) {
        return tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: JSON chunk", w->path);
    }
    const size_t text_size = strlen(text), json_size = (text_size + 3) & ~(size_t)3;
    const size_t total = 12 + 8 + json_size + 8 + bin_size;
    if (total > UINT32_MAX) {
        free(text);
        return too_big(w, total);
    }
    unsigned char header[20];
    put32(header, 0x46546C67); /* "glTF" */
    put32(header + 4, 2);
    put32(header + 8, (uint32_t)total);
    put32(header + 12, (uint32_t)json_size);
    put32(header + 16, 0x4E4F534A); /* "JSON" */
    tb_status status = write_all(w, header, sizeof header);
    if (status == TB_STATUS_OK) {
        status = write_all(w, text, text_size);
    }
    if (status == TB_STATUS_OK) {
        status = write_all(w, "   ", json_size - text_size); /* JSON pads with spaces */
    }
    free(text);
    put32(header, (uint32_t)bin_size);
    put32(header + 4, 0x004E4942); /* "BIN" */
    if (status == TB_STATUS_OK) {
        status = write_all(w, header, 8);
    }
    if (status == TB_STATUS_OK) {
        status = write_all(w, g->buffer, g->size);
    }
    return status == TB_STATUS_OK ? write_all(w, "\0\0\0", bin_size - g->size) : status;
}

/* RFC 4648 base64 of the buffer behind the data URI's prefix. */
static char *data_uri(const tb__gltf *g)
{
    static const char prefix[] = "data:application/octet-stream;base64,";
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = malloc(sizeof prefix + 4 * ((g->size + 2) / 3));
    if (out == NULL) {
        return NULL;
    }
    memcpy(out, prefix, sizeof prefix - 1);
    char *p = out + sizeof prefix - 1;
    for (size_t k = 0; k < g->size; k += 3) {
        const size_t left = g->size - k;
        const uint32_t v = (uint32_t)g->buffer[k] << 16 |
                           (left > 1 ? (uint32_t)g->buffer[k + 1] << 8 : 0) |
                           (left > 2 ? g->buffer[k + 2] : 0);
        *p++ = digits[v >> 18];
        *p++ = digits[(v >> 12) & 63];
        *p++ = left > 1 ? digits[(v >> 6) & 63] : '=';
        *p++ = left > 2 ? digits[v & 63] : '=';
    }
    *p = '\0';
    return out;
}

tb_status tb__gltf_write_text(tb__gltf *g, json_t *root, tb_writer *w)
{
    if (g->size > UINT32_MAX) {
        return too_big(w, g->size);
    }
    char *uri = data_uri(g);
    json_object_set_new(root, "buffers",
                        json_pack("[{s:I, s:s}]", "byteLength", (json_int_t)g->size, "uri",
                                  uri != NULL ? uri : ""));
    free(uri);
    char *text = uri != NULL ? json_dumps(root, JSON_INDENT(1)) : NULL;
    if (text == NULL) {
        return tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: glTF text", w->path);
    }
    tb_status status = write_all(w, text, strlen(text));
    free(text);
    return status == TB_STATUS_OK ? write_all(w, "\n", 1) : status;
}
