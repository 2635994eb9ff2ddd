/* Private: the row of operations the scene holds its constraints (src/constraints/) by.
 * Included by scene_internal.h after tb__effect_rate, which it needs. */
#ifndef TUMBLE_CONSTRAINT_OPS_H
#define TUMBLE_CONSTRAINT_OPS_H

/* The constraints the scene holds (src/constraints/: the joints), by pointer and one row of
 * operations, as it holds effect rows: the scene names no constraint kind. NULL row: none. */
typedef struct tb__constraint_ops {
    /* The derivative's last stage: adds the constraint forces into dP and dL of dydt, after the
     * applied loads (the effects) wrote theirs, the motions filled by kinematics. 0, >0
     * recoverable (a singular solve), <0 fatal. Pure but for the rows' own scratch. */
    int (*apply)(void *constraints, const tb_scene *scene, double t, const double *y, double *dydt);
    /* The post-step projection of y at t onto the constraints (positions, then momenta); 0 or
     * >0 when it cannot solve. Leaves asleep bodies as they are. */
    int (*project)(void *constraints, const tb_scene *scene, double t, double *y);
    /* Links the bodies the constraints hold together into one sleeping island
     * (tb__scene_sleep_link). */
    void (*link_islands)(const void *constraints, const tb_scene *scene);
    /* Frees the constraints (tb_scene_destroy). */
    void (*destroy)(void *constraints);
    /* An adaptive method's boundary: the start of each advance, at the state and time the last
     * one handed out (accepted, unlike CVODE's projections, which run on trial steps too):
     * decisions that change the right-hand side (a joint breaking) are taken there. 0, or the
     * derivative's failure. */
    int (*at_output)(void *constraints, const tb_scene *scene, double t, double *y);
    /* The stability guard's modes of the constrained bodies at y (NULL: none); 0 or failed */
    int (*rate)(void *constraints, const tb_scene *scene, const double *y, tb__effect_rate *out);
    /* Adaptive methods' events: root_count functions written by roots into g; at_event at
     * every event stop may change y (an impact) if it moves effects_generation. 0 or <0. */
    size_t (*root_count)(const void *constraints);
    int (*roots)(void *constraints, const tb_scene *scene, double t, const double *y, double *g);
    int (*at_event)(void *constraints, const tb_scene *scene, double t, double *y);
    /* What the constraints keep of what the effects conserve: clears the fields of c that they
     * break (tb_scene_conserved). */
    void (*conserved)(const void *constraints, const tb_scene *scene, tb_conserved *c);
    /* An integrator made or reset at t (tb__scene_restart): what a later time of another run
     * decided outside y (a joint broken after t) is undone, so that a run from a state is the
     * same whatever ran on the scene before. NULL: nothing to undo. */
    void (*restart)(void *constraints, const tb_scene *scene, double t);
    /* The constraints' potential energy at y (J: soft joints' springs); NULL: none. */
    double (*potential_energy)(const void *constraints, const tb_scene *scene, const double *y);
} tb__constraint_ops;

#endif
