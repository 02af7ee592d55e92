/*
 * adaptive.c: online adaptation on a Cortex-M4F (QEMU mps2-an386), in float: the
 * adaptive compensator (hyst_adaptive_*_f32) drives a simulated actuator whose k1 grows by 30 %
 * and whose output gain falls by 30 % over the first 60 % of the run, then stay. Beside it, the
 * fitted model's plain inverse (hyst_shaped_model_init_inverse_f32) drives a copy of the same
 * actuator, so the two tracking errors can be compared.
 *
 * The actuator is the C API's own f32 shaped model, rebuilt each sample with the drifted
 * parameters, its memory carried over with hyst_shaped_model_get_memory_f32 and
 * hyst_shaped_model_set_memory_f32; its measurement carries uniform noise of sigma NOISE.
 *
 * Prints, through semihosting:
 *
 *   samples <SAMPLES>
 *   rms adaptive <first tenth> <last tenth>      tracking RMS (measured - desired)
 *   rms fixed <first tenth> <last tenth>         the same with the fitted model's inverse
 *   parameter <name> <estimate> <truth at the end>
 *   counts <updated> <rest> <starting> <dead zone> <bad input> <out of range> <bad output> <refused>
 *   # adaptive: pass    (or "# adaptive: FAIL ..." and exit status 1)
 *
 * It passes when every call returned HYST_OK, the adaptive RMS of the last tenth is at most 1/3
 * of the fixed inverse's, and the final k1 and output gain are within 5 % of the truth's.
 * scripts/test-firmware runs it and checks those lines again. No libc: plain C99 floats.
 */
#include <stdint.h>

#include "driver.h"
#include "hyst.h"
#include "semihost.h"

#define SAMPLES 40000
#define DRIFT_END (SAMPLES * 6 / 10)
#define TENTH (SAMPLES / 10)
/* sigma of the measurement noise (output units; the output spans about 3). */
#define NOISE 2e-3f

/* The fitted model: y = GAIN * H(K1, K2)[x] + OFFSET. */
#define K1 0.15f
#define K2 10.0f
#define GAIN 2.0f
#define OFFSET 0.1f

/* ------------------------------------------------------------------------------------------ */
/* Output (no libc). */

static char line[128];
static int len;

static void put_str(const char *s) {
    while (*s != '\0' && len < (int)sizeof line - 2) {
        line[len++] = *s++;
    }
}

static void put_float(float x) {
    char text[16];
    text[drv_format_float(x, text)] = '\0';
    put_str(text);
}

static void put_uint(uint64_t v) {
    char digits[21];
    int n = 0;
    do {
        digits[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (n > 0 && len < (int)sizeof line - 2) {
        line[len++] = digits[--n];
    }
}

static void emit(void) {
    line[len++] = '\n';
    line[len] = '\0';
    semihost_write0(line);
    len = 0;
}

/* ------------------------------------------------------------------------------------------ */
/* The test signal, the noise, the truth. */

/* sin(2 pi t) for t in [0, 1): symmetries down to [0, 1/4], then Taylor to x^11. */
static float sin_turns(float t) {
    float sign = 1.0f, x, x2;
    if (t >= 0.5f) {
        t -= 0.5f;
        sign = -1.0f;
    }
    if (t > 0.25f) {
        t = 0.5f - t;
    }
    x = 6.28318531f * t;
    x2 = x * x;
    return sign * x *
           (1.0f +
            x2 * (-1.66666667e-1f +
                  x2 * (8.33333333e-3f +
                        x2 * (-1.98412698e-4f + x2 * (2.75573192e-6f + x2 * -2.50521084e-8f)))));
}

static float wave(int k, int period) {
    return sin_turns((float)(k % period) / (float)period);
}

/* The desired output: reversals of slowly changing amplitude with minor loops on them, and a
 * rest (the last value held) in every fifth block of 2000 samples. */
static float desired(int k) {
    float a;
    if ((k / 2000) % 5 == 4) {
        k = (k / 2000) * 2000 - 1;
    }
    a = 0.55f + 0.35f * wave(k, 13000);
    return OFFSET + GAIN * 0.8f * (a * wave(k, 1500) + 0.25f * wave(k, 370));
}

/* Uniform noise of sigma NOISE (a 64-bit LCG). */
static uint64_t noise_state = 2026u;
static float noise(void) {
    float u;
    noise_state = noise_state * 6364136223846793005u + 1442695040888963407u;
    u = (float)(uint32_t)(noise_state >> 40) * (1.0f / 16777216.0f); /* [0, 1) */
    return NOISE * 1.73205081f * (2.0f * u - 1.0f);
}

/* The drift's progress at sample k: 0 -> 1 over the first 60 %, then 1. */
static float ramp(int k) {
    return k >= DRIFT_END ? 1.0f : (float)k / (float)DRIFT_END;
}

static float truth_k1(int k) {
    return K1 * (1.0f + 0.3f * ramp(k));
}

static float truth_gain(int k) {
    return GAIN * (1.0f - 0.3f * ramp(k));
}

/* The model's parameters with k1 and the output gain given. */
static hyst_shaped_model_params_f32 params(float k1, float gain) {
    hyst_shaped_model_params_f32 p = {0};
    p.k1 = k1;
    p.k2.kind = HYST_K2_CONSTANT;
    p.k2.value = K2;
    p.input.kind = HYST_SHAPING_IDENTITY;
    p.input.pre_gain = 1.0f;
    p.input.post_gain = 1.0f;
    p.output.kind = HYST_SHAPING_IDENTITY;
    p.output.pre_gain = 1.0f;
    p.output.post_gain = gain;
    p.output.post_offset = OFFSET;
    return p;
}

/* The truth at sample k: rebuilt with its parameters at k, its memory carried over. */
static int32_t truth_at(hyst_shaped_model_f32 *truth, int k) {
    hyst_shaped_model_params_f32 p = params(truth_k1(k), truth_gain(k));
    hyst_memory_f32 memory;
    int32_t status = hyst_shaped_model_get_memory_f32(truth, &memory);
    status |= hyst_shaped_model_init_direct_f32(truth, &p);
    status |= hyst_shaped_model_set_memory_f32(truth, &memory);
    return status;
}

/* sqrt(x), x >= 0, by Newton's method (no libm). */
static float root(float x) {
    float r = x > 1.0f ? x : 1.0f;
    int i;
    if (x <= 0.0f) {
        return 0.0f;
    }
    for (i = 0; i < 60; i++) {
        r = 0.5f * (r + x / r);
    }
    return r;
}

static float relative_error(float estimate, float truth) {
    float e = estimate / truth - 1.0f;
    return e < 0.0f ? -e : e;
}

/* ------------------------------------------------------------------------------------------ */

int main(void) {
    static hyst_adaptive_f32 adaptive;
    static hyst_shaped_model_f32 fixed, truth, fixed_truth;
    static const char *const names[6] = {"k1", "k2", "gain", "offset", "input_gain", "input_offset"};
    hyst_shaped_model_params_f32 fitted = params(K1, GAIN);
    hyst_adaptive_config_f32 cfg;
    hyst_adaptive_sample_counts counts;
    float sum[2][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}}; /* [adaptive, fixed][first, last tenth] */
    float rms[2][2], value[6], truth_value[6];
    int32_t status = HYST_OK;
    int k, i, failed = 0;

    status |= hyst_adaptive_config_default_f32(&cfg, NOISE);
    status |= hyst_adaptive_init_f32(&adaptive, &fitted, &cfg);
    status |= hyst_shaped_model_init_inverse_f32(&fixed, &fitted);
    status |= hyst_shaped_model_init_direct_f32(&truth, &fitted);
    status |= hyst_shaped_model_init_direct_f32(&fixed_truth, &fitted);

    for (k = 0; k < SAMPLES; k++) {
        float d = desired(k), n = noise(), x, xf, y, yf;
        int32_t what;
        status |= hyst_adaptive_step_f32(&adaptive, d, &x);
        status |= truth_at(&truth, k);
        status |= hyst_shaped_model_step_f32(&truth, x, &y);
        y += n;
        status |= hyst_adaptive_measure_f32(&adaptive, y, (float *)0, &what);

        status |= hyst_shaped_model_step_f32(&fixed, d, &xf);
        status |= truth_at(&fixed_truth, k);
        status |= hyst_shaped_model_step_f32(&fixed_truth, xf, &yf);
        yf += n;

        if (k < TENTH || k >= SAMPLES - TENTH) {
            int part = k < TENTH ? 0 : 1;
            sum[0][part] += (y - d) * (y - d);
            sum[1][part] += (yf - d) * (yf - d);
        }
    }

    put_str("samples ");
    put_uint(SAMPLES);
    emit();
    for (i = 0; i < 2; i++) {
        rms[i][0] = root(sum[i][0] / (float)TENTH);
        rms[i][1] = root(sum[i][1] / (float)TENTH);
        put_str(i == 0 ? "rms adaptive " : "rms fixed ");
        put_float(rms[i][0]);
        put_str(" ");
        put_float(rms[i][1]);
        emit();
    }
    truth_value[0] = truth_k1(SAMPLES);
    truth_value[1] = K2;
    truth_value[2] = truth_gain(SAMPLES);
    truth_value[3] = OFFSET;
    truth_value[4] = 1.0f;
    truth_value[5] = 0.0f;
    for (i = 0; i < 6; i++) {
        status |= hyst_adaptive_parameter_f32(&adaptive, i, &value[i]);
        put_str("parameter ");
        put_str(names[i]);
        put_str(" ");
        put_float(value[i]);
        put_str(" ");
        put_float(truth_value[i]);
        emit();
    }
    status |= hyst_adaptive_counts_f32(&adaptive, &counts);
    put_str("counts ");
    put_uint(counts.updated);
    put_str(" ");
    put_uint(counts.rest);
    put_str(" ");
    put_uint(counts.starting);
    put_str(" ");
    put_uint(counts.dead_zone);
    put_str(" ");
    put_uint(counts.bad_input);
    put_str(" ");
    put_uint(counts.out_of_range);
    put_str(" ");
    put_uint(counts.bad_output);
    put_str(" ");
    put_uint(counts.refused);
    emit();

    put_str("# adaptive: ");
    if (status != HYST_OK) {
        put_str("FAIL: a call did not return HYST_OK; ");
        failed = 1;
    }
    if (!(rms[0][1] <= rms[1][1] / 3.0f)) {
        put_str("FAIL: adaptive rms of the last tenth above 1/3 of the fixed inverse's; ");
        failed = 1;
    }
    if (!(relative_error(value[0], truth_value[0]) <= 0.05f &&
          relative_error(value[2], truth_value[2]) <= 0.05f)) {
        put_str("FAIL: k1 or gain more than 5 % from the truth; ");
        failed = 1;
    }
    if (!failed) {
        put_str("pass");
    }
    emit();
    return failed;
}
