/* Writers: the scene's joints as drawn (glTF): each joint's anchor in its first body's shape
 * frame, where a marker rides with the body's node, and the marker's size. */
#include "export/writer_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"
#include "tumble/joints.h"

#include <math.h>
#include <stdlib.h>

/* 1.5 times the body's smallest principal radius of gyration sqrt(I_min / M), so that the
 * sphere stands out of a thin body (a box's I_min is M (a^2 + b^2) / 12 for its two shorter
 * sides: 1.5 sqrt of it passes half of the shortest, a / 2), at most half its largest (a plate
 * would make it large); 1 cm when the mass properties give no length. */
static double marker_radius(const tb__look *look)
{
    const tb_mass_properties *m = &look->mass;
    const double smallest = fmin(m->moments[0], fmin(m->moments[1], m->moments[2]));
    const double largest = fmax(m->moments[0], fmax(m->moments[1], m->moments[2]));
    const double radius = fmin(1.5 * sqrt(smallest / m->mass), 0.5 * sqrt(largest / m->mass));
    return isfinite(radius) && radius > 0 ? radius : 0.01;
}

tb_status tb__looks_joints(tb__looks *looks, const tb_scene *scene, tb_error *error)
{
    const size_t count = tb_scene_joint_count(scene);
    if (count == 0) {
        return TB_STATUS_OK;
    }
    looks->joints = tb__malloc_array(count, sizeof *looks->joints);
    if (looks->joints == NULL) {
        return tb__set_error(error, TB_STATUS_OUT_OF_MEMORY, "writer: %zu joints", count);
    }
    const double *y = tb_scene_states_const(scene);
    for (size_t j = 0; j < count; ++j) {
        tb_joint_def def;
        tb_scene_joint_def(scene, j, &def);
        tb__joint_mark *mark = &looks->joints[j];
        mark->type = tb_joint_type_name(def.type);
        mark->body_a = def.body_a;
        mark->body_b = def.body_b;
        double origin[3], q[4];
        tb_scene_body_shape_pose(scene, y, def.body_a, origin, q);
        const double arm[3] = {def.anchor[0] - origin[0], def.anchor[1] - origin[1],
                               def.anchor[2] - origin[2]};
        tb__q_rotate_inverse(mark->anchor, q, arm);
        mark->radius = marker_radius(&looks->bodies[def.body_a]);
    }
    looks->joint_count = count;
    return TB_STATUS_OK;
}
