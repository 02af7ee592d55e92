/*
 * host_reference.c: the firmware's test run (driver.c) on the host, against the host's
 * libhyst.a (cargo build -p hyst-capi --release), and the comparison of the two.
 *
 *   host_reference                  prints the lines main.c prints on the Cortex-M4F
 *   host_reference --compare FILE   compares FILE (the firmware's output) with them: the same
 *                                   lines, and every value (the float its hex bits encode)
 *                                   within 1e-6 relative to the larger of the two values and of
 *                                   the largest magnitude of its series (see compare())
 *   host_reference --identical FILE the same lines, and every value with the same bits
 *
 * Exit status 0 on success, 1 on any error or difference.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "driver.h"

#define TOLERANCE 1e-6
#define MAX_LINES 4096
#define MAX_LINE 128

static char host_lines[MAX_LINES][MAX_LINE];
static int host_count;
static int host_overflow;

static void print_line(const char *line) {
    fputs(line, stdout);
}

static void keep_line(const char *line) {
    if (host_count == MAX_LINES || strlen(line) >= MAX_LINE) {
        host_overflow = 1;
        return;
    }
    strcpy(host_lines[host_count++], line);
}

/* "v <series> <index> <hex> <decimal>": the series, index and float of a value line. */
static int parse_value(const char *line, char *series, long *index, float *value) {
    unsigned long bits;
    uint32_t b;
    if (sscanf(line, "v %15s %ld %lx", series, index, &bits) != 3) {
        return 0;
    }
    b = (uint32_t)bits;
    memcpy(value, &b, sizeof *value);
    return 1;
}

/* The largest magnitude of each series in the host's lines: the scale of a value's rounding
 * error. A value computed as a difference of larger ones (the operator near a zero crossing, the
 * compensator's x + a1 x' + a2 x'') carries the rounding of those: measured against its own small
 * magnitude, a last-bit difference in expf on one side can exceed 1e-6. */
#define MAX_SERIES 16
static char series_name[MAX_SERIES][16];
static double series_peak[MAX_SERIES];
static int series_count;

static double *peak_of(const char *series) {
    int i;
    for (i = 0; i < series_count; i++) {
        if (strcmp(series_name[i], series) == 0) {
            return &series_peak[i];
        }
    }
    if (series_count == MAX_SERIES) {
        return NULL;
    }
    strcpy(series_name[series_count], series);
    series_peak[series_count] = 0.0;
    return &series_peak[series_count++];
}

static double magnitude(float x) {
    return x < 0 ? -(double)x : (double)x;
}

/* exact != 0: every value must have the host's bits. Otherwise each value must be within
 * TOLERANCE of the host's, relative to the larger of the two values and of the series' peak. */
static int compare(const char *path, int exact) {
    FILE *f = fopen(path, "r");
    char line[MAX_LINE + 2];
    int n = 0, i, mismatches = 0, values = 0, identical = 0, beyond_plain = 0;
    double worst = 0.0, worst_plain = 0.0;
    char worst_at[64] = "-";

    if (f == NULL) {
        fprintf(stderr, "host_reference: cannot open %s\n", path);
        return 1;
    }
    for (i = 0; i < host_count; i++) {
        char hs[16];
        long hi;
        float hv;
        double *peak;
        if (parse_value(host_lines[i], hs, &hi, &hv) && (peak = peak_of(hs)) != NULL &&
            magnitude(hv) > *peak) {
            *peak = magnitude(hv);
        }
    }
    while (fgets(line, sizeof line, f) != NULL) {
        char fs[16], hs[16];
        long fi, hi;
        float fv, hv;
        if (n >= host_count) {
            fprintf(stderr, "line %d: the firmware printed more lines than the host: %s", n + 1,
                    line);
            mismatches++;
            break;
        }
        if (parse_value(line, fs, &fi, &fv)) {
            double diff, plain, scaled, *peak;
            if (!parse_value(host_lines[n], hs, &hi, &hv) || strcmp(fs, hs) != 0 || fi != hi) {
                fprintf(stderr, "line %d differs:\n  firmware: %s  host:     %s", n + 1, line,
                        host_lines[n]);
                mismatches++;
                n++;
                continue;
            }
            values++;
            if (memcmp(&fv, &hv, sizeof fv) == 0) {
                identical++;
                n++;
                continue;
            }
            diff = (double)fv - (double)hv;
            diff = diff < 0 ? -diff : diff;
            plain = magnitude(fv) > magnitude(hv) ? magnitude(fv) : magnitude(hv);
            peak = peak_of(hs);
            scaled = peak != NULL && *peak > plain ? *peak : plain;
            plain = plain > 0 ? diff / plain : diff;
            scaled = scaled > 0 ? diff / scaled : diff;
            if (plain > TOLERANCE) {
                beyond_plain++;
            }
            if (exact || !(scaled <= TOLERANCE)) { /* !(<=) also catches NaN */
                fprintf(stderr, "line %d: %s (relative %.3g, to the series' peak %.3g):\n"
                        "  firmware: %s  host:     %s", n + 1,
                        exact ? "not bit-identical" : "beyond the tolerance", plain, scaled,
                        line, host_lines[n]);
                mismatches++;
            }
            if (scaled > worst) {
                worst = scaled;
                snprintf(worst_at, sizeof worst_at, "%s %ld", fs, fi);
            }
            if (plain > worst_plain) {
                worst_plain = plain;
            }
        } else if (line[0] == '~' && host_lines[n][0] == '~') {
            /* information that may differ by rounding (driver.h) */
        } else if (strcmp(line, host_lines[n]) != 0) {
            fprintf(stderr, "line %d differs:\n  firmware: %s  host:     %s", n + 1, line,
                    host_lines[n]);
            mismatches++;
        }
        n++;
    }
    fclose(f);
    if (n < host_count) {
        fprintf(stderr, "the firmware stopped after %d of the host's %d lines\n", n, host_count);
        mismatches++;
    }
    if (identical == values) {
        printf("%d values: all bit-identical", values);
    } else {
        printf("%d values: %d bit-identical, %d differ: largest difference %.3g of the series' "
               "peak (at %s; tolerance %g), largest relative to the value itself %.3g (%d values "
               "beyond %g by that measure)",
               values, identical, values - identical, worst, worst_at, TOLERANCE, worst_plain,
               beyond_plain, TOLERANCE);
    }
    printf("; %s\n", mismatches == 0 ? "pass" : "FAIL");
    return mismatches == 0 ? 0 : 1;
}

int main(int argc, char **argv) {
    int errors;
    if (argc == 1) {
        errors = drv_run(print_line);
        return errors == 0 ? 0 : 1;
    }
    if (argc == 3 && (strcmp(argv[1], "--compare") == 0 || strcmp(argv[1], "--identical") == 0)) {
        errors = drv_run(keep_line);
        if (host_overflow) {
            fprintf(stderr, "host_reference: more than %d lines\n", MAX_LINES);
            return 1;
        }
        if (errors != 0) {
            fprintf(stderr, "host_reference: %d errors in the host's own run\n", errors);
            return 1;
        }
        return compare(argv[2], strcmp(argv[1], "--identical") == 0);
    }
    fprintf(stderr, "usage: host_reference [--compare | --identical FIRMWARE_OUTPUT]\n");
    return 2;
}
