#include "span.h"

#include <stdlib.h>
#include <string.h>

bool tb_test_short(void)
{
    const char *value = getenv("TUMBLE_TEST_SHORT");
    return value != NULL && value[0] != '\0' && strcmp(value, "0") != 0;
}

double tb_test_span(double full, double short_span)
{
    return tb_test_short() ? short_span : full;
}
