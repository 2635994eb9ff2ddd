/* Private: the events and step limits of contact (effect_contact_events.c), named by the stepping
 * rows (tb__effect_stepping) of the contact effect (effect_contact.c) and the ground
 * (effect_ground.c). */
#ifndef TUMBLE_CONTACT_EVENTS_H
#define TUMBLE_CONTACT_EVENTS_H

#include "contact/narrow_phase.h"
#include "effects/effect_contact.h"
#include "effects/effect_ground.h"

/* Pairs are found this far apart (m), so points appear before they touch, at zero force, and
 * pairs this close link their bodies' islands (sleep.c). */
#define TB__CONTACT_MARGIN 1e-3

/* Makes contact->lookahead for contact->bodies (pairs within TB__EVENT_LOOKAHEAD); the detail
 * names what failed. release frees it (NULL is fine). */
tb_status tb__contact_events_create(tb_scene *scene, tb__contact_params *contact);
void tb__contact_events_release(tb__contact_params *contact);

/* tb__effect_stepping.event_gaps, adaptive_step_limit and tunnel_step of contact between bodies. */
void tb__contact_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                            double *gap, bool signs);
/* tb__effect_stepping.wake_gaps and wake_links of contact between bodies (sleeping islands). */
void tb__contact_wake_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                           double *gap, double *wake, bool signs);
void tb__contact_wake_links(const tb__effect *effect, const tb_scene *scene, const double *y,
                            double dt);
double tb__contact_step_limit(const tb__effect *effect, const tb_scene *scene, const double *y,
                              const double *dydt);
double tb__contact_tunnel_step(const tb__effect *effect, const tb_scene *scene, const double *y,
                               double dt, char *which, size_t size);
/* The tunnelling step pair by pair (contact_tunnel.c), at least tb__contact_tunnel_step's quick
 * bound: the least over pairs of the thinner one's half-thickness (plus the gap between them)
 * over a bound on their relative speed where they can meet; the pair in which (size bytes). */
double tb__contact_tunnel_pairs(const tb__contact_params *contact, const tb_scene *scene,
                                const double *y, char *which, size_t size);
/* Half the thickness of body id's shape across its thinnest direction (m), INFINITY for a body
 * of no thickness or without a shape. */
double tb__contact_half_thickness(const tb_scene *scene, size_t id);

/* tb__effect_stepping.check_impacts of contact between bodies: refuses a state in which the two
 * fastest bodies could close by more than the thinnest body's half-thickness before the law stops
 * them (TB_STATUS_INVALID_ARGUMENT, the detail naming both). */
tb_status tb__contact_check_impacts(const tb__effect *effect, const tb_scene *scene,
                                    const double *y, char *detail);

/* tb__effect_stepping.event_gaps of a ground plane: each body's lowest contact point's height
 * (signs: see tb__effect_stepping.event_gaps). */
void tb__ground_event_gaps(const tb__effect *effect, const tb_scene *scene, const double *y,
                           double *gap, bool signs);

/* tb__effect_ops.event_pairs of contact between bodies and of a ground plane
 * (effect_contact_event_pairs.c): the pairs contact events watch. */
size_t tb__contact_event_pairs(const tb__effect *effect, const tb_scene *scene, const double *y,
                               tb__event_pair *out, size_t capacity);
size_t tb__ground_event_pairs(const tb__effect *effect, const tb_scene *scene, const double *y,
                              tb__event_pair *out, size_t capacity);

/* The part of a law that splits its stiffness among a manifold's points (k / count, the contact
 * between bodies and a shape on a plane) pushing at m's deepest point when the pair lands: 1 /
 * the points within TB__CONTACT_MARGIN of the deepest (tb__event_pair.share). */
double tb__manifold_landing_share(const tb__contact_manifold *m);

/* tb__effect_stepping.impact_law of contact between bodies and of a ground plane
 * (effect_contact_event_pairs.c). */
void tb__contact_impact_law(const tb__effect *effect, const tb_scene *scene,
                            const tb__event_pair *pair, struct tb__impact_law *out);
void tb__ground_impact_law(const tb__effect *effect, const tb_scene *scene,
                           const tb__event_pair *pair, struct tb__impact_law *out);

#endif
