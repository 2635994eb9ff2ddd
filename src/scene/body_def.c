/* A body's definition checked, and the constants the derivative divides by (moved from
 * scene.c when body kinds made it too long; one concept: what a body is made from). */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "mass/mass_internal.h"

#include <math.h>
#include <string.h>

static tb_status validate_name(tb_scene *scene, const char *name)
{
    if (name == NULL) {
        return TB_STATUS_OK;
    }
    const size_t length = strlen(name);
    if (length == 0 || length >= TB_NAME_SIZE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.name: must have 1 to %d characters, got %zu", TB_NAME_SIZE - 1,
                              length);
    }
    size_t existing;
    if (tb__scene_lookup_name(scene, name, &existing)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.name: \"%s\" is already body %zu's name", name, existing);
    }
    return TB_STATUS_OK;
}

tb_status tb__scene_validate_body_def(tb_scene *scene, const tb_body_def *def)
{
    if (def->internal_cookie != TB__BODY_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_body_def_default()");
    }
    if (validate_name(scene, def->name) != TB_STATUS_OK) {
        return TB_STATUS_INVALID_ARGUMENT;
    }
    tb_error error;
    /* a body with no state needs no mass (tb__body_kind_from_def checks the rest) */
    tb_status status =
        def->motion == TB_MOTION_DYNAMIC ? tb_mass_validate(&def->mass, &error) : TB_STATUS_OK;
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "def.mass.%s", error.message);
    }
    status = tb__check_unit_quaternion(def->orientation, "def.orientation", &error);
    if (status != TB_STATUS_OK) {
        return tb__scene_fail(scene, status, "%s", error.message);
    }
    status = tb__check_vector(scene, def->position, "def.position");
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, def->velocity, "def.velocity");
    }
    if (status == TB_STATUS_OK) {
        status = tb__check_vector(scene, def->angular_velocity, "def.angular_velocity");
    }
    return status;
}

/* The constants the derivative divides by: a finite mass or moment whose inverse overflows
 * (a subnormal mass) is refused here, naming the field (NOT_FINITE: the value it makes is),
 * rather than turning every state into
 * infinity at the first step. */
tb_status tb__scene_body_constants(tb_scene *scene, const tb_mass_properties *props, tb__body *out)
{
    out->mass = props->mass;
    out->inv_mass = 1.0 / props->mass;
    if (!isfinite(out->inv_mass)) {
        return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                              "def.mass.mass: %g kg is too small: 1/mass overflows", props->mass);
    }
    for (int k = 0; k < 3; ++k) {
        out->inv_moments[k] = 1.0 / props->moments[k];
        if (!isfinite(out->inv_moments[k])) {
            return tb__scene_fail(scene, TB_STATUS_NOT_FINITE,
                                  "def.mass.moments[%d]: %g kg m^2 is too small: 1/moment "
                                  "overflows",
                                  k, props->moments[k]);
        }
    }
    return TB_STATUS_OK;
}
