/* Private: the shared validators. Each checks one input and, when it is bad, writes a detail
 * naming the input (`what`) and its value into detail (TB_DETAIL_SIZE bytes, may be NULL) and
 * returns the status every entry point gives that kind of bad input: a NULL required pointer
 * TB_STATUS_NULL_POINTER, NaN or infinity TB_STATUS_NOT_FINITE, a finite value outside its
 * domain TB_STATUS_INVALID_ARGUMENT, an id past the count TB_STATUS_OUT_OF_RANGE. */
#ifndef TUMBLE_VALIDATE_H
#define TUMBLE_VALIDATE_H

#include "tumble/status.h"

#include <stdbool.h>
#include <stddef.h>

tb_status tb__validate_pointer(char *detail, const void *pointer, const char *what);
tb_status tb__validate_finite(char *detail, double value, const char *what);
/* finite and >= 0 */
tb_status tb__validate_nonnegative(char *detail, double value, const char *what);
/* finite and > 0 */
tb_status tb__validate_positive(char *detail, double value, const char *what);
/* non-NULL, three finite numbers */
tb_status tb__validate_vector(char *detail, const double *v, const char *what);
/* index < count; `counted` names what count counts ("bodies") */
tb_status tb__validate_index(char *detail, size_t index, size_t count, const char *what,
                             const char *counted);
/* The one checked multiply: every size computed from a caller's count (a byte count for an
 * allocation, a number of doubles) goes through it or through the wrappers below. a * b into
 * *out, or false (and *out untouched) when the product does not fit in size_t. */
bool tb__size_product(size_t a, size_t b, size_t *out);
/* tb__size_product for an entry point: TB_STATUS_OUT_OF_MEMORY with a detail naming `what`
 * when a * b does not fit */
tb_status tb__validate_size_product(char *detail, size_t a, size_t b, const char *what,
                                    size_t *out);
/* malloc and realloc of count items of size bytes each: NULL (and, for realloc, p untouched)
 * when count * size does not fit in size_t, as when the memory is not there. (calloc checks
 * its own product.) */
void *tb__malloc_array(size_t count, size_t size);
void *tb__realloc_array(void *p, size_t count, size_t size);
/* A growing array *data of *capacity items of size bytes: room for needed items, the capacity
 * at least doubled when it grows (so n pushes cost O(n)); false when memory runs out (then
 * *data and *capacity are as they were). */
bool tb__grow_array(void **data, size_t *capacity, size_t needed, size_t size);
/* Names equal ignoring ASCII case, for the name tables (methods, interpolations); strcasecmp is
 * POSIX, not C11, and follows the locale. */
bool tb__same_name(const char *a, const char *b);

#endif
