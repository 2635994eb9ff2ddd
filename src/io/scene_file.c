/* Scene files: parsing with jansson, JSON helpers that name the place of every error, and the
 * top level, integrator and output sections. Bodies and effects have files of their own. */
#include "io/scene_file_internal.h"

#include "core/detail.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

tb_status tb__load_fail(tb__loader *ld, tb_status status, const char *path, const char *format, ...)
{
    char message[TB_DETAIL_SIZE];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return tb__set_error(ld->error, status, "%s: %s%s%s", ld->name, path, path[0] ? ": " : "",
                         message);
}

static const char *kind_of(const json_t *value)
{
    switch (json_typeof(value)) {
    case JSON_OBJECT:
        return "an object";
    case JSON_ARRAY:
        return "an array";
    case JSON_STRING:
        return "a string";
    case JSON_INTEGER:
    case JSON_REAL:
        return "a number";
    case JSON_TRUE:
    case JSON_FALSE:
        return "a boolean";
    default:
        return "null";
    }
}

void tb__path_index(char *out, size_t size, const char *path, const char *key, size_t index)
{
    snprintf(out, size, "%s%s%s[%zu]", path, path[0] && key[0] ? "." : "", key, index);
}

/* "path.key" */
static void member_path(char *out, size_t size, const char *path, const char *key)
{
    snprintf(out, size, "%s%s%s", path, path[0] ? "." : "", key);
}

tb_status tb__json_object(tb__loader *ld, const json_t *value, const char *path,
                          const char *const *allowed)
{
    if (!json_is_object(value)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, path, "must be an object, got %s",
                             kind_of(value));
    }
    const char *key;
    const json_t *member;
    json_object_foreach((json_t *)value, key, member)
    {
        bool known = false;
        for (size_t k = 0; allowed[k] != NULL && !known; ++k) {
            known = strcmp(key, allowed[k]) == 0;
        }
        if (!known) {
            char list[160] = "";
            for (size_t k = 0; allowed[k] != NULL; ++k) {
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", k ? ", " : "",
                         allowed[k]);
            }
            char where[160];
            member_path(where, sizeof where, path, key);
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "unknown key (known here: %s)",
                                 list);
        }
    }
    return TB_STATUS_OK;
}

/* The member, or NULL; fails if it is required and missing. */
static tb_status member(tb__loader *ld, const json_t *object, const char *path, const char *key,
                        bool required, const char *expected, const json_t **out)
{
    *out = json_object_get(object, key);
    if (*out == NULL && required) {
        char where[160];
        member_path(where, sizeof where, path, key);
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "missing (%s)", expected);
    }
    return TB_STATUS_OK;
}

static tb_status number_value(tb__loader *ld, const json_t *value, const char *where, double *out)
{
    if (!json_is_number(value)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be a number, got %s",
                             kind_of(value));
    }
    const double number = json_number_value(value);
    if (!isfinite(number)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be finite, got %g", number);
    }
    *out = number;
    return TB_STATUS_OK;
}

tb_status tb__json_number(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          bool required, double *out)
{
    const json_t *value;
    tb_status status = member(ld, object, path, key, required, "a number", &value);
    if (status != TB_STATUS_OK || value == NULL) {
        return status;
    }
    char where[160];
    member_path(where, sizeof where, path, key);
    return number_value(ld, value, where, out);
}

tb_status tb__json_numbers(tb__loader *ld, const json_t *value, const char *where, size_t n,
                           double *out)
{
    if (!json_is_array(value) || json_array_size(value) != n) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "must be an array of %zu numbers, "
                             "got %s%s",
                             n, kind_of(value), json_is_array(value) ? " of another length" : "");
    }
    double values[16];
    for (size_t i = 0; i < n && i < 16; ++i) {
        char item[176];
        snprintf(item, sizeof item, "%s[%zu]", where, i);
        tb_status status = number_value(ld, json_array_get(value, i), item, &values[i]);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    memcpy(out, values, n * sizeof(double));
    return TB_STATUS_OK;
}

tb_status tb__json_vector(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          size_t n, bool required, double *out)
{
    const json_t *value;
    char expected[48];
    snprintf(expected, sizeof expected, "an array of %zu numbers", n);
    tb_status status = member(ld, object, path, key, required, expected, &value);
    if (status != TB_STATUS_OK || value == NULL) {
        return status;
    }
    char where[160];
    member_path(where, sizeof where, path, key);
    return tb__json_numbers(ld, value, where, n, out);
}

tb_status tb__json_string(tb__loader *ld, const json_t *object, const char *path, const char *key,
                          bool required, const char **out)
{
    const json_t *value;
    tb_status status = member(ld, object, path, key, required, "a string", &value);
    if (status != TB_STATUS_OK || value == NULL) {
        return status;
    }
    if (!json_is_string(value)) {
        char where[160];
        member_path(where, sizeof where, path, key);
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be a string, got %s",
                             kind_of(value));
    }
    *out = json_string_value(value);
    return TB_STATUS_OK;
}

tb_status tb__json_count(tb__loader *ld, const json_t *object, const char *path, const char *key,
                         bool required, long *out)
{
    double value = (double)*out;
    tb_status status = tb__json_number(ld, object, path, key, required, &value);
    if (status == TB_STATUS_OK && (value != floor(value) || value < 0 || value > 1e9)) {
        char where[160];
        member_path(where, sizeof where, path, key);
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                               "must be a whole number from 0 to 1e9, got %g", value);
    }
    if (status == TB_STATUS_OK) {
        *out = (long)value;
    }
    return status;
}

tb_status tb__check_positive_at(tb__loader *ld, const char *path, const char *key, double value)
{
    if (!(value > 0)) {
        char where[160];
        member_path(where, sizeof where, path, key);
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be > 0, got %g", value);
    }
    return TB_STATUS_OK;
}

tb_status tb__check_non_negative_at(tb__loader *ld, const char *path, const char *key, double value)
{
    if (!(value >= 0)) {
        char where[160];
        member_path(where, sizeof where, path, key);
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "must be >= 0, got %g", value);
    }
    return TB_STATUS_OK;
}

/* --- integrator and output ---------------------------------------------------------------- */

static tb_status load_linear_solver(tb__loader *ld, const json_t *object, tb_integrator_def *def)
{
    const char *name = NULL;
    tb_status status = tb__json_string(ld, object, "integrator", "linear_solver", false, &name);
    if (status != TB_STATUS_OK || name == NULL) {
        return status;
    }
    static const char *const names[] = {"auto", "dense", "krylov"};
    for (int k = 0; k < 3; ++k) {
        if (strcmp(name, names[k]) == 0) {
            def->linear_solver = (tb_linear_solver)k;
            return TB_STATUS_OK;
        }
    }
    return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.linear_solver",
                         "must be one of auto, dense, krylov, got \"%s\"", name);
}

/* Settings of the other kind of method are refused rather than ignored: a "dt" next to
 * "cvode-bdf" is a mistake the user should hear about. */
static tb_status check_settings_fit(tb__loader *ld, const json_t *object, tb_method method)
{
    static const char *const fixed_only[] = {"dt", "allow_unstable", NULL};
    static const char *const adaptive_only[] = {"rtol",      "atol",          "max_steps",
                                                "max_order", "linear_solver", NULL};
    const bool adaptive = tb_method_is_adaptive(method);
    const char *const *wrong = adaptive ? fixed_only : adaptive_only;
    for (size_t k = 0; wrong[k] != NULL; ++k) {
        if (json_object_get(object, wrong[k]) != NULL) {
            char where[64];
            snprintf(where, sizeof where, "integrator.%s", wrong[k]);
            return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "applies to %s methods, not to %s",
                                 adaptive ? "fixed-step (euler, midpoint, rk4)"
                                          : "adaptive (cvode-adams, cvode-bdf)",
                                 tb_method_name(method));
        }
    }
    return TB_STATUS_OK;
}

static tb_status load_integrator(tb__loader *ld, const json_t *object)
{
    static const char *const keys[] = {"method",    "dt",        "rtol",          "atol",
                                       "max_steps", "max_order", "linear_solver", "allow_unstable",
                                       NULL};
    tb_status status = tb__json_object(ld, object, "integrator", keys);
    tb_integrator_def *def = &ld->run.integrator;
    const char *method = NULL;
    if (status == TB_STATUS_OK) {
        status = tb__json_string(ld, object, "integrator", "method", false, &method);
    }
    if (status == TB_STATUS_OK && method != NULL &&
        tb_method_from_name(method, &def->method) != TB_STATUS_OK) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.method",
                               "must be one of euler, midpoint, rk4, cvode-adams, cvode-bdf, got "
                               "\"%s\"",
                               method);
    }
    if (status == TB_STATUS_OK) {
        status = check_settings_fit(ld, object, def->method);
    }
    long max_order = def->max_order;
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "integrator", "dt", false, &def->dt);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "integrator", "dt", def->dt);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "integrator", "rtol", false, &def->rtol);
    }
    if (status == TB_STATUS_OK && !(def->rtol >= 1e-15 && def->rtol < 1)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.rtol",
                               "must be in [1e-15, 1), got %g", def->rtol);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "integrator", "atol", false, &def->atol);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_non_negative_at(ld, "integrator", "atol", def->atol);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_count(ld, object, "integrator", "max_steps", false, &def->max_steps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "integrator", "max_steps", (double)def->max_steps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_count(ld, object, "integrator", "max_order", false, &max_order);
    }
    if (status == TB_STATUS_OK && max_order > tb_method_order(def->method)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.max_order",
                               "must be at most %d for %s, got %ld", tb_method_order(def->method),
                               tb_method_name(def->method), max_order);
    }
    def->max_order = (int)max_order;
    const json_t *unstable = json_object_get(object, "allow_unstable");
    if (status == TB_STATUS_OK && unstable != NULL && !json_is_boolean(unstable)) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "integrator.allow_unstable",
                               "must be true or false, got %s", kind_of(unstable));
    }
    tb_scene_set_allow_unstable(ld->scene, unstable != NULL && json_is_true(unstable));
    return status == TB_STATUS_OK ? load_linear_solver(ld, object, def) : status;
}

static tb_status load_output(tb__loader *ld, const json_t *object)
{
    static const char *const keys[] = {"fps", "duration", NULL};
    tb_status status = tb__json_object(ld, object, "output", keys);
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "output", "fps", false, &ld->run.fps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_positive_at(ld, "output", "fps", ld->run.fps);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, object, "output", "duration", false, &ld->run.duration);
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_non_negative_at(ld, "output", "duration", ld->run.duration);
    }
    return status;
}

/* --- top level ---------------------------------------------------------------------------- */

static tb_status load_document(tb__loader *ld, const json_t *root)
{
    static const char *const keys[] = {"description", "bodies", "effects",
                                       "integrator",  "output", NULL};
    tb_status status = tb__json_object(ld, root, "", keys);
    const char *description = NULL;
    if (status == TB_STATUS_OK) {
        status = tb__json_string(ld, root, "", "description", false, &description);
    }
    const json_t *bodies = json_object_get(root, "bodies");
    if (status == TB_STATUS_OK && bodies == NULL) {
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, "bodies",
                               "missing (an array of at least one body)");
    }
    if (status == TB_STATUS_OK) {
        status = tb__load_bodies(ld, bodies);
    }
    const json_t *section = json_object_get(root, "effects");
    if (status == TB_STATUS_OK && section != NULL) {
        status = tb__load_effects(ld, section);
    }
    section = json_object_get(root, "integrator");
    if (status == TB_STATUS_OK && section != NULL) {
        status = load_integrator(ld, section);
    }
    section = json_object_get(root, "output");
    if (status == TB_STATUS_OK && section != NULL) {
        status = load_output(ld, section);
    }
    return status;
}

static tb_status load_json(tb__loader *ld, json_t *root, tb_scene **out_scene, tb_run_def *out_run)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_error scene_error;
    tb_status status = tb_scene_create(&scene_def, &ld->scene, &scene_error);
    if (status != TB_STATUS_OK) {
        json_decref(root);
        return tb__load_fail(ld, status, "", "%s", scene_error.message);
    }
    ld->run = tb_run_def_default();
    status = load_document(ld, root);
    json_decref(root);
    if (status != TB_STATUS_OK) {
        tb_scene_destroy(ld->scene);
        return status;
    }
    *out_scene = ld->scene;
    if (out_run != NULL) {
        *out_run = ld->run;
    }
    return TB_STATUS_OK;
}

/* JSON syntax errors: "name:line:column: text"; a file that cannot be read: an I/O error. */
static tb_status syntax_error(tb__loader *ld, const json_error_t *error)
{
    if (error->line < 0) {
        return tb__set_error(ld->error, TB_STATUS_IO_ERROR, "%s: cannot read: %s", ld->name,
                             error->text);
    }
    return tb__set_error(ld->error, TB_STATUS_PARSE_ERROR, "%s:%d:%d: %s", ld->name, error->line,
                         error->column, error->text);
}

tb_status tb_scene_load_string(const char *json, const char *name, const char *base_directory,
                               tb_scene **out_scene, tb_run_def *out_run, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (json == NULL || out_scene == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             json == NULL ? "json" : "out_scene");
    }
    *out_scene = NULL;
    tb__loader ld = {.name = name != NULL ? name : "<string>",
                     .directory = base_directory != NULL ? base_directory : "",
                     .error = out_error};
    json_error_t error;
    json_t *root = json_loads(json, JSON_REJECT_DUPLICATES, &error);
    if (root == NULL) {
        return syntax_error(&ld, &error);
    }
    return load_json(&ld, root, out_scene, out_run);
}

tb_status tb_scene_load_file(const char *path, tb_scene **out_scene, tb_run_def *out_run,
                             tb_error *out_error)
{
    tb__clear_error(out_error);
    if (path == NULL || out_scene == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             path == NULL ? "path" : "out_scene");
    }
    *out_scene = NULL;
    char directory[1024] = "";
    const char *slash = strrchr(path, '/');
    if (slash != NULL && (size_t)(slash - path) < sizeof directory - 1) {
        memcpy(directory, path, (size_t)(slash - path) + 1);
        directory[slash - path + 1] = '\0';
    }
    tb__loader ld = {.name = path, .directory = directory, .error = out_error};
    /* Open and probe it here, so that a directory or unreadable file is reported as what it
     * is rather than as JSON that ended early. */
    FILE *file = fopen(path, "rb");
    const int first = file != NULL ? fgetc(file) : EOF;
    if (file == NULL || (first == EOF && ferror(file))) {
        const int reason = errno;
        if (file != NULL) {
            fclose(file);
        }
        return tb__set_error(out_error, TB_STATUS_IO_ERROR, "%s: cannot read: %s", path,
                             strerror(reason));
    }
    ungetc(first, file);
    json_error_t error;
    json_t *root = json_loadf(file, JSON_REJECT_DUPLICATES, &error);
    fclose(file);
    if (root == NULL) {
        return syntax_error(&ld, &error);
    }
    return load_json(&ld, root, out_scene, out_run);
}
