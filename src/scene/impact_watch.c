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
#include "core/validate.h"
#include "tumble/contact_events.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Impacts the log has room for when it is made: head_on_balls' one and the cradle's 16 in 1.5 s
 * without a step allocating; past it the log doubles at the impact that fills it. */
#define LOG_START 32

struct tb__impacts {
    const tb_scene *scene;
    struct tb__event_watch *watch; /* NULL while not watched */
    double dt, resolution;         /* s, and the h omega resolved */
    double latest;                 /* s: the latest counted impact's time (-inf: none) */
    tb_unresolved_impacts found;
    /* every counted impact, in the order seen, so that a reset to t keeps those at or before
     * it; short: one could not be logged (memory), and such a reset starts again at zero */
    tb_impact *log;
    size_t logged, log_capacity;
    bool short_log;
};

struct tb__event_watch *tb__scene_impact_watch(const tb_scene *scene)
{
    return scene->impacts != NULL ? scene->impacts->watch : NULL;
}

void tb__scene_impacts_free(tb_scene *scene)
{
    tb__scene_impacts_discard(scene->impacts);
    scene->impacts = NULL;
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

/* impact counted into found's three figures. */
static void add(tb_unresolved_impacts *found, const tb_impact *impact)
{
    if (found->count == 0 || earlier(impact, &found->first)) {
        found->first = *impact;
    }
    if (found->count == 0 || faster(impact, &found->fastest)) {
        found->fastest = *impact;
    }
    found->count++;
}

/* impact into the log, which doubles when full (at an impact, never at other steps). */
static void log_impact(struct tb__impacts *impacts, const tb_impact *impact)
{
    if (impacts->logged == impacts->log_capacity) {
        const size_t capacity = 2 * impacts->log_capacity;
        tb_impact *log = tb__realloc_array(impacts->log, capacity, sizeof *log);
        if (log == NULL) {
            impacts->short_log = true;
            return;
        }
        impacts->log = log;
        impacts->log_capacity = capacity;
    }
    impacts->log[impacts->logged++] = *impact;
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
    add(&impacts->found, &impact);
    impacts->latest = fmax(impacts->latest, impact.t);
    log_impact(impacts, &impact);
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
    tb_impact *log = tb__malloc_array(LOG_START, sizeof *log);
    struct tb__event_watch *watch =
        impacts != NULL && log != NULL ? tb__event_watch_create(scene, seen, impacts) : NULL;
    if (watch == NULL) {
        free(log);
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
                                    .found = {.watched = true, .dt = dt, .resolution = resolution},
                                    .log = log,
                                    .log_capacity = LOG_START};
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
    /* the run goes back over impacts it counted, and will meet them again: the count keeps
     * those at or before t (all of them logged), or starts again at zero (a log left short) */
    tb_unresolved_impacts *found = &impacts->found;
    found->count = 0;
    memset(&found->first, 0, sizeof found->first);
    memset(&found->fastest, 0, sizeof found->fastest);
    impacts->latest = -INFINITY;
    size_t kept = 0;
    for (size_t k = 0; k < impacts->logged && !impacts->short_log; ++k) {
        if (impacts->log[k].t <= t) {
            add(found, &impacts->log[k]);
            impacts->latest = fmax(impacts->latest, impacts->log[k].t);
            impacts->log[kept++] = impacts->log[k];
        }
    }
    impacts->logged = kept;
    impacts->short_log = false;
}

void tb__scene_impacts_discard(struct tb__impacts *pending)
{
    if (pending != NULL) {
        tb__event_watch_free(pending->watch);
        free(pending->log);
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
