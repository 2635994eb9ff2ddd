/* Writers: NumPy .npz, written without NumPy: a zip archive of stored (uncompressed) .npy
 * files, format version 1.0 (numpy.lib.format). The arrays are in the byte order of the
 * machine that wrote them, which their headers state ('<f8' on x86 and ARM). */
#include "io/writer_internal.h"

#include "core/detail.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* One .npy member: a header naming dtype and shape, then the data. */
typedef struct npy_array {
    const char *name; /* member "<name>.npy" */
    char descr[32];   /* dtype, e.g. "<f8", "<U12" */
    size_t shape[3];  /* dimensions, rank of them used */
    int rank;         /* 0 for a scalar */
    const void *data; /* row-major */
    size_t data_size; /* bytes */
} npy_array;

/* A zip member's place in the file, for the central directory. */
typedef struct zip_entry {
    char name[32];
    uint32_t crc, size, offset;
} zip_entry;

#define TB__NPZ_MEMBERS 10
#define TB__DOS_DATE ((1u << 5) | 1u) /* 1980-01-01, the first date zip can say */

static bool little_endian(void)
{
    const uint16_t probe = 1;
    return *(const unsigned char *)&probe == 1;
}

/* CRC-32 of zip (reflected polynomial 0xEDB88320), eight bytes a step ("slicing by 8"):
 * table[k][b] is the CRC of byte b followed by k zero bytes. */
typedef struct crc_tables {
    uint32_t table[8][256];
} crc_tables;

static void crc_tables_init(crc_tables *c)
{
    for (uint32_t b = 0; b < 256; ++b) {
        uint32_t crc = b;
        for (int bit = 0; bit < 8; ++bit) {
            crc = crc & 1 ? (crc >> 1) ^ 0xEDB88320u : crc >> 1;
        }
        c->table[0][b] = crc;
    }
    for (uint32_t b = 0; b < 256; ++b) {
        for (int k = 1; k < 8; ++k) {
            const uint32_t previous = c->table[k - 1][b];
            c->table[k][b] = (previous >> 8) ^ c->table[0][previous & 0xff];
        }
    }
}

static uint32_t crc32_update(const crc_tables *c, uint32_t crc, const void *data, size_t size)
{
    const unsigned char *p = data;
    crc = ~crc;
    for (; size >= 8; size -= 8, p += 8) {
        const uint32_t low = crc ^ ((uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
                                    (uint32_t)p[3] << 24);
        crc = c->table[7][low & 0xff] ^ c->table[6][(low >> 8) & 0xff] ^
              c->table[5][(low >> 16) & 0xff] ^ c->table[4][low >> 24] ^ c->table[3][p[4]] ^
              c->table[2][p[5]] ^ c->table[1][p[6]] ^ c->table[0][p[7]];
    }
    for (; size > 0; --size, ++p) {
        crc = (crc >> 8) ^ c->table[0][(crc ^ *p) & 0xff];
    }
    return ~crc;
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
static size_t npy_header(const npy_array *a, char *out, size_t size)
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

/* Local file header (stored, no data descriptor: the CRC is known before the data). */
static tb_status write_member(tb_writer *w, const crc_tables *crc, const npy_array *a,
                              zip_entry *entry, uint32_t *offset)
{
    char header[256];
    const size_t header_size = npy_header(a, header, sizeof header);
    const uint64_t size = (uint64_t)header_size + a->data_size;
    if (size > UINT32_MAX - 1024 || (uint64_t)*offset + size + 1024 > UINT32_MAX) {
        return tb__set_detail(w->detail, TB_STATUS_UNSUPPORTED,
                              "%s: %s.npy: over 4 GiB needs zip64, which this writer does not "
                              "write; write fewer frames or bodies per file",
                              w->path, a->name);
    }
    snprintf(entry->name, sizeof entry->name, "%s.npy", a->name);
    entry->crc =
        crc32_update(crc, crc32_update(crc, 0, header, header_size), a->data, a->data_size);
    entry->size = (uint32_t)size;
    entry->offset = *offset;
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
    if (status == TB_STATUS_OK) {
        status = write_bytes(w, header, header_size);
    }
    if (status == TB_STATUS_OK) {
        status = write_bytes(w, a->data, a->data_size);
    }
    *offset += (uint32_t)(sizeof local + name_length + size);
    return status;
}

static tb_status write_directory(tb_writer *w, const zip_entry *entries, size_t count,
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
                               int rank, npy_array *a)
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

static void float_array(const char *name, const double *data, const tb__frames *f, size_t width,
                        npy_array *a)
{
    memset(a, 0, sizeof *a);
    a->name = name;
    snprintf(a->descr, sizeof a->descr, "%cf8", little_endian() ? '<' : '>');
    a->shape[0] = f->count;
    a->shape[1] = f->body_count;
    a->shape[2] = width;
    a->rank = width > 0 ? 3 : 1;
    a->data = data;
    a->data_size = f->count * (width > 0 ? f->body_count * width : 1) * sizeof(double);
}

/* The arrays that are text: the body names and the metadata. */
static size_t text_arrays(const tb_writer *w, npy_array *arrays, uint32_t **text)
{
    text[0] = unicode_array("names", w->names[0], w->body_count, TB_NAME_SIZE, 1, &arrays[0]);
    size_t count = 1;
    for (size_t k = 0; k < sizeof metadata / sizeof metadata[0]; ++k, ++count) {
        text[count] = unicode_array(metadata[k][0], metadata[k][1], 1, 0, 0, &arrays[count]);
    }
    return count;
}

tb_status tb__npz_write(tb_writer *w)
{
    const tb__frames *f = &w->frames;
    npy_array arrays[TB__NPZ_MEMBERS];
    uint32_t *text[TB__NPZ_MEMBERS] = {NULL};
    float_array("t", f->t, f, 0, &arrays[0]);
    float_array("position", f->position, f, 3, &arrays[1]);
    float_array("orientation", f->orientation, f, 4, &arrays[2]);
    float_array("velocity", f->velocity, f, 3, &arrays[3]);
    float_array("angular_velocity", f->angular_velocity, f, 3, &arrays[4]);
    const size_t count = 5 + text_arrays(w, arrays + 5, text + 5);
    tb_status status = TB_STATUS_OK;
    for (size_t k = 5; k < count && status == TB_STATUS_OK; ++k) {
        if (text[k] == NULL) {
            status = tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "%s: %s array", w->path,
                                    arrays[k].name);
        }
    }
    crc_tables crc;
    crc_tables_init(&crc);
    zip_entry entries[TB__NPZ_MEMBERS];
    uint32_t offset = 0;
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        status = write_member(w, &crc, &arrays[k], &entries[k], &offset);
    }
    if (status == TB_STATUS_OK) {
        status = write_directory(w, entries, count, offset);
    }
    for (size_t k = 5; k < count; ++k) {
        free(text[k]);
    }
    return status;
}
