/* Writers: the scene's joints as drawn (glTF) and described (USD): each joint's anchor in its
 * first body's shape frame, where a marker rides with the body's node, and the marker's size;
 * the anchor and the joint's frame (x along its axis) in both bodies' shape frames. */
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

/* The rotation taking x = (1, 0, 0) to the unit vector n the shortest way: (1 + n.x, x cross
 * n) normalised, i.e. (cos h, sin h k) for the turn 2h about k; n = -x turns pi about z. */
static void frame_of_axis(const double n[3], double q[4])
{
    const double w = 1.0 + n[0];
    if (w < 1e-12) {
        q[0] = 0.0, q[1] = 0.0, q[2] = 0.0, q[3] = 1.0;
        return;
    }
    const double norm = sqrt(w * w + n[2] * n[2] + n[1] * n[1]);
    q[0] = w / norm, q[1] = 0.0, q[2] = -n[2] / norm, q[3] = n[1] / norm;
}

/* Where the anchor and the joint's frame (joint -> world, q_joint) sit in body's shape frame
 * (the world's for TB_WORLD): anchor R^T (a - o), frame q* q_joint. */
static void in_body_frame(const tb_scene *scene, const double *y, size_t body,
                          const double anchor[3], const double q_joint[4], double out_anchor[3],
                          double out_frame[4])
{
    double origin[3] = {0.0, 0.0, 0.0}, q[4] = {1.0, 0.0, 0.0, 0.0};
    if (body != TB_WORLD) {
        tb_scene_body_shape_pose(scene, y, body, origin, q);
    }
    const double arm[3] = {anchor[0] - origin[0], anchor[1] - origin[1], anchor[2] - origin[2]};
    tb__q_rotate_inverse(out_anchor, q, arm);
    const double conjugate[4] = {q[0], -q[1], -q[2], -q[3]};
    tb__q_mul(out_frame, conjugate, q_joint);
}

static void mark_joint(tb__joint_mark *mark, const tb_scene *scene, size_t j)
{
    tb_joint_def def;
    tb_scene_joint_def(scene, j, &def);
    const double *y = tb_scene_states_const(scene);
    mark->def = def;
    mark->type = tb_joint_type_name(def.type);
    mark->body_a = def.body_a;
    mark->body_b = def.body_b;
    double n[3] = {0.0, 0.0, 1.0}, q_joint[4];
    (void)tb__v3_direction(def.axis, n); /* non-zero: tb_scene_add_joint checked it */
    frame_of_axis(n, q_joint);
    in_body_frame(scene, y, def.body_a, def.anchor, q_joint, mark->anchor, mark->frame_a);
    in_body_frame(scene, y, def.body_b, def.anchor, q_joint, mark->anchor_b, mark->frame_b);
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
    for (size_t j = 0; j < count; ++j) {
        tb__joint_mark *mark = &looks->joints[j];
        mark_joint(mark, scene, j);
        mark->radius = marker_radius(&looks->bodies[mark->body_a]);
    }
    looks->joint_count = count;
    return TB_STATUS_OK;
}
