/* A ground plane's checks of its set-up: contact points and shapes that start too deep in the
 * plane or reach too far for its penetration. They run outside the derivative. */
#include "effects/effect_ground.h"

#include "core/detail.h"
#include "effects/effect_contact_check.h"
#include "effects/ground_shapes.h"
#include "math/tb_math.h"

#include <float.h>

/* How deep (in penetrations) a body may start inside a plane. The contact pushes a point d deep
 * with d / penetration times the weight it carries, and would launch the body at about
 * d sqrt(g / penetration): 2.8 cm/s from 10 penetrations at the defaults, 1 m/s with
 * penetration 1e-3, 366 m/s (damped, penetration 1e-3) from 10 m. Deeper than this is a set-up
 * mistake, refused. */
#define TB__START_DEPTH_PENETRATIONS 10.0

tb_status tb__ground_check_shape(const tb__effect *effect, tb_scene *scene, size_t id)
{
    if (!tb__ground_meets_shape(effect, scene, id)) {
        return TB_STATUS_OK;
    }
    return tb__contact_check_shape_size(scene, id, tb__ground_of(effect)->penetration,
                                        (size_t)(effect - scene->effects), "a ground plane");
}

tb_status tb__ground_shapes_check_sizes(const tb__effect *effect, tb_scene *scene)
{
    tb_status status = TB_STATUS_OK;
    for (size_t id = 0; id < scene->body_count && status == TB_STATUS_OK; ++id) {
        if (tb__ground_meets_shape(effect, scene, id)) {
            status = tb__contact_check_shape_size(scene, id, tb__ground_of(effect)->penetration,
                                                  scene->effect_count, "a ground plane");
        }
    }
    return status;
}

tb_status tb__ground_shapes_check_start(const tb__effect *effect, const tb_scene *scene,
                                        const double *y, size_t first, size_t end, double limit,
                                        char *detail)
{
    for (size_t id = first; id < end; ++id) {
        double depth;
        int touching;
        if (tb__ground_shape_touch(effect, scene, y, id, &depth, &touching) && depth > limit) {
            return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                                  "body %zu (\"%s\"): its shape starts %.3g m inside the ground "
                                  "plane, deeper than %.3g m (10 penetrations), from which the "
                                  "contact would launch it: start it above the plane",
                                  id, scene->names[id], depth, limit);
        }
    }
    return TB_STATUS_OK;
}

/* Refuses contact point j when it starts deeper than TB__START_DEPTH_PENETRATIONS penetrations
 * inside the plane, naming the body and its depth, or lies so far from its body's centre of mass
 * that its depth's rounding exceeds the penetration (F95, as a shape's). */
static tb_status check_point_start(const tb__ground_params *ground, const tb_scene *scene,
                                   const double *y, size_t j, char *detail)
{
    const tb__contact *c = &scene->contacts[j];
    const double reach = tb__v3_norm(c->r) + c->radius;
    if (!(reach * DBL_EPSILON <= ground->penetration)) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "body %zu (\"%s\"): contact point %zu lies %.3g m from its centre of "
                              "mass, where its depth is known to %.3g m only, more than the ground "
                              "plane's penetration %.3g m: its contact force would be rounding "
                              "noise larger than its weight; bring the point in or give the plane "
                              "a larger penetration",
                              c->body, scene->names[c->body], j, reach, reach * DBL_EPSILON,
                              ground->penetration);
    }
    const double limit = TB__START_DEPTH_PENETRATIONS * ground->penetration;
    tb__motion motion;
    tb__body_motion_at(scene, scene->time, y, c->body, &motion);
    double arm[3];
    const double depth = tb__ground_point_depth(ground, c, &motion, arm);
    if (depth > limit) {
        return tb__set_detail(detail, TB_STATUS_INVALID_ARGUMENT,
                              "body %zu (\"%s\"): starts %.3g m inside the ground plane (contact "
                              "point %zu), deeper than %g penetrations (%.3g m), from which the "
                              "contact would launch it: start it above the plane",
                              c->body, scene->names[c->body], depth, j,
                              TB__START_DEPTH_PENETRATIONS, limit);
    }
    return TB_STATUS_OK;
}

tb_status tb__ground_check_start(const tb__effect *effect, const tb_scene *scene, const double *y,
                                 char *detail)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    tb_status status = tb__ground_shapes_refresh(effect, scene, detail);
    for (size_t j = 0; j < scene->contact_count && status == TB_STATUS_OK; ++j) {
        status = check_point_start(ground, scene, y, j, detail);
    }
    const double limit = TB__START_DEPTH_PENETRATIONS * ground->penetration;
    return status == TB_STATUS_OK ? tb__ground_shapes_check_start(effect, scene, y, 0,
                                                                  scene->body_count, limit, detail)
                                  : status;
}

tb_status tb__ground_check_points(const tb__effect *effect, const tb_scene *scene, const double *y,
                                  size_t id, size_t first, char *detail)
{
    const tb__ground_params *ground = tb__ground_of(effect);
    const tb_status noted =
        tb__ground_shapes_note_points(effect, scene, id, first < scene->contact_count, detail);
    tb_status status = noted;
    for (size_t j = first; j < scene->contact_count && status == TB_STATUS_OK; ++j) {
        status = check_point_start(ground, scene, y, j, detail);
    }
    if (status == TB_STATUS_OK) {
        status = tb__ground_check_shape(effect, (tb_scene *)scene, id); /* its size (F95) */
    }
    const double limit = TB__START_DEPTH_PENETRATIONS * ground->penetration;
    if (status == TB_STATUS_OK) {
        status = tb__ground_shapes_check_start(effect, scene, y, id, id + 1, limit, detail);
    }
    if (noted == TB_STATUS_OK && status != TB_STATUS_OK) { /* refused: the flag as it was */
        tb__ground_shapes_unnote(effect);
    }
    return status;
}
