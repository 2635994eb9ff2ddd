#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geometry.h"

#include "math/tb_math.h"

tb__collision_shape *test_shape(const tb_shape *shape)
{
    char detail[256] = "";
    tb_status status;
    tb__collision_shape *made = tb__collision_shape_make(shape, detail, &status);
    if (made == NULL) {
        fail_msg("shape refused: %s", detail);
    }
    return made;
}

tb__collision_shape *test_sphere(double radius)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_SPHERE;
    s.radius = radius;
    return test_shape(&s);
}

tb__collision_shape *test_box(double x, double y, double z)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_BOX;
    tb__v3_set(s.size, x, y, z);
    return test_shape(&s);
}

tb__collision_shape *test_capsule(double radius, double length)
{
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CAPSULE;
    s.radius = radius;
    s.length = length;
    return test_shape(&s);
}

void test_pose(double pose[TB__POSE_SIZE], double x, double y, double z, const double axis[3],
               double angle)
{
    tb__v3_set(pose, x, y, z);
    const double n = tb__v3_norm(axis), s = sin(0.5 * angle) / n;
    pose[3] = cos(0.5 * angle);
    tb__v3_set(pose + 4, s * axis[0], s * axis[1], s * axis[2]);
}

double test_uniform(uint64_t *state, double low, double high)
{
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    return low + (high - low) * (double)(*state >> 11) * 0x1.0p-53;
}

void test_random_quaternion(uint64_t *state, double q[4])
{
    const double u1 = test_uniform(state, 0, 1), u2 = test_uniform(state, 0, 6.283185307179586),
                 u3 = test_uniform(state, 0, 6.283185307179586);
    const double a = sqrt(1 - u1), b = sqrt(u1);
    q[0] = a * sin(u2);
    q[1] = a * cos(u2);
    q[2] = b * sin(u3);
    q[3] = b * cos(u3);
}
