/* The scene file's "keys" and "interpolation" (src/io/scene_file_keys.c): an inline body parsed
 * with jansson gives the keys written in it, and each bad input is refused naming the body, the
 * key's index and the field. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "io/scene_file_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct parsed {
    tb_status status;
    tb_error error;
    tb_body_key *keys;
    size_t count;
    tb_interpolation interpolation;
} parsed;

static parsed parse(const char *json)
{
    json_error_t syntax;
    json_t *body = json_loads(json, 0, &syntax);
    if (body == NULL) {
        print_error("test JSON: %s\n", syntax.text);
    }
    assert_non_null(body);
    parsed p = {.keys = NULL, .count = 99, .interpolation = (tb_interpolation)99};
    tb__loader ld = {.name = "scene.json", .error = &p.error};
    p.status = tb__load_keys(&ld, body, "bodies[1]", &p.keys, &p.count, &p.interpolation);
    json_decref(body);
    return p;
}

static void assert_doubles(const double *actual, const double *expected, size_t n)
{
    assert_memory_equal(actual, expected, n * sizeof(double));
}

/* The paddle, plus a third key with an angular velocity: every number as written. */
static void test_keys_are_read_as_written(void **state)
{
    (void)state;
    parsed p = parse("{\"interpolation\": \"cubic\", \"keys\": ["
                     "{\"t\": 0, \"position\": [0, -1, 0.2], \"orientation\": [1, 0, 0, 0]},"
                     "{\"t\": 0.5, \"position\": [0, 1, 0.2], \"orientation\": [1, 0, 0, 0],"
                     " \"velocity\": [0, 4, 0]},"
                     "{\"t\": 1.25, \"position\": [1, 2, 3], \"orientation\": [0, 0, 0, 2],"
                     " \"angular_velocity\": [0.5, 0, -7]}]}");
    assert_int_equal(p.status, TB_STATUS_OK);
    assert_int_equal(p.count, 3);
    assert_int_equal(p.interpolation, TB_INTERPOLATION_CUBIC);
    const double times[3] = {0, 0.5, 1.25};
    const double positions[3][3] = {{0, -1, 0.2}, {0, 1, 0.2}, {1, 2, 3}};
    const double orientations[3][4] = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0, 0, 0, 2}};
    for (size_t k = 0; k < 3; ++k) {
        assert_doubles(&p.keys[k].t, &times[k], 1);
        assert_doubles(p.keys[k].position, positions[k], 3);
        assert_doubles(p.keys[k].orientation, orientations[k], 4);
        assert_int_equal(p.keys[k].has_velocity, k == 1);
        assert_int_equal(p.keys[k].has_angular_velocity, k == 2);
    }
    assert_doubles(p.keys[1].velocity, (const double[3]){0, 4, 0}, 3);
    assert_doubles(p.keys[2].angular_velocity, (const double[3]){0.5, 0, -7}, 3);
    free(p.keys);
}

/* Without "interpolation" the curve is cubic; names are read ignoring case. */
static void test_interpolation_defaults_to_cubic_and_ignores_case(void **state)
{
    (void)state;
    static const char *const bodies[] = {
        "{\"keys\": [{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}]}",
        "{\"interpolation\": \"Linear\", \"keys\": [{\"t\": 0, \"position\": [0, 0, 0], "
        "\"orientation\": [1, 0, 0, 0]}]}",
        "{\"interpolation\": \"step\", \"keys\": [{\"t\": 0, \"position\": [0, 0, 0], "
        "\"orientation\": [1, 0, 0, 0]}]}",
    };
    const tb_interpolation expected[] = {TB_INTERPOLATION_CUBIC, TB_INTERPOLATION_LINEAR,
                                         TB_INTERPOLATION_STEP};
    for (int k = 0; k < 3; ++k) {
        parsed p = parse(bodies[k]);
        assert_int_equal(p.status, TB_STATUS_OK);
        assert_int_equal(p.interpolation, expected[k]);
        assert_int_equal(p.count, 1);
        free(p.keys);
    }
}

#define KEY0 "{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}"

/* One row per bad input: the body and what the message must say (after "scene.json: "). */
static const struct {
    const char *body;
    const char *message;
} bad_bodies[] = {
    {"{}", "bodies[1].keys: must be a non-empty array of {t, position, orientation}, got nothing"},
    {"{\"keys\": []}", "bodies[1].keys: must be a non-empty array"},
    {"{\"keys\": {\"t\": 0}}", "bodies[1].keys: must be a non-empty array"},
    {"{\"keys\": [" KEY0 ", 3]}", "bodies[1].keys[1]: must be an object, got a number"},
    {"{\"keys\": [" KEY0 ", {\"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}]}",
     "bodies[1].keys[1].t: missing"},
    {"{\"keys\": [{\"t\": 0, \"position\": [0, 0], \"orientation\": [1, 0, 0, 0]}]}",
     "bodies[1].keys[0].position: must be an array of 3 numbers"},
    {"{\"keys\": [{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, \"x\", 0]}]}",
     "bodies[1].keys[0].orientation[2]: must be a number, got a string"},
    {"{\"keys\": [{\"t\": 0, \"position\": [0, 0, 0]}]}", "bodies[1].keys[0].orientation: missing"},
    {"{\"keys\": [{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0], "
     "\"rotation\": 1}]}",
     "bodies[1].keys[0].rotation: unknown key"},
    {"{\"keys\": [" KEY0 ", " KEY0 "]}", "bodies[1].keys[1].t: must be > keys[0].t = 0, got 0"},
    {"{\"keys\": [" KEY0 ", {\"t\": 1, \"position\": [0, 0, 0], \"orientation\": [0, 0, 0, 0]}]}",
     "bodies[1].keys[1].orientation: must be a nonzero quaternion"},
    {"{\"interpolation\": \"linear\", \"keys\": [{\"t\": 0, \"position\": [0, 0, 0], "
     "\"orientation\": [1, 0, 0, 0], \"velocity\": [1, 0, 0]}]}",
     "bodies[1].keys[0].velocity: only cubic interpolation reads it (this curve is linear)"},
    {"{\"keys\": [{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0], "
     "\"angular_velocity\": null}]}",
     "bodies[1].keys[0].angular_velocity: must be an array of 3 numbers, got null"},
    {"{\"interpolation\": \"spline\", \"keys\": [" KEY0 "]}",
     "bodies[1].interpolation: unknown interpolation \"spline\"; interpolations: linear, cubic, "
     "step"},
    {"{\"interpolation\": 3, \"keys\": [" KEY0 "]}",
     "bodies[1].interpolation: must be a string, got a number"},
};

/* BAD_SCENE, the message naming the place, and the outputs untouched. */
static void test_bad_keys_are_refused_naming_the_key_and_field(void **state)
{
    (void)state;
    for (size_t r = 0; r < sizeof bad_bodies / sizeof bad_bodies[0]; ++r) {
        parsed p = parse(bad_bodies[r].body);
        print_message("%s\n", p.error.message);
        assert_int_equal(p.status, TB_STATUS_BAD_SCENE);
        assert_int_equal(p.error.status, TB_STATUS_BAD_SCENE);
        assert_memory_equal(p.error.message, "scene.json: ", strlen("scene.json: "));
        assert_non_null(strstr(p.error.message, bad_bodies[r].message));
        assert_null(p.keys);
        assert_int_equal(p.count, 99);
        assert_int_equal(p.interpolation, 99);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keys_are_read_as_written),
        cmocka_unit_test(test_interpolation_defaults_to_cubic_and_ignores_case),
        cmocka_unit_test(test_bad_keys_are_refused_naming_the_key_and_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
