/* Status codes: one list gives names and messages, so every code has both and no two codes
 * share a value or a name. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/status.h"

#include <string.h>

static const tb_status all_statuses[] = {
#define AS_VALUE(name, value, message) TB_STATUS_##name,
    TB_STATUS_LIST(AS_VALUE)
#undef AS_VALUE
};
#define STATUS_COUNT (sizeof all_statuses / sizeof all_statuses[0])

static void test_every_status_has_a_distinct_name_and_message(void **state)
{
    (void)state;
    for (size_t i = 0; i < STATUS_COUNT; ++i) {
        const char *name = tb_status_name(all_statuses[i]);
        const char *message = tb_status_string(all_statuses[i]);
        assert_string_not_equal(name, "UNKNOWN");
        assert_string_not_equal(message, "unknown status");
        for (size_t j = 0; j < i; ++j) {
            assert_int_not_equal(all_statuses[i], all_statuses[j]);
            assert_string_not_equal(name, tb_status_name(all_statuses[j]));
            assert_string_not_equal(message, tb_status_string(all_statuses[j]));
        }
    }
}

static void test_success_is_zero_and_errors_are_negative(void **state)
{
    (void)state;
    assert_int_equal(TB_STATUS_OK, 0);
    assert_string_equal(tb_status_name(TB_STATUS_OK), "OK");
    for (size_t i = 1; i < STATUS_COUNT; ++i) {
        assert_true(all_statuses[i] < 0);
    }
}

static void test_unknown_status_is_named_as_unknown(void **state)
{
    (void)state;
    assert_string_equal(tb_status_name((tb_status)-999), "UNKNOWN");
    assert_string_equal(tb_status_string((tb_status)42), "unknown status");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_status_has_a_distinct_name_and_message),
        cmocka_unit_test(test_success_is_zero_and_errors_are_negative),
        cmocka_unit_test(test_unknown_status_is_named_as_unknown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
