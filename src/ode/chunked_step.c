/* Fixed-step methods on separable systems (tb_ode_system.blocks.size): each step finishes a
 * cache-sized chunk of blocks at a time, every stage, the hook and the finiteness check of a
 * chunk while it is in cache; in the system's lane layout when it has one
 * (tb_ode_system.blocks.lanes), so that the arithmetic runs across blocks in the vector unit; and
 * the chunks shared among threads. A chunk is always the same blocks, whatever the thread count,
 * and each block's arithmetic is its own, so the result is the same bits for any thread count. */
#include "ode/integrator.h"

#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

/* Components in one chunk without lanes (9 bodies of 13). The chunk's buffers (state, stage
 * derivative, stage input, new state) stay in L1 whatever the chunk; smaller chunks left less of
 * the next chunk's memory traffic unhidden. Measured with RK4 at 100000 bodies
 * (bench_throughput): 95, 100, 107, 110 ns a body-step for 128, 256, 512, 1024 doubles, against
 * 81-84 ns at 1000 bodies for all four. */
#define TB__CHUNK_DOUBLES 128

/* Buffers a thread needs per chunk: the chunk in the lane layout and the new chunk (lanes
 * only), the stepper's two of scratch; without lanes the new chunk and the scratch. */
#define TB__CHUNK_BUFFERS 4

/* Chunks a thread must have for a step to be shared out: below that, starting and joining the
 * threads (microseconds, far more on a loaded machine) costs more than the thread saves. 8
 * lane groups are 256 bodies. */
#define TB__CHUNKS_PER_THREAD 8

/* The most threads a step is shared among. */
#define TB__MAX_THREADS 256

void tb__chunk_layout(tb_integrator *integrator, int threads)
{
    const tb_ode_system *system = &integrator->system;
    const size_t blocks = system->n / system->blocks.size;
    size_t per_chunk = system->blocks.lanes;
    if (per_chunk == 0) {
        per_chunk = TB__CHUNK_DOUBLES / system->blocks.size;
        per_chunk = per_chunk == 0 ? 1 : per_chunk < blocks ? per_chunk : blocks;
    }
    integrator->chunk_blocks = per_chunk;
    /* a whole number of cache lines */
    const size_t per_line = TB__LINE / sizeof(double);
    integrator->chunk_work =
        (TB__CHUNK_BUFFERS * per_chunk * system->blocks.size + per_line - 1) / per_line * per_line;
#ifdef _OPENMP
    if (threads == 0) {
        threads = omp_get_num_procs();
    }
#endif
    const size_t chunks = (blocks + per_chunk - 1) / per_chunk;
    /* no more threads than have TB__CHUNKS_PER_THREAD chunks each, nor than the library was
     * built to start */
    size_t count = threads < 1 ? 1 : (size_t)threads;
#ifndef _OPENMP
    count = 1;
#endif
    const size_t worth = chunks / TB__CHUNKS_PER_THREAD;
    count = count < worth ? count : worth;
    count = count < TB__MAX_THREADS ? count : TB__MAX_THREADS;
    integrator->threads = count < 1 ? 1 : (int)count;
}

/* A chunk of a separable system seen as a system of its own, for the steppers. */
typedef struct chunk {
    const tb_ode_system *system;
    size_t first_block, block_count;
} chunk;

static int chunk_derivative(double t, const double *y, double *dydt, void *ctx)
{
    const chunk *c = ctx;
    return c->system->blocks.derivative(t, y, dydt, c->first_block, c->block_count, c->system->ctx);
}

static int chunk_hook(double t, double *y, void *ctx)
{
    const chunk *c = ctx;
    return c->system->blocks.post_step(t, y, c->first_block, c->block_count, c->system->ctx);
}

static int lanes_derivative(double t, const double *y, double *dydt, void *ctx)
{
    const chunk *c = ctx;
    return c->system->blocks.lanes_derivative(t, y, dydt, c->first_block, c->block_count,
                                              c->system->ctx);
}

static int lanes_hook(double t, double *y, void *ctx)
{
    const chunk *c = ctx;
    return c->system->blocks.lanes_post_step(t, y, c->first_block, c->block_count, c->system->ctx);
}

/* count blocks of size components from y into the lane layout of `lanes` blocks, the lanes past
 * count filled with the last block. Component by component: the stores run along a row. */
TB__CLONES static void to_lanes(const double *restrict y, double *restrict out, size_t size,
                                size_t count, size_t lanes)
{
    for (size_t c = 0; c < size; ++c) {
        double *row = out + c * lanes;
        for (size_t j = 0; j < count; ++j) {
            row[j] = y[size * j + c];
        }
        for (size_t j = count; j < lanes; ++j) {
            row[j] = y[size * (count - 1) + c];
        }
    }
}

/* The first count blocks of a lane group back into blocks of size components at y. */
TB__CLONES static void from_lanes(const double *restrict group, double *restrict y, size_t size,
                                  size_t count, size_t lanes)
{
    for (size_t c = 0; c < size; ++c) {
        const double *row = group + c * lanes;
        for (size_t j = 0; j < count; ++j) {
            y[size * j + c] = row[j];
        }
    }
}

/* The first non-finite component of a lane group's real blocks, counted as in the blocks'
 * own layout; size * count if none (the padding lanes are copies of a real one). */
static size_t lanes_first_non_finite(const double *group, size_t size, size_t count, size_t lanes)
{
    if (tb__first_non_finite(group, size * lanes) == size * lanes) {
        return size * count;
    }
    for (size_t j = 0; j < count; ++j) {
        for (size_t c = 0; c < size; ++c) {
            if (!(group[c * lanes + j] - group[c * lanes + j] == 0.0)) {
                return size * j + c;
            }
        }
    }
    return size * count;
}

/* Asks for y[from, to) ahead of use, one request per 64-byte line, so that the next chunk
 * arrives from memory while this one is computed (measured: RK4 at 100000 bodies 136 -> 95 ns
 * a body-step). */
static void prefetch(const double *y, size_t from, size_t to)
{
#if defined(__GNUC__) || defined(__clang__)
    for (size_t i = from; i < to; i += 8) {
        __builtin_prefetch(y + i, 0, 3);
    }
#else
    (void)y, (void)from, (void)to;
#endif
}

/* What one thread does in a step: its chunks in order, each written into y once it succeeded
 * (its old values kept in before), until the first failure. */
typedef struct thread_range {
    _Alignas(64) size_t first_chunk; /* a cache line each: threads write only their own */
    size_t end_chunk;
    size_t written; /* components of y replaced, from the range's first */
    long evals;     /* the stages of one chunk */
    tb__step_failure failure;
} thread_range;

/* Steps the blocks [first, first + count), at y + offset, into the lane layout or into fresh;
 * work: TB__CHUNK_BUFFERS chunks. Returns where the new chunk is. */
static const double *step_chunk(const tb_integrator *integrator, size_t first, size_t count,
                                double *work, double h, double t_last, double t_end,
                                thread_range *range)
{
    const tb_ode_system *system = &integrator->system;
    const size_t size = system->blocks.size, offset = first * size;
    const size_t lanes = system->blocks.lanes, length = (lanes > 0 ? lanes : count) * size;
    double *input = work, *fresh = work + length, *scratch = work + 2 * length;
    chunk c = {system, first, count};
    tb_ode_system part = {.n = length, .ctx = &c};
    const double *y = integrator->y + offset;
    if (lanes > 0) {
        to_lanes(y, input, size, count, lanes);
        y = input;
        part.derivative = lanes_derivative;
        part.post_step = system->post_step != NULL ? lanes_hook : NULL;
    } else {
        part.derivative = chunk_derivative;
        part.post_step = system->post_step != NULL ? chunk_hook : NULL; /* block_post_step set */
    }
    long evals = 0;
    tb__step_failure *failure = &range->failure;
    int rc = integrator->entry->step(&part, integrator->t, h, t_last, y, fresh, scratch, &evals);
    range->evals = evals;
    if (rc != 0) {
        *failure = (tb__step_failure){TB_STATUS_DERIVATIVE_FAILED, rc, 0, 0, 0.0};
        return fresh;
    }
    rc = part.post_step != NULL ? part.post_step(t_end, fresh, part.ctx) : 0;
    if (rc != 0) {
        *failure = (tb__step_failure){TB_STATUS_HOOK_FAILED, rc, rc, 0, 0.0};
    }
    const size_t bad = lanes > 0 ? lanes_first_non_finite(fresh, size, count, lanes)
                                 : tb__first_non_finite(fresh, length);
    if (bad < size * count) {
        const size_t lane = bad / size, component = bad % size;
        const double value = lanes > 0 ? fresh[component * lanes + lane] : fresh[bad];
        *failure = (tb__step_failure){TB_STATUS_STATE_NOT_FINITE, 0, rc, offset + bad, value};
    }
    return fresh;
}

/* One thread's chunks; work: its TB__CHUNK_BUFFERS chunks. */
static void step_range(const tb_integrator *integrator, double *work, double h, double t_last,
                       double t_end, thread_range *range)
{
    const tb_ode_system *system = &integrator->system;
    const size_t size = system->blocks.size, blocks = system->n / size;
    const size_t per_chunk = integrator->chunk_blocks;
    double *y = integrator->y, *before = integrator->y_new;
    range->written = 0;
    range->failure.status = TB_STATUS_OK;
    for (size_t k = range->first_chunk; k < range->end_chunk; ++k) {
        const size_t first = k * per_chunk;
        const size_t count = blocks - first < per_chunk ? blocks - first : per_chunk;
        const size_t offset = first * size, length = count * size;
        prefetch(y, offset + length,
                 offset + 2 * length < system->n ? offset + 2 * length : system->n);
        const double *fresh = step_chunk(integrator, first, count, work, h, t_last, t_end, range);
        if (range->failure.status != TB_STATUS_OK) {
            return;
        }
        memcpy(before + offset, y + offset, length * sizeof(double));
        if (system->blocks.lanes > 0) {
            from_lanes(fresh, y + offset, size, count, system->blocks.lanes);
        } else {
            memcpy(y + offset, fresh, length * sizeof(double));
        }
        range->written += length;
    }
}

tb_status tb__take_chunked_step(tb_integrator *integrator, double h, double t_last, double t_end)
{
    const tb_ode_system *system = &integrator->system;
    const size_t blocks = system->n / system->blocks.size, per_chunk = integrator->chunk_blocks;
    const size_t chunks = (blocks + per_chunk - 1) / per_chunk;
    const int threads =
        integrator->threads < TB__MAX_THREADS ? integrator->threads : TB__MAX_THREADS;
    thread_range ranges[TB__MAX_THREADS];
    for (int k = 0; k < threads; ++k) {
        ranges[k].first_chunk = chunks * (size_t)k / (size_t)threads;
        ranges[k].end_chunk = chunks * (size_t)(k + 1) / (size_t)threads;
    }
    if (threads == 1) {
        step_range(integrator, integrator->work, h, t_last, t_end, &ranges[0]);
    } else {
#ifdef _OPENMP
#pragma omp parallel for schedule(static, 1) num_threads(threads)
#endif
        for (int k = 0; k < threads; ++k) {
            step_range(integrator, integrator->work + (size_t)k * integrator->chunk_work, h, t_last,
                       t_end, &ranges[k]);
        }
    }
    /* the first failure in block order is the one reported; every chunk written is undone */
    const thread_range *failed = NULL;
    for (int k = 0; k < threads && failed == NULL; ++k) {
        failed = ranges[k].failure.status != TB_STATUS_OK ? &ranges[k] : NULL;
    }
    integrator->stats.derivative_evals += (failed != NULL ? failed : &ranges[0])->evals;
    if (failed == NULL) {
        return TB_STATUS_OK;
    }
    for (int k = 0; k < threads; ++k) {
        const size_t offset = ranges[k].first_chunk * per_chunk * system->blocks.size;
        memcpy(integrator->y + offset, integrator->y_new + offset,
               ranges[k].written * sizeof(double));
    }
    return tb__fixed_report(integrator, &failed->failure, h, t_end);
}
