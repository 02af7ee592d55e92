/*
 * driver.h: the test run shared by the firmware (main.c, on a Cortex-M4F under QEMU) and the
 * host reference (host_reference.c): the same C code on both sides, so the two print the same
 * lines when libhyst computes the same floats.
 *
 * No libc: the signal (a sine with a growing amplitude and minor loops), the number formatting
 * and the line buffer are written here in plain C99 float and integer arithmetic.
 */
#ifndef HYST_FIRMWARE_DRIVER_H
#define HYST_FIRMWARE_DRIVER_H

#include <stdint.h>

/* Samples per series. */
#define DRV_SAMPLES 500

/* Where the driver's text goes: called once per line, with a NUL-terminated line that ends in
 * '\n'. */
typedef void (*drv_write_fn)(const char *line);

/*
 * Runs the test signal through the f32 C API and writes one line per output value:
 *
 *   v <series> <index> <IEEE-754 bits in hex> <the value, 9 significant digits>
 *
 * series: inv (H^-1[x]), dir (H[H^-1[x]], gives x back), shp (the shaped model on x), cmp (the
 * n = 2 compensator's command). Lines that start with '#' are text that must be the same on
 * every machine; those that start with '~' (the round trip's largest error, itself a rounding
 * error, and how far the compensator's integrators drift from the reference) are information
 * that may differ in the last bits. The last line is
 * "# done: <values> values, <errors> errors". Returns the number of errors (a status other than
 * HYST_OK, or a round trip off by more than 1e-5): 0 on success.
 */
int drv_run(drv_write_fn write);

/* The text of a float as drv_run prints it: "-1.23456789e-03" (9 significant digits, correctly
 * rounded, for 2^-37 <= |x| < 2^63 and 0; "inf", "nan", and "~" for other magnitudes, whose
 * hex bits still hold the exact value). `out` holds at least 16 bytes. Returns the length. */
int drv_format_float(float x, char *out);

/* The bits of a float (the exact value printed in hex). */
uint32_t drv_float_bits(float x);

#endif /* HYST_FIRMWARE_DRIVER_H */
