/* A test's allocation counter: linking tests/support/counting_malloc.c into a test replaces
 * malloc, calloc and realloc with glibc's own behind a count (free is passed through), so a
 * test can assert that a call allocates nothing. Not for sanitizer builds, whose runtime owns
 * malloc. */
#ifndef TUMBLE_TEST_COUNTING_MALLOC_H
#define TUMBLE_TEST_COUNTING_MALLOC_H

extern long counted_allocations; /* malloc, calloc and realloc calls so far */
/* While above 0, each malloc, calloc and realloc fails (returns NULL) and counts it down: a
 * test of what a failed allocation leaves. 0 by default. */
extern long failing_allocations;
/* While above 0, each malloc, calloc and realloc counts it down, and the one that takes it to 0
 * fails: failing_allocation_at = k fails the k-th allocation from now alone (a sweep over k
 * fails each allocation of a call in turn). 0 by default. */
extern long failing_allocation_at;

#endif
