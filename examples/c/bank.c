/*
 * bank: a bank of operators (hyst_bank_*, host part) for the 97 actuators of a deformable
 * mirror, called from C99 with every result checked.
 *
 *   bank
 *
 * Each actuator has its own k1, k2 and memory. The bank of inverse operators H^-1 is stepped
 * one control period at a time (hyst_bank_step) and, in a second bank, a block of periods at
 * once (hyst_bank_process, time-major); each channel is compared with a scalar inverse
 * (hyst_operator_*) within the bank's stated tolerance |dy| <= 1e-13 max(|y|, k1) (float:
 * 1e-5). Then the errors: an invalid k1 and a NaN sample name their channel and leave every
 * memory as it was; a channel's memory moves from the bank to a scalar operator and back.
 * Prints one line per failed check and `bank: N passed, M failed`; exits 1 on any failure.
 */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hyst.h"

#define ACTUATORS 97
#define PERIODS 2000

static int passed, failed;

static void check(int ok, int line, const char *what)
{
    if (ok) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "bank.c:%d: FAILED: %s\n", line, what);
    }
}

#define CHECK(cond) check((cond), __LINE__, #cond)

/* The desired deflection of actuator c at period t (a moving wavefront with reversals). */
static double desired(int t, int c)
{
    double s = t * 0.01;
    return (0.2 + 0.002 * c) * sin(s * (1.0 + 0.05 * c)) + 0.05 * cos(3.3 * s + c);
}

static double k1_of(int c) { return 0.05 + 0.001 * c; }
static double k2_of(int c) { return 4.0 + 0.05 * c; }

static int close_to(double bank, double scalar, double k1, double tol)
{
    double scale = fabs(scalar) > k1 ? fabs(scalar) : k1;
    return fabs(bank - scalar) <= tol * scale;
}

int main(void)
{
    double k1[ACTUATORS], k2[ACTUATORS];
    float k1f[ACTUATORS], k2f[ACTUATORS];
    for (int c = 0; c < ACTUATORS; c++) {
        k1[c] = k1_of(c);
        k2[c] = k2_of(c);
        k1f[c] = (float)k1[c];
        k2f[c] = (float)k2[c];
    }

    /* Two banks of inverses H^-1 (inverse = 1) and the scalar inverses to compare with. */
    hyst_bank *stepped = NULL, *blocked = NULL;
    size_t channel = 0;
    CHECK(hyst_bank_create(k1, k2, ACTUATORS, 1, &stepped, &channel) == HYST_OK);
    CHECK(hyst_bank_create(k1, k2, ACTUATORS, 1, &blocked, &channel) == HYST_OK);
    if (stepped == NULL || blocked == NULL) {
        fprintf(stderr, "bank: cannot create the banks\n");
        return 1;
    }
    CHECK(hyst_bank_channels(stepped) == ACTUATORS);
    static hyst_operator scalar[ACTUATORS];
    for (int c = 0; c < ACTUATORS; c++) {
        CHECK(hyst_operator_init_inverse(&scalar[c], k1[c], k2[c]) == HYST_OK);
    }

    /* The block: all periods, time-major (x[t * ACTUATORS + c]), processed in place. */
    double *block = malloc(sizeof(double) * PERIODS * ACTUATORS);
    if (block == NULL) {
        return 1;
    }
    for (int t = 0; t < PERIODS; t++) {
        for (int c = 0; c < ACTUATORS; c++) {
            block[t * ACTUATORS + c] = desired(t, c);
        }
    }
    CHECK(hyst_bank_process(blocked, block, block, PERIODS, &channel) == HYST_OK);

    /* One control period at a time. */
    int agree = 1, same_as_block = 1;
    for (int t = 0; t < PERIODS; t++) {
        double ud[ACTUATORS], v[ACTUATORS];
        for (int c = 0; c < ACTUATORS; c++) {
            ud[c] = desired(t, c);
        }
        CHECK(hyst_bank_step(stepped, ud, v, &channel) == HYST_OK);
        for (int c = 0; c < ACTUATORS; c++) {
            double one = 0.0;
            if (hyst_operator_step(&scalar[c], ud[c], &one) != HYST_OK
                || !close_to(v[c], one, k1[c], 1e-13)) {
                agree = 0;
            }
            if (v[c] != block[t * ACTUATORS + c]) {
                same_as_block = 0;
            }
        }
    }
    CHECK(agree);
    CHECK(same_as_block);
    free(block);

    /* A NaN on actuator 42: refused, its channel named, no memory changed. */
    hyst_memory before, after;
    CHECK(hyst_bank_get_memory(stepped, 42, &before) == HYST_OK);
    CHECK(before.has_history == 1);
    double ud[ACTUATORS], v[ACTUATORS];
    for (int c = 0; c < ACTUATORS; c++) {
        ud[c] = 0.0;
    }
    ud[42] = nan("");
    channel = 0;
    CHECK(hyst_bank_step(stepped, ud, v, &channel) == HYST_ERR_NON_FINITE);
    CHECK(channel == 42);
    CHECK(hyst_bank_get_memory(stepped, 42, &after) == HYST_OK);
    CHECK(memcmp(&before, &after, sizeof before) == 0);

    /* Actuator 7's memory into a scalar operator and back into another channel. */
    hyst_memory m;
    CHECK(hyst_bank_get_memory(stepped, 7, &m) == HYST_OK);
    hyst_operator moved;
    CHECK(hyst_operator_init_inverse(&moved, k1[7], k2[7]) == HYST_OK);
    CHECK(hyst_operator_set_memory(&moved, &m) == HYST_OK);
    CHECK(hyst_bank_set_memory(blocked, 7, &m) == HYST_OK);
    CHECK(hyst_bank_get_memory(stepped, ACTUATORS, &m) == HYST_ERR_LENGTH);

    /* An invalid k1 on actuator 13: the bank is not created and the channel is named. */
    k1[13] = -1.0;
    hyst_bank *bad = NULL;
    channel = 0;
    CHECK(hyst_bank_create(k1, k2, ACTUATORS, 1, &bad, &channel) == HYST_ERR_INVALID_PARAMETER);
    CHECK(channel == 13 && bad == NULL);
    CHECK(hyst_bank_step(NULL, ud, v, NULL) == HYST_ERR_NULL_POINTER);

    /* The float twin against the float scalar operator. */
    hyst_bank_f32 *single = NULL;
    CHECK(hyst_bank_create_f32(k1f, k2f, ACTUATORS, 1, &single, NULL) == HYST_OK);
    static hyst_operator_f32 scalar_f[ACTUATORS];
    int agree_f = single != NULL;
    for (int c = 0; c < ACTUATORS; c++) {
        CHECK(hyst_operator_init_inverse_f32(&scalar_f[c], k1f[c], k2f[c]) == HYST_OK);
    }
    for (int t = 0; single != NULL && t < PERIODS; t++) {
        float udf[ACTUATORS], vf[ACTUATORS];
        for (int c = 0; c < ACTUATORS; c++) {
            udf[c] = (float)desired(t, c);
        }
        if (hyst_bank_step_f32(single, udf, vf, NULL) != HYST_OK) {
            agree_f = 0;
        }
        for (int c = 0; c < ACTUATORS; c++) {
            float one = 0.0f;
            if (hyst_operator_step_f32(&scalar_f[c], udf[c], &one) != HYST_OK
                || !close_to(vf[c], one, k1f[c], 1e-5)) {
                agree_f = 0;
            }
        }
    }
    CHECK(agree_f);

    hyst_bank_free(stepped);
    hyst_bank_free(blocked);
    hyst_bank_free_f32(single);
    hyst_bank_free(NULL);
    printf("bank: %d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
