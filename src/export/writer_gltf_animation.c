/* Writers: glTF animation channels from the frames: per body a LINEAR translation of its shape
 * origin and a rotation of its shape frame, both in tumble's world (the root node turns them
 * to glTF's y up). Quaternions go out as glTF orders them, (x, y, z, w), each key on the side
 * of the previous one (q and -q are one rotation; the spline and slerp must not go the long
 * way round). */
#include "export/writer_gltf_internal.h"

#include "core/validate.h"
#include "math/tb_math.h"

#include <stdlib.h>

/* Key k's quaternion of body id, (w, x, y, z), turned to the hemisphere of previous. */
static void key_quaternion(const tb__frames *f, size_t k, size_t id, const double previous[4],
                           double q[4])
{
    const double *source = f->orientation + 4 * (k * f->body_count + id);
    const double dot = source[0] * previous[0] + source[1] * previous[1] + source[2] * previous[2] +
                       source[3] * previous[3];
    const double sign = dot < 0 ? -1.0 : 1.0;
    for (int i = 0; i < 4; ++i) {
        q[i] = sign * source[i];
    }
}

/* glTF's (x, y, z, w) order. */
static void put_xyzw(float *out, const double q[4])
{
    out[0] = (float)q[1];
    out[1] = (float)q[2];
    out[2] = (float)q[3];
    out[3] = (float)q[0];
}

/* Rotation sampler output: LINEAR keys, or CUBICSPLINE triples (in-tangent, value,
 * out-tangent) with both tangents dq/dt = 1/2 (0, omega) (x) q (omega in the world, rad/s; the
 * shape frame's quaternion obeys the same equation as the principal frame's, which differs
 * from it by a constant factor on the right). */
static void rotation_keys(const tb__frames *f, size_t id, bool cubic, float *out)
{
    double previous[4] = {1, 0, 0, 0}, q[4], dq[4];
    for (size_t k = 0; k < f->count; ++k) {
        key_quaternion(f, k, id, previous, q);
        for (int i = 0; i < 4; ++i) {
            previous[i] = q[i];
        }
        if (!cubic) {
            put_xyzw(out + 4 * k, q);
            continue;
        }
        const double *omega = f->angular_velocity + 3 * (k * f->body_count + id);
        const double half_omega[4] = {0.0, 0.5 * omega[0], 0.5 * omega[1], 0.5 * omega[2]};
        tb__q_mul(dq, half_omega, q);
        put_xyzw(out + 12 * k, dq);
        put_xyzw(out + 12 * k + 4, q);
        put_xyzw(out + 12 * k + 8, dq);
    }
}

static json_t *sampler(long input, long output, const char *interpolation)
{
    return json_pack("{s:i, s:i, s:s}", "input", (json_int_t)input, "output", (json_int_t)output,
                     "interpolation", interpolation);
}

static json_t *channel(size_t sampler_index, size_t node, const char *path)
{
    return json_pack("{s:i, s:{s:i, s:s}}", "sampler", (json_int_t)sampler_index, "target", "node",
                     (json_int_t)node, "path", path);
}

static long times_accessor(tb__gltf *g, const tb__frames *f, float *scratch)
{
    for (size_t k = 0; k < f->count; ++k) {
        scratch[k] = (float)f->t[k];
    }
    const double first = scratch[0], last = scratch[f->count - 1];
    return tb__gltf_accessor(g, scratch, f->count, TB__GLTF_SCALAR, TB__GLTF_ANIMATION, &first,
                             &last);
}

/* Body id's two samplers and channels; its node is id + 1 (node 0 is the root). */
static void body_channels(tb__gltf *g, const tb__frames *f, size_t id, bool cubic, long times,
                          float *scratch, json_t *samplers, json_t *channels)
{
    for (size_t k = 0; k < f->count; ++k) {
        for (int i = 0; i < 3; ++i) {
            scratch[3 * k + i] = (float)f->position[3 * (k * f->body_count + id) + i];
        }
    }
    const long translation =
        tb__gltf_accessor(g, scratch, f->count, TB__GLTF_VEC3, TB__GLTF_ANIMATION, NULL, NULL);
    rotation_keys(f, id, cubic, scratch);
    const long rotation = tb__gltf_accessor(g, scratch, (cubic ? 3 : 1) * f->count, TB__GLTF_VEC4,
                                            TB__GLTF_ANIMATION, NULL, NULL);
    json_array_append_new(channels, channel(json_array_size(samplers), id + 1, "translation"));
    json_array_append_new(samplers, sampler(times, translation, "LINEAR"));
    json_array_append_new(channels, channel(json_array_size(samplers), id + 1, "rotation"));
    json_array_append_new(samplers, sampler(times, rotation, cubic ? "CUBICSPLINE" : "LINEAR"));
}

void tb__gltf_add_animation(tb__gltf *g, const tb_writer *w)
{
    const tb__frames *f = &w->frames;
    if (f->count < 2 || w->body_count == 0) {
        return; /* one frame is a still: the nodes hold it (glTF wants 2 keys a spline) */
    }
    float *scratch =
        tb__malloc_array(f->count, 12 * sizeof *scratch); /* the largest: cubic rotation */
    if (scratch == NULL) {
        g->failed = true;
        return;
    }
    const bool cubic = w->rotation_keys == TB_ROTATION_CUBICSPLINE;
    const long times = times_accessor(g, f, scratch);
    json_t *samplers = json_array(), *channels = json_array();
    for (size_t id = 0; id < w->body_count; ++id) {
        body_channels(g, f, id, cubic, times, scratch, samplers, channels);
    }
    free(scratch);
    json_array_append_new(g->animations, json_pack("{s:s, s:o, s:o}", "name", "tumble run",
                                                   "channels", channels, "samplers", samplers));
}
