/* Scene files: a file builds the scene the API would, and every mistake is refused with a
 * message that names its place (line and column for syntax, a JSON path for meaning). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/tumble.h"

#include <stdio.h>
#include <string.h>

/* The file and the API describe the same box: same mass properties, same state, same run. */
static void test_a_scene_file_builds_what_the_api_builds(void **state)
{
    (void)state;
    const char *json = "{\"bodies\": [{\"name\": \"b\", \"shape\": {\"type\": \"box\", \"size\": "
                       "[0.1, 0.2, 0.3]}, \"density\": 1000, \"position\": [1, 2, 3], "
                       "\"orientation\": [0.8, 0.6, 0, 0], \"velocity\": [0, 1, 0], "
                       "\"angular_velocity_body\": [0, 0, 2]}],"
                       " \"effects\": [{\"type\": \"gravity\"}],"
                       " \"integrator\": {\"method\": \"cvode-bdf\", \"rtol\": 1e-7},"
                       " \"output\": {\"fps\": 24, \"duration\": 2}}";
    tb_scene *loaded = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "box.json", NULL, &loaded, &run, &error),
                     TB_STATUS_OK);

    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *built = NULL;
    tb_scene_create(&scene_def, &built, NULL);
    tb_body_def def = tb_body_def_default();
    tb_mass_from_box(TB_MASS_DENSITY, 1000, (double[]){0.1, 0.2, 0.3}, &def.mass, NULL);
    memcpy(def.position, (double[]){1, 2, 3}, sizeof def.position);
    memcpy(def.orientation, (double[]){0.8, 0.6, 0, 0}, sizeof def.orientation);
    def.velocity[1] = 1.0;
    /* body z turned by 73.7 degrees about x: (0, 0, 2) -> (0, -2 sin, 2 cos) with the half
     * angle's sin 0.6, cos 0.8: sin = 0.96, cos = 0.28 */
    memcpy(def.angular_velocity, (double[]){0, -2 * 0.96, 2 * 0.28}, sizeof def.angular_velocity);
    tb_scene_add_body(built, &def, NULL);
    for (int k = 0; k < TB_STATE_SIZE; ++k) {
        assert_near(tb_scene_states(loaded)[k], tb_scene_states(built)[k], 1e-12);
    }
    assert_string_equal(tb_scene_body_name(loaded, 0), "b");
    assert_int_equal(tb_scene_effect_count(loaded), 1);
    assert_int_equal(run.integrator.method, TB_METHOD_CVODE_BDF);
    assert_near(run.integrator.rtol, 1e-7, 0.0);
    assert_near(run.fps, 24.0, 0.0);
    assert_near(run.duration, 2.0, 0.0);
    tb_scene_destroy(built);
    tb_scene_destroy(loaded);
}

/* A minimal valid body, to build bad scenes around. */
#define BODY "{\"name\": \"a\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1}"

static const struct {
    const char *label;
    const char *json;
    tb_status status;
    const char *message; /* the whole message must contain this */
} bad[] = {
    {"truncated", "{\"bodies\": [" BODY, TB_STATUS_PARSE_ERROR, "t.json:1:"},
    {"syntax, line 3", "{\n\"bodies\": [" BODY "],\n  \"effects\": [}\n", TB_STATUS_PARSE_ERROR,
     "t.json:3:"},
    {"not an object", "[1, 2]", TB_STATUS_BAD_SCENE, "t.json: must be an object, got an array"},
    {"no bodies", "{}", TB_STATUS_BAD_SCENE, "t.json: bodies: missing"},
    {"empty bodies", "{\"bodies\": []}", TB_STATUS_BAD_SCENE, "bodies: must be a non-empty"},
    {"unknown top key", "{\"bodies\": [" BODY "], \"gravity\": 9.81}", TB_STATUS_BAD_SCENE,
     "gravity: unknown key"},
    {"unknown body key", "{\"bodies\": [{\"name\": \"a\", \"mas\": 1}]}", TB_STATUS_BAD_SCENE,
     "bodies[0].mas: unknown key"},
    {"negative mass named",
     "{\"bodies\": [{\"name\": \"c\", \"shape\": {\"type\": \"box\", \"size\": [1, 1, 1]}, "
     "\"mass\": -1}]}",
     TB_STATUS_BAD_SCENE, "t.json: bodies[0].mass: must be > 0, got -1"},
    {"string mass", "{\"bodies\": [{\"name\": \"a\", \"mass\": \"1\", \"inertia\": [1, 1, 1]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].mass: must be a number, got a string"},
    {"short vector", "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"inertia\": [1, 1]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].inertia: must be 3 principal moments"},
    {"indefinite tensor",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"inertia\": [[1,0,0],[0,1,0],[0,0,-1]]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: inertia: not positive definite"},
    {"no shape and no inertia", "{\"bodies\": [{\"name\": \"a\", \"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "needs a shape, or mass with inertia"},
    {"mass and density",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"sphere\", \"radius\": 1}, "
     "\"mass\": 1, \"density\": 2}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: give mass or density, not both"},
    {"unknown shape",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"cone\"}, \"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape: type: must be one of box"},
    {"zero radius",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"sphere\", \"radius\": 0}, "
     "\"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape.radius: must be > 0, got 0"},
    {"duplicate name", "{\"bodies\": [" BODY ", " BODY "]}", TB_STATUS_BAD_SCENE,
     "bodies[1]: name: \"a\" is already the name of bodies[0]"},
    {"non-unit orientation",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"inertia\": [1, 1, 1], \"orientation\": "
     "[1, 1, 0, 0]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].orientation: must be a unit quaternion"},
    {"unknown body in effect",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"drag\", \"body\": \"b\"}]}",
     TB_STATUS_BAD_SCENE, "effects[0].body: no body is named \"b\""},
    {"unknown effect", "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"magnet\"}]}",
     TB_STATUS_BAD_SCENE, "effects[0].type: must be one of gravity"},
    {"negative stiffness",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"spring\", \"body_a\": \"a\", "
     "\"point_b\": [0, 0, 1], \"stiffness\": -5}]}",
     TB_STATUS_BAD_SCENE, "effects[0].stiffness: must be >= 0, got -5"},
    {"mu_s below mu_k",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"ground\", \"static_friction\": 0.1, "
     "\"kinetic_friction\": 0.4}]}",
     TB_STATUS_BAD_SCENE, "effects[0]: static_friction: must be finite and >= kinetic"},
    {"bad method", "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"rk45\"}}",
     TB_STATUS_BAD_SCENE, "integrator.method: must be one of euler"},
    {"dt for cvode",
     "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"cvode-bdf\", \"dt\": 0.01}}",
     TB_STATUS_BAD_SCENE, "integrator.dt: applies to fixed-step"},
    {"zero fps", "{\"bodies\": [" BODY "], \"output\": {\"fps\": 0}}", TB_STATUS_BAD_SCENE,
     "output.fps: must be > 0, got 0"},
    {"huge number", "{\"bodies\": [" BODY "], \"output\": {\"fps\": 1e999}}", TB_STATUS_PARSE_ERROR,
     "t.json:1:"},
    {"duplicate key", "{\"bodies\": [" BODY "], \"output\": {\"fps\": 1, \"fps\": 2}}",
     TB_STATUS_PARSE_ERROR, "duplicate object key"},
    {"missing mesh file",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"file\": "
     "\"nowhere.obj\"}, \"density\": 1}]}",
     TB_STATUS_IO_ERROR, "bodies[0].shape: file: cannot read"},
    {"badly wound inline mesh",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"vertices\": "
     "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,2,1],[0,1,3],[0,3,2],[1,3,2]]}, "
     "\"density\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: edge"},
};

static void test_bad_scene_files_are_refused_naming_the_place(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        tb_scene *scene = (tb_scene *)&bad; /* must be set to NULL */
        tb_run_def run = tb_run_def_default();
        const tb_run_def before = run;
        tb_error error;
        const tb_status status =
            tb_scene_load_string(bad[i].json, "t.json", NULL, &scene, &run, &error);
        print_message("%-24s %s\n", bad[i].label, error.message);
        assert_int_equal(status, bad[i].status);
        assert_null(scene);
        assert_non_null(strstr(error.message, bad[i].message));
        assert_memory_equal(&run, &before, sizeof run);
    }
}

/* Deep nesting is a syntax error from the parser's depth limit, not a crash. */
static void test_deeply_nested_json_is_refused(void **state)
{
    (void)state;
    enum { DEPTH = 100000 };
    static char json[2 * DEPTH + 1];
    memset(json, '[', DEPTH);
    memset(json + DEPTH, ']', DEPTH);
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "deep.json", NULL, &scene, NULL, &error),
                     TB_STATUS_PARSE_ERROR);
    assert_null(scene);
    print_message("%s\n", error.message);
}

/* A mesh from an OBJ file next to the scene: a cube of side 2 and density 1 weighs 8 kg with
 * moments 8 (2^2 + 2^2) / 12 = 16/3. */
static void test_mesh_files_are_read_relative_to_the_scene(void **state)
{
    (void)state;
    const char *directory = TUMBLE_TEST_BUILD_DIR "/";
    char path[512];
    snprintf(path, sizeof path, "%scube.obj", directory);
    FILE *obj = fopen(path, "w");
    assert_non_null(obj);
    fputs("# a cube of side 2\n"
          "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
          "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
          obj);
    fclose(obj);
    const char *json = "{\"bodies\": [{\"name\": \"cube\", \"shape\": {\"type\": \"mesh\", "
                       "\"file\": \"cube.obj\"}, \"density\": 1}]}";
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "m.json", directory, &scene, NULL, &error),
                     TB_STATUS_OK);
    tb_mass_properties mass;
    tb_scene_get_mass(scene, 0, &mass);
    assert_near(mass.mass, 8.0, 1e-12);
    for (int i = 0; i < 3; ++i) {
        assert_near(mass.moments[i], 16.0 / 3.0, 1e-12);
    }
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_scene_file_builds_what_the_api_builds),
        cmocka_unit_test(test_bad_scene_files_are_refused_naming_the_place),
        cmocka_unit_test(test_deeply_nested_json_is_refused),
        cmocka_unit_test(test_mesh_files_are_read_relative_to_the_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
