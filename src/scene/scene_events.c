/* The scene's events for the generic integrators: one root function per body (its gap to what
 * it can touch, from every effect with events), the adaptive step limit near contacts and the
 * fixed-step limit that keeps bodies from passing through each other (effect rows:
 * tb__effect_stepping.event_gaps, adaptive_step_limit, tunnel_step). */
#include "scene/scene_internal.h"

#include "core/detail.h"

#include <math.h>
#include <stdio.h>

/* m: what an exactly zero gap becomes (tb__scene_event_gaps). */
#define TB__GAP_FOR_ZERO 1e-150

bool tb__scene_has_events(const tb_scene *scene)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        if (tb__stepping_of(&scene->effects[k])->event_gaps != NULL) {
            return true;
        }
    }
    return false;
}

/* Every body's gap (and, with wake not NULL, wake gap) at y: each effect's event_gaps, or its
 * wake_gaps doing both in one pass where there are wake gaps to find; with signs, exact in sign
 * only (tb__effect_stepping.event_gaps). */
static void fill_gaps(tb_scene *scene, double t, const double *y, double *gap, double *wake,
                      bool signs)
{
    scene->time = t; /* bodies without a state, at t */
    for (size_t i = 0; i < scene->body_count; ++i) {
        gap[i] = TB__EVENT_LOOKAHEAD;
    }
    for (size_t i = 0; i < scene->body_count && wake != NULL; ++i) {
        wake[i] = TB__EVENT_LOOKAHEAD;
    }
    /* nothing asleep: no pair of an awake and an asleep body, every wake gap the look-ahead */
    const bool any_asleep = scene->sleep != NULL && scene->sleep->asleep_count > 0;
    /* Effects with wake gaps (contact between bodies) last: their pass skips the pairs above
     * both bodies' gaps so far, more of them once the ground's are in; fmin is exact and
     * commutative, so the gaps are the same bits in any order. */
    for (int last = 0; last < 2; ++last) {
        for (size_t k = 0; k < scene->effect_count; ++k) {
            const tb__effect *effect = &scene->effects[k];
            const tb__effect_stepping *stepping = tb__stepping_of(effect);
            if ((stepping->wake_gaps != NULL) != (last == 1)) {
                continue;
            }
            if (wake != NULL && any_asleep && stepping->wake_gaps != NULL) {
                stepping->wake_gaps(effect, scene, y, stepping->event_gaps != NULL ? gap : NULL,
                                    wake, signs);
            } else if (stepping->event_gaps != NULL) {
                stepping->event_gaps(effect, scene, y, gap, signs);
            }
        }
    }
    /* A gap is a difference of positions (z ~ 0.2 m: doubles 3e-17 m apart), so a slow crossing
     * is exactly 0 over a stretch of time longer than CVODE's root tolerance, which it refuses
     * ("root found at and very near t"). A tiny positive gap in its place keeps the crossing and
     * removes the plateau; tiny, yet far from underflow, since CVODE finds a sign change from the
     * product of two values (DBL_MIN times -1e-16 rounds to -0, and the root came back for
     * ever). The wake gaps the same. */
    for (size_t i = 0; i < scene->body_count; ++i) {
        gap[i] = gap[i] == 0.0 ? TB__GAP_FOR_ZERO : gap[i];
    }
    for (size_t i = 0; i < scene->body_count && wake != NULL; ++i) {
        wake[i] = wake[i] == 0.0 ? TB__GAP_FOR_ZERO : wake[i];
    }
}

int tb__scene_event_gaps(double t, const double *y, double *gap, void *ctx)
{
    fill_gaps(ctx, t, y, gap, NULL, false);
    return 0;
}

static size_t constraint_root_count(const tb_scene *scene)
{
    const tb__constraint_ops *ops = scene->constraint_ops;
    return ops != NULL && ops->root_count != NULL ? ops->root_count(scene->constraints) : 0;
}

static size_t effect_root_count(const tb_scene *scene)
{
    return tb__scene_has_events(scene) ? (scene->sleep != NULL ? 2 : 1) * scene->body_count : 0;
}

size_t tb__scene_root_count(const tb_scene *scene)
{
    return effect_root_count(scene) + constraint_root_count(scene);
}

/* The effects' gaps (and wake gaps where bodies can sleep), then the constraints' roots. */
static int roots(tb_scene *scene, double t, const double *y, double *g, bool signs)
{
    const size_t effects = effect_root_count(scene);
    if (effects > 0) {
        fill_gaps(scene, t, y, g, effects > scene->body_count ? g + scene->body_count : NULL,
                  signs);
    }
    if (constraint_root_count(scene) > 0) {
        scene->time = t; /* bodies without a state, at t */
        return scene->constraint_ops->roots(scene->constraints, scene, t, y, g + effects);
    }
    return 0;
}

int tb__scene_roots(double t, const double *y, double *g, void *ctx)
{
    return roots(ctx, t, y, g, false);
}

int tb__scene_root_signs(double t, const double *y, double *g, void *ctx)
{
    return roots(ctx, t, y, g, true);
}

double tb__scene_step_limit(double t, const double *y, const double *dydt, void *ctx)
{
    tb_scene *scene = ctx;
    scene->time = t; /* bodies without a state, at t */
    /* asked once per accepted adaptive step, with its state: a boundary for contact events */
    tb__scene_events_observe(scene, t, y, false);
    double limit = INFINITY;
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *effect = &scene->effects[k];
        if (tb__stepping_of(effect)->step_start != NULL) {
            tb__stepping_of(effect)->step_start(effect, scene, y);
        }
        if (tb__stepping_of(effect)->adaptive_step_limit != NULL) {
            limit =
                fmin(limit, tb__stepping_of(effect)->adaptive_step_limit(effect, scene, y, dydt));
        }
    }
    return limit;
}

double tb__scene_tunnel_step(const tb_scene *scene, const double *y, double dt, char *which)
{
    double limit = INFINITY;
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *effect = &scene->effects[k];
        char what[TB_DETAIL_SIZE / 2];
        const double step =
            tb__stepping_of(effect)->tunnel_step != NULL
                ? tb__stepping_of(effect)->tunnel_step(effect, scene, y, dt, what, sizeof what)
                : INFINITY;
        if (step < limit) {
            limit = step;
            snprintf(which, TB_DETAIL_SIZE, "effect %zu (a %s): %s", k, effect->ops->name, what);
        }
    }
    return limit;
}

double tb__scene_split_limit(double t, const double *y, double h, void *ctx)
{
    tb_scene *scene = ctx;
    scene->time = t; /* bodies without a state, at t */
    char which[TB_DETAIL_SIZE];
    return tb__scene_tunnel_step(scene, y, h, which);
}

tb_status tb__scene_check_impacts(const tb_scene *scene, const double *y, char *detail)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        const tb__effect *effect = &scene->effects[k];
        char what[TB_DETAIL_SIZE];
        const tb_status status =
            tb__stepping_of(effect)->check_impacts != NULL
                ? tb__stepping_of(effect)->check_impacts(effect, scene, y, what)
                : TB_STATUS_OK;
        if (status != TB_STATUS_OK) {
            return tb__set_detail(detail, status, "effect %zu (a %s): %s", k, effect->ops->name,
                                  what);
        }
    }
    return TB_STATUS_OK;
}
