/* Private: the body-motion accessor (body_motion.c). Every read of a body's state asks these,
 * by id; nothing else indexes y by body. Included at the end of scene_internal.h. */
#ifndef TUMBLE_BODY_MOTION_H
#define TUMBLE_BODY_MOTION_H

/* Body id's slot (the index of its 13 doubles in y), or TB_NO_SLOT. */
static inline size_t tb__body_slot(const tb_scene *scene, size_t id)
{
    return scene->slots[id];
}

/* Body id's 13 states in y (or its derivative in dydt), NULL for a body with no state. For
 * writers of a dynamic body's state and readers of its momenta. */
static inline const double *tb__body_state(const tb_scene *scene, const double *y, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? NULL : y + TB_STATE_SIZE * slot;
}
static inline double *tb__body_state_mut(const tb_scene *scene, double *y, size_t id)
{
    const size_t slot = scene->slots[id];
    return slot == TB_NO_SLOT ? NULL : y + TB_STATE_SIZE * slot;
}

/* Body id's constants: a dynamic body's, or for a body that cannot move an infinitely heavy
 * one (inverse mass and inverse inertia 0, mass INFINITY). */
const tb__body *tb__body_constants(const tb_scene *scene, size_t id);

/* Body id's motion at time t and state y: centre of mass, orientation, velocities. For a
 * dynamic body read from y (bit for bit tb__body_motion's). */
void tb__body_motion_at(const tb_scene *scene, double t, const double *y, size_t id,
                        tb__motion *out);
/* Its pose alone (centre of mass, unit principal -> world quaternion), as tb__body_motion_at
 * gives it, for the hot paths that need no velocity (shape poses of the broad phase). */
void tb__body_pose_at(const tb_scene *scene, double t, const double *y, size_t id, double out_x[3],
                      double out_q[4]);

/* dP += f and dL += arm x f for body id, by its slot (tb__add_load); nothing for a body with
 * no state (whose reaction is a read-out, not a state). */
void tb__add_body_load(const tb_scene *scene, double *dydt, size_t id, const double arm[3],
                       const double f[3]);

#endif
