/* Writers: a scene's joints in USD, each a UsdPhysics joint prim under /world: ball as
 * PhysicsSphericalJoint, hinge as PhysicsRevoluteJoint, slider as PhysicsPrismaticJoint, fixed
 * as PhysicsFixedJoint. physics:body0 is the joint's body_b (none for the world: the schema's
 * "empty for the world") and physics:body1 its body_a, so that the schema's joint coordinate
 * (body1's joint frame against body0's) is tumble's (body_a against body_b, docs/joints.md,
 * Limits). localPos0/1 and localRot0/1 place one joint frame, its x along the joint's axis
 * (physics:axis "X"), in each body's Xform (the shape frame; the world's for none), where the
 * bodies stand at the first frame. Limits in the schema's units: degrees (revolute), metres
 * (prismatic); break force N and torque N m (the stage's kilogramsPerUnit and metersPerUnit are
 * 1). The schema's attributes are floats (point3f, quatf, float): a joint's frames meet to
 * float rounding, about 6e-8 of the anchors' distances from the bodies' origins. A stop's
 * restitution, a motor and a soft joint have no attribute in UsdPhysics and are not written;
 * customData tumbleJoint names the type and the joint's index. */
#include "export/writer_internal.h"

#include <math.h>

#define TB__DEGREES_PER_RADIAN (180.0 / 3.14159265358979323846)

static const char *const prim_types[TB_JOINT_TYPE_COUNT] = {
    [TB_JOINT_BALL] = "PhysicsSphericalJoint",
    [TB_JOINT_HINGE] = "PhysicsRevoluteJoint",
    [TB_JOINT_SLIDER] = "PhysicsPrismaticJoint",
    [TB_JOINT_FIXED] = "PhysicsFixedJoint",
};

static void put_body(FILE *file, int k, size_t body, char (*body_prims)[TB__USD_NAME_SIZE])
{
    if (body != TB_WORLD) {
        fprintf(file, "        rel physics:body%d = </world/%s>\n", k, body_prims[body]);
    }
}

static void put_frame(FILE *file, int k, const double anchor[3], const double q[4])
{
    fprintf(file,
            "        point3f physics:localPos%d = (%.9g, %.9g, %.9g)\n"
            "        quatf physics:localRot%d = (%.9g, %.9g, %.9g, %.9g)\n",
            k, anchor[0], anchor[1], anchor[2], k, q[0], q[1], q[2], q[3]);
}

/* A hinge's limits in degrees, a slider's in metres; the axis they are about. */
static void put_limits(FILE *file, const tb_joint_def *def)
{
    if (def->type != TB_JOINT_HINGE && def->type != TB_JOINT_SLIDER) {
        return;
    }
    fputs("        uniform token physics:axis = \"X\"\n", file);
    if (def->has_limits) {
        const double scale = def->type == TB_JOINT_HINGE ? TB__DEGREES_PER_RADIAN : 1.0;
        fprintf(
            file,
            "        float physics:lowerLimit = %.9g\n        float physics:upperLimit = %.9g\n",
            def->limits[0] * scale, def->limits[1] * scale);
    }
}

void tb__usd_put_joint(const tb_writer *w, size_t j, const char *prim,
                       char (*body_prims)[TB__USD_NAME_SIZE])
{
    const tb__joint_mark *mark = &w->looks.joints[j];
    const tb_joint_def *def = &mark->def;
    FILE *file = w->file;
    fprintf(file,
            "    def %s \"%s\" (\n        customData = {\n            int tumbleIndex = %zu\n"
            "            string tumbleJoint = \"%s\"\n        }\n    )\n    {\n",
            prim_types[def->type], prim, j, mark->type);
    put_body(file, 0, mark->body_b, body_prims);
    put_body(file, 1, mark->body_a, body_prims);
    put_frame(file, 0, mark->anchor_b, mark->frame_b);
    put_frame(file, 1, mark->anchor, mark->frame_a);
    put_limits(file, def);
    if (isfinite(def->break_force)) {
        fprintf(file, "        float physics:breakForce = %.9g\n", def->break_force);
    }
    if (isfinite(def->break_torque)) {
        fprintf(file, "        float physics:breakTorque = %.9g\n", def->break_torque);
    }
    fputs("    }\n\n", file);
}
