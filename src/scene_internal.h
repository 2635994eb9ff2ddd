/* Private: the scene object, shared by the scene, read-out, effect and derivative sources. */
#ifndef TUMBLE_SCENE_INTERNAL_H
#define TUMBLE_SCENE_INTERNAL_H

#include "tumble/scene.h"

/* What the derivative needs of a body, packed together for the hot loop. */
typedef struct tb__body {
    double mass;           /* kg */
    double inv_mass;       /* 1/kg */
    double inv_moments[3]; /* 1/(kg m^2), principal frame */
} tb__body;

typedef struct tb__effect tb__effect;

/* Adds the effect's forces into dydt[13 i + 7 .. 9] and torques into dydt[13 i + 10 .. 12].
 * Pure: reads y, writes only those slots. */
typedef void (*tb__effect_apply)(const tb__effect *effect, const tb_scene *scene, double t,
                                 const double *y, double *dydt);

/* One entry of the compiled effect list: the function and its parameters, nothing else. */
struct tb__effect {
    tb__effect_apply apply;
    size_t body;
    double vector[3]; /* force, torque or acceleration (principal frame if body-fixed) */
    double point[3];  /* application point, principal frame, relative to the centre of mass */
};

struct tb_scene {
    size_t body_count;
    size_t body_capacity;
    double *states;                 /* 13 * body_capacity */
    tb__body *bodies;               /* body_capacity */
    tb_mass_properties *mass_props; /* body_capacity, as given */
    tb__effect *effects;
    size_t effect_count;
    size_t effect_capacity;
    bool renormalize;
    double quaternion_drift; /* largest | |q| - 1 | seen by the renormalisation hook */
    char detail[TB_DETAIL_SIZE];
};

/* Writes scene->detail and returns status. */
tb_status tb__scene_fail(tb_scene *scene, tb_status status, const char *format, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Checks id against the body count, writing the detail on failure. */
tb_status tb__scene_check_id(const tb_scene *scene, size_t id, const char *what);

/* Appends an effect, growing the list if needed; nothing changes on failure. */
tb_status tb__scene_push_effect(tb_scene *scene, const tb__effect *effect);

/* Body i's quaternion in y, normalised, into q. */
void tb__unit_quaternion(const double *y, size_t i, double q[4]);

/* omega (world) of body i from y. */
void tb__angular_velocity(const tb_scene *scene, const double *y, size_t i, double omega[3]);

#endif
