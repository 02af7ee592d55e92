/*
 * driver.c: the test run of the f32 firmware API, shared by the firmware and the host reference
 * (see driver.h). Plain C99 without libc; float arithmetic only (no double), compiled with
 * -ffp-contract=off on both sides so that the compiler cannot fuse a multiply and an add on one
 * side only: the signal is then the same bits on the Cortex-M4F and on the host.
 */
#include "driver.h"

#include "hyst.h"

/* ------------------------------------------------------------------------------------------- */
/* Text. */

#define LINE_MAX 96

struct line {
    char text[LINE_MAX];
    int len;
};

static void put_char(struct line *l, char c) {
    if (l->len < LINE_MAX - 2) { /* room for '\n' and NUL */
        l->text[l->len++] = c;
    }
}

static void put_str(struct line *l, const char *s) {
    while (*s != '\0') {
        put_char(l, *s++);
    }
}

static void put_uint(struct line *l, uint32_t v) {
    char digits[10];
    int n = 0;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0) {
        put_char(l, digits[--n]);
    }
}

static void put_hex(struct line *l, uint32_t v) {
    static const char hex[] = "0123456789abcdef";
    int shift;
    for (shift = 28; shift >= 0; shift -= 4) {
        put_char(l, hex[(v >> shift) & 0xfu]);
    }
}

static void put_float(struct line *l, float x) {
    char text[16];
    int n = drv_format_float(x, text);
    int i;
    for (i = 0; i < n; i++) {
        put_char(l, text[i]);
    }
}

static void emit(drv_write_fn write, struct line *l) {
    l->text[l->len++] = '\n';
    l->text[l->len] = '\0';
    write(l->text);
    l->len = 0;
}

uint32_t drv_float_bits(float x) {
    union {
        float f;
        uint32_t u;
    } v;
    v.f = x;
    return v.u;
}

int drv_format_float(float x, char *out) {
    uint32_t bits = drv_float_bits(x);
    uint32_t field = (bits >> 23) & 0xffu;
    uint32_t fraction = bits & 0x7fffffu;
    uint64_t m, ip, fr = 0, mask = 0;
    int e, k = 0, n = 0, count = 0, exp10 = -1, sticky = 0, i;
    char digits[10], idig[20];
    int ni = 0;

    if ((bits >> 31) != 0u) {
        out[n++] = '-';
    }
    if (field == 0xffu) {
        const char *s = fraction != 0u ? "nan" : "inf";
        while (*s != '\0') {
            out[n++] = *s++;
        }
        out[n] = '\0';
        return n;
    }
    if (field == 0u) {
        m = fraction;
        e = -149;
    } else {
        m = fraction | 0x800000u;
        e = (int)field - 150;
    }
    if (m == 0u) {
        const char *s = "0.00000000e+00";
        while (*s != '\0') {
            out[n++] = *s++;
        }
        out[n] = '\0';
        return n;
    }
    if (e >= 40 || e < -60) { /* beyond the exact 64-bit arithmetic below: see the hex bits */
        out[n++] = '~';
        out[n] = '\0';
        return n;
    }

    /* x = m 2^e exactly: integer part ip and fraction fr / 2^k, both exact in 64 bits. */
    if (e >= 0) {
        ip = m << e;
    } else {
        k = -e;
        ip = m >> k;
        mask = ((uint64_t)1 << k) - 1u;
        fr = m & mask;
    }
    while (ip != 0u) {
        idig[ni++] = (char)('0' + (int)(ip % 10u));
        ip /= 10u;
    }
    if (ni > 0) {
        exp10 = ni - 1;
    }
    for (i = ni - 1; i >= 0; i--) {
        if (count < 10) {
            digits[count++] = idig[i];
        } else if (idig[i] != '0') {
            sticky = 1;
        }
    }
    while (fr != 0u && count < 10) { /* fr < 2^60, so 10 fr fits */
        uint64_t d;
        fr *= 10u;
        d = fr >> k;
        fr &= mask;
        if (count == 0 && d == 0u) {
            exp10--; /* a leading zero of a number below 1 */
            continue;
        }
        digits[count++] = (char)('0' + (int)d);
    }
    if (fr != 0u) {
        sticky = 1;
    }
    while (count < 10) {
        digits[count++] = '0';
    }

    /* Round the 10 exact digits (and the sticky rest) to 9, ties to even. */
    if (digits[9] > '5' || (digits[9] == '5' && (sticky || ((digits[8] - '0') & 1)))) {
        for (i = 8; i >= 0; i--) {
            if (digits[i] == '9') {
                digits[i] = '0';
            } else {
                digits[i]++;
                break;
            }
        }
        if (i < 0) { /* 9.99999999x rounded up to 10 */
            digits[0] = '1';
            exp10++;
        }
    }

    out[n++] = digits[0];
    out[n++] = '.';
    for (i = 1; i < 9; i++) {
        out[n++] = digits[i];
    }
    out[n++] = 'e';
    out[n++] = exp10 < 0 ? '-' : '+';
    if (exp10 < 0) {
        exp10 = -exp10;
    }
    out[n++] = (char)('0' + exp10 / 10);
    out[n++] = (char)('0' + exp10 % 10);
    out[n] = '\0';
    return n;
}

/* ------------------------------------------------------------------------------------------- */
/* The test signal. */

#define TWO_PI 6.28318531f

/* sin(2 pi t) for t in [0, 1): symmetries down to [0, pi/2], then Taylor to x^11 (|error| below
 * 1e-7; what matters here is that it is the same float arithmetic on both machines). */
static float sin_turns(float t) {
    float sign = 1.0f, x, x2;
    if (t >= 0.5f) {
        t -= 0.5f;
        sign = -1.0f;
    }
    if (t > 0.25f) {
        t = 0.5f - t;
    }
    x = TWO_PI * t;
    x2 = x * x;
    return sign * x *
           (1.0f +
            x2 * (-1.66666667e-1f +
                  x2 * (8.33333333e-3f +
                        x2 * (-1.98412698e-4f + x2 * (2.75573192e-6f + x2 * -2.50521084e-8f)))));
}

static float cos_turns(float t) {
    t += 0.25f;
    if (t >= 1.0f) {
        t -= 1.0f;
    }
    return sin_turns(t);
}

/* The fraction of a period at sample i (exact phase bookkeeping in integers). */
static float turns(int i, int period) {
    return (float)(i % period) / (float)period;
}

/* Amplitude growing linearly from 0.1 to 2.0 over the run. */
static float amplitude(int i) {
    return 0.1f + 1.9f * (float)i / (float)(DRV_SAMPLES - 1);
}

/* The operator's input: a sine of period 100 samples with a growing amplitude, plus a quarter as
 * much of a sine of period 9 samples, fast enough to reverse the input inside each half period:
 * minor loops nested in growing major loops. */
static float signal(int i) {
    return amplitude(i) * (sin_turns(turns(i, 100)) + 0.25f * sin_turns(turns(i, 9)));
}

/* The compensator's reference r(t) = A(t) (sin(w1 t) + C2 sin(w2 t)), A(t) = A0 + A1 t, periods
 * of P1 and P2 samples of DT seconds: the new input u_new = r''(t) of its two integrators, taken
 * at mid-sample (t + dt/2), which keeps the integrated v close to r. Over the run's 1 s,
 * |r| <= 1.312 (1 + 0.3) = 1.71, inside the range (-2.95, 3.05) of the model's tanh output. */
#define DT 0.002f
#define P1 100
#define P2 20
#define C2 0.3f
#define A0 0.032f
#define A1 1.28f

static float reference_term(float t, int period, float c, int derivative) {
    float w = TWO_PI / ((float)period * DT);
    float phase = t / ((float)period * DT);
    float a = A0 + A1 * t;
    float s, co;
    phase -= (float)(int)phase;
    s = sin_turns(phase);
    co = cos_turns(phase);
    if (derivative == 0) {
        return c * a * s;
    }
    if (derivative == 1) {
        return c * (A1 * s + a * w * co);
    }
    return c * (2.0f * A1 * w * co - a * w * w * s);
}

static float reference(float t, int derivative) {
    return reference_term(t, P1, 1.0f, derivative) + reference_term(t, P2, C2, derivative);
}

/* ------------------------------------------------------------------------------------------- */
/* The run. */

#define K1 0.2f
#define K2 8.0f

/* The shaped model: a cubic ψ_in, an affine k2 law with both clamps reached, a tanh ψ_out. */
static const hyst_shaped_model_params_f32 MODEL = {
    .k1 = K1,
    .k2 = {.kind = HYST_K2_AFFINE, .value = 8.0f, .slope = 2.0f, .min = 4.0f, .max = 12.0f},
    .input = {.kind = HYST_SHAPING_POLYNOMIAL,
              .p = {0.0f, 1.0f, 0.0f, 0.1f, -3.0f, 3.0f},
              .pre_gain = 1.0f,
              .pre_offset = 0.0f,
              .post_gain = 1.0f,
              .post_offset = 0.0f},
    .output = {.kind = HYST_SHAPING_TANH,
               .p = {3.0f, 2.0f, 0.0f, 0.0f, 0.0f, 0.0f},
               .pre_gain = 1.0f,
               .pre_offset = 0.0f,
               .post_gain = 1.0f,
               .post_offset = 0.05f},
};

struct run {
    drv_write_fn write;
    struct line line;
    uint32_t values;
    uint32_t errors;
};

static void value(struct run *r, const char *series, int i, float y) {
    struct line *l = &r->line;
    put_str(l, "v ");
    put_str(l, series);
    put_char(l, ' ');
    put_uint(l, (uint32_t)i);
    put_char(l, ' ');
    put_hex(l, drv_float_bits(y));
    put_char(l, ' ');
    put_float(l, y);
    emit(r->write, l);
    r->values++;
}

/* Counts and reports a status other than HYST_OK. */
static void check(struct run *r, const char *what, int i, int32_t status) {
    struct line *l = &r->line;
    if (status == HYST_OK) {
        return;
    }
    r->errors++;
    put_str(l, "# error: ");
    put_str(l, what);
    put_char(l, ' ');
    put_uint(l, (uint32_t)i);
    put_str(l, ": status ");
    put_uint(l, (uint32_t)status);
    emit(r->write, l);
}

int drv_run(drv_write_fn write) {
    /* The states: opaque blocks, 8-byte aligned by their uint64_t words. */
    hyst_operator_f32 inverse, direct;
    hyst_shaped_model_f32 shaped;
    hyst_shaped_compensator_f32 comp;
    struct run r;
    const float a[2] = {0.9f, 1.0f}; /* plant 1 / (s^2 + 0.9 s + 1) */
    float v0[2], v[2], worst = 0.0f, drift = 0.0f;
    int i;

    r.write = write;
    r.line.len = 0;
    r.values = 0;
    r.errors = 0;

    put_str(&r.line, "# hyst f32: ");
    put_uint(&r.line, DRV_SAMPLES);
    put_str(&r.line, " samples; k1 0.2, k2 8; series inv dir shp cmp");
    emit(write, &r.line);

    v0[0] = reference(0.0f, 0);
    v0[1] = reference(0.0f, 1);
    check(&r, "init inverse", 0, hyst_operator_init_inverse_f32(&inverse, K1, K2));
    check(&r, "init direct", 0, hyst_operator_init_direct_f32(&direct, K1, K2));
    check(&r, "init shaped", 0, hyst_shaped_model_init_direct_f32(&shaped, &MODEL));
    check(&r, "init compensator", 0, hyst_shaped_compensator_init_f32(&comp, &MODEL, 1.0f, a, v0, 2));
    if (r.errors != 0u) {
        return (int)r.errors;
    }

    for (i = 0; i < DRV_SAMPLES; i++) {
        float x = signal(i), command, back, y, u, err;
        float t_mid = ((float)i + 0.5f) * DT;

        check(&r, "inv", i, hyst_operator_step_f32(&inverse, x, &command));
        value(&r, "inv", i, command);
        check(&r, "dir", i, hyst_operator_step_f32(&direct, command, &back));
        value(&r, "dir", i, back);
        err = back - x;
        if (err < 0.0f) {
            err = -err;
        }
        if (err > worst) {
            worst = err;
        }
        check(&r, "shp", i, hyst_shaped_model_step_f32(&shaped, x, &y));
        value(&r, "shp", i, y);
        check(&r, "cmp", i, hyst_shaped_compensator_step_f32(&comp, reference(t_mid, 2), DT, &u));
        value(&r, "cmp", i, u);
        check(&r, "cmp state", i, hyst_shaped_compensator_get_state_f32(&comp, v, 0));
        err = v[0] - reference((float)(i + 1) * DT, 0);
        if (err < 0.0f) {
            err = -err;
        }
        if (err > drift) {
            drift = err;
        }
    }
    /* H[H^-1[x]] = x up to float rounding (inputs of size <= 2.5). The worst case is itself a
     * rounding error, so it is information, not a value to compare ("~" line). */
    put_str(&r.line, "~ round trip: max |H[H^-1[x]] - x| = ");
    put_float(&r.line, worst);
    put_str(&r.line, " (limit 1e-5)");
    emit(write, &r.line);
    if (worst > 1e-5f) {
        check(&r, "round trip above 1e-5", 0, HYST_ERR_INTERNAL);
    }
    /* The compensator's integrators follow r (up to the sampling of u_new). */
    put_str(&r.line, "~ compensator: max |v - r| = ");
    put_float(&r.line, drift);
    emit(write, &r.line);

    put_str(&r.line, "# done: ");
    put_uint(&r.line, r.values);
    put_str(&r.line, " values, ");
    put_uint(&r.line, r.errors);
    put_str(&r.line, " errors");
    emit(write, &r.line);
    return (int)r.errors;
}
