/* Mass properties: mass, centre of mass, principal moments and principal axes, from point
 * masses, primitives, closed triangle meshes, a full inertia tensor, or a composite of parts.
 *
 * Frames. A shape is described in its own "shape frame" (the frame its vertices, points or
 * sizes are given in). The "principal frame" has its origin at the centre of mass and its
 * axes along the principal axes of inertia; it is the body frame tumble integrates in, so
 * the inertia tensor is diagonal there. Units are SI: kg, m, kg m^2, kg/m^3. */
#ifndef TUMBLE_MASS_H
#define TUMBLE_MASS_H

#include "tumble/export.h"

#include "tumble/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The range of mass properties tumble accepts. Every physical rigid body lies far inside it
 * (an electron is 9.1e-31 kg, a hydrogen molecule's moment of inertia 4.6e-48 kg m^2, the
 * Milky Way 3e42 kg). Outside it double precision stops carrying the physics: the derivative
 * multiplies the momenta by 1/m and I^-1 every step, and those reciprocals, or v = P/m,
 * omega = I^-1 L and the kinetic energy made from them, overflow to infinity or sink into
 * subnormal numbers that have lost their digits (on which GSL's eigen-solver does not even
 * terminate). A mass outside is refused with TB_STATUS_INVALID_ARGUMENT; moments outside,
 * from any constructor, with TB_STATUS_BAD_MASS_PROPERTIES; tb_mass_validate refuses both. */
#define TB_MASS_MIN 1e-100   /* kg */
#define TB_MASS_MAX 1e100    /* kg */
#define TB_MOMENT_MIN 1e-200 /* kg m^2: a TB_MASS_MIN body 1e-50 m across */
#define TB_MOMENT_MAX 1e200  /* kg m^2: a TB_MASS_MAX body 1e50 m across */

typedef struct tb_mass_properties {
    double mass;        /* kg, in [TB_MASS_MIN, TB_MASS_MAX] */
    double center[3];   /* centre of mass in the shape frame, m */
    double moments[3];  /* principal moments about the centre of mass, kg m^2, each in
                           [TB_MOMENT_MIN, TB_MOMENT_MAX]; in the order of the principal
                           axes (see "Principal frame" below), not necessarily ascending */
    double rotation[4]; /* unit quaternion (w, x, y, z) taking principal-frame vectors to
                           shape-frame vectors; w >= 0 */
} tb_mass_properties;

/* Whether the inputs are a mass or a density. */
typedef enum tb_mass_mode {
    TB_MASS_GIVEN = 0, /* value is the mass, kg */
    TB_MASS_DENSITY    /* value is the density, kg/m^3 */
} tb_mass_mode;

/* Principal frame. When the inertia tensor is already diagonal in the shape frame (every
 * primitive below, points placed symmetrically) the shape axes are kept: rotation is the
 * identity and moments[i] is the moment about shape axis i. Otherwise GSL's symmetric
 * eigen-solver finds the axes, the moments come out ascending and rotation is proper
 * (det +1). Code should read rotation rather than assume either case. */

/* Solid primitives centred at the shape origin; cylinder and capsule axes along shape z.
 * mode says whether value is the mass (kg) or the density (kg/m^3). */

/* Solid sphere of radius r (m): I = 2/5 m r^2. */
TB_API tb_status tb_mass_from_sphere(tb_mass_mode mode, double value, double radius,
                                     tb_mass_properties *out_props, tb_error *out_error);

/* Solid box with full edge lengths size[3] (m): I_x = m (b^2 + c^2) / 12, ... */
TB_API tb_status tb_mass_from_box(tb_mass_mode mode, double value, const double size[3],
                                  tb_mass_properties *out_props, tb_error *out_error);

/* Solid cylinder of radius r and length h along z: I_z = m r^2 / 2,
 * I_x = I_y = m (3 r^2 + h^2) / 12. */
TB_API tb_status tb_mass_from_cylinder(tb_mass_mode mode, double value, double radius,
                                       double length, tb_mass_properties *out_props,
                                       tb_error *out_error);

/* Solid capsule: a cylinder of radius r and length h along z capped by two hemispheres of
 * radius r (total length h + 2 r). */
TB_API tb_status tb_mass_from_capsule(tb_mass_mode mode, double value, double radius, double length,
                                      tb_mass_properties *out_props, tb_error *out_error);

/* Solid ellipsoid with semi-axes a, b, c along x, y, z: I_x = m (b^2 + c^2) / 5, ... */
TB_API tb_status tb_mass_from_ellipsoid(tb_mass_mode mode, double value, const double semi_axes[3],
                                        tb_mass_properties *out_props, tb_error *out_error);

/* Point masses: positions[3 * count] (shape frame, m), masses[count] (kg, each in
 * [TB_MASS_MIN, TB_MASS_MAX]).
 * I_xx = sum m (y^2 + z^2), I_xy = - sum m x y, ... about the centre of mass. Points that
 * all lie on one line give a singular tensor and are rejected. */
TB_API tb_status tb_mass_from_points(const double *positions, const double *masses, size_t count,
                                     tb_mass_properties *out_props, tb_error *out_error);

/* A closed, consistently oriented (outward normals by the right-hand rule), non-degenerate
 * triangle mesh of uniform density: vertices[3 * vertex_count] (m),
 * triangles[3 * triangle_count] (vertex indices). Volume integrals by signed tetrahedra,
 * about the centroid of the triangles' corners. Vertices no triangle uses are ignored (they
 * must still be finite). */
TB_API tb_status tb_mass_from_mesh(tb_mass_mode mode, double value, const double *vertices,
                                   size_t vertex_count, const unsigned *triangles,
                                   size_t triangle_count, tb_mass_properties *out_props,
                                   tb_error *out_error);

/* A full inertia tensor I[9] (row-major, kg m^2, about the centre of mass, shape frame),
 * the mass and the centre of mass: diagonalised into principal moments and a proper
 * rotation. Rejected unless symmetric (relative 1e-9), positive definite, and its principal
 * moments satisfy the triangle inequality I1 + I2 >= I3 (relative 1e-9). */
TB_API tb_status tb_mass_from_tensor(double mass, const double center[3], const double inertia[9],
                                     tb_mass_properties *out_props, tb_error *out_error);

/* A part of a composite: its own mass properties, placed in the composite's shape frame by
 * the position of the part's shape origin and the rotation of the part's shape frame
 * (unit quaternion, part shape -> composite shape). */
typedef struct tb_mass_part {
    tb_mass_properties props;
    double position[3];
    double orientation[4];
} tb_mass_part;

/* Combines parts by the parallel-axis theorem into one rigid body. */
TB_API tb_status tb_mass_combine(const tb_mass_part *parts, size_t count,
                                 tb_mass_properties *out_props, tb_error *out_error);

/* The inertia tensor of props about its centre of mass in the shape frame (row-major). */
TB_API tb_status tb_mass_tensor(const tb_mass_properties *props, double out_inertia[9]);

/* Inverse of an inertia tensor (row-major), validated as tb_mass_from_tensor does:
 * symmetric, positive definite, triangle inequality. */
TB_API tb_status tb_mass_tensor_inverse(const double inertia[9], double out_inverse[9],
                                        tb_error *out_error);

/* Checks props: finite; mass in [TB_MASS_MIN, TB_MASS_MAX]; moments in
 * [TB_MOMENT_MIN, TB_MOMENT_MAX] in any order (the constructors keep a primitive's shape axes,
 * so a box's moments may descend), the smallest above 1e-12 of the largest, and the triangle
 * inequality within 1e-9 relative; rotation a unit quaternion (|q| = 1 within 1e-4). A finite
 * value out of its range is TB_STATUS_INVALID_ARGUMENT, a non-finite one
 * TB_STATUS_NOT_FINITE, moments no body has TB_STATUS_BAD_MASS_PROPERTIES. */
TB_API tb_status tb_mass_validate(const tb_mass_properties *props, tb_error *out_error);

#ifdef __cplusplus
}
#endif

#endif
