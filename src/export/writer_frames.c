/* Writers: what a frame holds per body, and the frames kept for the formats written at close. */
#include "export/writer_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <stdlib.h>
#include <string.h>

tb_status tb__frames_init(tb__frames *frames, size_t body_count)
{
    memset(frames, 0, sizeof *frames);
    frames->body_count = body_count;
    return TB_STATUS_OK;
}

static bool grow(double **array, size_t per_frame, size_t capacity)
{
    size_t doubles = 0;
    double *grown = tb__size_product(capacity, per_frame, &doubles)
                        ? tb__realloc_array(*array, doubles, sizeof(double))
                        : NULL;
    if (grown != NULL) {
        *array = grown;
    }
    return grown != NULL;
}

/* Room for one more frame; the arrays double, so appending costs O(1) amortised. */
static tb_status reserve(tb__frames *f)
{
    if (f->count < f->capacity) {
        return TB_STATUS_OK;
    }
    const size_t capacity = f->capacity < 16 ? 16 : 2 * f->capacity;
    const size_t n = f->body_count;
    if (capacity > SIZE_MAX / (4 * sizeof(double) * (n > 0 ? n : 1))) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    /* each grow keeps the old array on failure, so a failed reserve loses nothing */
    const bool grown = grow(&f->t, 1, capacity) && grow(&f->position, 3 * n, capacity) &&
                       grow(&f->orientation, 4 * n, capacity) &&
                       grow(&f->velocity, 3 * n, capacity) &&
                       grow(&f->angular_velocity, 3 * n, capacity);
    if (!grown) {
        return TB_STATUS_OUT_OF_MEMORY;
    }
    f->capacity = capacity;
    return TB_STATUS_OK;
}

tb_status tb__frames_slot(tb__frames *f, double **out_parts)
{
    const tb_status status = reserve(f);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const size_t n = f->body_count, k = f->count;
    out_parts[0] = f->t + k;
    out_parts[1] = f->position + 3 * n * k;
    out_parts[2] = f->orientation + 4 * n * k;
    out_parts[3] = f->velocity + 3 * n * k;
    out_parts[4] = f->angular_velocity + 3 * n * k;
    return TB_STATUS_OK;
}

void tb__frames_free(tb__frames *f)
{
    free(f->t);
    free(f->position);
    free(f->orientation);
    free(f->velocity);
    free(f->angular_velocity);
    memset(f, 0, sizeof *f);
}
