/* Writers: NumPy .npz, written without NumPy: a zip archive of stored (uncompressed) .npy
 * files, format version 1.0 (numpy.lib.format). The arrays are in the byte order of the
 * machine that wrote them, which their headers state ('<f8' on x86 and ARM). */
#include "export/writer_npz_internal.h"

#include "core/detail.h"

#include <libdeflate.h>

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define TB__DOS_DATE ((1u << 5) | 1u) /* 1980-01-01, the first date zip can say */

static bool little_endian(void)
{
    const uint16_t probe = 1;
    return *(const unsigned char *)&probe == 1;
}

uint32_t tb__crc32_update(uint32_t crc, const void *data, size_t size)
{
    return size == 0 ? crc : libdeflate_crc32(crc, data, size);
}

static void put16(unsigned char *p, unsigned v)
{
    p[0] = (unsigned char)(v & 0xff);
    p[1] = (unsigned char)((v >> 8) & 0xff);
}

static void put32(unsigned char *p, uint32_t v)
{
    put16(p, v & 0xffff);
    put16(p + 2, v >> 16);
}

/* The header: magic, version 1.0, length, then the dict padded with spaces to a multiple of
 * 64 bytes and ended by '\n' (numpy.lib.format's alignment). Returns its length. */
size_t tb__npy_header(const tb__npy_array *a, char *out, size_t size)
{
    char shape[96] = "";
    for (int k = 0; k < a->rank; ++k) {
        const size_t used = strlen(shape);
        snprintf(shape + used, sizeof shape - used, "%zu, ", a->shape[k]);
    }
    if (a->rank > 1) {
        shape[strlen(shape) - 2] = '\0'; /* (F, B, 3) ; a rank-1 shape keeps "(F,)" */
    } else if (a->rank == 1) {
        shape[strlen(shape) - 1] = '\0';
    }
    char dict[192];
    int length =
        snprintf(dict, sizeof dict, "{'descr': '%s', 'fortran_order': False, 'shape': (%s), }",
                 a->descr, shape);
    const size_t total = ((10 + (size_t)length + 1 + 63) / 64) * 64;
    if (total > size) {
        return 0;
    }
    memcpy(out, "\x93NUMPY\x01\x00", 8);
    put16((unsigned char *)out + 8, (unsigned)(total - 10));
    memcpy(out + 10, dict, (size_t)length);
    memset(out + 10 + length, ' ', total - 10 - (size_t)length - 1);
    out[total - 1] = '\n';
    return total;
}

static tb_status write_bytes(tb_writer *w, const void *data, size_t size)
{
    errno = 0;
    return size == 0 || fwrite(data, 1, size, w->file) == size
               ? TB_STATUS_OK
               : tb__writer_io_failure(w, "write failed");
}

tb_status tb__npz_member_layout(tb_writer *w, const tb__npy_array *a, uint32_t offset,
                                tb__zip_entry *entry, char *header, size_t *out_head_size)
{
    const size_t header_size = tb__npy_header(a, header, TB__NPY_HEADER_MAX);
    const uint64_t size = (uint64_t)header_size + a->data_size;
    if (size > UINT32_MAX - 1024 || (uint64_t)offset + size + 1024 > UINT32_MAX) {
        return tb__set_detail(w->detail, TB_STATUS_UNSUPPORTED,
                              "%s: %s.npy: over 4 GiB needs zip64, which this writer does not "
                              "write; write fewer frames or bodies per file",
                              w->path, a->name);
    }
    snprintf(entry->name, sizeof entry->name, "%s.npy", a->name);
    entry->size = (uint32_t)size;
    entry->offset = offset;
    *out_head_size = header_size;
    return TB_STATUS_OK;
}

/* Local file header (stored, no data descriptor: the CRC is known before the header is
 * written), the member's name and its .npy header. */
tb_status tb__npz_write_head(tb_writer *w, const tb__zip_entry *entry, const char *header,
                             size_t header_size)
{
    const size_t name_length = strlen(entry->name);
    unsigned char local[30] = {0x50, 0x4b, 0x03, 0x04};
    put16(local + 4, 20); /* version needed: 2.0 */
    put16(local + 12, TB__DOS_DATE);
    put32(local + 14, entry->crc);
    put32(local + 18, entry->size);
    put32(local + 22, entry->size);
    put16(local + 26, (unsigned)name_length);
    tb_status status = write_bytes(w, local, sizeof local);
    if (status == TB_STATUS_OK) {
        status = write_bytes(w, entry->name, name_length);
    }
    return status == TB_STATUS_OK ? write_bytes(w, header, header_size) : status;
}

/* A member whose data is in memory, at the file's position (offset into the archive). */
static tb_status write_member(tb_writer *w, const tb__npy_array *a, tb__zip_entry *entry,
                              uint32_t *offset)
{
    char header[TB__NPY_HEADER_MAX];
    size_t header_size = 0;
    tb_status status = tb__npz_member_layout(w, a, *offset, entry, header, &header_size);
    if (status != TB_STATUS_OK) {
        return status;
    }
    entry->crc = tb__crc32_update(tb__crc32_update(0, header, header_size), a->data, a->data_size);
    status = tb__npz_write_head(w, entry, header, header_size);
    if (status == TB_STATUS_OK) {
        status = write_bytes(w, a->data, a->data_size);
    }
    *offset += (uint32_t)(30 + strlen(entry->name) + entry->size);
    return status;
}

static tb_status write_directory(tb_writer *w, const tb__zip_entry *entries, size_t count,
                                 uint32_t offset)
{
    uint32_t directory_size = 0;
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        const size_t name_length = strlen(entries[k].name);
        unsigned char central[46] = {0x50, 0x4b, 0x01, 0x02};
        put16(central + 4, 20); /* made by: version 2.0 */
        put16(central + 6, 20);
        put16(central + 14, TB__DOS_DATE);
        put32(central + 16, entries[k].crc);
        put32(central + 20, entries[k].size);
        put32(central + 24, entries[k].size);
        put16(central + 28, (unsigned)name_length);
        put32(central + 42, entries[k].offset);
        status = write_bytes(w, central, sizeof central);
        if (status == TB_STATUS_OK) {
            status = write_bytes(w, entries[k].name, name_length);
        }
        directory_size += (uint32_t)(sizeof central + name_length);
    }
    unsigned char end[22] = {0x50, 0x4b, 0x05, 0x06};
    put16(end + 8, (unsigned)count);
    put16(end + 10, (unsigned)count);
    put32(end + 12, directory_size);
    put32(end + 16, offset);
    return status == TB_STATUS_OK ? write_bytes(w, end, sizeof end) : status;
}

/* UTF-8 text as UTF-32 code points (NumPy's 'U' dtype); malformed bytes become U+FFFD. */
static size_t utf32(const char *text, uint32_t *out, size_t capacity)
{
    const unsigned char *s = (const unsigned char *)text;
    size_t n = 0;
    while (*s != '\0' && n < capacity) {
        int extra = *s >= 0xf0 ? 3 : *s >= 0xe0 ? 2 : *s >= 0xc0 ? 1 : 0;
        uint32_t c = extra == 0 ? *s : *s & (0x3f >> extra);
        bool ok = *s < 0x80 || extra > 0;
        ++s;
        for (; extra > 0 && ok; --extra, ++s) {
            ok = (*s & 0xc0) == 0x80;
            c = (c << 6) | (*s & 0x3f);
        }
        out[n++] = ok ? c : 0xfffd;
    }
    return n;
}

/* A fixed-width unicode array of count strings, the k-th at first + k * stride bytes: rank 1
 * (body names), or rank 0 for a single string (metadata). */
static uint32_t *unicode_array(const char *name, const char *first, size_t count, size_t stride,
                               int rank, tb__npy_array *a)
{
    memset(a, 0, sizeof *a);
    a->name = name;
    a->rank = rank;
    a->shape[0] = count;
    size_t width = 1;
    for (size_t k = 0; k < count; ++k) {
        const size_t length = strlen(first + k * stride);
        width = length > width ? length : width;
    }
    uint32_t *data = calloc(count * width, sizeof *data);
    for (size_t k = 0; k < count && data != NULL; ++k) {
        utf32(first + k * stride, data + k * width, width);
    }
    snprintf(a->descr, sizeof a->descr, "%cU%zu", little_endian() ? '<' : '>', width);
    a->data = data;
    a->data_size = count * width * sizeof *data;
    return data;
}

static const char *const metadata[][2] = {
    {"units", "SI: t s, position m, velocity m/s, angular_velocity rad/s"},
    {"up_axis", "z"},
    {"frame", "world frame, z up; position, orientation and velocity are those of each body's "
              "shape frame (its origin and its shape -> world rotation)"},
    {"quaternion_order", "w,x,y,z"},
};

void tb__npz_float_arrays(size_t frame_count, size_t body_count, const tb__frames *frames,
                          tb__npy_array arrays[TB__NPZ_FLOATS])
{
    static const char *const names[TB__NPZ_FLOATS] = {"t", "position", "orientation", "velocity",
                                                      "angular_velocity"};
    static const size_t widths[TB__NPZ_FLOATS] = {0, 3, 4, 3, 3};
    const double *data[TB__NPZ_FLOATS] = {NULL};
    if (frames != NULL) {
        data[0] = frames->t, data[1] = frames->position, data[2] = frames->orientation;
        data[3] = frames->velocity, data[4] = frames->angular_velocity;
    }
    for (size_t k = 0; k < TB__NPZ_FLOATS; ++k) {
        tb__npy_array *a = &arrays[k];
        memset(a, 0, sizeof *a);
        a->name = names[k];
        snprintf(a->descr, sizeof a->descr, "%cf8", little_endian() ? '<' : '>');
        a->shape[0] = frame_count;
        a->shape[1] = body_count;
        a->shape[2] = widths[k];
        a->rank = widths[k] > 0 ? 3 : 1;
        a->data = data[k];
        a->data_size = frame_count * (widths[k] > 0 ? body_count * widths[k] : 1) * sizeof(double);
    }
}

/* The arrays that are text: the body names and the metadata. */
static size_t text_arrays(const tb_writer *w, tb__npy_array *arrays, uint32_t **text)
{
    text[0] = unicode_array("names", w->names[0], w->body_count, TB_NAME_SIZE, 1, &arrays[0]);
    size_t count = 1;
    for (size_t k = 0; k < sizeof metadata / sizeof metadata[0]; ++k, ++count) {
        text[count] = unicode_array(metadata[k][0], metadata[k][1], 1, 0, 0, &arrays[count]);
    }
    return count;
}

tb_status tb__npz_write_tail(tb_writer *w, tb__zip_entry *entries, uint32_t offset)
{
    tb__npy_array arrays[TB__NPZ_MEMBERS - TB__NPZ_FLOATS];
    uint32_t *text[TB__NPZ_MEMBERS - TB__NPZ_FLOATS] = {NULL};
    const size_t count = text_arrays(w, arrays, text);
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        if (text[k] == NULL) {
            status = tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: %s array", w->path,
                                    arrays[k].name);
        }
    }
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = write_member(w, &arrays[k], &entries[TB__NPZ_FLOATS + k], &offset);
    }
    if (status == TB_STATUS_OK) {
        status = write_directory(w, entries, TB__NPZ_FLOATS + count, offset);
    }
    for (size_t k = 0; k < count; ++k) {
        free(text[k]);
    }
    return status;
}

tb_status tb__npz_write(tb_writer *w)
{
    tb__npy_array arrays[TB__NPZ_FLOATS];
    tb__npz_float_arrays(w->frames.count, w->body_count, &w->frames, arrays);
    tb__zip_entry entries[TB__NPZ_MEMBERS];
    uint32_t offset = 0;
    tb_status status = TB_STATUS_OK;
    for (size_t k = 0; k < TB__NPZ_FLOATS && status == TB_STATUS_OK; ++k) {
        status = write_member(w, &arrays[k], &entries[k], &offset);
    }
    return status == TB_STATUS_OK ? tb__npz_write_tail(w, entries, offset) : status;
}
