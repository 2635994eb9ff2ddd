/* Private: the shared validators. Each checks one input and, when it is bad, writes a detail
 * naming the input (`what`) and its value into detail (TB_DETAIL_SIZE bytes, may be NULL) and
 * returns the status every entry point gives that kind of bad input: a NULL required pointer
 * TB_STATUS_NULL_POINTER, NaN or infinity TB_STATUS_NOT_FINITE, a finite value outside its
 * domain TB_STATUS_INVALID_ARGUMENT, an id past the count TB_STATUS_OUT_OF_RANGE. */
#ifndef TUMBLE_VALIDATE_H
#define TUMBLE_VALIDATE_H

#include "tumble/status.h"

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
/* a * b without overflowing size_t, into *out */
tb_status tb__validate_size_product(char *detail, size_t a, size_t b, const char *what,
                                    size_t *out);

#endif
