/* Scene files: a keyframed body's "keys" and "interpolation" (docs/scene-format.md, "keys").
 * The keys are checked by tb_keyframes_create itself, so the file and the C API refuse the same
 * keys with the same words, here prefixed with the body's path. */
#include "io/scene_file_internal.h"

#include "core/detail.h"
#include "core/validate.h"

#include <stdio.h>
#include <stdlib.h>

/* One key object: "t", "position", "orientation", optional "velocity", "angular_velocity". */
static tb_status load_key(tb__loader *ld, const json_t *value, const char *where, tb_body_key *key)
{
    static const char *const allowed[] = {"t",        "position",         "orientation",
                                          "velocity", "angular_velocity", NULL};
    *key = tb_body_key_default();
    tb_status status = tb__json_object(ld, value, where, allowed);
    if (status == TB_STATUS_OK) {
        status = tb__json_number(ld, value, where, "t", true, &key->t);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, value, where, "position", 3, true, key->position);
    }
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, value, where, "orientation", 4, true, key->orientation);
    }
    key->has_velocity = json_object_get(value, "velocity") != NULL;
    if (status == TB_STATUS_OK) {
        status = tb__json_vector(ld, value, where, "velocity", 3, false, key->velocity);
    }
    key->has_angular_velocity = json_object_get(value, "angular_velocity") != NULL;
    if (status == TB_STATUS_OK) {
        status =
            tb__json_vector(ld, value, where, "angular_velocity", 3, false, key->angular_velocity);
    }
    return status;
}

/* "interpolation": a name tb_interpolation_parse knows; "cubic" when absent. */
static tb_status load_interpolation(tb__loader *ld, const json_t *body, const char *path,
                                    tb_interpolation *out)
{
    const char *name = NULL;
    tb_status status = tb__json_string(ld, body, path, "interpolation", false, &name);
    *out = TB_INTERPOLATION_CUBIC;
    tb_error error;
    if (status == TB_STATUS_OK && name != NULL &&
        tb_interpolation_parse(name, out, &error) != TB_STATUS_OK) {
        char where[160];
        snprintf(where, sizeof where, "%s%sinterpolation", path, path[0] ? "." : "");
        status = tb__load_fail(ld, TB_STATUS_BAD_SCENE, where, "%s", error.message);
    }
    return status;
}

/* The keys as tb_keyframes_create sees them: its refusal, whose detail starts with the key
 * ("keys[2].t: ..."), becomes the body's ("scene.json: bodies[1].keys[2].t: ..."). */
static tb_status check_keys(tb__loader *ld, const char *path, const tb_body_key *keys, size_t count,
                            tb_interpolation interpolation)
{
    tb_keyframes *keyframes = NULL;
    tb_error error;
    const tb_status status = tb_keyframes_create(keys, count, interpolation, &keyframes, &error);
    tb_keyframes_destroy(keyframes);
    if (status == TB_STATUS_OUT_OF_MEMORY) {
        return tb__load_fail(ld, status, path, "keys: %s", error.message);
    }
    if (status != TB_STATUS_OK) {
        return tb__set_error(ld->error, TB_STATUS_BAD_SCENE, "%s: %s%s%s", ld->name, path,
                             path[0] ? "." : "", error.message);
    }
    return TB_STATUS_OK;
}

tb_status tb__load_keys(tb__loader *ld, const json_t *body, const char *path,
                        tb_body_key **out_keys, size_t *out_count,
                        tb_interpolation *out_interpolation)
{
    const json_t *list = json_object_get(body, "keys");
    char where[160];
    snprintf(where, sizeof where, "%s%skeys", path, path[0] ? "." : "");
    if (!json_is_array(list) || json_array_size(list) == 0) {
        return tb__load_fail(ld, TB_STATUS_BAD_SCENE, where,
                             "must be a non-empty array of {t, position, orientation}, got %s",
                             list == NULL          ? "nothing"
                             : json_is_array(list) ? "an empty array"
                                                   : tb__json_kind(list));
    }
    tb_interpolation interpolation;
    tb_status status = load_interpolation(ld, body, path, &interpolation);
    const size_t count = json_array_size(list);
    tb_body_key *keys = status == TB_STATUS_OK ? tb__malloc_array(count, sizeof *keys) : NULL;
    if (status == TB_STATUS_OK && keys == NULL) {
        status = tb__load_fail(ld, TB_STATUS_OUT_OF_MEMORY, where, "%zu keys", count);
    }
    for (size_t k = 0; k < count && status == TB_STATUS_OK; ++k) {
        char item[176];
        tb__path_index(item, sizeof item, path, "keys", k);
        status = load_key(ld, json_array_get(list, k), item, &keys[k]);
    }
    if (status == TB_STATUS_OK) {
        status = check_keys(ld, path, keys, count, interpolation);
    }
    if (status != TB_STATUS_OK) {
        free(keys);
        return status;
    }
    *out_keys = keys;
    *out_count = count;
    *out_interpolation = interpolation;
    return TB_STATUS_OK;
}
