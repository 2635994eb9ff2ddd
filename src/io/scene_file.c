/* Scene files: parsing with jansson, JSON helpers that name the place of every error, and the
 * top level, integrator and output sections. Bodies, effects and joints have files of their
 * own. */
#include "io/scene_file_internal.h"

#include "core/detail.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TB__OPTIONS_COOKIE 0x5f11e

tb_scene_file_options tb_scene_file_options_default(void)
{
    tb_scene_file_options options;
    memset(&options, 0, sizeof options);
    options.allow_paths_outside = false;
    options.mesh_root = NULL;
    options.max_mesh_file_bytes = TB_SCENE_FILE_MAX_MESH_BYTES;
    options.internal_cookie = TB__OPTIONS_COOKIE;
    return options;
}

/* The options, or the defaults for NULL; refused if not made by the default function. */
static tb_status take_options(const tb_scene_file_options *options, tb_scene_file_options *out,
                              tb_error *error)
{
    *out = options != NULL ? *options : tb_scene_file_options_default();
    if (out->internal_cookie != TB__OPTIONS_COOKIE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "options: not initialised by tb_scene_file_options_default()");
    }
    if (out->max_mesh_file_bytes == 0) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "options.max_mesh_file_bytes: must be > 0, got 0");
    }
    return TB_STATUS_OK;
}

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

const char *tb__json_kind(const json_t *value)
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
                             tb__json_kind(value));
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
                             tb__json_kind(value));
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
                             n, tb__json_kind(value),
                             json_is_array(value) ? " of another length" : "");
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
                             tb__json_kind(value));
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

/* --- top level ---------------------------------------------------------------------------- */

/* "sleeping": true (the default) or false: whether islands of resting bodies sleep. */
static tb_status load_sleeping(tb__loader *ld, const json_t *root)
{
    const json_t *sleeping = json_object_get(root, "sleeping");
    if (sleeping != NULL && !json_is_boolean(sleeping)) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, "sleeping", "must be true or false, got %s",
                             tb__json_kind(sleeping));
    }
    return tb_scene_set_sleeping(ld->scene, sleeping == NULL || json_is_true(sleeping));
}

static tb_status load_document(tb__loader *ld, const json_t *root)
{
    static const char *const keys[] = {"description", "bodies", "effects",  "joints",
                                       "integrator",  "output", "sleeping", NULL};
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
    section = json_object_get(root, "joints");
    if (status == TB_STATUS_OK && section != NULL) {
        status = tb__load_joints(ld, section);
    }
    section = json_object_get(root, "integrator");
    if (status == TB_STATUS_OK && section != NULL) {
        status = tb__load_integrator(ld, section);
    }
    /* no dt: the scene's default step (tb_scene_default_step), resolved for the method run */
    if (status == TB_STATUS_OK && !tb_method_is_adaptive(ld->run.integrator.method) &&
        (section == NULL || json_object_get(section, "dt") == NULL)) {
        ld->run.integrator.dt = 0.0;
    }
    section = json_object_get(root, "output");
    if (status == TB_STATUS_OK && section != NULL) {
        status = tb__load_output(ld, section);
    }
    return status == TB_STATUS_OK ? load_sleeping(ld, root) : status;
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

tb_status tb_scene_load_string_with_options(const char *json, const char *name,
                                            const char *base_directory,
                                            const tb_scene_file_options *options,
                                            tb_scene **out_scene, tb_run_def *out_run,
                                            tb_error *out_error)
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
    tb_status status = take_options(options, &ld.options, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    json_error_t error;
    json_t *root = json_loads(json, JSON_REJECT_DUPLICATES, &error);
    if (root == NULL) {
        return syntax_error(&ld, &error);
    }
    return load_json(&ld, root, out_scene, out_run);
}

tb_status tb_scene_load_string(const char *json, const char *name, const char *base_directory,
                               tb_scene **out_scene, tb_run_def *out_run, tb_error *out_error)
{
    return tb_scene_load_string_with_options(json, name, base_directory, NULL, out_scene, out_run,
                                             out_error);
}

/* (A fixed buffer once dropped folders of 1023 bytes or more, and meshes were read from the
 * current directory instead.) */
char *tb__folder_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    const size_t length = slash != NULL ? (size_t)(slash - path) + 1 : 0;
    char *folder = malloc(length + 1);
    if (folder != NULL) {
        memcpy(folder, path, length);
        folder[length] = '\0';
    }
    return folder;
}

/* Opens and probes path, so that a directory or unreadable file is reported as what it is
 * rather than as JSON that ended early. */
static tb_status open_scene_file(const char *path, const char *shown, FILE **out, tb_error *error)
{
    FILE *file = fopen(path, "rb");
    const int first = file != NULL ? fgetc(file) : EOF;
    if (file == NULL || (first == EOF && ferror(file))) {
        const int reason = errno;
        if (file != NULL) {
            fclose(file);
        }
        return tb__set_error(error, TB_STATUS_IO_ERROR, "%s: cannot read: %s", shown,
                             strerror(reason));
    }
    ungetc(first, file);
    *out = file;
    return TB_STATUS_OK;
}

tb_status tb_scene_load_file_with_options(const char *path, const tb_scene_file_options *options,
                                          tb_scene **out_scene, tb_run_def *out_run,
                                          tb_error *out_error)
{
    tb__clear_error(out_error);
    if (path == NULL || out_scene == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             path == NULL ? "path" : "out_scene");
    }
    *out_scene = NULL;
    tb__loader ld = {.error = out_error};
    tb__shown_path(ld.shown_name, path);
    ld.name = ld.shown_name;
    FILE *file = NULL;
    tb_status status = take_options(options, &ld.options, out_error);
    if (status == TB_STATUS_OK) {
        status = open_scene_file(path, ld.name, &file, out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    char *directory = tb__folder_of(path);
    if (directory == NULL) {
        fclose(file);
        return tb__set_error(out_error, TB_STATUS_OUT_OF_MEMORY, "%s: the folder's name", ld.name);
    }
    ld.directory = directory;
    json_error_t error;
    json_t *root = json_loadf(file, JSON_REJECT_DUPLICATES, &error);
    fclose(file);
    status = root == NULL ? syntax_error(&ld, &error) : load_json(&ld, root, out_scene, out_run);
    free(directory);
    return status;
}

tb_status tb_scene_load_file(const char *path, tb_scene **out_scene, tb_run_def *out_run,
                             tb_error *out_error)
{
    return tb_scene_load_file_with_options(path, NULL, out_scene, out_run, out_error);
}
