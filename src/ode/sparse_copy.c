/* The system's CSR Jacobian handed to SUNDIALS (sparse_copy.h). */
#include "ode/sparse_copy.h"

#include "core/validate.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

bool tb__ode_sparse_reserve(tb_ode_sparse *J, size_t capacity)
{
    size_t *columns = tb__realloc_array(J->columns, capacity, sizeof(size_t));
    J->columns = columns != NULL ? columns : J->columns;
    double *values = tb__realloc_array(J->values, capacity, sizeof(double));
    J->values = values != NULL ? values : J->values;
    if (columns == NULL || values == NULL) {
        return false;
    }
    J->capacity = capacity;
    return true;
}

size_t tb__add_larger_columns(double *into, const double *from, size_t count,
                              const size_t *column_of, size_t n, double ratio, double floor,
                              double *taken)
{
    memset(taken, 0, n * sizeof *taken);
    size_t columns = 0;
    for (size_t e = 0; e < count; ++e) {
        const size_t j = column_of != NULL ? column_of[e] : e / n;
        if (taken[j] == 0.0 && fabs(from[e]) > ratio * fabs(into[e]) && fabs(from[e]) > floor) {
            taken[j] = 1.0;
            ++columns;
        }
    }
    for (size_t e = 0; e < count && columns > 0; ++e) {
        if (taken[column_of != NULL ? column_of[e] : e / n] != 0.0) {
            into[e] += from[e];
        }
    }
    return columns;
}

#ifdef TB_HAVE_KLU
bool tb__klu_pattern_reserve(tb__klu_pattern *p, size_t n, size_t capacity)
{
    sunindextype *analysed =
        n + 1 > SIZE_MAX - capacity
            ? NULL
            : tb__realloc_array(p->analysed, n + 1 + capacity, sizeof(sunindextype));
    p->analysed = analysed != NULL ? analysed : p->analysed;
    return analysed != NULL;
}

bool tb__klu_copy(const tb_ode_sparse *J, bool shifted, double h_gamma, SUNMatrix A,
                  tb__klu_pattern *p)
{
    const size_t n = J->n, entries = J->row_starts[n];
    sunindextype *rows = SUNSparseMatrix_IndexPointers(A);
    sunindextype *columns = SUNSparseMatrix_IndexValues(A);
    double *data = SUNSparseMatrix_Data(A);
    bool same = entries == p->entries;
    for (size_t i = 0; i <= n; ++i) {
        rows[i] = (sunindextype)J->row_starts[i];
        same = same && p->analysed[i] == rows[i];
    }
    for (size_t i = 0; i < n; ++i) {
        for (size_t e = J->row_starts[i]; e < J->row_starts[i + 1]; ++e) {
            columns[e] = (sunindextype)J->columns[e];
            same = same && p->analysed[n + 1 + e] == columns[e];
        }
    }
    if (shifted) {
        for (size_t i = 0; i < n; ++i) {
            for (size_t e = J->row_starts[i]; e < J->row_starts[i + 1]; ++e) {
                data[e] = -h_gamma * J->values[e] + (J->columns[e] == i ? 1.0 : 0.0);
            }
        }
    } else {
        memcpy(data, J->values, entries * sizeof(double));
    }
    if (!same) {
        memcpy(p->analysed, rows, (n + 1) * sizeof(sunindextype));
        memcpy(p->analysed + n + 1, columns, entries * sizeof(sunindextype));
        p->entries = entries;
    }
    return same;
}
#endif
