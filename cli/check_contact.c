/* tumble check's report of what collides with what: each contact effect's bodies and material,
 * the ground planes and the bodies whose points they touch, the shapes, the pairs touching at
 * the start, and what looks like a mistake. All read from the library (contact_info.h). */
#include "check_contact.h"

#include "summary.h"

#include <stdio.h>
#include <stdlib.h>

/* Above this many penetrations an overlap at the start stores far more energy than a resting
 * contact ever does: the ground refuses a body 10 penetrations deep for the same reason. */
#define DEEP_OVERLAP 10.0
/* Lines of touching pairs and names of bodies listed per line before "... and N more". */
#define MAX_LISTED 20

static const char *shape_name(const tb_scene *scene, size_t id)
{
    static const char *const names[] = {"none",      "sphere",      "box",    "capsule", "cylinder",
                                        "ellipsoid", "convex hull", "points", "compound"};
    tb_shape_type type = TB_SHAPE_NONE;
    tb_scene_body_shape_type(scene, id, &type);
    return (unsigned)type < sizeof names / sizeof names[0] ? names[type] : "?";
}

static bool has_shape(const tb_scene *scene, size_t id)
{
    tb_shape_type type = TB_SHAPE_NONE;
    return tb_scene_body_shape_type(scene, id, &type) == TB_STATUS_OK && type != TB_SHAPE_NONE;
}

static void print_material(double e, double mu_s, double mu_k, double penetration)
{
    printf("    restitution %g, static friction %g, kinetic friction %g, penetration %g m\n", e,
           mu_s, mu_k, penetration);
}

static void print_contact_effect(const tb_scene *scene, const tb_contact_info *c, int *warnings)
{
    size_t shaped = 0;
    for (size_t k = 0; k < c->body_count; ++k) {
        shaped += has_shape(scene, c->bodies[k]);
    }
    printf("  effects[%zu]: contact between %s (%zu):", c->effect,
           c->every_body ? "every body with a shape" : "the bodies listed", shaped);
    size_t listed = 0;
    for (size_t k = 0; k < c->body_count && listed < MAX_LISTED; ++k) {
        if (has_shape(scene, c->bodies[k])) {
            printf(" %s", tb_scene_body_name(scene, c->bodies[k]));
            listed += 1;
        }
    }
    if (shaped > listed) {
        printf(" ... and %zu more", shaped - listed);
    }
    printf("\n");
    print_material(c->restitution, c->static_friction, c->kinetic_friction, c->penetration);
    for (size_t k = 0; !c->every_body && k < c->body_count; ++k) {
        if (!has_shape(scene, c->bodies[k])) {
            printf("warning: effects[%zu] names %s, which has no shape: it touches nothing\n",
                   c->effect, tb_scene_body_name(scene, c->bodies[k]));
            *warnings += 1;
        }
    }
    if (shaped < 2) {
        printf("warning: effects[%zu] has %zu %s with a shape: no pair can touch\n", c->effect,
               shaped, summary_plural(shaped, "body", "bodies"));
        *warnings += 1;
    }
}

static void print_ground(const tb_scene *scene, const tb_ground_info *g)
{
    printf("  effects[%zu]: ground plane, normal (%g, %g, %g), offset %g m, under the contact "
           "points of:",
           g->effect, g->normal[0], g->normal[1], g->normal[2], g->offset);
    size_t touched = 0;
    for (size_t id = 0; id < tb_scene_body_count(scene); ++id) {
        size_t points = 0;
        tb_scene_body_contact_point_count(scene, id, &points);
        if (points > 0 && touched++ < MAX_LISTED) {
            printf(" %s (%zu)", tb_scene_body_name(scene, id), points);
        }
    }
    if (touched > MAX_LISTED) {
        printf(" ... and %zu more", touched - MAX_LISTED);
    }
    printf(touched == 0 ? " no body\n" : "\n");
    print_material(g->restitution, g->static_friction, g->kinetic_friction, g->penetration);
}

static void print_shapes(const tb_scene *scene)
{
    printf("  shapes:");
    const size_t bodies = tb_scene_body_count(scene);
    for (size_t id = 0; id < bodies && id < MAX_LISTED; ++id) {
        printf(" %s %s%s", tb_scene_body_name(scene, id), shape_name(scene, id),
               id + 1 < bodies ? "," : "");
    }
    if (bodies > MAX_LISTED) {
        printf(" ... and %zu more", bodies - MAX_LISTED);
    }
    printf("\n");
}

/* Pairs two contact effects both act on: their forces add (twice the stiffness). The bodies
 * with a shape that both list, marked in a per-body table so that large scenes stay linear. */
static void print_double_cover(const tb_scene *scene, const tb_contact_info *a,
                               const tb_contact_info *b, int *warnings)
{
    const size_t bodies = tb_scene_body_count(scene);
    unsigned char *in = calloc(bodies + 1, 1);
    if (in == NULL) {
        return;
    }
    for (size_t k = 0; k < a->body_count; ++k) {
        in[a->bodies[k]] = has_shape(scene, a->bodies[k]);
    }
    size_t common = 0, first[2] = {0, 0};
    for (size_t k = 0; k < b->body_count; ++k) {
        if (in[b->bodies[k]] == 1) {
            in[b->bodies[k]] = 2; /* counted once */
            if (common < 2) {
                first[common] = b->bodies[k];
            }
            common += 1;
        }
    }
    free(in);
    if (common >= 2) {
        const size_t pairs = common * (common - 1) / 2;
        const size_t low = first[0] < first[1] ? first[0] : first[1];
        const size_t high = first[0] < first[1] ? first[1] : first[0];
        printf("warning: effects[%zu] and effects[%zu] both act on %s-%s", a->effect, b->effect,
               tb_scene_body_name(scene, low), tb_scene_body_name(scene, high));
        if (pairs > 1) {
            printf(" and %zu more %s", pairs - 1, summary_plural(pairs - 1, "pair", "pairs"));
        }
        printf(": their forces add, twice as stiff as either says\n");
        *warnings += 1;
    }
}

/* The penetration of the effect at index effect (contact or ground), for the deep-overlap test. */
static double penetration_of(const tb_scene *scene, size_t effect)
{
    tb_contact_info c;
    for (size_t k = 0; tb_scene_get_contact(scene, k, &c) == TB_STATUS_OK; ++k) {
        if (c.effect == effect) {
            return c.penetration;
        }
    }
    tb_ground_info g;
    for (size_t k = 0; tb_scene_get_ground(scene, k, &g) == TB_STATUS_OK; ++k) {
        if (g.effect == effect) {
            return g.penetration;
        }
    }
    return 0.0;
}

static void print_touch(const tb_scene *scene, const tb_contact_touch *t, int *warnings)
{
    const char *a = tb_scene_body_name(scene, t->body_a);
    if (t->body_b == TB_WORLD) {
        printf("  %s on the ground effects[%zu]: %g m deep (%d %s)\n", a, t->effect, t->depth,
               t->points, summary_plural((size_t)t->points, "point", "points"));
    } else if (t->depth > 0) {
        printf("  %s and %s (effects[%zu]): overlapping by %g m (%d %s)\n", a,
               tb_scene_body_name(scene, t->body_b), t->effect, t->depth, t->points,
               summary_plural((size_t)t->points, "point", "points"));
    } else {
        printf("  %s and %s (effects[%zu]): %g m apart, within the 1 mm the pair finder looks\n", a,
               tb_scene_body_name(scene, t->body_b), t->effect, -t->depth);
    }
    const double penetration = penetration_of(scene, t->effect);
    if (t->body_b != TB_WORLD && penetration > 0 && t->depth > DEEP_OVERLAP * penetration) {
        printf("warning: %s and %s overlap by %g m at the start, %.3g times effects[%zu]'s "
               "penetration: the contact will throw them apart\n",
               a, tb_scene_body_name(scene, t->body_b), t->depth, t->depth / penetration,
               t->effect);
        *warnings += 1;
    }
}

static void print_touching(const tb_scene *scene, int *warnings)
{
    size_t count = 0;
    tb_scene_contact_touching(scene, tb_scene_states_const(scene), NULL, 0, &count);
    tb_contact_touch *touches = malloc((count + 1) * sizeof *touches);
    if (touches == NULL) {
        return;
    }
    tb_scene_contact_touching(scene, tb_scene_states_const(scene), touches, count, &count);
    printf(count == 0 ? "touching at the start: nothing\n" : "touching at the start:\n");
    for (size_t k = 0; k < count && k < MAX_LISTED; ++k) {
        print_touch(scene, &touches[k], warnings);
    }
    if (count > MAX_LISTED) {
        printf("  ... and %zu more\n", count - MAX_LISTED);
    }
    free(touches);
}

int cli_check_contact(const tb_scene *scene)
{
    const size_t contacts = tb_scene_contact_count(scene), grounds = tb_scene_ground_count(scene);
    int warnings = 0;
    if (contacts + grounds == 0) {
        return 0;
    }
    printf("what collides with what:\n");
    tb_contact_info c, other;
    for (size_t k = 0; tb_scene_get_contact(scene, k, &c) == TB_STATUS_OK; ++k) {
        print_contact_effect(scene, &c, &warnings);
        for (size_t j = 0; j < k && tb_scene_get_contact(scene, j, &other) == TB_STATUS_OK; ++j) {
            print_double_cover(scene, &other, &c, &warnings);
        }
    }
    tb_ground_info g;
    for (size_t k = 0; tb_scene_get_ground(scene, k, &g) == TB_STATUS_OK; ++k) {
        print_ground(scene, &g);
    }
    print_shapes(scene);
    print_touching(scene, &warnings);
    return warnings;
}
