/* Mass properties of primitives, point masses, full tensors and composites. Every path ends
 * in tb_mass_from_tensor, which finds the principal frame. */
#include "tumble/mass.h"

#include "core/detail.h"
#include "mass/mass_internal.h"
#include "mass/principal_axes.h"
#include "math/tb_math.h"

#include <math.h>
#include <stddef.h>

#define TB__PI 3.14159265358979323846
/* A unit quaternion may be off by this much in norm (inputs typed with 4-5 digits). */
#define TB__UNIT_QUATERNION_TOLERANCE 1e-4

tb_status tb__check_positive(double value, const char *what, tb_error *error)
{
    if (!isfinite(value)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "%s: must be finite, got %g", what,
                             value);
    }
    if (!(value > 0)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "%s: must be > 0, got %g", what,
                             value);
    }
    return TB_STATUS_OK;
}

tb_status tb__check_mass(double mass, const char *what, tb_error *error)
{
    tb_status status = tb__check_positive(mass, what, error);
    if (status == TB_STATUS_OK && (mass < TB_MASS_MIN || mass > TB_MASS_MAX)) {
        status = tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                               "%s: must be from %g to %g kg (TB_MASS_MIN, TB_MASS_MAX), got %g",
                               what, TB_MASS_MIN, TB_MASS_MAX, mass);
    }
    return status;
}

tb_status tb__check_unit_quaternion(const double q[4], const char *what, tb_error *error)
{
    if (!tb__all_finite(q, 4)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "%s: contains NaN or infinity", what);
    }
    const double norm = tb__q_norm(q);
    if (fabs(norm - 1.0) > TB__UNIT_QUATERNION_TOLERANCE) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "%s: must be a unit quaternion (|q| = 1 within %g), got |q| = %g",
                             what, TB__UNIT_QUATERNION_TOLERANCE, norm);
    }
    return TB_STATUS_OK;
}

tb_status tb__resolve_mass(tb_mass_mode mode, double value, double volume, double *mass,
                           tb_error *error)
{
    if (mode != TB_MASS_GIVEN && mode != TB_MASS_DENSITY) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT, "mode: unknown mass mode %d",
                             (int)mode);
    }
    if (mode == TB_MASS_GIVEN) {
        tb_status status = tb__check_mass(value, "mass", error);
        if (status == TB_STATUS_OK) {
            *mass = value;
        }
        return status;
    }
    tb_status status = tb__check_positive(value, "density", error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double product = value * volume;
    if (!(product >= TB_MASS_MIN && product <= TB_MASS_MAX)) {
        return tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                             "density: %g kg/m^3 times the volume %g m^3 gives a mass of %g kg, "
                             "outside %g to %g kg (TB_MASS_MIN, TB_MASS_MAX)",
                             value, volume, product, TB_MASS_MIN, TB_MASS_MAX);
    }
    *mass = product;
    return TB_STATUS_OK;
}

static tb_status from_diagonal(double mass, double ixx, double iyy, double izz,
                               tb_mass_properties *out, tb_error *error)
{
    const double I[9] = {ixx, 0, 0, 0, iyy, 0, 0, 0, izz};
    const double origin[3] = {0, 0, 0};
    return tb_mass_from_tensor(mass, origin, I, out, error);
}

tb_status tb_mass_from_sphere(tb_mass_mode mode, double value, double radius,
                              tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    double mass;
    tb_status status = tb__check_positive(radius, "radius", out_error);
    if (status == TB_STATUS_OK) {
        status =
            tb__resolve_mass(mode, value, 4.0 / 3.0 * TB__PI * pow(radius, 3), &mass, out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double i = 0.4 * mass * radius * radius;
    return from_diagonal(mass, i, i, i, out_props, out_error);
}

static tb_status check_three_positive(const double v[3], const char *what, tb_error *error)
{
    static const char *const names[3] = {"[0]", "[1]", "[2]"};
    char label[64];
    for (int i = 0; i < 3; ++i) {
        snprintf(label, sizeof label, "%s%s", what, names[i]);
        tb_status status = tb__check_positive(v[i], label, error);
        if (status != TB_STATUS_OK) {
            return status;
        }
    }
    return TB_STATUS_OK;
}

tb_status tb_mass_from_box(tb_mass_mode mode, double value, const double size[3],
                           tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (size == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "size is NULL");
    }
    double mass;
    tb_status status = check_three_positive(size, "size", out_error);
    if (status == TB_STATUS_OK) {
        status = tb__resolve_mass(mode, value, size[0] * size[1] * size[2], &mass, out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double x2 = size[0] * size[0], y2 = size[1] * size[1], z2 = size[2] * size[2];
    return from_diagonal(mass, mass * (y2 + z2) / 12, mass * (x2 + z2) / 12, mass * (x2 + y2) / 12,
                         out_props, out_error);
}

static tb_status check_radius_length(double radius, double length, tb_error *error)
{
    tb_status status = tb__check_positive(radius, "radius", error);
    if (status == TB_STATUS_OK) {
        status = tb__check_positive(length, "length", error);
    }
    return status;
}

tb_status tb_mass_from_cylinder(tb_mass_mode mode, double value, double radius, double length,
                                tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    double mass;
    tb_status status = check_radius_length(radius, length, out_error);
    if (status == TB_STATUS_OK) {
        status = tb__resolve_mass(mode, value, TB__PI * radius * radius * length, &mass, out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double r2 = radius * radius, h2 = length * length;
    const double across = mass * (3 * r2 + h2) / 12;
    return from_diagonal(mass, across, across, 0.5 * mass * r2, out_props, out_error);
}

tb_status tb_mass_from_capsule(tb_mass_mode mode, double value, double radius, double length,
                               tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    const double r = radius, h = length;
    const double cylinder_volume = TB__PI * r * r * h;
    const double hemisphere_volume = 2.0 / 3.0 * TB__PI * r * r * r;
    double mass;
    tb_status status = check_radius_length(radius, length, out_error);
    if (status == TB_STATUS_OK) {
        status = tb__resolve_mass(mode, value, cylinder_volume + 2 * hemisphere_volume, &mass,
                                  out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* Split the mass in proportion to volume. A hemisphere's centre of mass sits 3r/8 from its
     * flat face; its moment about a diameter of that face is 2/5 m r^2, so about the capsule's
     * centre (parallel axes through its own centre of mass) it is
     * m (2/5 r^2 - (3r/8)^2 + (h/2 + 3r/8)^2) = m (2/5 r^2 + h^2/4 + 3 h r / 8). */
    const double total_volume = cylinder_volume + 2 * hemisphere_volume;
    const double m_cyl = mass * cylinder_volume / total_volume;
    const double m_hemi = mass * hemisphere_volume / total_volume;
    const double axial = 0.5 * m_cyl * r * r + 2 * 0.4 * m_hemi * r * r;
    const double across = m_cyl * (3 * r * r + h * h) / 12 +
                          2 * m_hemi * (0.4 * r * r + 0.25 * h * h + 0.375 * h * r);
    return from_diagonal(mass, across, across, axial, out_props, out_error);
}

tb_status tb_mass_from_ellipsoid(tb_mass_mode mode, double value, const double semi_axes[3],
                                 tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (semi_axes == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "semi_axes is NULL");
    }
    const double *s = semi_axes;
    double mass;
    tb_status status = check_three_positive(s, "semi_axes", out_error);
    if (status == TB_STATUS_OK) {
        status = tb__resolve_mass(mode, value, 4.0 / 3.0 * TB__PI * s[0] * s[1] * s[2], &mass,
                                  out_error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double a2 = s[0] * s[0], b2 = s[1] * s[1], c2 = s[2] * s[2];
    return from_diagonal(mass, mass * (b2 + c2) / 5, mass * (a2 + c2) / 5, mass * (a2 + b2) / 5,
                         out_props, out_error);
}

void tb__add_point_inertia(double I[9], double m, const double d[3])
{
    /* Parallel-axis term of a point mass m at offset d: m (|d|^2 Id - d d^T). */
    const double d2 = tb__v3_dot(d, d);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            I[3 * i + j] += m * ((i == j ? d2 : 0.0) - d[i] * d[j]);
        }
    }
}

tb_status tb_mass_from_points(const double *positions, const double *masses, size_t count,
                              tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (positions == NULL || masses == NULL || out_props == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             positions == NULL ? "positions"
                             : masses == NULL  ? "masses"
                                               : "out_props");
    }
    if (count == 0) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT, "count: must be > 0");
    }
    double mass = 0.0, center[3] = {0, 0, 0};
    for (size_t k = 0; k < count; ++k) {
        char label[48];
        snprintf(label, sizeof label, "masses[%zu]", k);
        tb_status status = tb__check_mass(masses[k], label, out_error);
        if (status != TB_STATUS_OK) {
            return status;
        }
        if (!tb__all_finite(positions + 3 * k, 3)) {
            return tb__set_error(out_error, TB_STATUS_NOT_FINITE,
                                 "positions[%zu]: contains NaN or infinity", k);
        }
        mass += masses[k];
        tb__v3_axpy(center, masses[k], positions + 3 * k);
    }
    tb__v3_set(center, center[0] / mass, center[1] / mass, center[2] / mass);
    double I[9] = {0};
    for (size_t k = 0; k < count; ++k) {
        const double *p = positions + 3 * k;
        const double d[3] = {p[0] - center[0], p[1] - center[1], p[2] - center[2]};
        tb__add_point_inertia(I, masses[k], d);
    }
    return tb_mass_from_tensor(mass, center, I, out_props, out_error);
}

tb_status tb_mass_from_tensor(double mass, const double center[3], const double inertia[9],
                              tb_mass_properties *out_props, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (center == NULL || inertia == NULL || out_props == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             center == NULL    ? "center"
                             : inertia == NULL ? "inertia"
                                               : "out_props");
    }
    tb_status status = tb__check_mass(mass, "mass", out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (!tb__all_finite(center, 3)) {
        return tb__set_error(out_error, TB_STATUS_NOT_FINITE, "center: contains NaN or infinity");
    }
    tb_mass_properties props;
    status = tb__principal_axes(inertia, "inertia", props.moments, props.rotation, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    props.mass = mass;
    tb__v3_copy(props.center, center);
    *out_props = props;
    return TB_STATUS_OK;
}

tb_status tb_mass_tensor(const tb_mass_properties *props, double out_inertia[9])
{
    if (props == NULL || out_inertia == NULL) {
        return TB_STATUS_NULL_POINTER;
    }
    double R[9];
    tb__q_to_matrix(R, props->rotation);
    tb__m3_rotate_diagonal(out_inertia, R, props->moments);
    return TB_STATUS_OK;
}

/* Each moment positive and in [TB_MOMENT_MIN, TB_MOMENT_MAX], named by index. */
static tb_status check_moment_range(const double moments[3], tb_error *error)
{
    tb_status status = check_three_positive(moments, "moments", error);
    for (int i = 0; i < 3 && status == TB_STATUS_OK; ++i) {
        if (moments[i] < TB_MOMENT_MIN || moments[i] > TB_MOMENT_MAX) {
            status = tb__set_error(error, TB_STATUS_INVALID_ARGUMENT,
                                   "moments[%d]: must be from %g to %g kg m^2 (TB_MOMENT_MIN, "
                                   "TB_MOMENT_MAX), got %g",
                                   i, TB_MOMENT_MIN, TB_MOMENT_MAX, moments[i]);
        }
    }
    return status;
}

tb_status tb_mass_validate(const tb_mass_properties *props, tb_error *out_error)
{
    tb__clear_error(out_error);
    if (props == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "props is NULL");
    }
    tb_status status = tb__check_mass(props->mass, "mass", out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    if (!tb__all_finite(props->center, 3)) {
        return tb__set_error(out_error, TB_STATUS_NOT_FINITE, "center: contains NaN or infinity");
    }
    status = check_moment_range(props->moments, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    status = tb__check_unit_quaternion(props->rotation, "rotation", out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    const double I[9] = {props->moments[0], 0, 0, 0, props->moments[1], 0, 0, 0, props->moments[2]};
    double moments[3], rotation[4];
    return tb__principal_axes(I, "moments", moments, rotation, out_error);
}

tb_status tb_mass_combine(const tb_mass_part *parts, size_t count, tb_mass_properties *out_props,
                          tb_error *out_error)
{
    tb__clear_error(out_error);
    if (parts == NULL || out_props == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             parts == NULL ? "parts" : "out_props");
    }
    if (count == 0) {
        return tb__set_error(out_error, TB_STATUS_INVALID_ARGUMENT, "count: must be > 0");
    }
    double mass = 0.0, center[3] = {0, 0, 0};
    for (size_t k = 0; k < count; ++k) {
        const tb_mass_part *part = &parts[k];
        tb_error part_error;
        tb_status status = tb_mass_validate(&part->props, &part_error);
        if (status == TB_STATUS_OK) {
            status = tb__check_unit_quaternion(part->orientation, "orientation", &part_error);
        }
        if (status == TB_STATUS_OK && !tb__all_finite(part->position, 3)) {
            status = tb__set_error(&part_error, TB_STATUS_NOT_FINITE,
                                   "position: contains NaN or infinity");
        }
        if (status != TB_STATUS_OK) {
            return tb__set_error(out_error, status, "parts[%zu].%s", k, part_error.message);
        }
        double c[3];
        tb__q_rotate(c, part->orientation, part->props.center);
        tb__v3_axpy(c, 1.0, part->position);
        mass += part->props.mass;
        tb__v3_axpy(center, part->props.mass, c);
    }
    tb__v3_set(center, center[0] / mass, center[1] / mass, center[2] / mass);
    double I[9] = {0};
    for (size_t k = 0; k < count; ++k) {
        const tb_mass_part *part = &parts[k];
        double q[4], R[9], own[9], d[3];
        tb__q_mul(q, part->orientation, part->props.rotation); /* principal -> composite */
        tb__q_to_matrix(R, q);
        tb__m3_rotate_diagonal(own, R, part->props.moments);
        tb__q_rotate(d, part->orientation, part->props.center);
        for (int i = 0; i < 3; ++i) {
            d[i] += part->position[i] - center[i];
        }
        for (int i = 0; i < 9; ++i) {
            I[i] += own[i];
        }
        tb__add_point_inertia(I, part->props.mass, d);
    }
    return tb_mass_from_tensor(mass, center, I, out_props, out_error);
}
