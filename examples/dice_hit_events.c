/* Three dice thrown with spin onto a static box-shaped table (1.2 x 0.8 x 0.75 m, its top at
 * z = 0.75 m), reporting every hit harder than 0.1 m/s as it happens (a sound designer's click
 * track), stepped with RK4 at the scene's default step.
 *
 * Checks (exit 1 if one fails):
 *   - every die stays over the table top, away from its edges, so that a die's depth in the
 *     table is the height of its lowest corner below the top (the geometry alone);
 *   - every begin of a die on the table lies in the step where that depth first goes positive;
 *   - the begins and ends of each die on the table are as many as those sign changes;
 *   - every hit closes at 0.1 m/s or faster and comes with its begin. */
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DICE 3
#define MAX_EVENTS 512
#define MAX_STEPS 200000
#define TABLE 3 /* the table's body id: added after the dice (0, 1, 2) */
#define TABLE_TOP 0.75
#define TABLE_HALF_X 0.6
#define TABLE_HALF_Y 0.4

typedef struct track {
    tb_contact_event events[MAX_EVENTS];
    size_t count;
} track;

static void on_event(const tb_contact_event *event, void *ctx)
{
    track *t = ctx;
    if (event->kind == TB_CONTACT_HIT) {
        printf("  hit  t = %.6f s  die %zu on %s at %.2f m/s\n", event->t, event->body_a,
               event->body_b == TABLE ? "the table" : "a die", event->speed);
    }
    if (t->count < MAX_EVENTS) {
        t->events[t->count] = *event;
    }
    t->count++;
}

static int check(const char *what, int ok)
{
    printf("  %-64s %s\n", what, ok ? "ok" : "FAILED");
    return ok;
}

static size_t add_die(tb_scene *scene, int k)
{
    const double size[3] = {0.05, 0.05, 0.05};
    tb_body_def def = tb_body_def_default();
    tb_mass_from_box(TB_MASS_GIVEN, 0.1, size, &def.mass, NULL);
    def.position[0] = 0.1 * k;
    def.position[2] = TABLE_TOP + 0.2 + 0.08 * k;
    def.velocity[0] = 0.5 - 0.3 * k;
    def.velocity[1] = 0.2 * k;
    def.angular_velocity[0] = 8.0 + 3.0 * k;
    def.angular_velocity[1] = 5.0 - 4.0 * k;
    size_t id = 0;
    tb_scene_add_body(scene, &def, &id);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, sizeof size);
    tb_scene_set_body_shape(scene, id, &shape);
    return id;
}

/* The table: static, no state, infinitely heavy; the contact pushes the dice off its box. */
static void add_table(tb_scene *scene)
{
    tb_body_def def = tb_body_def_default();
    def.name = "table";
    def.motion = TB_MOTION_STATIC;
    def.position[2] = 0.5 * TABLE_TOP;
    size_t id = 0;
    tb_scene_add_body(scene, &def, &id);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = 2.0 * TABLE_HALF_X;
    shape.size[1] = 2.0 * TABLE_HALF_Y;
    shape.size[2] = TABLE_TOP;
    tb_scene_set_body_shape(scene, id, &shape);
}

/* The height of die id's lowest corner above the table top at the scene's state (m); *inside
 * cleared when a corner is not over the table with a die's size to spare from its edges. */
static double lowest_corner(const tb_scene *scene, size_t id, int *inside)
{
    double lowest = INFINITY;
    for (int c = 0; c < 8; ++c) {
        const double corner[3] = {c & 1 ? 0.025 : -0.025, c & 2 ? 0.025 : -0.025,
                                  c & 4 ? 0.025 : -0.025};
        double x[3];
        tb_scene_body_point(scene, tb_scene_states_const(scene), id, corner, x, NULL);
        lowest = fmin(lowest, x[2] - TABLE_TOP);
        *inside &= fabs(x[0]) < TABLE_HALF_X - 0.05 && fabs(x[1]) < TABLE_HALF_Y - 0.05;
    }
    return lowest;
}

/* Each die's crossings of the table top, step by step: the step's end time of each fall below
 * it; inside: every corner stayed over the table at every step. */
typedef struct geometry {
    double fall_end[DICE][64], fall_start[DICE][64];
    size_t falls[DICE], rises[DICE];
    int inside;
} geometry;

static int run(tb_scene *scene, geometry *g)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.0; /* the scene's default step (stiff contact) */
    tb_integrator *integrator = NULL;
    if (tb_scene_integrator_create(scene, &def, 0.0, &integrator) != TB_STATUS_OK) {
        fprintf(stderr, "integrator: %s\n", tb_scene_detail(scene));
        return 0;
    }
    double height[DICE], t = 0.0;
    for (size_t i = 0; i < DICE; ++i) {
        height[i] = lowest_corner(scene, i, &g->inside);
    }
    for (long step = 0; step < MAX_STEPS && t < 1.0; ++step) {
        if (tb_integrator_step(integrator) != TB_STATUS_OK) {
            fprintf(stderr, "step: %s\n", tb_integrator_detail(integrator));
            tb_integrator_destroy(integrator);
            return 0;
        }
        const double now = tb_integrator_time(integrator);
        for (size_t i = 0; i < DICE; ++i) {
            const double h = lowest_corner(scene, i, &g->inside);
            if (height[i] >= 0.0 && h < 0.0 && g->falls[i] < 64) {
                g->fall_start[i][g->falls[i]] = t;
                g->fall_end[i][g->falls[i]++] = now;
            }
            g->rises[i] += height[i] < 0.0 && h >= 0.0;
            height[i] = h;
        }
        t = now;
    }
    tb_integrator_destroy(integrator);
    return 1;
}

int main(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    if (tb_scene_create(&scene_def, &scene, NULL) != TB_STATUS_OK) {
        return 1;
    }
    for (int k = 0; k < DICE; ++k) {
        add_die(scene, k);
    }
    add_table(scene);
    tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81});
    tb_contact_def contact = tb_contact_def_default();
    tb_scene_add_contact(scene, &contact);
    static track events;
    tb_contact_events_def def = tb_contact_events_def_default();
    def.fn = on_event;
    def.ctx = &events;
    def.hit_threshold = 0.1; /* m/s */
    if (tb_scene_set_contact_events(scene, &def) != TB_STATUS_OK) {
        fprintf(stderr, "events: %s\n", tb_scene_detail(scene));
        return 1;
    }
    static geometry g = {.inside = 1};
    int ok = run(scene, &g) && events.count <= MAX_EVENTS;
    size_t begins[DICE] = {0}, ends[DICE] = {0}, outside = 0, bad_hits = 0;
    for (size_t k = 0; k < events.count && k < MAX_EVENTS; ++k) {
        const tb_contact_event *e = &events.events[k];
        if (e->kind == TB_CONTACT_HIT) {
            bad_hits += e->speed < def.hit_threshold || k == 0 ||
                        events.events[k - 1].kind != TB_CONTACT_BEGIN;
        }
        if (e->body_b != TABLE || e->kind == TB_CONTACT_HIT) {
            continue;
        }
        const size_t i = e->body_a;
        if (e->kind == TB_CONTACT_BEGIN) {
            const size_t n = begins[i]++;
            outside += n >= g.falls[i] || !(e->t > g.fall_start[i][n] && e->t <= g.fall_end[i][n]);
        } else {
            ends[i]++;
        }
    }
    printf("dice on the table: %zu events\n", events.count);
    for (size_t i = 0; i < DICE; ++i) {
        printf("  die %zu: %zu begins, %zu ends; the geometry %zu falls, %zu rises\n", i, begins[i],
               ends[i], g.falls[i], g.rises[i]);
        ok &= check("begins and ends equal the geometry's touches",
                    begins[i] == g.falls[i] && ends[i] == g.rises[i] && g.falls[i] > 0);
    }
    ok &= check("every die's corners over the table, 5 cm from its edges", g.inside);
    ok &= check("every begin in the step where the depth first goes positive", outside == 0);
    ok &= check("every hit at 0.1 m/s or faster, after its begin", bad_hits == 0);
    tb_scene_destroy(scene);
    return ok ? 0 : 1;
}
