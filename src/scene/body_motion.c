/* The body-motion accessor: a body's slot in y, its constants and its motion at (t, y), by id.
 * Every read of a body's state goes through here, so that a body with no state is a case of
 * these functions and not of their callers. */
#include "scene/scene_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <math.h>
#include <string.h>

static const char *const kind_names[] = {"dynamic", "static", "keyframed"};

/* What a body that cannot move offers every law: no inverse mass, no inverse inertia. */
static const tb__body immovable = {.mass = INFINITY};

const tb__body *tb__body_constants(const tb_scene *scene, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? &immovable : &scene->bodies[slot];
}

/* A static body's motion: its pose, at rest. */
static void fixed_motion(const tb__body_kind *kind, tb__motion *out)
{
    for (int k = 0; k < 3; ++k) {
        out->x[k] = kind->x[k];
        out->v[k] = 0.0;
        out->omega[k] = 0.0;
    }
    for (int k = 0; k < 4; ++k) {
        out->q[k] = kind->q[k];
    }
}

void tb__body_motion_at(const tb_scene *scene, double t, const double *y, size_t id,
                        tb__motion *out)
{
    (void)t;
    const size_t slot = scene->slots[id];
    if (slot == TB_NO_SLOT) {
        fixed_motion(&scene->kinds[id], out);
        return;
    }
    tb__body_motion(&scene->bodies[slot], y + TB_STATE_SIZE * slot, out);
}

void tb__body_pose_at(const tb_scene *scene, double t, const double *y, size_t id, double out_x[3],
                      double out_q[4])
{
    (void)t;
    const size_t slot = scene->slots[id];
    if (slot == TB_NO_SLOT) {
        tb__motion motion;
        fixed_motion(&scene->kinds[id], &motion);
        memcpy(out_x, motion.x, sizeof motion.x);
        memcpy(out_q, motion.q, sizeof motion.q);
        return;
    }
    const double *s = y + TB_STATE_SIZE * slot;
    out_x[0] = s[TB_STATE_X];
    out_x[1] = s[TB_STATE_X + 1];
    out_x[2] = s[TB_STATE_X + 2];
    tb__unit_quaternion(s, 0, out_q);
}

tb_status tb_scene_body_slot(const tb_scene *scene, size_t id, size_t *out_slot)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_slot == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_slot is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_slot = scene->slots[id];
    }
    return status;
}

tb_mass_properties tb__fixed_mass_properties(void)
{
    return (tb_mass_properties){.mass = INFINITY,
                                .moments = {INFINITY, INFINITY, INFINITY},
                                .rotation = {1.0, 0.0, 0.0, 0.0}};
}

tb_status tb__body_kind_from_def(tb_scene *scene, const tb_body_def *def, tb__body_kind *out)
{
    if (def->motion != TB_MOTION_STATIC && def->motion != TB_MOTION_KEYFRAMED) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.motion: %d is not a motion kind (TB_MOTION_DYNAMIC, "
                              "TB_MOTION_STATIC or TB_MOTION_KEYFRAMED)",
                              (int)def->motion);
    }
    const double *v = def->velocity, *w = def->angular_velocity;
    if (def->motion == TB_MOTION_STATIC &&
        (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 || w[0] != 0.0 || w[1] != 0.0 || w[2] != 0.0)) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def.%svelocity: a static body does not move, got (%g, %g, %g)",
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? "" : "angular_",
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[0] : w[0],
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[1] : w[1],
                              v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0 ? v[2] : w[2]);
    }
    out->motion = def->motion;
    const double norm = tb__q_norm(def->orientation);
    for (int k = 0; k < 4; ++k) {
        out->q[k] = def->orientation[k] / norm;
    }
    tb__v3_copy(out->x, def->position);
    return TB_STATUS_OK;
}

tb_status tb__scene_check_dynamic(const tb_scene *scene, size_t id, const char *what)
{
    if (scene->slots[id] == TB_NO_SLOT) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_INVALID_ARGUMENT,
                              "%s: body %zu (\"%s\") is %s: it has no state to change", what, id,
                              scene->names[id], kind_names[scene->kinds[id].motion]);
    }
    return TB_STATUS_OK;
}

tb_status tb_scene_body_motion_kind(const tb_scene *scene, size_t id, tb_body_motion *out_motion)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out_motion == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out_motion is NULL");
    }
    tb_status status = tb__scene_check_id(scene, id, "id");
    if (status == TB_STATUS_OK) {
        *out_motion = scene->kinds[id].motion;
    }
    return status;
}
