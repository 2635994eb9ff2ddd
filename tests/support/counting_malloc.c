/* The replacements counting_malloc.h describes. */
#include "counting_malloc.h"

#include <stddef.h>

/* glibc's own entry points, which the replacements forward to. */
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t count, size_t size);
extern void *__libc_realloc(void *pointer, size_t size);
extern void __libc_free(void *pointer);

long counted_allocations;
long failing_allocations;
long failing_allocation_at;

/* Whether this allocation is one of those made to fail. */
static int fails(void)
{
    if (failing_allocations > 0) {
        --failing_allocations;
        return 1;
    }
    if (failing_allocation_at > 0) {
        return --failing_allocation_at == 0;
    }
    return 0;
}

void *malloc(size_t size)
{
    ++counted_allocations;
    return fails() ? NULL : __libc_malloc(size);
}
void *calloc(size_t count, size_t size)
{
    ++counted_allocations;
    return fails() ? NULL : __libc_calloc(count, size);
}
void *realloc(void *pointer, size_t size)
{
    ++counted_allocations;
    return fails() ? NULL : __libc_realloc(pointer, size);
}
void free(void *pointer)
{
    __libc_free(pointer);
}
