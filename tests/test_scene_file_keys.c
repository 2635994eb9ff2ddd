/* The scene file's "keys" and "interpolation" (src/io/scene_file_keys.c): an inline body parsed
 * with jansson gives the keys written in it, and each bad input is refused naming the body, the
 * key's index and the field; a keyframed body loaded from a scene file follows those keys, and
 * the loader refuses a keyframed body's misplaced fields naming the body. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "io/scene_file_internal.h"
#include "tumble/tumble.h"

#include <math.h>
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

/* A scene file's keyframed body: a paddle turning about z while it moves, on a cubic curve
 * whose middle key gives its velocity and angular velocity, beside a dynamic ball. */
#define PADDLE_KEYS                                                                                \
    "[{\"t\": 0, \"position\": [0, -1, 0.2], \"orientation\": [1, 0, 0, 0]},"                      \
    " {\"t\": 0.5, \"position\": [0, 1, 0.2], \"orientation\": [0.9238795325112867, 0, 0, "        \
    "0.3826834323650898], \"velocity\": [0, 4, 0], \"angular_velocity\": [0, 0, 1.5]},"            \
    " {\"t\": 1.25, \"position\": [1, 2, 3], \"orientation\": [0.7071067811865476, 0, 0, "         \
    "0.7071067811865476]}]"
#define BALL_BODY                                                                                  \
    "{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1, "       \
    "\"position\": [5, 5, 5]}"

static const char paddle_scene[] =
    "{\"bodies\": [" BALL_BODY ", {\"name\": \"paddle\", \"motion\": \"keyframed\", "
    "\"shape\": {\"type\": \"box\", \"size\": [0.4, 0.05, 0.3]}, \"interpolation\": \"cubic\", "
    "\"keys\": " PADDLE_KEYS "}]}";

/* Body id's frame values (position, orientation, velocity, angular velocity) at time t. */
static void frame_at(tb_scene *scene, size_t id, double t, double out[TB_FRAME_VALUES])
{
    assert_int_equal(tb_scene_set_time(scene, t), TB_STATUS_OK);
    double values[2 * TB_FRAME_VALUES];
    assert_int_equal(tb_scene_frame_values(scene, tb_scene_states(scene), values), TB_STATUS_OK);
    memcpy(out, values + TB_FRAME_VALUES * id, TB_FRAME_VALUES * sizeof(double));
}

/* The curve passes through its keys (the Hermite basis is 1 and 0 there, exp(0) the identity):
 * the pose at each key time equals the key to rounding, 1e-12 for numbers of order 1 (the
 * orientation up to its sign, q and -q being one turn); the middle key's tangents are the
 * velocity and angular velocity it gives (the Hermite basis's derivative at s = 0). The
 * paddle has no slot, and the ball keeps slot 0. */
static void test_a_keyframed_body_from_a_file_follows_its_keys(void **state)
{
    (void)state;
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(paddle_scene, "k.json", NULL, &scene, NULL, &error),
                     TB_STATUS_OK);
    tb_body_motion motion;
    assert_int_equal(tb_scene_body_motion_kind(scene, 1, &motion), TB_STATUS_OK);
    assert_int_equal(motion, TB_MOTION_KEYFRAMED);
    size_t slot = 0;
    assert_int_equal(tb_scene_body_slot(scene, 1, &slot), TB_STATUS_OK);
    assert_true(slot == TB_NO_SLOT);
    assert_int_equal(tb_scene_body_slot(scene, 0, &slot), TB_STATUS_OK);
    assert_int_equal(slot, 0);
    const double times[3] = {0, 0.5, 1.25};
    const double positions[3][3] = {{0, -1, 0.2}, {0, 1, 0.2}, {1, 2, 3}};
    const double eighth_turn = atan(1.0) / 2; /* pi / 8: half of 45 degrees */
    const double c45 = cos(eighth_turn), s45 = sin(eighth_turn), c90 = sqrt(0.5);
    const double orientations[3][4] = {{1, 0, 0, 0}, {c45, 0, 0, s45}, {c90, 0, 0, c90}};
    for (size_t k = 0; k < 3; ++k) {
        double v[TB_FRAME_VALUES];
        frame_at(scene, 1, times[k], v);
        for (int i = 0; i < 3; ++i) {
            assert_float_equal(v[i], positions[k][i], 1e-12);
        }
        const double sign = v[3] * orientations[k][0] + v[6] * orientations[k][3] < 0 ? -1 : 1;
        for (int i = 0; i < 4; ++i) {
            assert_float_equal(v[3 + i], sign * orientations[k][i], 1e-12);
        }
    }
    double v[TB_FRAME_VALUES];
    frame_at(scene, 1, 0.5, v);
    const double velocity[6] = {0, 4, 0, 0, 0, 1.5};
    for (int i = 0; i < 6; ++i) {
        assert_float_equal(v[7 + i], velocity[i], 1e-12);
    }
    tb_scene_destroy(scene);
}

/* Between keys the file's body moves as the C API's keys do (tb_keyframes_sample on the same
 * keys): the loader hands them over unchanged; the frame values pass the orientation through
 * the body's principal frame and back (a product of unit quaternions), a few ulp: 1e-14. */
static void test_a_keyframed_body_from_a_file_moves_as_the_api_keys(void **state)
{
    (void)state;
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(paddle_scene, "k.json", NULL, &scene, NULL, &error),
                     TB_STATUS_OK);
    parsed p = parse("{\"keys\": " PADDLE_KEYS "}");
    assert_int_equal(p.status, TB_STATUS_OK);
    tb_keyframes *keyframes = NULL;
    assert_int_equal(tb_keyframes_create(p.keys, p.count, p.interpolation, &keyframes, NULL),
                     TB_STATUS_OK);
    for (double t = -0.25; t < 1.5; t += 0.0625) {
        tb_body_motion_sample sample;
        assert_int_equal(tb_keyframes_sample(t, keyframes, &sample), 0);
        double v[TB_FRAME_VALUES];
        frame_at(scene, 1, t, v);
        const double *expected[4] = {sample.position, sample.orientation, sample.velocity,
                                     sample.angular_velocity};
        const int start[5] = {0, 3, 7, 10, 13};
        for (int part = 0; part < 4; ++part) {
            for (int i = start[part]; i < start[part + 1]; ++i) {
                assert_float_equal(v[i], expected[part][i - start[part]], 1e-14);
            }
        }
    }
    tb_keyframes_destroy(keyframes);
    free(p.keys);
    tb_scene_destroy(scene);
}

#define KEY_ZERO "[{\"t\": 0, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}]"
static const struct {
    const char *body;
    const char *message;
} bad_keyframed[] = {
    {"{\"name\": \"p\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1, "
     "\"keys\": " KEY_ZERO "}",
     "bodies[1]: keys and interpolation are for \"motion\": \"keyframed\""},
    {"{\"name\": \"p\", \"motion\": \"static\", \"interpolation\": \"linear\"}",
     "bodies[1]: keys and interpolation are for \"motion\": \"keyframed\""},
    {"{\"name\": \"p\", \"motion\": \"keyframed\"}", "bodies[1].keys: must be a non-empty array"},
    {"{\"name\": \"p\", \"motion\": \"keyframed\", \"position\": [0, 0, 1], \"keys\": " KEY_ZERO
     "}",
     "bodies[1]: a keyframed body's pose comes from its keys: no position or orientation"},
    {"{\"name\": \"p\", \"motion\": \"keyframed\", \"orientation\": [1, 0, 0, 0], "
     "\"keys\": " KEY_ZERO "}",
     "bodies[1]: a keyframed body's pose comes from its keys"},
    {"{\"name\": \"p\", \"motion\": \"keyframed\", \"velocity\": [1, 0, 0], \"keys\": " KEY_ZERO
     "}",
     "bodies[1]: a keyframed body's velocities come from its keys"},
    {"{\"name\": \"p\", \"motion\": \"keyframed\", \"angular_velocity_body\": [0, 0, 1], "
     "\"keys\": " KEY_ZERO "}",
     "bodies[1]: a keyframed body's velocities come from its keys"},
    {"{\"name\": \"p\", \"motion\": \"keyframed\", \"keys\": " KEY_ZERO
     ", \"shape\": {\"type\": \"box\", \"size\": [1, 1, 1]}, \"contact\": {\"points\": "
     "[{\"position\": [0, 0, -0.5]}]}}",
     "bodies[1].contact: a keyframed body has no contact points: ground planes push only dynamic "
     "bodies"},
    {"{\"name\": \"p\", \"motion\": \"static\", \"contact\": {\"points\": [{\"position\": "
     "[0, 0, 0]}]}, \"shape\": {\"type\": \"box\", \"size\": [1, 1, 1]}}",
     "bodies[1].contact: a static body has no contact points"},
};

/* Each refused BAD_SCENE with a message naming the body, no scene made, the run untouched. The
 * velocity cases were read and silently unused before, and so were contact points on a static or
 * keyframed body (ground planes push neither). */
static void test_bad_keyframed_bodies_are_refused_naming_the_body(void **state)
{
    (void)state;
    for (size_t r = 0; r < sizeof bad_keyframed / sizeof bad_keyframed[0]; ++r) {
        char json[1024];
        snprintf(json, sizeof json, "{\"bodies\": [" BALL_BODY ", %s]}", bad_keyframed[r].body);
        tb_scene *scene = (tb_scene *)json; /* must be set to NULL */
        tb_run_def run = tb_run_def_default();
        const tb_run_def before = run;
        tb_error error;
        const tb_status status = tb_scene_load_string(json, "k.json", NULL, &scene, &run, &error);
        print_message("%s\n", error.message);
        assert_int_equal(status, TB_STATUS_BAD_SCENE);
        assert_null(scene);
        assert_non_null(strstr(error.message, bad_keyframed[r].message));
        assert_memory_equal(&run, &before, sizeof run);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_keys_are_read_as_written),
        cmocka_unit_test(test_interpolation_defaults_to_cubic_and_ignores_case),
        cmocka_unit_test(test_bad_keys_are_refused_naming_the_key_and_field),
        cmocka_unit_test(test_a_keyframed_body_from_a_file_follows_its_keys),
        cmocka_unit_test(test_a_keyframed_body_from_a_file_moves_as_the_api_keys),
        cmocka_unit_test(test_bad_keyframed_bodies_are_refused_naming_the_body),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
