/* Private: the pieces of a NumPy .npz (a zip archive of stored .npy members) that the two
 * ways of writing one share: all frames kept in memory and written at close (writer_npz.c),
 * or frames streamed to their places in the file by a writer thread (writer_npz_stream.c). */
#ifndef TUMBLE_WRITER_NPZ_INTERNAL_H
#define TUMBLE_WRITER_NPZ_INTERNAL_H

#include "export/writer_internal.h"

#include <stdint.h>

/* One .npy member: a header naming dtype and shape, then the data. */
typedef struct tb__npy_array {
    const char *name; /* member "<name>.npy" */
    char descr[32];   /* dtype, e.g. "<f8", "<U12" */
    size_t shape[3];  /* dimensions, rank of them used */
    int rank;         /* 0 for a scalar */
    const void *data; /* row-major; NULL for an array streamed to the file */
    size_t data_size; /* bytes */
} tb__npy_array;

/* A zip member's place in the file, for the central directory. */
typedef struct tb__zip_entry {
    char name[32];
    uint32_t crc, size, offset; /* size: of the .npy (header and data), bytes */
} tb__zip_entry;

/* The five float arrays (t, position, orientation, velocity, angular_velocity) come first. */
#define TB__NPZ_FLOATS 5
#define TB__NPZ_MEMBERS 10
/* The longest .npy header written (a shape of three 20-digit numbers fits), bytes. */
#define TB__NPY_HEADER_MAX 256

/* The CRC-32 of zip (ISO 3309) of what crc covered followed by size bytes of data (crc 0: of
 * nothing), by libdeflate. */
uint32_t tb__crc32_update(uint32_t crc, const void *data, size_t size);

/* The header of a .npy (magic, version 1.0, the dict padded to a multiple of 64 bytes) into
 * out; its length. */
size_t tb__npy_header(const tb__npy_array *a, char *out, size_t size);

/* The float arrays for frame_count frames of body_count bodies; their data pointers are those
 * of frames (NULL: streamed). */
void tb__npz_float_arrays(size_t frame_count, size_t body_count, const tb__frames *frames,
                          tb__npy_array arrays[TB__NPZ_FLOATS]);

/* Bytes from a member's start to its .npy data (zip local header, name, .npy header): fills
 * entry's name and size and *header with the .npy header (TB__NPY_HEADER_MAX bytes).
 * TB_STATUS_UNSUPPORTED (the detail naming the array) when the member or the archive up to
 * its end would pass 4 GiB, which needs zip64. */
tb_status tb__npz_member_layout(tb_writer *w, const tb__npy_array *a, uint32_t offset,
                                tb__zip_entry *entry, char *header, size_t *out_head_size);

/* Writes a member's zip local header, name and .npy header at the file's position. */
tb_status tb__npz_write_head(tb_writer *w, const tb__zip_entry *entry, const char *header,
                             size_t header_size);

/* Writes, at the file's position (offset bytes into the archive), the text members (body
 * names, metadata) and then the central directory of entries[0..TB__NPZ_FLOATS) (the float
 * members, already in the file) and of the text members. */
tb_status tb__npz_write_tail(tb_writer *w, tb__zip_entry *entries, uint32_t offset);

/* Starts streaming frame_count frames into w's file (its writer thread, or the caller's thread
 * if none can start). TB_STATUS_OUT_OF_MEMORY, TB_STATUS_UNSUPPORTED (over 4 GiB). */
tb_status tb__npz_stream_open(tb_writer *w, size_t frame_count);
/* The place of the next frame: t[1], position[3 n], orientation[4 n], velocity[3 n],
 * angular_velocity[3 n]. Hands a full block of frames to the writer first, so it may report
 * TB_STATUS_IO_ERROR (a block that failed to be written; the detail says why). */
tb_status tb__npz_stream_slot(tb_writer *w, double **out_parts);
/* The slot's frame is complete. */
void tb__npz_stream_commit(tb_writer *w);
/* Writes the last frames, waits for the writer, and finishes the archive. */
tb_status tb__npz_stream_finish(tb_writer *w);
/* Stops the writer thread and frees the stream; accepts NULL. */
void tb__npz_stream_free(tb__npz_stream *stream);

#endif
