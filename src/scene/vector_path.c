/* Run-time choice of the vector path (tumble/scene.h tb_vector_path): which of the lane
 * kernels compiled into this build (lanes.h) the processor can run, and which one a scene's
 * integrators use. Reads the processor's features only; keeps no state. */
#include "scene/lanes.h"

#include "core/detail.h"
#include "core/validate.h"

#include <stdlib.h>
#include <string.h>

static const char *const path_names[TB_VECTOR_PATH_COUNT] = {"auto", "none", "baseline", "avx2",
                                                             "avx512"};

const char *tb_vector_path_name(tb_vector_path path)
{
    return (int)path >= 0 && path < TB_VECTOR_PATH_COUNT ? path_names[path] : NULL;
}

tb_status tb_vector_path_parse(const char *name, tb_vector_path *out_path)
{
    if (name == NULL || out_path == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    for (int k = 0; k < TB_VECTOR_PATH_COUNT; ++k) {
        if (strcmp(name, path_names[k]) == 0) {
            *out_path = (tb_vector_path)k;
            return TB_STATUS_OK;
        }
    }
    return TB_STATUS_INVALID_ARGUMENT;
}

/* The kernels of a path if this build has them and the processor runs them, else NULL (also
 * for AUTO and NONE). */
static const tb__lanes_kernels *path_kernels(tb_vector_path path)
{
    switch (path) {
    case TB_VECTOR_PATH_BASELINE:
        return &tb__lanes_kernels_baseline;
#ifdef TB__LANES_X86
    case TB_VECTOR_PATH_AVX2:
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") ? &tb__lanes_kernels_avx2 : NULL;
    case TB_VECTOR_PATH_AVX512:
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx512f") ? &tb__lanes_kernels_avx512 : NULL;
#endif
    default:
        return NULL;
    }
}

bool tb_vector_path_supported(tb_vector_path path)
{
    return path == TB_VECTOR_PATH_AUTO || path == TB_VECTOR_PATH_NONE || path_kernels(path) != NULL;
}

tb_vector_path tb_vector_path_best(void)
{
    for (int k = TB_VECTOR_PATH_COUNT - 1; k > TB_VECTOR_PATH_BASELINE; --k) {
        if (path_kernels((tb_vector_path)k) != NULL) {
            return (tb_vector_path)k;
        }
    }
    return TB_VECTOR_PATH_BASELINE;
}

tb_status tb_scene_set_vector_path(tb_scene *scene, tb_vector_path path)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if ((int)path < 0 || path >= TB_VECTOR_PATH_COUNT) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT, "path: unknown vector path %d",
                              (int)path);
    }
    if (!tb_vector_path_supported(path)) {
        return tb__scene_fail(scene, TB_STATUS_UNSUPPORTED,
                              "path: %s is not supported by this processor or build (best: %s)",
                              path_names[path], path_names[tb_vector_path_best()]);
    }
    scene->vector_path = (int)path;
    return TB_STATUS_OK;
}

tb_vector_path tb_scene_vector_path(const tb_scene *scene)
{
    return scene == NULL ? TB_VECTOR_PATH_COUNT : (tb_vector_path)scene->vector_path;
}

const tb__lanes_kernels *tb__scene_lanes_kernels(const tb_scene *scene)
{
    if (tb__lanes_for(scene->slot_count) == 0 || scene->vector_path == TB_VECTOR_PATH_NONE) {
        return NULL;
    }
    const tb_vector_path path = scene->vector_path == TB_VECTOR_PATH_AUTO
                                    ? tb_vector_path_best()
                                    : (tb_vector_path)scene->vector_path;
    return path_kernels(path);
}

tb_status tb__scene_prepare_lanes(tb_scene *scene)
{
    const size_t lanes = tb__lanes_for(scene->slot_count);
    const size_t groups = (scene->slot_count + lanes - 1) / lanes;
    const size_t size = groups * lanes * TB__LANE_CONSTANTS;
    if (size > scene->lane_constants_size) {
        double *grown = tb__realloc_array(scene->lane_constants, size, sizeof(double));
        if (grown == NULL) {
            return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY,
                                  "the lane layout of %zu bodies' constants", scene->slot_count);
        }
        scene->lane_constants = grown;
        scene->lane_constants_size = size;
    }
    for (size_t g = 0; g < groups; ++g) {
        double *rows = scene->lane_constants + g * lanes * TB__LANE_CONSTANTS;
        for (size_t j = 0; j < lanes; ++j) {
            const size_t i =
                g * lanes + j < scene->slot_count ? g * lanes + j : scene->slot_count - 1;
            const tb__body *body = &scene->bodies[i];
            rows[TB__LANE_MASS * lanes + j] = body->mass;
            rows[TB__LANE_INV_MASS * lanes + j] = body->inv_mass;
            for (size_t k = 0; k < 3; ++k) {
                rows[(TB__LANE_INV_MOMENTS + k) * lanes + j] = body->inv_moments[k];
            }
        }
    }
    return TB_STATUS_OK;
}
