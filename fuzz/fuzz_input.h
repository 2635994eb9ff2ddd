/* Reading a fuzz input as a stream of choices: bytes, small counts and doubles that favour the
 * values where numerical code breaks (zero, subnormals, the ends of the double range, NaN,
 * infinities, step sizes and times that make loops long). An exhausted input reads as zeros,
 * so every input is a complete program. Shared by the fuzz targets; header-only. */
#ifndef TUMBLE_FUZZ_INPUT_H
#define TUMBLE_FUZZ_INPUT_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct fuzz_input {
    const uint8_t *data;
    size_t size;
    size_t position;
} fuzz_input;

static inline uint8_t fuzz_byte(fuzz_input *in)
{
    return in->position < in->size ? in->data[in->position++] : 0;
}

static inline int fuzz_exhausted(const fuzz_input *in)
{
    return in->position >= in->size;
}

/* A choice in [0, count). */
static inline unsigned fuzz_choice(fuzz_input *in, unsigned count)
{
    return count == 0 ? 0 : fuzz_byte(in) % count;
}

static inline uint64_t fuzz_u64(fuzz_input *in)
{
    uint64_t value = 0;
    for (int i = 0; i < 8; ++i) {
        value = value << 8 | fuzz_byte(in);
    }
    return value;
}

/* Magnitudes where code breaks: subnormal, the smallest normal, steps so small or times so
 * large that loops never end, the largest finite double, overflow of products (1e200^2). */
static const double fuzz_magnitudes[] = {
    0.0,   5e-324, 1e-320, 1e-310, DBL_MIN, 1e-300,    1e-200, 1e-100, 1e-30,   1e-16,    1e-15,
    1e-12, 1e-9,   1e-6,   1e-4,   1e-3,    1.0 / 240, 0.01,   0.1,    0.25,    0.5,      1.0,
    2.0,   3.0,    9.81,   10.0,   100.0,   1e3,       1e6,    1e9,    1e10,    1e15,     1e16,
    1e18,  0x1p61, 0x1p64, 1e30,   1e100,   1e200,     1e300,  1e308,  DBL_MAX, INFINITY, NAN,
};

/* A double: mostly ordinary values, often an extreme magnitude of either sign, sometimes raw
 * bits (any NaN payload, any subnormal). */
static inline double fuzz_double(fuzz_input *in)
{
    const uint8_t selector = fuzz_byte(in);
    const size_t magnitude_count = sizeof fuzz_magnitudes / sizeof fuzz_magnitudes[0];
    switch (selector >> 6) {
    case 0: /* -4 .. 3.875 in steps of 1/8 */
        return (double)(selector & 63) / 8.0 - 4.0;
    case 1:
        return fuzz_magnitudes[(selector & 63) % magnitude_count];
    case 2:
        return -fuzz_magnitudes[(selector & 63) % magnitude_count];
    default: {
        const uint64_t bits = fuzz_u64(in);
        double value;
        memcpy(&value, &bits, sizeof value);
        return value;
    }
    }
}

/* A double that is usually a sensible positive size (0.1 .. 3.2 m or kg), else any double. */
static inline double fuzz_size(fuzz_input *in)
{
    const uint8_t selector = fuzz_byte(in);
    return selector < 160 ? 0.1 + (double)(selector % 32) / 10.0 : fuzz_double(in);
}

static inline void fuzz_vector(fuzz_input *in, double *out, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        out[i] = fuzz_double(in);
    }
}

#endif
