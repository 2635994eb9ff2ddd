/* Scene files' "joints" (issue 21): a file builds the joints the API would (tb_scene_joint_def
 * reads back what tb_scene_add_joint was given), and every mistake is refused with a message
 * that names its place; a file with an error loads nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/joints.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Two bodies to join: a door at the origin and a frame beside it. */
#define BODIES                                                                                     \
    "\"bodies\": [{\"name\": \"door\", \"shape\": {\"type\": \"box\", \"size\": [1, 0.1, 2]}, "    \
    "\"mass\": 10, \"position\": [0.5, 0, 1]}, {\"name\": \"frame\", \"shape\": {\"type\": "       \
    "\"box\", \"size\": [0.1, 0.1, 2]}, \"mass\": 5, \"position\": [-0.05, 0, 1]}]"
#define SCENE(joints)                                                                              \
    "{" BODIES ", \"effects\": [{\"type\": \"gravity\"}], \"joints\": [" joints "]}"
#define HINGE                                                                                      \
    "{\"type\": \"hinge\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 1], \"axis\": [0, 0, 1]"

/* The issue's four joint types (its "keep these names working" list, on these two bodies), each
 * read back: the file's anchor and axis are the world's at the start, as the API takes them. */
static void test_the_issue_joints_load_as_the_api_makes_them(void **state)
{
    (void)state;
    const char *json = SCENE(
        HINGE "},"
              "{\"type\": \"ball\", \"bodies\": [\"door\", \"frame\"], \"anchor\": [0, 0, 0.5]},"
              "{\"type\": \"hinge\", \"bodies\": [\"door\", \"frame\"], \"anchor\": [1, 0, 0.3], "
              "\"axis\": [0, 1, 0]},"
              "{\"type\": \"fixed\", \"bodies\": [\"door\", \"frame\"], \"anchor\": [0, 0, 1]},"
              "{\"type\": \"slider\", \"bodies\": [\"frame\"], \"anchor\": [0, 0, 1], "
              "\"axis\": [0, 0, 2]}");
    tb_scene *scene = NULL;
    tb_error error;
    const tb_status status = tb_scene_load_string(json, "j.json", NULL, &scene, NULL, &error);
    print_message("%s\n", status == TB_STATUS_OK ? "loaded" : error.message);
    assert_int_equal(status, TB_STATUS_OK);
    assert_int_equal(tb_scene_joint_count(scene), 5);
    tb_joint_def d[5];
    for (size_t j = 0; j < 5; ++j) {
        assert_int_equal(tb_scene_joint_def(scene, j, &d[j]), TB_STATUS_OK);
    }
    assert_int_equal(d[0].type, TB_JOINT_HINGE);
    assert_int_equal(d[0].body_a, 0);
    assert_int_equal(d[0].body_b, TB_WORLD); /* one name: joined to the world */
    assert_near(d[0].anchor[2], 1.0, 0.0);
    assert_int_equal(d[1].type, TB_JOINT_BALL);
    assert_int_equal(d[1].body_b, 1);
    assert_near(d[1].anchor[2], 0.5, 0.0);
    assert_int_equal(d[2].type, TB_JOINT_HINGE);
    const double *a = d[2].axis;
    assert_near(a[1] / sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), 1.0, 1e-15); /* y */
    assert_int_equal(d[3].type, TB_JOINT_FIXED);
    assert_true(isinf(d[3].break_force)); /* not given: never breaks */
    assert_int_equal(d[4].type, TB_JOINT_SLIDER);
    assert_int_equal(d[4].body_a, 1);
    assert_near(d[4].soft_frequency, 0.0, 0.0); /* not given: rigid */
    assert_int_equal(d[0].motor, TB_MOTOR_OFF);
    assert_false(d[0].has_limits);
    tb_scene_destroy(scene);
}

/* The door (body 0) alone in a scene, made with the API. */
static tb_scene *door_scene(void)
{
    tb_scene *built = NULL;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene_create(&scene_def, &built, NULL);
    tb_body_def body = tb_body_def_default();
    tb_mass_from_box(TB_MASS_GIVEN, 10, (double[]){1, 0.1, 2}, &body.mass, NULL);
    memcpy(body.position, (double[]){0.5, 0, 1}, sizeof body.position);
    tb_scene_add_body(built, &body, NULL);
    return built;
}

/* The options (limits, restitution, motor, breaking, soft) go to the library as the API takes
 * them: the file loads exactly when tb_scene_add_joint takes the same def, with the same
 * values read back; where the library refuses (it may refuse an option as unsupported), the
 * file's message is the library's after the joint's place. */
static void test_joint_options_reach_the_library_as_given(void **state)
{
    (void)state;
    static const char *const options[] = {
        HINGE ", \"limits\": [0, 1.5708], \"restitution\": 0.2}",
        HINGE ", \"motor\": {\"speed\": 6.28, \"max_torque\": 2.0}}",
        HINGE ", \"motor\": {\"target\": 0.5, \"max_torque\": 3.0}}",
        HINGE ", \"break_force\": 50, \"break_torque\": 7}",
        HINGE ", \"soft\": {\"frequency\": 5, \"damping_ratio\": 0.7}}",
    };
    for (size_t k = 0; k < sizeof options / sizeof options[0]; ++k) {
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_HINGE;
        def.body_a = 0;
        def.anchor[2] = 1.0;
        def.has_limits = k == 0;
        def.limits[1] = k == 0 ? 1.5708 : 0.0;
        def.restitution = k == 0 ? 0.2 : 0.0;
        def.motor = k == 1 ? TB_MOTOR_VELOCITY : k == 2 ? TB_MOTOR_POSITION : TB_MOTOR_OFF;
        def.motor_speed = k == 1 ? 6.28 : 0.0;
        def.motor_target = k == 2 ? 0.5 : 0.0;
        def.motor_max_force = k == 1 ? 2.0 : k == 2 ? 3.0 : 0.0;
        def.break_force = k == 3 ? 50.0 : INFINITY;
        def.break_torque = k == 3 ? 7.0 : INFINITY;
        def.soft_frequency = k == 4 ? 5.0 : 0.0;
        def.soft_damping_ratio = k == 4 ? 0.7 : 0.0;
        tb_scene *built = door_scene();
        const tb_status api = tb_scene_add_joint(built, &def, NULL);
        char json[1024];
        snprintf(json, sizeof json,
                 "{\"bodies\": [{\"name\": \"door\", \"shape\": {\"type\": \"box\", \"size\": "
                 "[1, 0.1, 2]}, \"mass\": 10, \"position\": [0.5, 0, 1]}], \"joints\": [%s]}",
                 options[k]);
        tb_scene *scene = NULL;
        tb_error error;
        const tb_status status = tb_scene_load_string(json, "t.json", NULL, &scene, NULL, &error);
        print_message("%s -> %s\n", options[k], status == TB_STATUS_OK ? "loaded" : error.message);
        assert_int_equal(status == TB_STATUS_OK, api == TB_STATUS_OK);
        if (api != TB_STATUS_OK) {
            char expected[TB_DETAIL_SIZE + 32];
            snprintf(expected, sizeof expected, "t.json: joints[0]: %s", tb_scene_detail(built));
            assert_string_equal(error.message, expected);
        } else {
            tb_joint_def loaded, made;
            tb_scene_joint_def(scene, 0, &loaded);
            tb_scene_joint_def(built, 0, &made);
            assert_memory_equal(&loaded, &made, sizeof loaded);
        }
        tb_scene_destroy(scene);
        tb_scene_destroy(built);
    }
}

static const struct {
    const char *label;
    const char *json;
    const char *message; /* the whole message must contain this */
} bad[] = {
    {"not a list", "{" BODIES ", \"joints\": {}}", "t.json: joints: must be an array of joints"},
    {"not an object", SCENE("3"), "joints[0]: must be an object with a \"type\""},
    {"no type", SCENE("{\"bodies\": [\"door\"]}"), "joints[0].type: missing"},
    {"unknown type", SCENE("{\"type\": \"hing\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0]}"),
     "joints[0].type: must be one of ball, hinge, slider, fixed, got \"hing\""},
    {"unknown key", SCENE(HINGE ", \"spring\": 3}"), "joints[0].spring: unknown key"},
    {"no bodies", SCENE("{\"type\": \"ball\", \"anchor\": [0, 0, 0]}"),
     "joints[0].bodies: missing (one body's name, joined to the world, or two)"},
    {"three bodies",
     SCENE("{\"type\": \"ball\", \"bodies\": [\"door\", \"frame\", \"door\"], \"anchor\": [0, 0, "
           "0]}"),
     "joints[0].bodies: must be an array of one or two body names"},
    {"no such body",
     SCENE("{\"type\": \"ball\", \"bodies\": [\"door\", \"dor\"], \"anchor\": [0, 0, 0]}"),
     "joints[0].bodies[1]: no body is named \"dor\""},
    {"a number for a body", SCENE("{\"type\": \"ball\", \"bodies\": [1], \"anchor\": [0, 0, 0]}"),
     "joints[0].bodies[0]: must be a body's name, got a number"},
    {"no anchor", SCENE("{\"type\": \"ball\", \"bodies\": [\"door\"]}"),
     "joints[0].anchor: missing (an array of 3 numbers)"},
    {"short anchor", SCENE("{\"type\": \"ball\", \"bodies\": [\"door\"], \"anchor\": [0, 0]}"),
     "joints[0].anchor: must be an array of 3 numbers"},
    {"zero axis, second joint",
     SCENE(HINGE "}, {\"type\": \"hinge\", \"bodies\": [\"frame\"], \"anchor\": [0, 0, 0], "
                 "\"axis\": [0, 0, 0]}"),
     "t.json: joints[1].axis: must be 3 finite numbers, not all 0"},
    {"a string in the axis",
     SCENE("{\"type\": \"slider\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0], \"axis\": [0, "
           "\"z\", 1]}"),
     "joints[0].axis: must be 3 finite numbers, not all 0"},
    {"hinge without axis",
     SCENE("{\"type\": \"hinge\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0]}"),
     "joints[0].axis: missing"},
    {"axis on a ball",
     SCENE("{\"type\": \"ball\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0], \"axis\": [0, 0, "
           "1]}"),
     "joints[0].axis: unknown key"},
    {"motor on a fixed joint",
     SCENE("{\"type\": \"fixed\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0], \"motor\": {}}"),
     "joints[0].motor: unknown key"},
    {"one limit", SCENE(HINGE ", \"limits\": [0]}"),
     "joints[0].limits: must be an array of 2 numbers"},
    {"restitution without limits", SCENE(HINGE ", \"restitution\": 0.5}"),
     "joints[0].restitution: applies at \"limits\", none given"},
    {"motor with speed and target",
     SCENE(HINGE ", \"motor\": {\"speed\": 1, \"target\": 1, \"max_torque\": 1}}"),
     "joints[0].motor: needs one of \"speed\" (rad/s) or \"target\" (rad)"},
    {"hinge motor with a force", SCENE(HINGE ", \"motor\": {\"speed\": 1, \"max_force\": 1}}"),
     "joints[0].motor.max_force: unknown key (known here: speed, target, max_torque)"},
    {"motor without a cap", SCENE(HINGE ", \"motor\": {\"speed\": 1}}"),
     "joints[0].motor.max_torque: missing (a number)"},
    {"slider motor with a torque",
     SCENE("{\"type\": \"slider\", \"bodies\": [\"door\"], \"anchor\": [0, 0, 0], \"axis\": [1, 0, "
           "0], \"motor\": {\"speed\": 1, \"max_torque\": 1}}"),
     "joints[0].motor.max_torque: unknown key (known here: speed, target, max_force)"},
    {"zero break force", SCENE(HINGE ", \"break_force\": 0}"),
     "joints[0].break_force: must be > 0, got 0"},
    {"break torque a string", SCENE(HINGE ", \"break_torque\": \"5\"}"),
     "joints[0].break_torque: must be a number, got a string"},
    {"soft without frequency", SCENE(HINGE ", \"soft\": {\"damping_ratio\": 1}}"),
     "joints[0].soft.frequency: missing"},
    {"soft with zero frequency", SCENE(HINGE ", \"soft\": {\"frequency\": 0}}"),
     "joints[0].soft.frequency: must be > 0, got 0"},
    {"soft with an unknown key", SCENE(HINGE ", \"soft\": {\"frequency\": 1, \"stiffness\": 1}}"),
     "joints[0].soft.stiffness: unknown key (known here: frequency, damping_ratio)"},
    /* the library's own refusals, prefixed with the joint's place */
    {"a body joined to itself",
     SCENE("{\"type\": \"ball\", \"bodies\": [\"door\", \"door\"], \"anchor\": [0, 0, 0]}"),
     "t.json: joints[0]: "},
    {"limits reversed", SCENE(HINGE ", \"limits\": [1, 0]}"), "t.json: joints[0]: "},
    {"restitution above 1", SCENE(HINGE ", \"limits\": [0, 1], \"restitution\": 2}"),
     "t.json: joints[0]: "},
    {"motor cap negative", SCENE(HINGE ", \"motor\": {\"speed\": 1, \"max_torque\": -1}}"),
     "t.json: joints[0]: "},
};

/* Each bad file: BAD_SCENE, the place named, no scene, the run untouched. */
static void test_bad_joints_are_refused_naming_the_place(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        tb_scene *scene = (tb_scene *)&bad; /* must be set to NULL */
        tb_run_def run = tb_run_def_default();
        const tb_run_def before = run;
        tb_error error;
        const tb_status status =
            tb_scene_load_string(bad[i].json, "t.json", NULL, &scene, &run, &error);
        print_message("%-28s %s\n", bad[i].label, error.message);
        assert_int_equal(status, TB_STATUS_BAD_SCENE);
        assert_null(scene);
        assert_non_null(strstr(error.message, bad[i].message));
        assert_memory_equal(&run, &before, sizeof run);
    }
}

/* The library's refusals come back as its own message (the field it names), after the place. */
static void test_the_library_message_comes_back_after_the_place(void **state)
{
    (void)state;
    const char *json = SCENE(HINGE ", \"limits\": [1, 0]}");
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "t.json", NULL, &scene, NULL, &error),
                     TB_STATUS_BAD_SCENE);
    /* what the API says to the same def */
    tb_scene *built = NULL;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene_create(&scene_def, &built, NULL);
    tb_body_def body = tb_body_def_default();
    tb_mass_from_box(TB_MASS_GIVEN, 10, (double[]){1, 0.1, 2}, &body.mass, NULL);
    tb_scene_add_body(built, &body, NULL);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = 0;
    def.anchor[2] = 1.0;
    def.has_limits = 1;
    def.limits[0] = 1.0;
    def.limits[1] = 0.0;
    assert_int_not_equal(tb_scene_add_joint(built, &def, NULL), TB_STATUS_OK);
    char expected[TB_DETAIL_SIZE + 32];
    snprintf(expected, sizeof expected, "t.json: joints[0]: %s", tb_scene_detail(built));
    print_message("%s\n", error.message);
    assert_string_equal(error.message, expected);
    tb_scene_destroy(built);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_issue_joints_load_as_the_api_makes_them),
        cmocka_unit_test(test_joint_options_reach_the_library_as_given),
        cmocka_unit_test(test_bad_joints_are_refused_naming_the_place),
        cmocka_unit_test(test_the_library_message_comes_back_after_the_place),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
