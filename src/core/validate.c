/* The shared validators (see validate.h): one place decides which status a kind of bad input
 * gets and how its detail reads. */
#include "core/validate.h"

#include "core/detail.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

tb_status tb__validate_pointer(char *detail, const void *pointer, const char *what)
{
    if (pointer == NULL) {
        return tb__set_detail(detail, TB_STATUS_NULL_POINTER, "%s is NULL", what);
    }
    return TB_STATUS_OK;
}

tb_status tb__validate_finite(char *detail, double value, const char *what)
{
    if (!isfinite(value)) {
        return tb__set_detail(detail, TB_STATUS_NOT_FINITE, "%s: must be finite, got %g", what,
                              value);
    }
    return TB_STATUS_OK;
}

tb_status tb__validate_nonnegative(char *detail, double value, const char *what)
{
    if (!isfinite(value)) {
        return tb__set_detail(detail, TB_STATUS_NOT_FINITE, "%s: must be finite and >= 0, got %g",
                              what, value);
    }
    if (value < 0) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "%s: must be finite and >= 0, got %g", what, value);
    }
    return TB_STATUS_OK;
}

tb_status tb__validate_positive(char *detail, double value, const char *what)
{
    if (!isfinite(value)) {
        return tb__set_detail(detail, TB_STATUS_NOT_FINITE, "%s: must be finite and > 0, got %g",
                              what, value);
    }
    if (!(value > 0)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "%s: must be finite and > 0, got %g", what, value);
    }
    return TB_STATUS_OK;
}

tb_status tb__validate_vector(char *detail, const double *v, const char *what)
{
    if (v == NULL) {
        return tb__set_detail(detail, TB_STATUS_NULL_POINTER, "%s is NULL", what);
    }
    if (!isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2])) {
        return tb__set_detail(detail, TB_STATUS_NOT_FINITE,
                              "%s: contains NaN or infinity (%g, %g, %g)", what, v[0], v[1], v[2]);
    }
    return TB_STATUS_OK;
}

tb_status tb__validate_index(char *detail, size_t index, size_t count, const char *what,
                             const char *counted)
{
    if (index >= count) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_RANGE, "%s: id %zu out of range (%zu %s)",
                              what, index, count, counted);
    }
    return TB_STATUS_OK;
}

bool tb__size_product(size_t a, size_t b, size_t *out)
{
    if (b != 0 && a > SIZE_MAX / b) {
        return false;
    }
    *out = a * b;
    return true;
}

tb_status tb__validate_size_product(char *detail, size_t a, size_t b, const char *what, size_t *out)
{
    if (!tb__size_product(a, b, out)) {
        return tb__set_detail(detail, TB_STATUS_OUT_OF_MEMORY,
                              "%s: %zu x %zu bytes is more than the address space", what, a, b);
    }
    return TB_STATUS_OK;
}

void *tb__malloc_array(size_t count, size_t size)
{
    size_t bytes;
    return tb__size_product(count, size, &bytes) ? malloc(bytes) : NULL;
}

void *tb__realloc_array(void *p, size_t count, size_t size)
{
    size_t bytes;
    return tb__size_product(count, size, &bytes) ? realloc(p, bytes) : NULL;
}

bool tb__grow_array(void **data, size_t *capacity, size_t needed, size_t size)
{
    if (needed <= *capacity) {
        return true;
    }
    const size_t next = needed > 2 * *capacity ? needed : 2 * *capacity;
    void *grown = tb__realloc_array(*data, next, size);
    if (grown == NULL) {
        return false;
    }
    *data = grown;
    *capacity = next;
    return true;
}

bool tb__same_name(const char *a, const char *b)
{
    for (;; ++a, ++b) {
        const int ca = *a >= 'A' && *a <= 'Z' ? *a - 'A' + 'a' : *a;
        const int cb = *b >= 'A' && *b <= 'Z' ? *b - 'A' + 'a' : *b;
        if (ca != cb) {
            return false;
        }
        if (ca == '\0') {
            return true;
        }
    }
}
