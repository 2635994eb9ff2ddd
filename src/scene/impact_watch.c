/* Unresolved impacts (include/tumble/contact_events.h, tb_scene_unresolved_impacts): where a
 * fixed step is longer than an impact's push, the step cannot resolve its restitution (an
 * L-stable step damps the bounce away). The scene counts those impacts with a watch of its own,
 * the contact events' (contact_event_watch.c) without a callback: each begin comes with its
 * pair's inverse mass, from which the effect's law (tb__effect_stepping.impact_law) gives the
 * impact's rate and duration.
 *
 * The watch is made only where some impact could count: a fixed step whose dt times the scene's
 * fastest oscillation (the stability guard's bound, which every pair's impact rate is below) is
 * above the method's resolution (tb__scene_impact_resolution). At the default step, under an
 * adaptive method, or where the guard holds an explicit method, there is no watch and no cost.
 * The watch reads the states at step boundaries and changes nothing, so a run's results are the
 * same bit for bit with and without it. */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "tumble/contact_events.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct tb__impacts {
    const tb_scene *scene;
    struct tb__event_watch *watch; /* NULL while not watched */
    double dt, resolution;         /* s, and the h omega resolved */
    double latest;                 /* s: the latest counted impact's time (-inf: none) */
    tb_unresolved_impacts found;
};

struct tb__event_watch *tb__scene_impact_watch(const tb_scene *scene)
{
    return scene->impacts != NULL ? scene->impacts->watch : NULL;
}

void tb__scene_impacts_free(tb_scene *scene)
{
    if (scene->impacts != NULL) {
        tb__event_watch_free(scene->impacts->watch);
        free(scene->impacts);
        scene->impacts = NULL;
    }
}

/* Whether a is to be kept over b as the fastest: faster, or as fast and earlier. */
static bool faster(const tb_impact *a, const tb_impact *b)
{
    return a->speed > b->speed || (a->speed == b->speed && a->t < b->t);
}

static bool earlier(const tb_impact *a, const tb_impact *b)
{
    if (a->t != b->t) {
        return a->t < b->t;
    }
    return a->body_a != b->body_a ? a->body_a < b->body_a : a->body_b < b->body_b;
}

/* tb__event_begin_fn: a begin, counted where it is an impact too fast for the step. */
static void seen(void *ctx, const struct tb_contact_event *event, const tb__event_pair *pair)
{
    struct tb__impacts *impacts = ctx;
    const tb__effect *effect = &impacts->scene->effects[event->effect];
    if (tb__stepping_of(effect)->impact_law == NULL || !(pair->inverse_mass > 0.0)) {
        return;
    }
    struct tb__impact_law law;
    tb__stepping_of(effect)->impact_law(effect, impacts->scene, pair, &law);
    if (!(event->speed > law.gravity * impacts->dt) ||
        !(law.rate * impacts->dt > impacts->resolution)) {
        return;
    }
    const tb_impact impact = {.t = event->t,
                              .body_a = event->body_a,
                              .body_b = event->body_b,
                              .effect = event->effect,
                              .speed = event->speed,
                              .duration = law.duration,
                              .steps = law.duration / impacts->dt};
    tb_unresolved_impacts *found = &impacts->found;
    if (found->count == 0 || earlier(&impact, &found->first)) {
        found->first = impact;
    }
    if (found->count == 0 || faster(&impact, &found->fastest)) {
        found->fastest = impact;
    }
    found->count++;
    impacts->latest = fmax(impacts->latest, impact.t);
}

/* Whether an effect of the scene makes impacts. */
static bool has_impacts(const tb_scene *scene)
{
    for (size_t k = 0; k < scene->effect_count; ++k) {
        if (tb__stepping_of(&scene->effects[k])->impact_law != NULL) {
            return true;
        }
    }
    return false;
}

tb_status tb__scene_impacts_prepare(tb_scene *scene, const double *y, tb_method method, double dt,
                                    struct tb__impacts **out_pending)
{
    *out_pending = NULL;
    double oscillation = 0.0;
    const double resolution = tb_method_is_adaptive(method) || !has_impacts(scene)
                                  ? INFINITY
                                  : tb__scene_impact_resolution(scene, y, method, &oscillation);
    const bool watched = dt * oscillation > resolution;
    if (!watched) {
        return TB_STATUS_OK;
    }
    struct tb__impacts *impacts = calloc(1, sizeof *impacts);
    struct tb__event_watch *watch =
        impacts != NULL ? tb__event_watch_create(scene, seen, impacts) : NULL;
    if (watch == NULL) {
        free(impacts);
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY,
                              "the count of unresolved impacts: room for the pairs of %zu bodies",
                              scene->body_count);
    }
    *impacts = (struct tb__impacts){.scene = scene,
                                    .watch = watch,
                                    .dt = dt,
                                    .resolution = resolution,
                                    .latest = -INFINITY,
                                    .found = {.watched = true, .dt = dt, .resolution = resolution}};
    *out_pending = impacts;
    return TB_STATUS_OK;
}

void tb__scene_impacts_commit(tb_scene *scene, struct tb__impacts *pending)
{
    tb__scene_impacts_free(scene);
    scene->impacts = pending;
}

void tb__scene_impacts_reset(tb_scene *scene, double t)
{
    struct tb__impacts *impacts = scene->impacts;
    if (impacts == NULL || !(impacts->latest > t)) {
        return; /* forward, or before no counted impact: the count stands */
    }
    /* the run goes back over an impact it counted, and will meet it again: the three figures
     * cannot forget it alone, so the count starts again at t */
    impacts->found.count = 0;
    memset(&impacts->found.first, 0, sizeof impacts->found.first);
    memset(&impacts->found.fastest, 0, sizeof impacts->found.fastest);
    impacts->latest = -INFINITY;
}

void tb__scene_impacts_discard(struct tb__impacts *pending)
{
    if (pending != NULL) {
        tb__event_watch_free(pending->watch);
        free(pending);
    }
}

tb_status tb_scene_unresolved_impacts(const tb_scene *scene, tb_unresolved_impacts *out)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    if (out == NULL) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_NULL_POINTER, "out is NULL");
    }
    memset(out, 0, sizeof *out);
    if (scene->impacts == NULL) {
        return TB_STATUS_OK;
    }
    *out = scene->impacts->found;
    const size_t dropped = tb__event_watch_dropped(scene->impacts->watch);
    if (dropped > 0) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_MEMORY,
                              "unresolved impacts: %zu pairs not watched (the list could not "
                              "grow): impacts may be missing",
                              dropped);
    }
    return TB_STATUS_OK;
}
