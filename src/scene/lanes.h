/* Private: the scene's derivative and renormalisation in lane layout (tb_ode_system.blocks.lanes),
 * for the vector unit. A lane group holds the 13 states of up to TB__LANES bodies component by
 * component: component c of lane j at [c * lanes + j]. The kernels (lanes_kernels.c and the
 * effects' lane forms in effect_lanes.c) are compiled once per vector path the build targets,
 * with TB_LANES_TARGET naming it, and the scene picks one path's table at run time
 * (vector_path.c). Every lane's arithmetic is the body-by-body path's, operation for operation
 * (no contraction into FMA: the kernels are built with -ffp-contract=off), so every path gives
 * the same bits. */
#ifndef TUMBLE_LANES_H
#define TUMBLE_LANES_H

#include "scene/scene_internal.h"

#include "tumble/ode.h"

/* Bodies per lane group: 32 (a chunk's four buffers of 416 doubles sit in L1), or 8 for a scene
 * of fewer than 32 bodies (less padding); no lanes below 8 bodies. */
#define TB__LANES 32
#define TB__LANES_SMALL 8

/* Lanes per group for a scene of `bodies` bodies, 0 for none. */
static inline size_t tb__lanes_for(size_t bodies)
{
    return bodies >= TB__LANES ? TB__LANES : bodies >= TB__LANES_SMALL ? TB__LANES_SMALL : 0;
}

/* The bodies' constants of a lane group, each a row of `lanes` (the lanes past the last body
 * repeat it): mass, inverse mass, the three inverse moments. */
enum { TB__LANE_MASS, TB__LANE_INV_MASS, TB__LANE_INV_MOMENTS, TB__LANE_CONSTANTS = 5 };

/* A lane group during one derivative: the bodies [first, first + count) in `lanes` lanes (the
 * lanes past count repeat the last body), their constants, and what the kinematics found. */
typedef struct tb__lanes {
    const tb_scene *scene;
    const double *y;
    double *dydt;
    size_t first, count, lanes;
    const double *constants;    /* TB__LANE_CONSTANTS rows of lanes */
    double omega[3][TB__LANES]; /* world angular velocity (rad/s) */
} tb__lanes;

/* Lays the bodies' constants out for the lane kernels (scene->lane_constants), growing the
 * array if needed; TB_STATUS_OUT_OF_MEMORY (nothing changed) if it cannot. */
tb_status tb__scene_prepare_lanes(tb_scene *scene);

/* One vector path's kernels. */
typedef struct tb__lanes_kernels {
    tb_ode_block_derivative derivative; /* tb_ode_system.blocks.lanes_derivative */
    tb_ode_block_hook normalize;        /* tb_ode_system.blocks.lanes_post_step */
} tb__lanes_kernels;

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define TB__LANES_X86 1
#endif

extern const tb__lanes_kernels tb__lanes_kernels_baseline;
#ifdef TB__LANES_X86
extern const tb__lanes_kernels tb__lanes_kernels_avx2;
extern const tb__lanes_kernels tb__lanes_kernels_avx512;
#endif

/* The kernels of the path the scene would use now, or NULL for none (tb_scene_set_vector_path;
 * too few bodies). */
const tb__lanes_kernels *tb__scene_lanes_kernels(const tb_scene *scene);

/* Before a loop over lanes whose arrays do not overlap (restrict on local pointers does not
 * tell gcc so, and too many pointers defeat its run-time alias checks). */
#if defined(__clang__)
#define TB__LANES_LOOP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define TB__LANES_LOOP _Pragma("GCC ivdep")
#else
#define TB__LANES_LOOP
#endif

/* Name of a per-target symbol: TB__LANES_NAME(x) is x_<target>. */
#define TB__LANES_CAT2(a, b) a##_##b
#define TB__LANES_CAT(a, b) TB__LANES_CAT2(a, b)
#define TB__LANES_NAME(x) TB__LANES_CAT(x, TB_LANES_TARGET)

/* An effect's lane form: its apply_bodies on every body of a lane group, operation for
 * operation. A kind's row (tb__effect_ops.lanes) holds one per vector path, the kernels of path
 * TB_LANES_TARGET call the member of that name (the effects' forms: src/effects/effect_lanes.h). */
typedef void (*tb__effect_lanes_form)(const tb__effect *effect, const tb__lanes *lanes);
struct tb__effect_lanes {
    tb__effect_lanes_form baseline;
    tb__effect_lanes_form avx2;   /* x86-64 only (TB__LANES_X86) */
    tb__effect_lanes_form avx512; /* x86-64 only */
};

#endif
