/* Scene files: a file builds the scene the API would, and every mistake is refused with a
 * message that names its place (line and column for syntax, a JSON path for meaning). */
#define _XOPEN_SOURCE 700 /* mkfifo, symlink, mkdir */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/tumble.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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
    /* F111: the library's detail named the C field ("bodies[0]: def.name: ...") */
    {"empty name", "{\"bodies\": [{\"name\": \"\", \"mass\": 1, \"inertia\": [1, 1, 1]}]}",
     TB_STATUS_BAD_SCENE, "t.json: bodies[0]: name: must have 1 to 63 characters, got 0"},
    {"64-character name",
     "{\"bodies\": [{\"name\": "
     "\"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\", "
     "\"mass\": 1, \"inertia\": [1, 1, 1]}]}",
     TB_STATUS_BAD_SCENE, "t.json: bodies[0]: name: must have 1 to 63 characters, got 64"},
    /* F119: the subnormal 1e-320 was shown as the double's 9.99989e-321 */
    {"subnormal rtol",
     "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"cvode-bdf\", \"rtol\": 1e-320}}",
     TB_STATUS_BAD_SCENE, "t.json: integrator.rtol: must be in [1e-15, 1), got 1e-320"},
    {"momentum overflow",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 1e100, \"inertia\": [1, 1, 1], "
     "\"velocity\": [1e300, 0, 0]}]}",
     TB_STATUS_BAD_SCENE, "t.json: bodies[0]: velocity: (1e+300, 0, 0) m/s"},
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
    {"contact with an unknown key",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"contact\", \"stiffness\": 5}]}",
     TB_STATUS_BAD_SCENE, "effects[0].stiffness: unknown key"},
    {"contact with an unknown body",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"contact\", \"bodies\": [\"b\"]}]}",
     TB_STATUS_BAD_SCENE, "effects[0].bodies: entry 0: no body is named \"b\""},
    {"contact naming a body twice",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"contact\", \"bodies\": [\"a\", "
     "\"a\"]}]}",
     TB_STATUS_BAD_SCENE, "effects[0].bodies: entry 1: \"a\" is listed twice (also entry 0)"},
    {"contact naming a body without a shape",
     "{\"bodies\": [" BODY ", {\"name\": \"c\", \"mass\": 1, \"inertia\": [1, 1, 1]}], "
     "\"effects\": [{\"type\": \"contact\", \"bodies\": [\"a\", \"c\"]}]}",
     TB_STATUS_BAD_SCENE, "effects[0].bodies: entry 1: \"c\" has no shape"},
    {"contact naming a number",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"contact\", \"bodies\": [3]}]}",
     TB_STATUS_BAD_SCENE, "effects[0].bodies: entry 0: must be a body's name"},
    {"contact restitution above 1",
     "{\"bodies\": [" BODY "], \"effects\": [{\"type\": \"contact\", \"restitution\": 2}]}",
     TB_STATUS_BAD_SCENE, "effects[0]: restitution: must be in [0, 1]"},
    {"bad method", "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"rk45\"}}",
     TB_STATUS_BAD_SCENE, "integrator.method: must be one of euler"},
    {"dt for cvode",
     "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"cvode-bdf\", \"dt\": 0.01}}",
     TB_STATUS_BAD_SCENE,
     "integrator.dt: applies to fixed-step methods (euler, midpoint, rk4, rosenbrock), not to "
     "cvode-bdf"},
    {"rtol for rk4",
     "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"rk4\", \"rtol\": 1e-8}}",
     TB_STATUS_BAD_SCENE,
     "integrator.rtol: applies to adaptive methods (cvode-adams, cvode-bdf, ark-imex), not to rk4"},
    {"linear_solver for adams",
     "{\"bodies\": [" BODY "], \"integrator\": {\"method\": \"cvode-adams\", "
     "\"linear_solver\": \"dense\"}}",
     TB_STATUS_BAD_SCENE,
     "integrator.linear_solver: applies to cvode-bdf, ark-imex only, not to cvode-adams"},
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
    /* Issue 11: mass properties no double can carry are refused, never a hang or infinity. */
    {"points: a 5e-324 kg point",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"points\", \"points\": ["
     "{\"position\": [0, 0, 0], \"mass\": 1}, {\"position\": [1, 0, 0], \"mass\": 1}, "
     "{\"position\": [0, 1, 0], \"mass\": 1}, {\"position\": [0.3, 0.2, 0.9], \"mass\": "
     "5e-324}]}}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape: masses[3]: must be from 1e-100 to 1e+100 kg"},
    {"inertia of 1e-322 entries",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"inertia\": [[1e-322, 1e-322, 0], "
     "[1e-322, 1e-322, 1e-322], [0, 1e-322, 1e-322]]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: inertia: largest entry 9.88131e-323 kg m^2 is outside"},
    {"mass 5e-324 (1/m = inf)",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 5e-324, \"inertia\": [1, 1, 1]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: mass: must be from 1e-100 to 1e+100 kg"},
    {"density with inertia",
     "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"density\": 2, \"inertia\": [1, 1, "
     "1]}]}",
     TB_STATUS_BAD_SCENE, "bodies[0]: density: applies to a shape"},
    {"radius on a box",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"box\", \"size\": [1, 1, 1], "
     "\"radius\": 2}, \"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape: radius: does not apply to a box shape (it takes size)"},
    {"file on a sphere",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"sphere\", \"radius\": 1, "
     "\"file\": \"x.obj\"}, \"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape: file: does not apply to a sphere shape"},
    {"length on an ellipsoid",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"ellipsoid\", \"semi_axes\": "
     "[1, 2, 3], \"length\": 1}, \"mass\": 1}]}",
     TB_STATUS_BAD_SCENE, "length: does not apply to an ellipsoid shape"},
    {"triangle index 1e10",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"vertices\": "
     "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,2,1],[0,1,3],[0,3,2],[1,2,1e10]]}, "
     "\"density\": 1}]}",
     TB_STATUS_BAD_SCENE,
     "bodies[0].shape.triangles[3]: vertex indices must be whole numbers from 0 to the number of "
     "vertices less one (4 vertices), got 1e+10"},
    {"triangle index 1.5",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"vertices\": "
     "[[0,0,0],[1,0,0],[0,1,0],[0,0,1]], \"triangles\": [[0,2,1],[0,1,3],[0,3,2],[1,2,1.5]]}, "
     "\"density\": 1}]}",
     TB_STATUS_BAD_SCENE, "got 1.5"},
    {"no vertices: the count is named",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"vertices\": [], "
     "\"triangles\": []}, \"density\": 1}]}",
     TB_STATUS_BAD_SCENE,
     "bodies[0]: vertex_count: a closed mesh needs at least 4 vertices and 4 triangles, got 0"},
    {"more than 1e9 frames",
     "{\"bodies\": [" BODY "], \"output\": {\"fps\": 1000, \"duration\": 1.1e6}}",
     TB_STATUS_BAD_SCENE,
     "output: duration: must be >= 0 and at most 1e9 frames (TB_RUN_MAX_FRAMES) at 1000 fps"},
    {"a points piece with its points (was: an unknown key \"points\")",
     "{\"bodies\": [{\"name\": \"a\", \"density\": 1, \"shape\": [{\"type\": \"box\", "
     "\"size\": [1, 1, 1]}, {\"type\": \"points\", \"points\": [{\"position\": [0, 0, 0], "
     "\"mass\": 1}]}]}]}",
     TB_STATUS_BAD_SCENE,
     "bodies[0].shape[1]: type: a points shape carries its own masses and cannot be a piece"},
    {"mesh file by absolute path outside",
     "{\"bodies\": [{\"name\": \"a\", \"shape\": {\"type\": \"mesh\", \"file\": "
     "\"/etc/passwd\"}, \"density\": 1}]}",
     TB_STATUS_BAD_SCENE, "bodies[0].shape: file: outside the folder mesh files must be in"},
};

static void test_bad_scene_files_are_refused_naming_the_place(void **state)
{
    (void)state;
    alarm(60); /* a hang (GSL on subnormal tensors) fails instead of stalling the suite */
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
    alarm(0);
}

/* max_steps is every method's step budget (the library enforces it on rk4 too): a scene file
 * gives it to a fixed step as to CVODE. Before, the loader refused it for rk4. A frame of 1/10 s
 * at dt = 1/1000 s is 100 steps: a budget of 99 refuses the run before its first frame, one
 * of 100 lets it run. */
static void test_max_steps_applies_to_a_fixed_step_too(void **state)
{
    (void)state;
    const long budgets[] = {99, 100};
    const tb_status expected[] = {TB_STATUS_TOO_MANY_STEPS, TB_STATUS_OK};
    for (size_t k = 0; k < 2; ++k) {
        char json[256];
        snprintf(json, sizeof json,
                 "{\"bodies\": [{\"name\": \"a\", \"mass\": 1, \"inertia\": [1, 1, 1]}], "
                 "\"integrator\": {\"method\": \"rk4\", \"dt\": 0.001, \"max_steps\": %ld}, "
                 "\"output\": {\"fps\": 10, \"duration\": 0.2}}",
                 budgets[k]);
        tb_scene *scene = NULL;
        tb_run_def run = tb_run_def_default();
        tb_error error;
        assert_int_equal(tb_scene_load_string(json, "t.json", NULL, &scene, &run, &error),
                         TB_STATUS_OK);
        assert_int_equal(run.integrator.max_steps, budgets[k]);
        assert_int_equal(tb_scene_run(scene, &run, NULL, NULL, NULL, &error), expected[k]);
        tb_scene_destroy(scene);
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

/* --- mesh files: what is read, from where ------------------------------------------------ */

#define CUBE_VERTICES                                                                              \
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
#define CUBE_FACES "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
#define CUBE_SCENE(file)                                                                           \
    "{\"bodies\": [{\"name\": \"cube\", \"shape\": {\"type\": \"mesh\", \"file\": \"" file         \
    "\"}, \"density\": 1}]}"

static void write_text(const char *path, const char *text)
{
    FILE *file = fopen(path, "w");
    assert_non_null(file);
    fputs(text, file);
    assert_int_equal(fclose(file), 0);
}

/* A folder under the build directory, emptied of what an earlier run left. */
static void fresh_folder(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", TUMBLE_TEST_BUILD_DIR, name);
    char command[1024];
    snprintf(command, sizeof command, "rm -rf '%s' && mkdir -p '%s'", out, out);
    assert_int_equal(system(command), 0);
}

/* Loads scene json with base directory folder and options; returns the status, the error in
 * *error. On success the cube must weigh 8 kg with moments 16/3 (side 2, density 1). */
static tb_status load_cube(const char *json, const char *folder,
                           const tb_scene_file_options *options, tb_error *error)
{
    tb_scene *scene = NULL;
    const tb_status status =
        tb_scene_load_string_with_options(json, "m.json", folder, options, &scene, NULL, error);
    print_message("%s -> %s\n", json, status == TB_STATUS_OK ? "ok" : error->message);
    if (status == TB_STATUS_OK) {
        tb_mass_properties mass;
        tb_scene_get_mass(scene, 0, &mass);
        assert_near(mass.mass, 8.0, 1e-12);
        for (int i = 0; i < 3; ++i) {
            assert_near(mass.moments[i], 16.0 / 3.0, 1e-12);
        }
    } else {
        assert_null(scene);
    }
    tb_scene_destroy(scene);
    return status;
}

/* OBJ lines of any length are one line: a comment of 1100 bytes used to be split at 1023 and
 * its tail ("v 1e5 0 0") read as a phantom vertex that shifted every index after it. */
static void test_long_obj_lines_are_one_line(void **state)
{
    (void)state;
    char folder[512], path[600];
    fresh_folder(folder, sizeof folder, "long_lines");
    static char text[4096];
    char comment[1200];
    memset(comment, ' ', sizeof comment);
    comment[0] = '#';
    snprintf(comment + 1023, sizeof comment - 1023, "v 1e5 0 0\n"); /* at byte 1024 */
    char spaced_vertex[1400]; /* the first vertex, its coordinates 1300 blanks apart */
    snprintf(spaced_vertex, sizeof spaced_vertex, "v -1%1300s-1 -1\n", " ");
    snprintf(text, sizeof text, "%s%s%s%s", comment, spaced_vertex, strchr(CUBE_VERTICES, '\n') + 1,
             CUBE_FACES);
    snprintf(path, sizeof path, "%s/cube.obj", folder);
    write_text(path, text);
    tb_error error;
    assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, NULL, &error), TB_STATUS_OK);
}

/* F13 (fuzz): a NUL byte ended an OBJ line early, so "f 1 4 3 2<NUL> 9" read as the face
 * 1 4 3 2 and the file was accepted with text the reader never saw. A NUL byte is refused, naming
 * its line: an OBJ file is text. */
static void test_a_nul_byte_in_an_obj_file_is_refused_by_line(void **state)
{
    (void)state;
    char folder[512], path[600];
    fresh_folder(folder, sizeof folder, "nul_byte");
    snprintf(path, sizeof path, "%s/cube.obj", folder);
    static const char tail[] = "\0 9\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    char text[512];
    const size_t head = strlen(CUBE_VERTICES "f 1 4 3 2");
    memcpy(text, CUBE_VERTICES "f 1 4 3 2", head);
    memcpy(text + head, tail, sizeof tail - 1);
    FILE *file = fopen(path, "wb");
    assert_non_null(file);
    assert_int_equal(fwrite(text, 1, head + sizeof tail - 1, file), head + sizeof tail - 1);
    assert_int_equal(fclose(file), 0);
    tb_error error;
    assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, NULL, &error), TB_STATUS_BAD_SCENE);
    assert_non_null(strstr(error.message, "cube.obj:9: a NUL byte"));
}

/* Statements a rigid body does not need are ignored (documented); any other is refused with
 * its line, rather than silently dropped. */
static void test_obj_statements_are_read_ignored_or_refused_by_line(void **state)
{
    (void)state;
    char folder[512], path[600];
    fresh_folder(folder, sizeof folder, "statements");
    snprintf(path, sizeof path, "%s/cube.obj", folder);
    write_text(path, "# exported\r\nmtllib cube.mtl\r\no cube\r\ng box\r\ns off\r\nusemtl grey\r\n"
                     "vn 0 0 1\r\nvt 0.5 0.5\r\n" CUBE_VERTICES "f 1/1/1 4/1/1 3//1 2\n"
                     "f -4 -3 -2 -1\n" /* negative: counted back from the latest vertex */
                     "f 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8 # last face\n");
    tb_error error;
    assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, NULL, &error), TB_STATUS_OK);

    static const struct {
        const char *text;
        const char *message;
    } refused[] = {
        {CUBE_VERTICES CUBE_FACES "l 1 2\n", "cube.obj:15: \"l\" statements are not supported"},
        {CUBE_VERTICES "f 1 4 0\n", "cube.obj:9: f: corner 3 is not the index of an earlier"},
        {CUBE_VERTICES "f 1 4 9\n", "cube.obj:9: f: corner 3"},
        {CUBE_VERTICES "f 1 4 1e1\n", "cube.obj:9: f: corner 3"},
        {CUBE_VERTICES "f 1 4 -9\n", "cube.obj:9: f: corner 3"},
        {CUBE_VERTICES "f 1 4\n", "cube.obj:9: f needs at least 3 corners, got 2"},
        {"v 1 2\n", "cube.obj:1: v needs 3 coordinates"},
        {"v 1 2 3 4\n", "cube.obj:1: v needs 3 coordinates"},
        {"v 1 2 nan\n", "cube.obj:1: v: coordinate 3 is not a finite number"},
        {"v 1 2 1e999\n", "cube.obj:1: v: coordinate 3 is not a finite number"},
        {"v 1 2 3x\n", "cube.obj:1: v: coordinate 3"},
    };
    for (size_t i = 0; i < sizeof refused / sizeof refused[0]; ++i) {
        write_text(path, refused[i].text);
        assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, NULL, &error),
                         TB_STATUS_BAD_SCENE);
        assert_non_null(strstr(error.message, refused[i].message));
    }
}

/* Only regular files of bounded size are read: /dev/zero never ends and opening a FIFO waits
 * for a writer. The alarm turns a hang into a failure. */
static void test_obj_reader_takes_regular_files_of_bounded_size(void **state)
{
    (void)state;
    alarm(30);
    char folder[512], path[600];
    fresh_folder(folder, sizeof folder, "special");
    snprintf(path, sizeof path, "%s/pipe.obj", folder);
    assert_int_equal(mkfifo(path, 0600), 0);
    tb_error error;
    assert_int_equal(load_cube(CUBE_SCENE("pipe.obj"), folder, NULL, &error), TB_STATUS_IO_ERROR);
    assert_non_null(strstr(error.message, "not a regular file"));
    /* the scene's folder itself ("." or ""): a directory, not a file "outside the folder ...:
     * /f is not in /f", as the check of the path said before it counted the folder as in it */
    static const char *const folders[] = {CUBE_SCENE("."), CUBE_SCENE("")};
    for (size_t i = 0; i < 2; ++i) {
        assert_int_equal(load_cube(folders[i], folder, NULL, &error), TB_STATUS_IO_ERROR);
        assert_non_null(strstr(error.message, "not a regular file (a directory"));
    }

    tb_scene_file_options anywhere = tb_scene_file_options_default();
    anywhere.allow_paths_outside = true;
    assert_int_equal(load_cube(CUBE_SCENE("/dev/zero"), folder, &anywhere, &error),
                     TB_STATUS_IO_ERROR);
    assert_non_null(strstr(error.message, "/dev/zero: not a regular file"));

    snprintf(path, sizeof path, "%s/cube.obj", folder);
    write_text(path, CUBE_VERTICES CUBE_FACES);
    const size_t size = strlen(CUBE_VERTICES CUBE_FACES);
    tb_scene_file_options small = tb_scene_file_options_default();
    small.max_mesh_file_bytes = size - 1;
    assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, &small, &error), TB_STATUS_IO_ERROR);
    char expected[96];
    snprintf(expected, sizeof expected, "%zu bytes, more than the %zu bytes allowed", size,
             size - 1);
    assert_non_null(strstr(error.message, expected));
    small.max_mesh_file_bytes = size;
    assert_int_equal(load_cube(CUBE_SCENE("cube.obj"), folder, &small, &error), TB_STATUS_OK);
    alarm(0);
}

/* Mesh files must be inside the scene's folder unless the caller widens it: "..", an absolute
 * path and a symbolic link that leads out are refused naming the file and the folder; the
 * options' allow_paths_outside and mesh_root let them in. */
static void test_mesh_files_stay_inside_the_scene_folder(void **state)
{
    (void)state;
    char root[512], scenes[600], path[700], link_path[700];
    fresh_folder(root, sizeof root, "confine");
    snprintf(scenes, sizeof scenes, "%s/scenes", root);
    assert_int_equal(mkdir(scenes, 0700), 0);
    snprintf(path, sizeof path, "%s/outside.obj", root);
    write_text(path, CUBE_VERTICES CUBE_FACES);
    snprintf(link_path, sizeof link_path, "%s/link.obj", scenes);
    assert_int_equal(symlink(path, link_path), 0);
    char absolute[800];
    snprintf(absolute, sizeof absolute, CUBE_SCENE("%s"), path);

    const char *escapes[] = {CUBE_SCENE("../outside.obj"), CUBE_SCENE("link.obj"), absolute,
                             CUBE_SCENE("./../scenes/../outside.obj")};
    tb_error error;
    for (size_t i = 0; i < sizeof escapes / sizeof escapes[0]; ++i) {
        assert_int_equal(load_cube(escapes[i], scenes, NULL, &error), TB_STATUS_BAD_SCENE);
        assert_non_null(strstr(error.message, "file: outside the folder mesh files must be in"));
        assert_non_null(strstr(error.message, "/confine/outside.obj is not in "));
        assert_non_null(strstr(error.message, "allow_paths_outside"));
    }
    tb_scene_file_options anywhere = tb_scene_file_options_default();
    anywhere.allow_paths_outside = true;
    tb_scene_file_options project = tb_scene_file_options_default();
    project.mesh_root = root;
    for (size_t i = 0; i < sizeof escapes / sizeof escapes[0]; ++i) {
        assert_int_equal(load_cube(escapes[i], scenes, &anywhere, &error), TB_STATUS_OK);
        assert_int_equal(load_cube(escapes[i], scenes, &project, &error), TB_STATUS_OK);
    }
    /* Inside is fine, also through a link that stays inside. */
    snprintf(path, sizeof path, "%s/inside.obj", scenes);
    write_text(path, CUBE_VERTICES CUBE_FACES);
    snprintf(link_path, sizeof link_path, "%s/inner_link.obj", scenes);
    assert_int_equal(symlink("inside.obj", link_path), 0);
    assert_int_equal(load_cube(CUBE_SCENE("inside.obj"), scenes, NULL, &error), TB_STATUS_OK);
    assert_int_equal(load_cube(CUBE_SCENE("inner_link.obj"), scenes, NULL, &error), TB_STATUS_OK);
    /* Options not made by the default function are refused. */
    tb_scene_file_options raw;
    memset(&raw, 0, sizeof raw);
    tb_scene *scene = (tb_scene *)&raw;
    assert_int_equal(tb_scene_load_string_with_options(CUBE_SCENE("inside.obj"), "m.json", scenes,
                                                       &raw, &scene, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_null(scene);
    assert_non_null(strstr(error.message, "options"));
}

/* The scene file's folder is kept whole however long (a 1024-byte buffer once dropped folders
 * of 1023 bytes or more, and meshes were read from the current directory); a path the system
 * cannot take is an error naming it, not a shorter path. */
static void test_long_scene_folders_are_kept_or_refused(void **state)
{
    (void)state;
    char folder[2048];
    fresh_folder(folder, sizeof folder, "long_folder");
    char part[201];
    memset(part, 'd', 200);
    part[200] = '\0';
    for (int level = 0; level < 6; ++level) { /* 6 x 201 bytes: past 1023 */
        snprintf(folder + strlen(folder), sizeof folder - strlen(folder), "/%s", part);
        assert_int_equal(mkdir(folder, 0700), 0);
    }
    assert_true(strlen(folder) > 1206);
    char path[2200];
    snprintf(path, sizeof path, "%s/long_cube.obj", folder);
    write_text(path, CUBE_VERTICES CUBE_FACES);
    snprintf(path, sizeof path, "%s/scene.json", folder);
    write_text(path, CUBE_SCENE("long_cube.obj"));
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, NULL, &error), TB_STATUS_OK);
    tb_mass_properties mass;
    tb_scene_get_mass(scene, 0, &mass);
    assert_near(mass.mass, 8.0, 1e-12);
    tb_scene_destroy(scene);

    /* A scene file whose path is longer than the system takes (PATH_MAX, 4096 on Linux),
     * made one folder at a time. */
    int parent = open(folder, O_RDONLY | O_DIRECTORY);
    assert_true(parent >= 0);
    size_t length = strlen(folder);
    for (; length <= 4200; length += 201) {
        assert_int_equal(mkdirat(parent, part, 0700), 0);
        const int child = openat(parent, part, O_RDONLY | O_DIRECTORY);
        assert_true(child >= 0);
        close(parent);
        parent = child;
    }
    const int scene_file = openat(parent, "scene.json", O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(scene_file >= 0);
    close(scene_file);
    close(parent);
    static char too_long[8192];
    snprintf(too_long, sizeof too_long, "%s", folder);
    for (size_t k = strlen(folder); k < length; k += 201) {
        snprintf(too_long + k, sizeof too_long - k, "/%s", part);
    }
    snprintf(too_long + strlen(too_long), sizeof too_long - strlen(too_long), "/scene.json");
    assert_int_equal(tb_scene_load_file(too_long, &scene, NULL, &error), TB_STATUS_IO_ERROR);
    assert_null(scene);
    assert_non_null(strstr(error.message, "File name too long"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_scene_file_builds_what_the_api_builds),
        cmocka_unit_test(test_bad_scene_files_are_refused_naming_the_place),
        cmocka_unit_test(test_max_steps_applies_to_a_fixed_step_too),
        cmocka_unit_test(test_deeply_nested_json_is_refused),
        cmocka_unit_test(test_mesh_files_are_read_relative_to_the_scene),
        cmocka_unit_test(test_long_obj_lines_are_one_line),
        cmocka_unit_test(test_obj_statements_are_read_ignored_or_refused_by_line),
        cmocka_unit_test(test_a_nul_byte_in_an_obj_file_is_refused_by_line),
        cmocka_unit_test(test_obj_reader_takes_regular_files_of_bounded_size),
        cmocka_unit_test(test_mesh_files_stay_inside_the_scene_folder),
        cmocka_unit_test(test_long_scene_folders_are_kept_or_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
