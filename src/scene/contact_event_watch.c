/* Contact events (include/tumble/contact_events.h): the pairs the effects find near each other
 * (tb__effect_ops.event_pairs) are watched from step boundary to step boundary, and a pair whose
 * gap changed sign in between gets its begin (and hit) or end.
 *
 * Times: between two boundaries t0 < t1 the pair's gap g(t) is the cubic Hermite of its values
 * and rates at both (the positions and velocities at the step's ends), and the event is where
 * that cubic crosses zero (bisection to the last bit). A fixed step's boundaries are its steps,
 * so the time's error is the cubic's, O(dt^4) (measured in tests/test_contact_events_api.c);
 * an adaptive method's are its accepted steps and its event stops, and the scene's root
 * functions (a gap per body) stop CVODE where a body's contact begins or ends, so the cubic's
 * zero lies at that stop.
 *
 * Impulse: the change of the pair's relative normal momentum over the contact, its effective
 * mass m (at the point, along the normal, at begin) times the change of the normal speed from
 * begin to end, plus m g tau for a uniform acceleration g that closes the pair and that the
 * pair's own motion does not cancel (a body on a ground plane, tau the contact's duration).
 * Exact for a pair that touches nothing else during the contact; for a pair in a stack the
 * other contacts' pushes count too (docs/events.md). */
#include "scene/scene_internal.h"

#include "core/detail.h"
#include "core/validate.h"
#include "math/tb_math.h"
#include "tumble/contact_events.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TB__CONTACT_EVENTS_COOKIE 0xe7e7
/* Bisection halvings of a step to locate a crossing: past the last bit of any step. */
#define TB__CROSSING_HALVINGS 64

/* A pair watched from one boundary to the next, with what its contact began with. */
typedef struct tb__watched_pair {
    tb__event_pair now;
    bool touching;
    bool has_older; /* seen at the boundary before too: */
    double older_t, older_gap, older_rate;
    double begin_t, begin_rate, inverse_mass, gravity;
} tb__watched_pair;

struct tb__event_watch {
    tb_contact_event_fn fn; /* NULL for a watch of the scene's own (impact_watch.c) */
    void *ctx;
    tb__event_begin_fn on_begin; /* NULL, or told of every begin with its pair's inverse mass */
    void *begin_ctx;
    double threshold;
    bool fixed;     /* which integrator kind's boundaries are heard */
    bool have_last; /* prev holds the pairs at last_t */
    double last_t;
    size_t capacity; /* pairs in prev, cur and found; 4 capacity events */
    tb__watched_pair *prev, *cur;
    size_t prev_count;
    tb__event_pair *found;
    tb_contact_event *events;
    size_t event_count;
    size_t dropped;
};

typedef struct tb__event_watch tb__watch;

const char *tb_contact_event_kind_name(tb_contact_event_kind kind)
{
    switch (kind) {
    case TB_CONTACT_BEGIN:
        return "begin";
    case TB_CONTACT_HIT:
        return "hit";
    case TB_CONTACT_END:
        return "end";
    }
    return "unknown";
}

tb_contact_events_def tb_contact_events_def_default(void)
{
    tb_contact_events_def def;
    memset(&def, 0, sizeof def);
    def.internal_cookie = TB__CONTACT_EVENTS_COOKIE;
    return def;
}

static void free_watch(tb__watch *watch)
{
    if (watch != NULL) {
        free(watch->prev);
        free(watch->cur);
        free(watch->found);
        free(watch->events);
        free(watch);
    }
}

/* The default room: 4 pairs per body + 16 (an overflow is a size no allocation meets). */
static size_t default_capacity(const tb_scene *scene)
{
    size_t capacity = 0;
    if (tb__size_product(scene->body_count, 4, &capacity)) {
        capacity += capacity + 16 > capacity ? 16 : 0;
    }
    return capacity;
}

/* Makes every array room for capacity pairs (4 capacity events); on failure the arrays that grew
 * keep their contents and the capacity stays. */
static bool grow(tb__watch *watch, size_t capacity)
{
    size_t events;
    if (!tb__size_product(capacity, 4, &events)) {
        return false;
    }
    void *p[4] = {tb__realloc_array(watch->prev, capacity, sizeof(tb__watched_pair)), NULL, NULL,
                  NULL};
    watch->prev = p[0] != NULL ? p[0] : watch->prev;
    p[1] = tb__realloc_array(watch->cur, capacity, sizeof(tb__watched_pair));
    watch->cur = p[1] != NULL ? p[1] : watch->cur;
    p[2] = tb__realloc_array(watch->found, capacity, sizeof(tb__event_pair));
    watch->found = p[2] != NULL ? p[2] : watch->found;
    p[3] = tb__realloc_array(watch->events, events, sizeof(tb_contact_event));
    watch->events = p[3] != NULL ? p[3] : watch->events;
    if (p[0] == NULL || p[1] == NULL || p[2] == NULL || p[3] == NULL) {
        return false;
    }
    watch->capacity = capacity;
    return true;
}

static tb_status check_def(tb_scene *scene, const tb_contact_events_def *def)
{
    if (def == NULL || def->fn == NULL) {
        return tb__scene_fail(scene, TB_STATUS_NULL_POINTER, "%s is NULL",
                              def == NULL ? "def" : "def->fn");
    }
    if (def->internal_cookie != TB__CONTACT_EVENTS_COOKIE) {
        return tb__scene_fail(scene, TB_STATUS_INVALID_ARGUMENT,
                              "def: not initialised by tb_contact_events_def_default()");
    }
    const tb_status status =
        tb__validate_nonnegative(scene->detail, def->hit_threshold, "def->hit_threshold");
    return status != TB_STATUS_OK ? status : tb__scene_check_idle(scene, "setting contact events");
}

tb_status tb_scene_set_contact_events(tb_scene *scene, const tb_contact_events_def *def)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    tb_status status = check_def(scene, def);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const size_t capacity = def->pair_capacity > 0 ? def->pair_capacity : default_capacity(scene);
    tb__watch *watch = calloc(1, sizeof *watch);
    if (watch == NULL || !grow(watch, capacity)) {
        free_watch(watch);
        return tb__scene_fail(scene, TB_STATUS_OUT_OF_MEMORY, "contact events: room for %zu pairs",
                              capacity);
    }
    watch->fn = def->fn;
    watch->ctx = def->ctx;
    watch->threshold = def->hit_threshold;
    free_watch(scene->contact_events);
    scene->contact_events = watch;
    return TB_STATUS_OK;
}

void tb_scene_clear_contact_events(tb_scene *scene)
{
    if (scene != NULL && scene->contact_events != NULL &&
        tb__scene_check_idle(scene, "clearing contact events") == TB_STATUS_OK) {
        tb__scene_events_free(scene);
    }
}

tb__watch *tb__event_watch_create(const tb_scene *scene, tb__event_begin_fn on_begin, void *ctx)
{
    tb__watch *watch = calloc(1, sizeof *watch);
    if (watch == NULL || !grow(watch, default_capacity(scene))) {
        free_watch(watch);
        return NULL;
    }
    watch->threshold = INFINITY; /* begins only: no hits */
    watch->on_begin = on_begin;
    watch->begin_ctx = ctx;
    return watch;
}

void tb__event_watch_free(tb__watch *watch)
{
    free_watch(watch);
}

size_t tb__event_watch_dropped(const tb__watch *watch)
{
    return watch != NULL ? watch->dropped : 0;
}

void tb__scene_events_free(tb_scene *scene)
{
    free_watch(scene->contact_events);
    scene->contact_events = NULL;
}

tb_status tb_scene_contact_events_status(const tb_scene *scene, size_t *out_dropped)
{
    if (scene == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    tb__scene_clear_detail(scene);
    const size_t dropped = scene->contact_events != NULL ? scene->contact_events->dropped : 0;
    if (out_dropped != NULL) {
        *out_dropped = dropped;
    }
    if (dropped > 0) {
        return tb__scene_fail((tb_scene *)scene, TB_STATUS_OUT_OF_MEMORY,
                              "contact events: %zu pairs not watched (the list could not grow)",
                              dropped);
    }
    return TB_STATUS_OK;
}

/* Every effect's pairs at y into watch->found, growing it at this boundary if they do not fit;
 * returns how many it holds. */
static size_t find_pairs(tb__watch *watch, const tb_scene *scene, const double *y)
{
    size_t total = 0;
    for (int attempt = 0; attempt < 2; ++attempt) {
        total = 0;
        for (size_t k = 0; k < scene->effect_count; ++k) {
            const tb__effect *effect = &scene->effects[k];
            if (tb__stepping_of(effect)->event_pairs != NULL) {
                const size_t used = total < watch->capacity ? total : watch->capacity;
                total += tb__stepping_of(effect)->event_pairs(effect, scene, y, watch->found + used,
                                                              watch->capacity - used);
                for (size_t j = used; j < total && j < watch->capacity; ++j) {
                    watch->found[j].effect = k;
                }
            }
        }
        if (total <= watch->capacity || attempt == 1 ||
            !grow(watch, total + total / 2 < total ? total : total + total / 2)) {
            break;
        }
    }
    if (total > watch->capacity) {
        watch->dropped += total - watch->capacity;
        total = watch->capacity;
    }
    return total;
}

static int compare_pairs(const void *left, const void *right)
{
    const tb__event_pair *a = left, *b = right;
    if (a->body_a != b->body_a) {
        return a->body_a < b->body_a ? -1 : 1;
    }
    if (a->body_b != b->body_b) {
        return a->body_b < b->body_b ? -1 : 1;
    }
    return a->effect < b->effect ? -1 : a->effect > b->effect; /* a body on two planes */
}

static int compare_events(const void *left, const void *right)
{
    const tb_contact_event *a = left, *b = right;
    if (a->t != b->t) {
        return a->t < b->t ? -1 : 1;
    }
    if (a->body_a != b->body_a) {
        return a->body_a < b->body_a ? -1 : 1;
    }
    if (a->body_b != b->body_b) {
        return a->body_b < b->body_b ? -1 : 1;
    }
    if (a->effect != b->effect) {
        return a->effect < b->effect ? -1 : 1;
    }
    return (int)a->kind - (int)b->kind;
}

/* Where the gap crosses zero between two boundaries: its time, its rate there and the fraction
 * of the step. */
typedef struct tb__crossing {
    double t, rate, fraction;
} tb__crossing;

/* The cubic Hermite of g (values g0, g1 and rates d0, d1 over a step h) at fraction s: its value
 * and rate. */
static void hermite(const double g[2], const double d[2], double h, double s, double *value,
                    double *rate)
{
    const double s2 = s * s, s3 = s2 * s;
    *value = (2.0 * s3 - 3.0 * s2 + 1.0) * g[0] + (s3 - 2.0 * s2 + s) * h * d[0] +
             (3.0 * s2 - 2.0 * s3) * g[1] + (s3 - s2) * h * d[1];
    *rate = (6.0 * (s2 - s) * (g[0] - g[1])) / h + (3.0 * s2 - 4.0 * s + 1.0) * d[0] +
            (3.0 * s2 - 2.0 * s) * d[1];
}

/* The zero of the cubic through (g, d) over a step h in fractions [low, high], where it changes
 * sign from g[0]'s: its fraction and rate. */
static double bisect(const double g[2], const double d[2], double h, double low, double high,
                     double *rate)
{
    const bool start_touching = g[0] < 0.0;
    double value;
    for (int k = 0; k < TB__CROSSING_HALVINGS; ++k) {
        const double mid = 0.5 * (low + high);
        hermite(g, d, h, mid, &value, rate);
        if ((value < 0.0) == start_touching) {
            low = mid;
        } else {
            high = mid;
        }
    }
    hermite(g, d, h, high, &value, rate);
    return high;
}

static tb__crossing locate(double t0, double t1, const tb__event_pair *before,
                           const tb__event_pair *after)
{
    const double g[2] = {before->gap, after->gap}, d[2] = {before->gap_rate, after->gap_rate};
    double rate;
    const double s = bisect(g, d, t1 - t0, 0.0, 1.0, &rate);
    return (tb__crossing){t0 + s * (t1 - t0), rate, s};
}

/* A fixed step's begin: the motion is free until the touch, but the law's force after it bends
 * the gap at t1 (its third derivative jumps by about omega^2 times the speed), which a cubic
 * through t1 follows only to O(dt^3 omega^2). The free cubic of the step before (the pair apart
 * at both its ends) carried on to its zero in (t0, t1] is O(dt^4) instead, exact for a fall. */
static bool extrapolate(const tb__watched_pair *was, double t0, double t1, tb__crossing *out)
{
    const double h = t0 - was->older_t;
    if (!was->has_older || !(h > 0.0) || was->older_gap < 0.0) {
        return false;
    }
    const double g[2] = {was->older_gap, was->now.gap};
    const double d[2] = {was->older_rate, was->now.gap_rate};
    const double last = 1.0 + (t1 - t0) / h;
    double value, rate;
    hermite(g, d, h, last, &value, &rate);
    if (!(value < 0.0)) {
        return false; /* the free cubic does not reach the touch: the plain one decides */
    }
    const double s = bisect(g, d, h, 1.0, last, &rate);
    const double t = t0 + (s - 1.0) * h;
    *out = (tb__crossing){t, rate, (t - t0) / (t1 - t0)};
    return true;
}

static tb_contact_event *push_event(tb__watch *watch, tb_contact_event_kind kind, double t,
                                    const tb__event_pair *before, const tb__event_pair *after,
                                    double fraction)
{
    tb_contact_event *e = &watch->events[watch->event_count++];
    *e = (tb_contact_event){.kind = kind,
                            .t = t,
                            .body_a = after->body_a,
                            .body_b = after->body_b,
                            .effect = after->effect};
    for (int k = 0; k < 3; ++k) {
        e->point[k] = before->point[k] + fraction * (after->point[k] - before->point[k]);
        e->normal[k] = before->normal[k] + fraction * (after->normal[k] - before->normal[k]);
    }
    const double length = tb__v3_norm(e->normal);
    for (int k = 0; k < 3 && length > 0.0; ++k) {
        e->normal[k] /= length;
    }
    return e;
}

static void begin(tb__watch *watch, tb__watched_pair *pair, const tb__event_pair *before,
                  tb__crossing c)
{
    pair->begin_t = c.t;
    pair->begin_rate = c.rate;
    pair->inverse_mass = pair->now.inverse_mass;
    pair->gravity = pair->now.gravity;
    const double speed = c.rate < 0.0 ? -c.rate : 0.0;
    tb_contact_event *e = push_event(watch, TB_CONTACT_BEGIN, c.t, before, &pair->now, c.fraction);
    e->speed = speed;
    if (watch->on_begin != NULL) {
        watch->on_begin(watch->begin_ctx, e, &pair->now);
    }
    if (speed >= watch->threshold && c.rate < 0.0) {
        push_event(watch, TB_CONTACT_HIT, c.t, before, &pair->now, c.fraction)->speed = speed;
    }
}

static void end(tb__watch *watch, const tb__watched_pair *was, const tb__event_pair *after,
                tb__crossing c)
{
    tb_contact_event *e = push_event(watch, TB_CONTACT_END, c.t, &was->now, after, c.fraction);
    e->speed = c.rate > 0.0 ? c.rate : 0.0;
    const double change = c.rate - was->begin_rate + was->gravity * (c.t - was->begin_t);
    e->impulse = was->inverse_mass > 0.0 ? change / was->inverse_mass : 0.0;
}

/* A touch made and gone inside one step: the pair apart at both ends, closing at the first and
 * opening at the second, and its approach carried on straight would have touched inside the step
 * (the step's cubic need not dip: a push shorter than the step turns the gap's rate between its
 * ends, and the cubic through them bends smoothly above zero). The touch at that approach's zero,
 * at the approach speed. */
static bool turned(const tb__event_pair *before, const tb__event_pair *after, double t0, double t1,
                   tb__crossing *out)
{
    const double h = t1 - t0;
    if (!(before->gap_rate < 0.0) || !(after->gap_rate > 0.0) || !(h > 0.0)) {
        return false;
    }
    const double s = -before->gap / (before->gap_rate * h);
    if (!(s >= 0.0 && s <= 1.0)) {
        return false;
    }
    *out = (tb__crossing){t0 + s * h, before->gap_rate, s};
    return true;
}

/* A pair seen at both boundaries (was at last_t, pair at t). The scene's impact count (a fixed
 * watch without a callback) also hears a touch made and gone inside one step: the push shorter
 * than the step that the count is for. */
static void follow(tb__watch *watch, const tb__watched_pair *was, tb__watched_pair *pair, double t)
{
    pair->begin_t = was->begin_t, pair->begin_rate = was->begin_rate;
    pair->inverse_mass = was->inverse_mass, pair->gravity = was->gravity;
    pair->has_older = true;
    pair->older_t = watch->last_t;
    pair->older_gap = was->now.gap, pair->older_rate = was->now.gap_rate;
    if (was->touching != pair->touching) {
        tb__crossing c;
        if (!watch->fixed || pair->touching == false || !extrapolate(was, watch->last_t, t, &c)) {
            c = locate(watch->last_t, t, &was->now, &pair->now);
        }
        if (pair->touching) {
            begin(watch, pair, &was->now, c);
        } else {
            end(watch, was, &pair->now, c);
        }
        return;
    }
    tb__crossing c;
    if (watch->fn == NULL && watch->fixed && !pair->touching &&
        turned(&was->now, &pair->now, watch->last_t, t, &c)) {
        begin(watch, pair, &was->now, c);
    }
}

/* A pair found touching with no record before (new within the look-ahead, or at the start): its
 * contact began where its gap, at its rate, was zero, no earlier than the last boundary. */
static void appear(tb__watch *watch, tb__watched_pair *pair, double t)
{
    double at = t;
    if (watch->have_last && pair->now.gap_rate < 0.0) {
        at = fmax(watch->last_t, t - pair->now.gap / pair->now.gap_rate);
    }
    begin(watch, pair, &pair->now, (tb__crossing){at, pair->now.gap_rate, 0.0});
}

static int key_order(const tb__watched_pair *a, const tb__watched_pair *b)
{
    return compare_pairs(&a->now, &b->now);
}

/* The events between the pairs at last_t (prev) and at t (cur, sorted like prev). */
static void compare(tb__watch *watch, size_t count, double t)
{
    size_t i = 0, j = 0;
    while (i < watch->prev_count || j < count) {
        const int order = i == watch->prev_count ? 1
                          : j == count           ? -1
                                                 : key_order(&watch->prev[i], &watch->cur[j]);
        if (order == 0) {
            follow(watch, &watch->prev[i++], &watch->cur[j++], t);
        } else if (order > 0) {
            if (watch->cur[j].touching) {
                appear(watch, &watch->cur[j], t);
            }
            ++j;
        } else {
            const tb__watched_pair *was = &watch->prev[i++];
            if (was->touching) { /* left the look-ahead within one step: it ended there */
                end(watch, was, &was->now, (tb__crossing){t, was->now.gap_rate, 0.0});
            }
        }
    }
}

static void observe(tb__watch *watch, tb_scene *scene, double t, const double *y, bool fixed)
{
    if (watch == NULL || watch->fixed != fixed || (watch->have_last && t == watch->last_t)) {
        return;
    }
    if (watch->have_last && t < watch->last_t) {
        watch->have_last = false; /* an integrator reset to an earlier time: start afresh */
    }
    const size_t count = find_pairs(watch, scene, y);
    qsort(watch->found, count, sizeof *watch->found, compare_pairs);
    for (size_t k = 0; k < count; ++k) {
        watch->cur[k] =
            (tb__watched_pair){.now = watch->found[k], .touching = watch->found[k].gap < 0.0};
    }
    watch->event_count = 0;
    watch->prev_count = watch->have_last ? watch->prev_count : 0;
    compare(watch, count, t);
    qsort(watch->events, watch->event_count, sizeof *watch->events, compare_events);
    for (size_t k = 0; k < watch->event_count && watch->fn != NULL; ++k) {
        watch->fn(&watch->events[k], watch->ctx);
    }
    tb__watched_pair *swap = watch->prev;
    watch->prev = watch->cur;
    watch->cur = swap;
    watch->prev_count = count;
    watch->last_t = t;
    watch->have_last = true;
}

void tb__scene_events_observe(tb_scene *scene, double t, const double *y, bool fixed)
{
    observe(scene->contact_events, scene, t, y, fixed);
    observe(tb__scene_impact_watch(scene), scene, t, y, fixed);
}

static void start(tb__watch *watch, tb_scene *scene, double t0, bool fixed)
{
    if (watch == NULL) {
        return;
    }
    if (watch->fixed != fixed || (watch->have_last && t0 < watch->last_t)) {
        watch->have_last = false;
    }
    watch->fixed = fixed;
    observe(watch, scene, t0, scene->states, fixed);
}

void tb__scene_events_start(tb_scene *scene, double t0, bool fixed)
{
    start(scene->contact_events, scene, t0, fixed);
    start(tb__scene_impact_watch(scene), scene, t0, fixed);
}

void tb__scene_at_event(double t, const double *y, void *ctx)
{
    tb_scene *scene = ctx;
    scene->time = t; /* bodies without a state, at t */
    tb__scene_events_observe(scene, t, y, false);
    if (scene->sleep != NULL) {
        tb__scene_sleep_at_event(t, y, ctx);
    }
    if (scene->constraint_ops != NULL && scene->constraint_ops->at_event != NULL) {
        /* a joint's stop: an impact changes y, the integrator's own state at the event, and
         * moves the right-hand side's generation, so the integrator restarts from it
         * (include/tumble/ode.h, at_event) */
        (void)scene->constraint_ops->at_event(scene->constraints, scene, t, (double *)y);
    }
}
