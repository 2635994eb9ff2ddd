/* Private: writing detail messages. Every error path goes through these so a message always
 * travels with its status. */
#ifndef TUMBLE_DETAIL_H
#define TUMBLE_DETAIL_H

#include "tumble/status.h"

#include <stdarg.h>

#if defined(__GNUC__) || defined(__clang__)
#define TB__PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define TB__PRINTF(fmt, args)
#endif

/* Formats into a TB_DETAIL_SIZE buffer (which may be NULL) and returns status. */
tb_status tb__set_detail(char *detail, tb_status status, const char *format, ...) TB__PRINTF(3, 4);
tb_status tb__vformat_detail(char *detail, tb_status status, const char *format, va_list args);

/* value with the fewest significant digits (1 to 17) that read back as it, into out (room for
 * 32): what was typed (a subnormal 1e-320 is "1e-320", where %g gives "9.99989e-321"), every
 * digit a value needs (1.0000001). Returns out. */
const char *tb__shortest(double value, char *out);

/* Fills a tb_error (which may be NULL) and returns status. */
tb_status tb__set_error(tb_error *error, tb_status status, const char *format, ...)
    TB__PRINTF(3, 4);
void tb__clear_error(tb_error *error);

#endif
