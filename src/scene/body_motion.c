/* The body-motion accessor: a body's slot in y, its constants and its motion at (t, y), by id.
 * Every read of a body's state goes through here, so that a body with no state is a case of
 * these functions and not of their callers. */
#include "scene/scene_internal.h"

#include <math.h>

/* What a body that cannot move offers every law: no inverse mass, no inverse inertia. */
static const tb__body immovable = {.mass = INFINITY};

const tb__body *tb__body_constants(const tb_scene *scene, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? &immovable : &scene->bodies[slot];
}

void tb__body_motion_at(const tb_scene *scene, double t, const double *y, size_t id,
                        tb__motion *out)
{
    (void)t;
    const size_t slot = scene->slots[id];
    tb__body_motion(&scene->bodies[slot], y + TB_STATE_SIZE * slot, out);
}

void tb__body_pose_at(const tb_scene *scene, double t, const double *y, size_t id, double out_x[3],
                      double out_q[4])
{
    (void)t;
    const double *s = y + TB_STATE_SIZE * scene->slots[id];
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
