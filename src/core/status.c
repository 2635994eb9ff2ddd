#include "tumble/status.h"

#include "core/detail.h"
#include "tumble/version.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

const char *tb_version(void)
{
    return TB_VERSION_STRING;
}

const char *tb_status_string(tb_status status)
{
    switch (status) {
#define TB__STATUS_MESSAGE(name, value, message)                                                   \
    case TB_STATUS_##name:                                                                         \
        return message;
        TB_STATUS_LIST(TB__STATUS_MESSAGE)
#undef TB__STATUS_MESSAGE
    }
    return "unknown status";
}

const char *tb_status_name(tb_status status)
{
    switch (status) {
#define TB__STATUS_NAME(name, value, message)                                                      \
    case TB_STATUS_##name:                                                                         \
        return #name;
        TB_STATUS_LIST(TB__STATUS_NAME)
#undef TB__STATUS_NAME
    }
    return "UNKNOWN";
}

tb_status tb__vformat_detail(char *detail, tb_status status, const char *format, va_list args)
{
    if (detail != NULL) {
        vsnprintf(detail, TB_DETAIL_SIZE, format, args);
    }
    return status;
}

tb_status tb__set_detail(char *detail, tb_status status, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    tb__vformat_detail(detail, status, format, args);
    va_end(args);
    return status;
}

tb_status tb__set_error(tb_error *error, tb_status status, const char *format, ...)
{
    if (error != NULL) {
        error->status = status;
        va_list args;
        va_start(args, format);
        tb__vformat_detail(error->message, status, format, args);
        va_end(args);
    }
    return status;
}

void tb__clear_error(tb_error *error)
{
    if (error != NULL) {
        error->status = TB_STATUS_OK;
        error->message[0] = '\0';
    }
}

const char *tb__shortest(double value, char *out)
{
    for (int digits = 1; digits <= 17; ++digits) {
        snprintf(out, 32, "%.*g", digits, value);
        if (strtod(out, NULL) == value) {
            return out;
        }
    }
    return out; /* NaN: "nan" */
}
