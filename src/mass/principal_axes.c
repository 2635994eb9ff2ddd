/* Principal axes and inverses of inertia tensors with GSL. GSL's default error handler
 * aborts, so every input is validated before GSL sees it: eigen-decomposition of a finite
 * symmetric 3x3 matrix cannot fail, and Cholesky only runs on a tensor shown positive
 * definite. GSL's symmetric eigen-solver does not terminate on subnormal entries, so it only
 * sees the tensor scaled to a largest entry of 1 with negligible entries set to zero. */
#include "mass/principal_axes.h"

#include "core/detail.h"
#include "math/tb_math.h"
#include "tumble/mass.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_vector.h>

#include <float.h>
#include <math.h>

/* Relative tolerance for symmetry and for the triangle inequality: inputs computed in double
 * precision by the caller (sums over meshes or points) carry this much round-off. */
#define TB__TENSOR_RELATIVE_TOLERANCE 1e-9
/* Smallest principal moment allowed, relative to the largest: below it the tensor is taken
 * as singular (collinear points, zero-thickness shapes). A needle of aspect 1:10^5 passes. */
#define TB__SINGULAR_RATIO 1e-12
/* Entries of the scaled tensor (largest entry 1) below this are set to zero before GSL sees
 * them: a symmetric perturbation E moves each eigenvalue by at most |E| (Weyl), so this moves
 * the moments by 3 DBL_EPSILON^2 of the largest, far below the solver's own DBL_EPSILON
 * round-off; and every product the solver forms stays a normal number. */
#define TB__NEGLIGIBLE_ENTRY (DBL_EPSILON * DBL_EPSILON)
/* Columns of the eigenvector matrix must be orthonormal to this (a few hundred round-offs)
 * before they are taken as a rotation. */
#define TB__ORTHONORMAL_TOLERANCE 1e-12

static double max_abs(const double *a, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i) {
        m = fmax(m, fabs(a[i]));
    }
    return m;
}

static tb_status check_symmetric(const double I[9], const char *what, tb_error *error)
{
    if (!tb__all_finite(I, 9)) {
        return tb__set_error(error, TB_STATUS_NOT_FINITE, "%s: contains NaN or infinity", what);
    }
    const double scale = max_abs(I, 9);
    static const int pairs[3][2] = {{1, 3}, {2, 6}, {5, 7}};
    for (int p = 0; p < 3; ++p) {
        const double a = I[pairs[p][0]], b = I[pairs[p][1]];
        if (fabs(a - b) > TB__TENSOR_RELATIVE_TOLERANCE * scale) {
            return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                                 "%s: not symmetric, element [%d] = %g but [%d] = %g", what,
                                 pairs[p][0], a, pairs[p][1], b);
        }
    }
    if (scale == 0.0) {
        return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES, "%s: is zero", what);
    }
    return TB_STATUS_OK;
}

/* The symmetrised tensor divided by scale, with negligible entries set to zero. */
static void scaled_tensor(const double I[9], double scale, double a[9])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double entry = 0.5 * (I[3 * i + j] / scale + I[3 * j + i] / scale);
            a[3 * i + j] = fabs(entry) < TB__NEGLIGIBLE_ENTRY ? 0.0 : entry;
        }
    }
}

/* Eigen-decomposition of a scaled tensor a (entries at most 1 in magnitude, none subnormal);
 * V's columns are the principal axes, made a proper rotation. */
static void eigen_decompose(const double a_in[9], double moments[3], double V[9])
{
    double a[9], vectors[9], values[3];
    for (int i = 0; i < 9; ++i) {
        a[i] = a_in[i];
    }
    gsl_matrix_view A = gsl_matrix_view_array(a, 3, 3);
    gsl_matrix_view evec = gsl_matrix_view_array(vectors, 3, 3);
    gsl_vector_view eval = gsl_vector_view_array(values, 3);
    /* 3x3: the workspace is a few dozen bytes, allocated at set-up only. */
    gsl_eigen_symmv_workspace *work = gsl_eigen_symmv_alloc(3);
    gsl_eigen_symmv(&A.matrix, &eval.vector, &evec.matrix, work);
    gsl_eigen_symmv_free(work);
    gsl_eigen_symmv_sort(&eval.vector, &evec.matrix, GSL_EIGEN_SORT_VAL_ASC);
    for (int i = 0; i < 9; ++i) {
        V[i] = vectors[i];
    }
    for (int i = 0; i < 3; ++i) {
        moments[i] = values[i];
    }
    const double det = V[0] * (V[4] * V[8] - V[5] * V[7]) - V[1] * (V[3] * V[8] - V[5] * V[6]) +
                       V[2] * (V[3] * V[7] - V[4] * V[6]);
    if (det < 0) { /* a reflection: flip the third axis to make the rotation proper */
        V[2] = -V[2];
        V[5] = -V[5];
        V[8] = -V[8];
    }
}

/* V^T V = Id within TB__ORTHONORMAL_TOLERANCE: the axes form a rotation. */
static bool orthonormal(const double V[9])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const double dot = V[i] * V[j] + V[3 + i] * V[3 + j] + V[6 + i] * V[6 + j];
            if (!(fabs(dot - (i == j ? 1.0 : 0.0)) <= TB__ORTHONORMAL_TOLERANCE)) {
                return false;
            }
        }
    }
    return true;
}

/* For a positive definite tensor the largest entry is its largest diagonal entry, which lies
 * between the smallest and the largest moment: outside [TB_MOMENT_MIN, TB_MOMENT_MAX] one of
 * the moments is too. Checked before the solver so it never sees subnormal numbers. */
static tb_status check_scale(double scale, const char *what, tb_error *error)
{
    if (scale < TB_MOMENT_MIN || scale > TB_MOMENT_MAX) {
        return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                             "%s: largest entry %g kg m^2 is outside the moments tumble accepts, "
                             "from %g to %g kg m^2 (TB_MOMENT_MIN, TB_MOMENT_MAX)",
                             what, scale, TB_MOMENT_MIN, TB_MOMENT_MAX);
    }
    return TB_STATUS_OK;
}

static tb_status check_moments(const double m[3], const char *what, tb_error *error)
{
    const double largest = fmax(m[0], fmax(m[1], m[2]));
    const double smallest = fmin(m[0], fmin(m[1], m[2]));
    if (!(smallest > TB__SINGULAR_RATIO * largest)) {
        return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                             "%s: not positive definite, principal moments (%g, %g, %g); "
                             "collinear points or a shape with no thickness?",
                             what, m[0], m[1], m[2]);
    }
    if (smallest < TB_MOMENT_MIN || largest > TB_MOMENT_MAX) {
        return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                             "%s: principal moments (%g, %g, %g) kg m^2 are outside the range "
                             "tumble accepts, from %g to %g kg m^2 (TB_MOMENT_MIN, TB_MOMENT_MAX)",
                             what, m[0], m[1], m[2], TB_MOMENT_MIN, TB_MOMENT_MAX);
    }
    for (int i = 0; i < 3; ++i) {
        const double others = m[(i + 1) % 3] + m[(i + 2) % 3];
        if (others < m[i] * (1.0 - TB__TENSOR_RELATIVE_TOLERANCE)) {
            return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                                 "%s: principal moments (%g, %g, %g) break the triangle "
                                 "inequality (%g + %g < %g); no mass distribution has them",
                                 what, m[0], m[1], m[2], m[(i + 1) % 3], m[(i + 2) % 3], m[i]);
        }
    }
    return TB_STATUS_OK;
}

/* The unit quaternion of the rotation V, normalised so that |q| = 1 to round-off whatever
 * the solver's last digits. */
static tb_status rotation_of(const double V[9], const char *what, double q[4], tb_error *error)
{
    if (!orthonormal(V)) {
        return tb__set_error(error, TB_STATUS_BAD_MASS_PROPERTIES,
                             "%s: the eigen-solver's principal axes are not orthonormal to %g",
                             what, TB__ORTHONORMAL_TOLERANCE);
    }
    tb__matrix_to_q(q, V);
    const double norm = tb__q_norm(q);
    for (int i = 0; i < 4; ++i) {
        q[i] /= norm;
    }
    return TB_STATUS_OK;
}

tb_status tb__principal_axes(const double I[9], const char *what, double out_moments[3],
                             double out_rotation[4], tb_error *error)
{
    tb_status status = check_symmetric(I, what, error);
    const double scale = max_abs(I, 9);
    if (status == TB_STATUS_OK) {
        status = check_scale(scale, what, error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    double a[9], moments[3], V[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    scaled_tensor(I, scale, a);
    const bool diagonal = a[1] == 0.0 && a[2] == 0.0 && a[5] == 0.0;
    if (diagonal) { /* keep the shape axes, and the moments exactly as given */
        tb__v3_set(moments, I[0], I[4], I[8]);
    } else {
        eigen_decompose(a, moments, V);
        for (int i = 0; i < 3; ++i) {
            moments[i] *= scale;
        }
    }
    double rotation[4];
    status = check_moments(moments, what, error);
    if (status == TB_STATUS_OK) {
        status = rotation_of(V, what, rotation, error);
    }
    if (status != TB_STATUS_OK) {
        return status;
    }
    tb__v3_copy(out_moments, moments);
    for (int i = 0; i < 4; ++i) {
        out_rotation[i] = rotation[i];
    }
    return TB_STATUS_OK;
}

tb_status tb_mass_tensor_inverse(const double inertia[9], double out_inverse[9],
                                 tb_error *out_error)
{
    tb__clear_error(out_error);
    if (inertia == NULL || out_inverse == NULL) {
        return tb__set_error(out_error, TB_STATUS_NULL_POINTER, "%s is NULL",
                             inertia == NULL ? "inertia" : "out_inverse");
    }
    double moments[3], rotation[4];
    tb_status status = tb__principal_axes(inertia, "inertia", moments, rotation, out_error);
    if (status != TB_STATUS_OK) {
        return status;
    }
    /* Positive definiteness is established above, so Cholesky cannot fail. */
    double a[9];
    for (int i = 0; i < 9; ++i) {
        a[i] = inertia[i];
    }
    gsl_matrix_view A = gsl_matrix_view_array(a, 3, 3);
    gsl_linalg_cholesky_decomp1(&A.matrix);
    gsl_linalg_cholesky_invert(&A.matrix);
    for (int i = 0; i < 9; ++i) {
        out_inverse[i] = a[i];
    }
    return TB_STATUS_OK;
}
