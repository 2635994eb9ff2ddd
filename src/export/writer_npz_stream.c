/* Writers: NumPy .npz streamed. When the number of frames is known (tb_writer_def.frame_count)
 * every array's place in the archive is known when the writer opens, so frames need not be
 * kept: the caller's thread reads each frame out into a block of frames, and a writer thread
 * appends each full block's slice of every array at that array's place in the file (pwrite)
 * and updates its CRC, while the caller integrates the next block. Two blocks take turns; the
 * caller waits only when the disk is slower than the integration. A write the thread cannot
 * make is kept (errno and offset) and reported by the caller's next hand-over or by close as
 * TB_STATUS_IO_ERROR naming the file and the system's reason. When no thread can be started
 * the caller's thread writes each block itself. */
#define _POSIX_C_SOURCE 200809L /* pwrite */
#include "export/writer_npz_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A block of frames this large (bytes) is handed to the writer at a time: large writes, and
 * small enough that the thread reads it back from the cache. */
#define TB__NPZ_BLOCK_BYTES ((size_t)1 << 20)

typedef struct npz_block {
    size_t count;                  /* frames in it */
    double *parts[TB__NPZ_FLOATS]; /* t, position, orientation, velocity, angular_velocity */
} npz_block;

struct tb__npz_stream {
    int fd;
    size_t body_count, frame_count, block_capacity; /* frames a block holds */
    size_t widths[TB__NPZ_FLOATS];                  /* doubles a frame in each array */
    tb__npy_array arrays[TB__NPZ_FLOATS];
    tb__zip_entry entries[TB__NPZ_MEMBERS];
    char headers[TB__NPZ_FLOATS][TB__NPY_HEADER_MAX];
    size_t header_sizes[TB__NPZ_FLOATS];
    uint64_t data_offsets[TB__NPZ_FLOATS]; /* where each array's data starts in the file */
    uint32_t end_offset;                   /* after the float members */
    npz_block blocks[2];
    int filling; /* the block the caller fills */
    /* owned by whoever writes blocks (the thread while it runs) */
    uint32_t crcs[TB__NPZ_FLOATS]; /* of each member's .npy so far */
    size_t frames_written;
    /* shared with the thread, under lock */
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t changed;
    bool lock_made, thread_started, stop;
    npz_block *handed; /* the block being written, NULL when the writer is idle */
    int error;         /* errno of the first failed write, 0 if none */
    uint64_t error_offset;
};

/* All of size bytes at offset; 0, or the errno of the failure (a disk that takes nothing more
 * without saying why counts as full). */
static int write_at(int fd, const void *data, size_t size, uint64_t offset)
{
    const char *p = data;
    while (size > 0) {
        const ssize_t done = pwrite(fd, p, size, (off_t)offset);
        if (done < 0 && errno == EINTR) {
            continue;
        }
        if (done <= 0) {
            return done < 0 && errno != 0 ? errno : ENOSPC;
        }
        p += done, size -= (size_t)done, offset += (uint64_t)done;
    }
    return 0;
}

/* Each array's slice of the block after the frames already written; 0 or the errno. */
static int write_block(tb__npz_stream *s, const npz_block *b, uint64_t *out_offset)
{
    for (size_t k = 0; k < TB__NPZ_FLOATS; ++k) {
        const size_t frame_bytes = s->widths[k] * sizeof(double);
        const size_t bytes = b->count * frame_bytes;
        const uint64_t offset = s->data_offsets[k] + (uint64_t)s->frames_written * frame_bytes;
        s->crcs[k] = tb__crc32_update(s->crcs[k], b->parts[k], bytes);
        const int error = write_at(s->fd, b->parts[k], bytes, offset);
        if (error != 0) {
            *out_offset = offset;
            return error;
        }
    }
    s->frames_written += b->count;
    return 0;
}

static void *writer_thread(void *context)
{
    tb__npz_stream *s = context;
    pthread_mutex_lock(&s->lock);
    for (;;) {
        while (s->handed == NULL && !s->stop) {
            pthread_cond_wait(&s->changed, &s->lock);
        }
        if (s->handed == NULL) {
            break; /* stopped, nothing left */
        }
        npz_block *block = s->handed;
        const bool skip = s->error != 0; /* after a failure the file is lost anyway */
        pthread_mutex_unlock(&s->lock);
        uint64_t offset = 0;
        const int error = skip ? 0 : write_block(s, block, &offset);
        pthread_mutex_lock(&s->lock);
        if (error != 0) {
            s->error = error;
            s->error_offset = offset;
        }
        s->handed = NULL;
        pthread_cond_broadcast(&s->changed);
    }
    pthread_mutex_unlock(&s->lock);
    return NULL;
}

/* The thread's failure, if any, as the writer's IO_ERROR. Call under lock or after join. */
static tb_status thread_status(tb_writer *w)
{
    const tb__npz_stream *s = w->stream;
    if (s->error == 0) {
        return TB_STATUS_OK;
    }
    w->failed = TB_STATUS_IO_ERROR;
    return tb__set_detail(w->detail, TB_STATUS_IO_ERROR, "%s: write failed: %s (at byte %llu)",
                          w->path, strerror(s->error), (unsigned long long)s->error_offset);
}

/* The filling block to the writer (after the one before it is written); the caller fills the
 * other block next. */
static tb_status hand_over(tb_writer *w)
{
    tb__npz_stream *s = w->stream;
    npz_block *block = &s->blocks[s->filling];
    tb_status status = TB_STATUS_OK;
    if (!s->thread_started) {
        if (s->error == 0) {
            s->error = write_block(s, block, &s->error_offset);
        }
        status = thread_status(w);
    } else {
        pthread_mutex_lock(&s->lock);
        while (s->handed != NULL) {
            pthread_cond_wait(&s->changed, &s->lock);
        }
        status = thread_status(w);
        if (status == TB_STATUS_OK) {
            s->handed = block;
            pthread_cond_broadcast(&s->changed);
        }
        pthread_mutex_unlock(&s->lock);
    }
    s->filling = 1 - s->filling;
    s->blocks[s->filling].count = 0;
    return status;
}

tb_status tb__npz_stream_slot(tb_writer *w, double **out_parts)
{
    tb__npz_stream *s = w->stream;
    if (s->blocks[s->filling].count == s->block_capacity) {
        const tb_status status = hand_over(w);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    const npz_block *b = &s->blocks[s->filling];
    for (size_t k = 0; k < TB__NPZ_FLOATS; ++k) {
        out_parts[k] = b->parts[k] + b->count * s->widths[k];
    }
    return TB_STATUS_OK;
}

void tb__npz_stream_commit(tb_writer *w)
{
    w->stream->blocks[w->stream->filling].count++;
}

/* Where each float member goes, its .npy header, and the CRC of that header to start from. */
static tb_status plan(tb_writer *w, tb__npz_stream *s)
{
    tb__npz_float_arrays(s->frame_count, s->body_count, NULL, s->arrays);
    uint64_t offset = 0;
    for (size_t k = 0; k < TB__NPZ_FLOATS; ++k) {
        size_t head = 0;
        const tb_status status = tb__npz_member_layout(w, &s->arrays[k], (uint32_t)offset,
                                                       &s->entries[k], s->headers[k], &head);
        if (status != TB_STATUS_OK) {
            return status;
        }
        s->header_sizes[k] = head;
        s->crcs[k] = tb__crc32_update(0, s->headers[k], head);
        s->data_offsets[k] = offset + 30 + strlen(s->entries[k].name) + head;
        offset = s->data_offsets[k] + s->arrays[k].data_size;
    }
    s->end_offset = (uint32_t)offset;
    return TB_STATUS_OK;
}

/* Two blocks of block_capacity frames, one allocation each. */
static bool make_blocks(tb__npz_stream *s)
{
    const size_t frame_doubles = 1 + 13 * s->body_count;
    size_t capacity = TB__NPZ_BLOCK_BYTES / (frame_doubles * sizeof(double));
    capacity = capacity < 1 ? 1 : capacity > s->frame_count ? s->frame_count : capacity;
    s->block_capacity = capacity;
    for (int b = 0; b < 2; ++b) {
        double *memory = tb__malloc_array(capacity, frame_doubles * sizeof(double));
        if (memory == NULL) {
            return false;
        }
        for (size_t k = 0; k < TB__NPZ_FLOATS; ++k) {
            s->blocks[b].parts[k] = memory;
            memory += capacity * s->widths[k];
        }
    }
    return true;
}

tb_status tb__npz_stream_open(tb_writer *w, size_t frame_count)
{
    tb__npz_stream *s = calloc(1, sizeof *s);
    if (s == NULL) {
        return tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY, "npz stream");
    }
    w->stream = s;
    s->fd = fileno(w->file);
    s->body_count = w->body_count;
    s->frame_count = frame_count;
    const size_t n = w->body_count, widths[TB__NPZ_FLOATS] = {1, 3 * n, 4 * n, 3 * n, 3 * n};
    memcpy(s->widths, widths, sizeof widths);
    tb_status status = plan(w, s);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (n > SIZE_MAX / 32 / sizeof(double) || !make_blocks(s)) {
        return tb__set_detail(w->detail, TB_STATUS_OUT_OF_MEMORY,
                              "npz stream: two blocks of frames of %zu bodies", n);
    }
    s->lock_made = pthread_mutex_init(&s->lock, NULL) == 0;
    if (s->lock_made && pthread_cond_init(&s->changed, NULL) != 0) {
        pthread_mutex_destroy(&s->lock);
        s->lock_made = false;
    }
    /* without a lock or a thread, the caller's thread writes the blocks */
    s->thread_started = s->lock_made && pthread_create(&s->thread, NULL, writer_thread, s) == 0;
    return TB_STATUS_OK;
}

/* Stops the writer after the block it holds; its status. */
static tb_status stop_thread(tb_writer *w)
{
    tb__npz_stream *s = w->stream;
    if (s->thread_started) {
        pthread_mutex_lock(&s->lock);
        s->stop = true;
        pthread_cond_broadcast(&s->changed);
        pthread_mutex_unlock(&s->lock);
        pthread_join(s->thread, NULL);
        s->thread_started = false;
    }
    return thread_status(w);
}

tb_status tb__npz_stream_finish(tb_writer *w)
{
    tb__npz_stream *s = w->stream;
    tb_status status = s->blocks[s->filling].count > 0 ? hand_over(w) : TB_STATUS_OK;
    const tb_status stopped = stop_thread(w);
    status = status != TB_STATUS_OK ? status : stopped;
    for (size_t k = 0; k < TB__NPZ_FLOATS && status == TB_STATUS_OK; ++k) {
        s->entries[k].crc = s->crcs[k];
        errno = 0;
        status = fseeko(w->file, (off_t)s->entries[k].offset, SEEK_SET) == 0
                     ? tb__npz_write_head(w, &s->entries[k], s->headers[k], s->header_sizes[k])
                     : tb__writer_io_failure(w, "seek failed");
    }
    errno = 0;
    if (status == TB_STATUS_OK && fseeko(w->file, (off_t)s->end_offset, SEEK_SET) != 0) {
        status = tb__writer_io_failure(w, "seek failed");
    }
    return status == TB_STATUS_OK ? tb__npz_write_tail(w, s->entries, s->end_offset) : status;
}

void tb__npz_stream_free(tb__npz_stream *s)
{
    if (s == NULL) {
        return;
    }
    if (s->thread_started) {
        pthread_mutex_lock(&s->lock);
        s->stop = true;
        pthread_cond_broadcast(&s->changed);
        pthread_mutex_unlock(&s->lock);
        pthread_join(s->thread, NULL);
    }
    if (s->lock_made) {
        pthread_mutex_destroy(&s->lock);
        pthread_cond_destroy(&s->changed);
    }
    free(s->blocks[0].parts[0]);
    free(s->blocks[1].parts[0]);
    free(s);
}
