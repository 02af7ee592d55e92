/*
 * smoke: the hyst C API (include/hyst.h) called from C99, with every result checked.
 *
 *   smoke [MODEL.toml]
 *
 * The firmware part in double and float: the operator pair (hyst_operator_*), the shaped model
 * with a polynomial input shaping and an affine output shaping (hyst_shaped_model_*) and the
 * Lemma 5.1 compensator for a plant of order 2 (hyst_shaped_compensator_*); each bad argument (NULL,
 * misaligned or uninitialised state, NaN, derivative order 5) and its documented status. With a
 * model file (from `hyst fit`), also the host part (hyst_model_*). Prints one line per failed
 * check and the summary `smoke: N passed, M failed`; exits 1 on any failure.
 */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hyst.h"

/* ------------------------------------------------------------------------------------------ */
/* Checks. */

static int passed, failed;

static void check(int ok, int line, const char *what)
{
    if (ok) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "smoke.c:%d: FAILED: %s\n", line, what);
    }
}

static void check_status(int got, int want, int line, const char *what)
{
    if (got == want) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "smoke.c:%d: FAILED: %s returned %d (%s), expected %d (%s)\n", line, what,
                got, hyst_status_message(got), want, hyst_status_message(want));
    }
}

/* |got - want| <= tol (1 + |want|): relative for large values, absolute near 0. */
static void check_close(double got, double want, double tol, int line, const char *what)
{
    if (fabs(got - want) <= tol * (1.0 + fabs(want))) {
        passed++;
    } else {
        failed++;
        fprintf(stderr, "smoke.c:%d: FAILED: %s: %.17g vs %.17g (tolerance %g)\n", line, what,
                got, want, tol);
    }
}

#define CHECK(cond) check((cond) != 0, __LINE__, #cond)
#define EXPECT(call, status) check_status((call), (status), __LINE__, #call)
#define CLOSE(got, want, tol) check_close((got), (want), (tol), __LINE__, #got " ~ " #want)

/* The largest relative difference seen, to check a whole run at once. */
static double worse(double worst, double got, double want)
{
    double d = fabs(got - want) / (1.0 + fabs(want));
    return d > worst || d != d ? d : worst;
}

/* A test input with reversals and minor loops. */
static double signal(int k)
{
    double t = k * 0.03;
    double amplitude = 0.4 + 0.04 * t;
    return (amplitude < 1.3 ? amplitude : 1.3) * sin(t) + 0.25 * cos(2.9 * t);
}

#define N_SAMPLES 2000

/* ------------------------------------------------------------------------------------------ */

static void status_messages(void)
{
    int s;
    for (s = -2; s <= 20; s++) {
        const char *text = hyst_status_message(s);
        CHECK(text != NULL && text[0] != '\0');
    }
    CHECK(strcmp(hyst_status_message(HYST_OK), "success") == 0);
    CHECK(strcmp(hyst_status_message(99), "unknown status") == 0);
    CHECK(HYST_MAX_ORDER == 4);
}

/* The operator pair in double: the inverse undoes the direct operator, process in place equals
 * step by step, the state is plain data, the memory can be saved and restored, derivatives. */
static void operator_f64(void)
{
    hyst_operator h, hinv, g, ginv, copy;
    hyst_memory saved, m;
    static double block[N_SAMPLES], expected[N_SAMPLES];
    double worst_back = 0, worst_inverse_first = 0, y, v, u;
    int k, same = 1;

    EXPECT(hyst_operator_init_direct(&h, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_inverse(&hinv, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_direct(&g, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_inverse(&ginv, 0.2, 8.0), HYST_OK);
    for (k = 0; k < N_SAMPLES; k++) {
        double x = signal(k);
        int s1 = hyst_operator_step(&h, x, &y);    /* y = H[x] */
        int s2 = hyst_operator_step(&hinv, y, &v); /* v = H^-1[H[x]] = x */
        int s3 = hyst_operator_step(&ginv, x, &u); /* u = H^-1[x] */
        int s4 = hyst_operator_step(&g, u, &y);    /* H[H^-1[x]] = x: the exact inverse */
        if (s1 || s2 || s3 || s4)
            same = 0;
        worst_back = worse(worst_back, v, x);
        worst_inverse_first = worse(worst_inverse_first, y, x);
    }
    CHECK(same);
    CHECK(worst_back <= 1e-12);
    CHECK(worst_inverse_first <= 1e-12);

    /* process in place == step by step, bit for bit */
    EXPECT(hyst_operator_init_direct(&h, 0.14, 5.0), HYST_OK);
    EXPECT(hyst_operator_init_direct(&g, 0.14, 5.0), HYST_OK);
    for (k = 0; k < N_SAMPLES; k++) {
        block[k] = signal(k);
        if (hyst_operator_step(&g, block[k], &expected[k]) != HYST_OK)
            same = 0;
    }
    EXPECT(hyst_operator_process(&h, block, block, N_SAMPLES), HYST_OK);
    CHECK(same && memcmp(block, expected, sizeof block) == 0);

    /* the state is plain data: a memcpy'd copy runs on identically */
    memcpy(&copy, &h, sizeof h);
    for (k = 0; k < 300; k++) {
        double a, b;
        hyst_operator_step(&h, signal(N_SAMPLES + k), &a);
        hyst_operator_step(&copy, signal(N_SAMPLES + k), &b);
        if (memcmp(&a, &b, sizeof a) != 0)
            same = 0;
    }
    CHECK(same);

    /* save the memory, continue, restore it (also into a fresh operator), continue: the same */
    EXPECT(hyst_operator_get_memory(&h, &saved), HYST_OK);
    CHECK(saved.has_history == 1 && (saved.direction == 1 || saved.direction == -1));
    CHECK(fabs(saved.reversal_output - saved.reversal_input) <= 0.14);
    EXPECT(hyst_operator_init_direct(&g, 0.14, 5.0), HYST_OK);
    EXPECT(hyst_operator_set_memory(&g, &saved), HYST_OK);
    for (k = 0; k < 300; k++)
        hyst_operator_step(&h, signal(3 * k), &block[k]);
    EXPECT(hyst_operator_set_memory(&h, &saved), HYST_OK);
    for (k = 0; k < 300; k++) {
        double a, b;
        hyst_operator_step(&h, signal(3 * k), &a);
        hyst_operator_step(&g, signal(3 * k), &b);
        if (a != block[k] || b != block[k])
            same = 0;
    }
    CHECK(same);
    /* memories the operator cannot be in are refused, and change nothing */
    EXPECT(hyst_operator_get_memory(&h, &saved), HYST_OK);
    m = saved;
    m.reversal_output = m.reversal_input + 1.0; /* outside the band |out - in| <= k1 */
    EXPECT(hyst_operator_set_memory(&h, &m), HYST_ERR_STATE_OUTSIDE_BAND);
    m = saved;
    m.direction = 0;
    EXPECT(hyst_operator_set_memory(&h, &m), HYST_ERR_INVALID_PARAMETER);
    m = saved;
    m.last_input = NAN;
    {
        int s = hyst_operator_set_memory(&h, &m);
        CHECK(s == HYST_ERR_INVALID_PARAMETER || s == HYST_ERR_STATE_OUTSIDE_BAND);
    }
    EXPECT(hyst_operator_get_memory(&h, &m), HYST_OK);
    CHECK(memcmp(&m, &saved, sizeof m) == 0);

    /* reset: no history; then as a fresh operator, bit for bit */
    EXPECT(hyst_operator_reset(&h), HYST_OK);
    EXPECT(hyst_operator_get_memory(&h, &m), HYST_OK);
    CHECK(m.has_history == 0);
    EXPECT(hyst_operator_init_direct(&g, 0.14, 5.0), HYST_OK);
    for (k = 0; k < 500; k++) {
        double a, b;
        hyst_operator_step(&h, signal(k + 7), &a);
        hyst_operator_step(&g, signal(k + 7), &b);
        if (memcmp(&a, &b, sizeof a) != 0)
            same = 0;
    }
    CHECK(same);
    /* a memory without history resets too */
    m.has_history = 0;
    EXPECT(hyst_operator_set_memory(&h, &m), HYST_OK);
    EXPECT(hyst_operator_get_memory(&h, &m), HYST_OK);
    CHECK(m.has_history == 0);

    /* derivatives: on a rising branch y = g(x); check g', g'' against central differences of
     * plain steps from copies of the same state, and the chain rule for x' != 1, x'' != 0 */
    {
        double x0 = 0.0, hstep = 1e-3, gp, gm, g0, d1[5], d2[5], jet[5] = {0, 1, 0, 0, 0};
        EXPECT(hyst_operator_init_direct(&h, 0.2, 8.0), HYST_OK);
        for (k = 0; k <= 50; k++)
            hyst_operator_step(&h, -0.5 + 0.01 * k - 0.02, &y); /* rising up to -0.02 */
        memcpy(&copy, &h, sizeof h);
        hyst_operator_step(&copy, x0 + hstep, &gp);
        memcpy(&copy, &h, sizeof h);
        hyst_operator_step(&copy, x0 - hstep, &gm);
        memcpy(&copy, &h, sizeof h);
        hyst_operator_step(&copy, x0, &g0);
        memcpy(&copy, &h, sizeof h);
        jet[0] = x0;
        EXPECT(hyst_operator_step_derivatives(&copy, jet, d1, 4), HYST_OK);
        CLOSE(d1[0], g0, 1e-15);
        CLOSE(d1[1], (gp - gm) / (2 * hstep), 1e-5);
        CLOSE(d1[2], (gp - 2 * g0 + gm) / (hstep * hstep), 1e-4);
        CHECK(d1[1] > 0 && d1[1] < 1 + 0.2 * 8.0 + 1e-9); /* 0 < dH/dv < 1 + k1 k2 */
        CHECK(d1[3] == d1[3] && d1[4] == d1[4]);
        memcpy(&copy, &h, sizeof h);
        jet[1] = 2.0;
        jet[2] = 0.5;
        EXPECT(hyst_operator_step_derivatives(&copy, jet, d2, 2), HYST_OK);
        CLOSE(d2[1], 2.0 * d1[1], 1e-12);
        CLOSE(d2[2], 4.0 * d1[2] + 0.5 * d1[1], 1e-12);
        /* order 0 is a plain step */
        memcpy(&copy, &h, sizeof h);
        EXPECT(hyst_operator_step_derivatives(&copy, jet, d2, 0), HYST_OK);
        CHECK(d2[0] == d1[0]);
        /* the inverse's derivative is the reciprocal */
        EXPECT(hyst_operator_init_inverse(&hinv, 0.2, 8.0), HYST_OK);
        EXPECT(hyst_operator_init_direct(&g, 0.2, 8.0), HYST_OK);
        {
            double xs[2] = {0.1, 1.0}, ys[2], back[2];
            EXPECT(hyst_operator_step_derivatives(&g, xs, ys, 1), HYST_OK);
            EXPECT(hyst_operator_step_derivatives(&hinv, ys, back, 1), HYST_OK);
            CLOSE(back[0], 0.1, 1e-15);
            CLOSE(back[1], 1.0, 1e-12);
        }
    }
}

/* The float twins agree with the double operator to 1e-5. */
static void operator_f32(void)
{
    hyst_operator h64, i64;
    hyst_operator_f32 h32, i32, copy;
    hyst_memory_f32 m;
    static float block[N_SAMPLES];
    double worst_direct = 0, worst_inverse = 0, worst_back = 0, worst_block = 0;
    int k, ok = 1;

    EXPECT(hyst_operator_init_direct(&h64, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_inverse(&i64, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_direct_f32(&h32, 0.2f, 8.0f), HYST_OK);
    EXPECT(hyst_operator_init_inverse_f32(&i32, 0.2f, 8.0f), HYST_OK);
    for (k = 0; k < N_SAMPLES; k++) {
        double x = (double)(float)signal(k), y64, v64;
        float y32, v32;
        ok &= hyst_operator_step(&h64, x, &y64) == HYST_OK;
        ok &= hyst_operator_step(&i64, x, &v64) == HYST_OK;
        ok &= hyst_operator_step_f32(&h32, (float)x, &y32) == HYST_OK;
        ok &= hyst_operator_step_f32(&i32, (float)x, &v32) == HYST_OK;
        worst_direct = worse(worst_direct, y32, y64);
        worst_inverse = worse(worst_inverse, v32, v64);
        block[k] = y32;
    }
    CHECK(ok);
    CHECK(worst_direct <= 1e-5);
    CHECK(worst_inverse <= 1e-5);

    /* process in place, and the inverse takes the direct output back (to float precision) */
    EXPECT(hyst_operator_init_inverse_f32(&i32, 0.2f, 8.0f), HYST_OK);
    EXPECT(hyst_operator_process_f32(&i32, block, block, N_SAMPLES), HYST_OK);
    for (k = 0; k < N_SAMPLES; k++)
        worst_back = worse(worst_back, block[k], (double)(float)signal(k));
    CHECK(worst_back <= 1e-5);

    /* memory, reset, derivatives, plain-data copies */
    EXPECT(hyst_operator_get_memory_f32(&h32, &m), HYST_OK);
    CHECK(m.has_history == 1);
    memcpy(&copy, &h32, sizeof copy);
    EXPECT(hyst_operator_reset_f32(&h32), HYST_OK);
    EXPECT(hyst_operator_set_memory_f32(&h32, &m), HYST_OK);
    {
        float a, b;
        hyst_operator_step_f32(&h32, 0.3f, &a);
        hyst_operator_step_f32(&copy, 0.3f, &b);
        CHECK(a == b);
    }
    m.reversal_output = m.reversal_input - 1.0f;
    EXPECT(hyst_operator_set_memory_f32(&h32, &m), HYST_ERR_STATE_OUTSIDE_BAND);
    {
        float x32[5] = {0.1f, 1.0f, -0.5f, 0.2f, 0.1f}, y32[5];
        double x64[5] = {0.1, 1.0, -0.5, 0.2, 0.1}, y64[5];
        EXPECT(hyst_operator_init_inverse_f32(&i32, 0.2f, 8.0f), HYST_OK);
        EXPECT(hyst_operator_init_inverse(&i64, 0.2, 8.0), HYST_OK);
        EXPECT(hyst_operator_step_derivatives_f32(&i32, x32, y32, 4), HYST_OK);
        EXPECT(hyst_operator_step_derivatives(&i64, x64, y64, 4), HYST_OK);
        for (k = 0; k < 5; k++)
            worst_block = worse(worst_block, y32[k], y64[k]);
        CHECK(worst_block <= 1e-5);
    }
}

/* ------------------------------------------------------------------------------------------ */
/* The shaped model: ψ_in a cubic polynomial (here increasing on [-5, 5], tangents outside),
 * ψ_out affine, k2 constant. */

static hyst_shaped_model_params params_f64(void)
{
    hyst_shaped_model_params p;
    memset(&p, 0, sizeof p);
    p.k1 = 0.105;
    p.k2.kind = HYST_K2_CONSTANT;
    p.k2.value = 8.0;
    p.input.kind = HYST_SHAPING_POLYNOMIAL;
    p.input.p[0] = 0.0; /* c0 + c1 z + c2 z^2 + c3 z^3 on [lo, hi] */
    p.input.p[1] = 1.0;
    p.input.p[2] = -0.098;
    p.input.p[3] = 0.004;
    p.input.p[4] = -5.0;
    p.input.p[5] = 5.0;
    p.input.pre_gain = 0.5;
    p.input.pre_offset = 0.1;
    p.input.post_gain = 1.0;
    p.input.post_offset = 0.0;
    p.output.kind = HYST_SHAPING_AFFINE;
    p.output.p[0] = 2.02; /* gain */
    p.output.p[1] = 0.3;  /* offset */
    p.output.pre_gain = 1.0;
    p.output.pre_offset = 0.0;
    p.output.post_gain = 1.5;
    p.output.post_offset = -0.2;
    return p;
}

static hyst_shaped_model_params_f32 params_f32(void)
{
    hyst_shaped_model_params p = params_f64();
    hyst_shaped_model_params_f32 q;
    int k;
    memset(&q, 0, sizeof q);
    q.k1 = (float)p.k1;
    q.k2.kind = p.k2.kind;
    q.k2.value = (float)p.k2.value;
    q.input.kind = p.input.kind;
    q.output.kind = p.output.kind;
    for (k = 0; k < 6; k++) {
        q.input.p[k] = (float)p.input.p[k];
        q.output.p[k] = (float)p.output.p[k];
    }
    q.input.pre_gain = (float)p.input.pre_gain;
    q.input.pre_offset = (float)p.input.pre_offset;
    q.input.post_gain = (float)p.input.post_gain;
    q.input.post_offset = (float)p.input.post_offset;
    q.output.pre_gain = (float)p.output.pre_gain;
    q.output.pre_offset = (float)p.output.pre_offset;
    q.output.post_gain = (float)p.output.post_gain;
    q.output.post_offset = (float)p.output.post_offset;
    return q;
}

static void shaped_model(void)
{
    hyst_shaped_model_params p = params_f64(), bad;
    hyst_shaped_model_params_f32 q = params_f32();
    hyst_shaped_model m, inv, copy;
    hyst_shaped_model_f32 m32, inv32;
    hyst_memory mem, mem2;
    static double block[N_SAMPLES], outputs[N_SAMPLES];
    double worst_back = 0, worst_f32 = 0, worst_inv_f32 = 0, y, c;
    int k, ok = 1;

    EXPECT(hyst_shaped_model_init_direct(&m, &p), HYST_OK);
    EXPECT(hyst_shaped_model_init_inverse(&inv, &p), HYST_OK);
    EXPECT(hyst_shaped_model_init_direct_f32(&m32, &q), HYST_OK);
    EXPECT(hyst_shaped_model_init_inverse_f32(&inv32, &q), HYST_OK);
    for (k = 0; k < N_SAMPLES; k++) {
        double x = 2.0 * signal(k);
        float y32, c32;
        ok &= hyst_shaped_model_step(&m, x, &y) == HYST_OK;   /* out = ψ_out(H[ψ_in(x)]) */
        ok &= hyst_shaped_model_step(&inv, y, &c) == HYST_OK; /* the exact inverse: x back */
        ok &= hyst_shaped_model_step_f32(&m32, (float)x, &y32) == HYST_OK;
        ok &= hyst_shaped_model_step_f32(&inv32, (float)y, &c32) == HYST_OK;
        worst_back = worse(worst_back, c, x);
        worst_f32 = worse(worst_f32, y32, y);
        worst_inv_f32 = worse(worst_inv_f32, c32, c);
        outputs[k] = y;
    }
    CHECK(ok);
    CHECK(worst_back <= 1e-12);
    CHECK(worst_f32 <= 1e-5);
    CHECK(worst_inv_f32 <= 1e-5);

    /* process in place: the inverse over the whole output record gives the inputs back */
    EXPECT(hyst_shaped_model_init_inverse(&inv, &p), HYST_OK);
    memcpy(block, outputs, sizeof block);
    EXPECT(hyst_shaped_model_process(&inv, block, block, N_SAMPLES), HYST_OK);
    worst_back = 0;
    for (k = 0; k < N_SAMPLES; k++)
        worst_back = worse(worst_back, block[k], 2.0 * signal(k));
    CHECK(worst_back <= 1e-12);
    {
        static float b32[N_SAMPLES];
        for (k = 0; k < N_SAMPLES; k++)
            b32[k] = (float)outputs[k];
        EXPECT(hyst_shaped_model_init_inverse_f32(&inv32, &q), HYST_OK);
        EXPECT(hyst_shaped_model_process_f32(&inv32, b32, b32, N_SAMPLES), HYST_OK);
        worst_back = 0;
        for (k = 0; k < N_SAMPLES; k++)
            worst_back = worse(worst_back, b32[k], 2.0 * signal(k));
        CHECK(worst_back <= 1e-5);
    }

    /* memory (in the operator's units), copies, reset */
    EXPECT(hyst_shaped_model_get_memory(&m, &mem), HYST_OK);
    CHECK(mem.has_history == 1 && fabs(mem.reversal_output - mem.reversal_input) <= 0.105);
    memcpy(&copy, &m, sizeof m);
    EXPECT(hyst_shaped_model_reset(&m), HYST_OK);
    EXPECT(hyst_shaped_model_get_memory(&m, &mem2), HYST_OK);
    CHECK(mem2.has_history == 0);
    EXPECT(hyst_shaped_model_set_memory(&m, &mem), HYST_OK);
    {
        double a, b;
        EXPECT(hyst_shaped_model_step(&m, 0.7, &a), HYST_OK);
        EXPECT(hyst_shaped_model_step(&copy, 0.7, &b), HYST_OK);
        CHECK(a == b);
    }
    mem.reversal_output = mem.reversal_input + 0.2; /* k1 = 0.105 */
    EXPECT(hyst_shaped_model_set_memory(&m, &mem), HYST_ERR_STATE_OUTSIDE_BAND);
    {
        hyst_memory_f32 m32mem;
        EXPECT(hyst_shaped_model_get_memory_f32(&m32, &m32mem), HYST_OK);
        CHECK(m32mem.has_history == 1);
        EXPECT(hyst_shaped_model_reset_f32(&m32), HYST_OK);
        EXPECT(hyst_shaped_model_set_memory_f32(&m32, &m32mem), HYST_OK);
    }

    /* derivatives through the shaping functions: the inverse's jet undoes the direct's */
    {
        double x[3] = {0.4, 0.8, -0.3}, yd[3], back[3];
        float x32[3] = {0.4f, 0.8f, -0.3f}, y32[3];
        EXPECT(hyst_shaped_model_init_direct(&m, &p), HYST_OK);
        EXPECT(hyst_shaped_model_init_inverse(&inv, &p), HYST_OK);
        EXPECT(hyst_shaped_model_init_direct_f32(&m32, &q), HYST_OK);
        EXPECT(hyst_shaped_model_step_derivatives(&m, x, yd, 2), HYST_OK);
        EXPECT(hyst_shaped_model_step_derivatives(&inv, yd, back, 2), HYST_OK);
        EXPECT(hyst_shaped_model_step_derivatives_f32(&m32, x32, y32, 2), HYST_OK);
        for (k = 0; k < 3; k++) {
            CLOSE(back[k], x[k], 1e-12);
            CLOSE(y32[k], yd[k], 1e-5);
        }
    }

    /* bad parameters: named by their status, and the block is untouched */
    EXPECT(hyst_shaped_model_init_direct(&m, &p), HYST_OK);
    EXPECT(hyst_shaped_model_step(&m, 0.25, &y), HYST_OK);
    memcpy(&copy, &m, sizeof m);
    bad = p;
    bad.input.p[3] = 0.0;
    bad.input.pre_gain = 1.0;
    bad.input.pre_offset = 0.0;
    bad.input.p[4] = 0.0;
    bad.input.p[5] = 6.0; /* 1 - 0.196 z turns at z = 5.1: not monotone on [0, 6] */
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_NOT_MONOTONE);
    EXPECT(hyst_shaped_model_init_inverse(&m, &bad), HYST_ERR_NOT_MONOTONE);
    bad = p;
    bad.output.kind = 42;
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_INVALID_PARAMETER);
    bad = p;
    bad.input.pre_gain = 0.0; /* a zeroed struct's gain: refused, not silently 0 */
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_INVALID_PARAMETER);
    bad = p;
    bad.k1 = NAN;
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_INVALID_PARAMETER);
    bad = p;
    bad.output.p[0] = NAN;
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_INVALID_PARAMETER);
    bad = p;
    bad.k2.kind = HYST_K2_AFFINE;
    bad.k2.slope = 1.0;
    bad.k2.min = 0.0; /* must be > 0 */
    bad.k2.max = 12.0;
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_ERR_INVALID_PARAMETER);
    {
        double a, b;
        EXPECT(hyst_shaped_model_step(&m, 0.6, &a), HYST_OK);
        EXPECT(hyst_shaped_model_step(&copy, 0.6, &b), HYST_OK);
        CHECK(a == b);
    }
    /* an affine k2 law, clamped (Proposition 4.3) */
    bad.k2.min = 4.0;
    EXPECT(hyst_shaped_model_init_direct(&m, &bad), HYST_OK);
    EXPECT(hyst_shaped_model_init_inverse(&inv, &bad), HYST_OK);
    worst_back = 0;
    for (k = 0; k < 500; k++) {
        ok &= hyst_shaped_model_step(&m, signal(k), &y) == HYST_OK;
        ok &= hyst_shaped_model_step(&inv, y, &c) == HYST_OK;
        worst_back = worse(worst_back, c, signal(k));
    }
    CHECK(ok);
    CHECK(worst_back <= 1e-2); /* inverse only up to Δk2 <= |φ'| k1 (Proposition 4.3) */

    /* a saturating output shaping: a desired output beyond its range is refused, the command
     * held */
    bad = p;
    bad.output.kind = HYST_SHAPING_LANGEVIN;
    bad.output.p[0] = 1.0; /* gain: out = 1.5 L(z) - 0.2 lies in (-1.7, 1.3) */
    bad.output.p[1] = 1.0; /* scale */
    EXPECT(hyst_shaped_model_init_inverse(&inv, &bad), HYST_OK);
    EXPECT(hyst_shaped_model_step(&inv, 0.5, &c), HYST_OK);
    y = c;
    EXPECT(hyst_shaped_model_step(&inv, 1.3, &c), HYST_ERR_OUT_OF_RANGE);
    CHECK(c == y);
    EXPECT(hyst_shaped_model_step(&inv, -5.0, &c), HYST_ERR_OUT_OF_RANGE);
    CHECK(c == y);
    EXPECT(hyst_shaped_model_step(&inv, 0.5, &c), HYST_OK);
    CHECK(c == y);
}

/* ------------------------------------------------------------------------------------------ */
/* The Lemma 5.1 compensator for b / (a2 s^2 + a1 s + 1): u = (x + a1 x' + a2 x'') / b with
 * x = ψ_in^-1(H^-1[ψ_out^-1(v)]) on the jet (v, v', v'' = u_new), checked against the shaped
 * inverse model's own jets from the compensator's memory; and where v is monotone the direct
 * model at x gives v back: the plant's hysteresis output follows v. */

static void compensator(void)
{
    const double b = 1.3, a[2] = {0.9, 1.0}, v0[2] = {0.2, 0.0}, dt = 1e-3;
    const float b32 = 1.3f, a32[2] = {0.9f, 1.0f}, v032[2] = {0.2f, 0.0f};
    hyst_shaped_model_params p = params_f64();
    hyst_shaped_model_params_f32 q = params_f32();
    hyst_shaped_compensator c;
    hyst_shaped_compensator_f32 c32;
    hyst_shaped_model inv, direct;
    hyst_memory mem;
    double worst_u = 0, worst_v = 0, worst_f32 = 0, v[2], u, x[3], jet[3];
    float v32[2], u32;
    int k, ok = 1, history = 1;

    /* at rest at v = 0.2, then v'' = 0.5: v rises monotonically */
    EXPECT(hyst_shaped_compensator_init(&c, &p, b, a, v0, 2), HYST_OK);
    EXPECT(hyst_shaped_model_init_inverse(&inv, &p), HYST_OK);
    EXPECT(hyst_shaped_model_init_direct(&direct, &p), HYST_OK);
    for (k = 0; k < 1000; k++) {
        double back;
        ok &= hyst_shaped_compensator_get_state(&c, v, NULL) == HYST_OK;
        ok &= hyst_shaped_compensator_step(&c, 0.5, dt, &u) == HYST_OK;
        jet[0] = v[0];
        jet[1] = v[1];
        jet[2] = 0.5;
        ok &= hyst_shaped_model_step_derivatives(&inv, jet, x, 2) == HYST_OK;
        ok &= hyst_shaped_model_step(&direct, x[0], &back) == HYST_OK;
        worst_u = worse(worst_u, u, (x[0] + a[0] * x[1] + a[1] * x[2]) / b);
        worst_v = worse(worst_v, back, v[0]);
    }
    CHECK(ok);
    CHECK(worst_u <= 1e-12);
    CHECK(worst_v <= 1e-12);
    EXPECT(hyst_shaped_compensator_get_state(&c, v, NULL), HYST_OK);
    CLOSE(v[0], 0.2 + 0.5 * 0.5 * 1.0 * 1.0, 1e-12); /* exact integrators: v0 + a t^2 / 2 */
    CLOSE(v[1], 0.5 * 1.0, 1e-12);

    /* an oscillating v'' (v turns): each command from the compensator's own memory, and the
     * float twin alongside */
    EXPECT(hyst_shaped_compensator_init(&c, &p, b, a, v0, 2), HYST_OK);
    EXPECT(hyst_shaped_compensator_init_f32(&c32, &q, b32, a32, v032, 2), HYST_OK);
    worst_u = 0;
    for (k = 0; k < 3000; k++) {
        double u_new = 2.0 * sin(k * 0.004);
        ok &= hyst_shaped_compensator_get_state(&c, v, &mem) == HYST_OK;
        ok &= hyst_shaped_model_set_memory(&inv, &mem) == HYST_OK;
        ok &= hyst_shaped_compensator_step(&c, u_new, dt, &u) == HYST_OK;
        ok &= hyst_shaped_compensator_step_f32(&c32, (float)u_new, (float)dt, &u32) == HYST_OK;
        jet[0] = v[0];
        jet[1] = v[1];
        jet[2] = u_new;
        ok &= hyst_shaped_model_step_derivatives(&inv, jet, x, 2) == HYST_OK;
        worst_u = worse(worst_u, u, (x[0] + a[0] * x[1] + a[1] * x[2]) / b);
        worst_f32 = worse(worst_f32, u32, u);
    }
    ok &= hyst_shaped_compensator_get_state(&c, v, &mem) == HYST_OK;
    history &= mem.has_history == 1;
    CHECK(ok);
    CHECK(history);
    CHECK(worst_u <= 1e-12);
    CHECK(worst_f32 <= 1e-5);
    EXPECT(hyst_shaped_compensator_get_state_f32(&c32, v32, NULL), HYST_OK);
    EXPECT(hyst_shaped_compensator_get_state(&c, v, NULL), HYST_OK);
    CLOSE(v32[0], v[0], 1e-5);
    CLOSE(v32[1], v[1], 1e-5);

    /* reference mode: the integrators are set to the reference */
    {
        double reference[3] = {0.3, 0.5, -0.1};
        float reference32[3] = {0.3f, 0.5f, -0.1f};
        EXPECT(hyst_shaped_compensator_get_state(&c, NULL, &mem), HYST_ERR_NULL_POINTER);
        EXPECT(hyst_shaped_compensator_get_state(&c, v, &mem), HYST_OK);
        EXPECT(hyst_shaped_model_set_memory(&inv, &mem), HYST_OK);
        EXPECT(hyst_shaped_compensator_track(&c, reference, &u), HYST_OK);
        EXPECT(hyst_shaped_compensator_track_f32(&c32, reference32, &u32), HYST_OK);
        EXPECT(hyst_shaped_model_step_derivatives(&inv, reference, x, 2), HYST_OK);
        CLOSE(u, (x[0] + a[0] * x[1] + a[1] * x[2]) / b, 1e-12);
        CLOSE(u32, u, 1e-5);
        EXPECT(hyst_shaped_compensator_get_state(&c, v, NULL), HYST_OK);
        CHECK(v[0] == 0.3 && v[1] == 0.5);
    }

    /* reset: back to v0, memory forgotten; a refused sample holds the last command (0 after a
     * reset) and changes nothing */
    EXPECT(hyst_shaped_compensator_reset(&c), HYST_OK);
    EXPECT(hyst_shaped_compensator_reset_f32(&c32), HYST_OK);
    EXPECT(hyst_shaped_compensator_get_state(&c, v, &mem), HYST_OK);
    CHECK(v[0] == v0[0] && v[1] == v0[1] && mem.has_history == 0);
    u = 42.0;
    EXPECT(hyst_shaped_compensator_step(&c, NAN, dt, &u), HYST_ERR_NON_FINITE);
    CHECK(u == 0.0);
    EXPECT(hyst_shaped_compensator_step(&c, 1.0, -dt, &u), HYST_ERR_NON_FINITE);
    EXPECT(hyst_shaped_compensator_step(&c, 1.0, INFINITY, &u), HYST_ERR_NON_FINITE);
    EXPECT(hyst_shaped_compensator_step_f32(&c32, NAN, 1e-3f, &u32), HYST_ERR_NON_FINITE);
    EXPECT(hyst_shaped_compensator_get_state(&c, v, &mem), HYST_OK);
    CHECK(v[0] == v0[0] && v[1] == v0[1] && mem.has_history == 0);
    {
        double reference[3] = {0.3, NAN, 0.0};
        u = 42.0;
        EXPECT(hyst_shaped_compensator_track(&c, reference, &u), HYST_ERR_NON_FINITE);
        CHECK(u == 42.0);
    }

    /* init: bad plants and orders */
    EXPECT(hyst_shaped_compensator_init(&c, &p, 0.0, a, NULL, 2), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_shaped_compensator_init(&c, &p, NAN, a, NULL, 2), HYST_ERR_INVALID_PARAMETER);
    {
        double a_nan[2] = {0.9, NAN}, v_inf[2] = {INFINITY, 0.0};
        EXPECT(hyst_shaped_compensator_init(&c, &p, b, a_nan, NULL, 2), HYST_ERR_INVALID_PARAMETER);
        EXPECT(hyst_shaped_compensator_init(&c, &p, b, a, v_inf, 2), HYST_ERR_INVALID_PARAMETER);
    }
    {
        double a5[5] = {1, 1, 1, 1, 1};
        float a5f[5] = {1, 1, 1, 1, 1};
        EXPECT(hyst_shaped_compensator_init(&c, &p, b, a5, NULL, 5), HYST_ERR_LENGTH);
        EXPECT(hyst_shaped_compensator_init_f32(&c32, &q, b32, a5f, NULL, 5), HYST_ERR_LENGTH);
        EXPECT(hyst_shaped_compensator_init(&c, &p, b, a5, NULL, 4), HYST_OK);
    }
    EXPECT(hyst_shaped_compensator_init(&c, &p, b, NULL, NULL, 2), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_init(&c, NULL, b, a, NULL, 2), HYST_ERR_NULL_POINTER);
    /* n = 0: no integrators, u = x / b */
    EXPECT(hyst_shaped_compensator_init(&c, &p, b, NULL, NULL, 0), HYST_OK);
    EXPECT(hyst_shaped_compensator_get_state(&c, NULL, NULL), HYST_OK);
    EXPECT(hyst_shaped_compensator_init(&c, &p, b, a, NULL, 2), HYST_OK);
    EXPECT(hyst_shaped_compensator_get_state(&c, NULL, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_get_state(&c, v, NULL), HYST_OK);
    CHECK(v[0] == 0.0 && v[1] == 0.0); /* v0 NULL: at rest at 0 */
}

/* ------------------------------------------------------------------------------------------ */
/* Every bad argument: NULL pointers, misaligned and uninitialised (zeroed) states, NaN, order 5,
 * with the documented status. */

static void bad_arguments(void)
{
    static uint64_t words[80]; /* room for the largest state, misaligned by a few bytes */
    unsigned char *bytes = (unsigned char *)words;
    hyst_operator op, zero_op;
    hyst_operator_f32 op32, zero_op32;
    hyst_shaped_model zero_m;
    hyst_shaped_model_f32 zero_m32;
    hyst_shaped_compensator zero_c;
    hyst_shaped_compensator_f32 zero_c32;
    hyst_memory mem, before, after;
    hyst_memory_f32 mem32;
    hyst_shaped_model_params p = params_f64();
    hyst_shaped_model_params_f32 q = params_f32();
    double y = 7.0, xs[6] = {0.1, 0.1, 0.1, 0.1, 0.1, 0.1}, ys[6], held;
    float y32 = 7.0f, xs32[6] = {0.1f, 0.1f, 0.1f, 0.1f, 0.1f, 0.1f}, ys32[6];
    int k;

    memset(&zero_op, 0, sizeof zero_op);
    memset(&zero_op32, 0, sizeof zero_op32);
    memset(&zero_m, 0, sizeof zero_m);
    memset(&zero_m32, 0, sizeof zero_m32);
    memset(&zero_c, 0, sizeof zero_c);
    memset(&zero_c32, 0, sizeof zero_c32);
    memset(&mem, 0, sizeof mem);
    memset(&mem32, 0, sizeof mem32);

    /* NULL state */
    EXPECT(hyst_operator_init_direct(NULL, 0.2, 8.0), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_init_inverse(NULL, 0.2, 8.0), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step(NULL, 0.1, &y), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step_derivatives(NULL, xs, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_process(NULL, xs, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_get_memory(NULL, &mem), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_set_memory(NULL, &mem), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_reset(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_init_direct_f32(NULL, 0.2f, 8.0f), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_init_inverse_f32(NULL, 0.2f, 8.0f), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step_f32(NULL, 0.1f, &y32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step_derivatives_f32(NULL, xs32, ys32, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_process_f32(NULL, xs32, ys32, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_get_memory_f32(NULL, &mem32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_set_memory_f32(NULL, &mem32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_reset_f32(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_direct(NULL, &p), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_inverse(NULL, &p), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_step(NULL, 0.1, &y), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_step_derivatives(NULL, xs, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_process(NULL, xs, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_get_memory(NULL, &mem), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_set_memory(NULL, &mem), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_reset(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_direct_f32(NULL, &q), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_inverse_f32(NULL, &q), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_step_f32(NULL, 0.1f, &y32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_step_derivatives_f32(NULL, xs32, ys32, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_process_f32(NULL, xs32, ys32, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_get_memory_f32(NULL, &mem32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_set_memory_f32(NULL, &mem32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_reset_f32(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_init(NULL, &p, 1.0, NULL, NULL, 0), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_step(NULL, 0.1, 1e-3, &y), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_track(NULL, xs, &y), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_get_state(NULL, ys, &mem), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_reset(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_init_f32(NULL, &q, 1.0f, NULL, NULL, 0), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_step_f32(NULL, 0.1f, 1e-3f, &y32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_track_f32(NULL, xs32, &y32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_get_state_f32(NULL, ys32, &mem32), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_reset_f32(NULL), HYST_ERR_NULL_POINTER);

    /* NULL data pointers with a valid state; n = 0 needs none */
    EXPECT(hyst_operator_init_direct(&op, 0.2, 8.0), HYST_OK);
    EXPECT(hyst_operator_init_direct_f32(&op32, 0.2f, 8.0f), HYST_OK);
    EXPECT(hyst_operator_step(&op, 0.1, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step_f32(&op32, 0.1f, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_process(&op, NULL, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_process(&op, xs, NULL, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_process(&op, NULL, NULL, 0), HYST_OK);
    EXPECT(hyst_operator_process_f32(&op32, NULL, NULL, 0), HYST_OK);
    EXPECT(hyst_operator_step_derivatives(&op, NULL, ys, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_step_derivatives(&op, xs, NULL, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_get_memory(&op, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_set_memory(&op, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_operator_get_memory_f32(&op32, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_direct(&zero_m, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_model_init_inverse_f32(&zero_m32, NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_shaped_compensator_init_f32(&zero_c32, NULL, 1.0f, NULL, NULL, 0), HYST_ERR_NULL_POINTER);

    /* uninitialised (zeroed) states: every call says so */
    EXPECT(hyst_operator_step(&zero_op, 0.1, &y), HYST_ERR_NOT_INITIALISED);
    CHECK(y == 7.0);
    EXPECT(hyst_operator_step_derivatives(&zero_op, xs, ys, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_process(&zero_op, xs, ys, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_get_memory(&zero_op, &mem), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_set_memory(&zero_op, &mem), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_reset(&zero_op), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_step_f32(&zero_op32, 0.1f, &y32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_step_derivatives_f32(&zero_op32, xs32, ys32, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_process_f32(&zero_op32, xs32, ys32, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_get_memory_f32(&zero_op32, &mem32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_set_memory_f32(&zero_op32, &mem32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_reset_f32(&zero_op32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_step(&zero_m, 0.1, &y), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_step_derivatives(&zero_m, xs, ys, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_process(&zero_m, xs, ys, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_get_memory(&zero_m, &mem), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_set_memory(&zero_m, &mem), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_reset(&zero_m), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_step_f32(&zero_m32, 0.1f, &y32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_step_derivatives_f32(&zero_m32, xs32, ys32, 1),
           HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_process_f32(&zero_m32, xs32, ys32, 1), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_get_memory_f32(&zero_m32, &mem32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_set_memory_f32(&zero_m32, &mem32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_model_reset_f32(&zero_m32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_step(&zero_c, 0.1, 1e-3, &y), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_track(&zero_c, xs, &y), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_get_state(&zero_c, ys, &mem), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_reset(&zero_c), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_step_f32(&zero_c32, 0.1f, 1e-3f, &y32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_track_f32(&zero_c32, xs32, &y32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_get_state_f32(&zero_c32, ys32, &mem32), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_shaped_compensator_reset_f32(&zero_c32), HYST_ERR_NOT_INITIALISED);
    /* a float state is not a double state, even in a block of the right size */
    {
        hyst_operator fake;
        memset(&fake, 0, sizeof fake);
        memcpy(&fake, &op32, sizeof op32);
        EXPECT(hyst_operator_step(&fake, 0.1, &y), HYST_ERR_NOT_INITIALISED);
    }

    /* misaligned states (the pointer 1 and 4 bytes past an 8-byte boundary) */
    for (k = 1; k <= 4; k += 3) {
        hyst_operator *mop = (hyst_operator *)(void *)(bytes + k);
        hyst_shaped_model *mm = (hyst_shaped_model *)(void *)(bytes + k);
        hyst_shaped_compensator *mc = (hyst_shaped_compensator *)(void *)(bytes + k);
        EXPECT(hyst_operator_init_direct(mop, 0.2, 8.0), HYST_ERR_MISALIGNED);
        EXPECT(hyst_operator_init_inverse(mop, 0.2, 8.0), HYST_ERR_MISALIGNED);
        EXPECT(hyst_operator_step(mop, 0.1, &y), HYST_ERR_MISALIGNED);
        EXPECT(hyst_operator_reset(mop), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_model_init_direct(mm, &p), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_model_step(mm, 0.1, &y), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_compensator_init(mc, &p, 1.0, NULL, NULL, 0), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_compensator_step(mc, 0.1, 1e-3, &y), HYST_ERR_MISALIGNED);
    }
    {
        hyst_operator_f32 *mop = (hyst_operator_f32 *)(void *)(bytes + 1);
        hyst_shaped_model_f32 *mm = (hyst_shaped_model_f32 *)(void *)(bytes + 1);
        hyst_shaped_compensator_f32 *mc = (hyst_shaped_compensator_f32 *)(void *)(bytes + 1);
        EXPECT(hyst_operator_init_direct_f32(mop, 0.2f, 8.0f), HYST_ERR_MISALIGNED);
        EXPECT(hyst_operator_step_f32(mop, 0.1f, &y32), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_model_init_inverse_f32(mm, &q), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_model_step_f32(mm, 0.1f, &y32), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_compensator_init_f32(mc, &q, 1.0f, NULL, NULL, 0), HYST_ERR_MISALIGNED);
        EXPECT(hyst_shaped_compensator_reset_f32(mc), HYST_ERR_MISALIGNED);
    }
    {
        int untouched = 1;
        for (k = 0; k < (int)sizeof words; k++)
            untouched &= bytes[k] == 0;
        CHECK(untouched); /* nothing was written */
    }

    /* invalid k1, k2: refused, the block untouched */
    EXPECT(hyst_operator_init_direct(&zero_op, -1.0, 8.0), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_operator_init_direct(&zero_op, 0.2, NAN), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_operator_init_inverse(&zero_op, INFINITY, 8.0), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_operator_init_inverse(&zero_op, 0.2, 0.0), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_operator_init_direct_f32(&zero_op32, NAN, 8.0f), HYST_ERR_INVALID_PARAMETER);
    EXPECT(hyst_operator_step(&zero_op, 0.1, &y), HYST_ERR_NOT_INITIALISED);
    EXPECT(hyst_operator_step_f32(&zero_op32, 0.1f, &y32), HYST_ERR_NOT_INITIALISED);

    /* NaN samples: refused, the last output held, the memory unchanged */
    EXPECT(hyst_operator_step(&op, 0.5, &y), HYST_OK);
    held = y;
    EXPECT(hyst_operator_get_memory(&op, &before), HYST_OK);
    EXPECT(hyst_operator_step(&op, NAN, &y), HYST_ERR_NON_FINITE);
    CHECK(y == held);
    EXPECT(hyst_operator_step(&op, -INFINITY, &y), HYST_ERR_NON_FINITE);
    CHECK(y == held);
    EXPECT(hyst_operator_get_memory(&op, &after), HYST_OK);
    CHECK(memcmp(&before, &after, sizeof before) == 0);
    EXPECT(hyst_operator_step_f32(&op32, 0.25f, &y32), HYST_OK);
    held = y32;
    EXPECT(hyst_operator_step_f32(&op32, NAN, &y32), HYST_ERR_NON_FINITE);
    CHECK(y32 == (float)held);
    {
        double x3[3] = {0.6, NAN, 0.7}, out[3];
        EXPECT(hyst_operator_process(&op, x3, out, 3), HYST_ERR_NON_FINITE);
        CHECK(out[1] == out[0] && out[2] > out[0]); /* the rest still processed */
    }
    {
        double jet[2] = {0.1, NAN}, out[2] = {9.0, 9.0};
        EXPECT(hyst_operator_step_derivatives(&op, jet, out, 1), HYST_ERR_NON_FINITE);
        CHECK(out[0] == 9.0 && out[1] == 9.0);
    }
    {
        hyst_shaped_model m;
        EXPECT(hyst_shaped_model_init_direct(&m, &p), HYST_OK);
        EXPECT(hyst_shaped_model_step(&m, 0.2, &y), HYST_OK);
        held = y;
        EXPECT(hyst_shaped_model_step(&m, NAN, &y), HYST_ERR_NON_FINITE);
        CHECK(y == held);
    }

    /* derivative order 5 > HYST_MAX_ORDER: refused, nothing written */
    for (k = 0; k < 6; k++)
        ys[k] = 9.0;
    EXPECT(hyst_operator_step_derivatives(&op, xs, ys, 5), HYST_ERR_LENGTH);
    EXPECT(hyst_operator_step_derivatives_f32(&op32, xs32, ys32, 5), HYST_ERR_LENGTH);
    {
        hyst_shaped_model m;
        hyst_shaped_model_f32 m32;
        EXPECT(hyst_shaped_model_init_inverse(&m, &p), HYST_OK);
        EXPECT(hyst_shaped_model_init_inverse_f32(&m32, &q), HYST_OK);
        EXPECT(hyst_shaped_model_step_derivatives(&m, xs, ys, 5), HYST_ERR_LENGTH);
        EXPECT(hyst_shaped_model_step_derivatives_f32(&m32, xs32, ys32, 5), HYST_ERR_LENGTH);
        EXPECT(hyst_shaped_model_step_derivatives(&m, xs, ys, 4), HYST_OK);
    }
    CHECK(ys[5] == 9.0);
}

/* ------------------------------------------------------------------------------------------ */
/* The host part: a fitted model file, run in one block or many. */

static void host_model(const char *path)
{
    char error[256], tiny[5];
    hyst_model *m;
    static double x[N_SAMPLES], whole[N_SAMPLES], blocks[N_SAMPLES];
    int k, ok = 1;

    /* a missing file: NULL and a message naming it; a small buffer is truncated safely */
    m = hyst_model_load("/nonexistent/model.toml", error, sizeof error);
    CHECK(m == NULL && strstr(error, "/nonexistent/model.toml") != NULL);
    memset(tiny, 1, sizeof tiny);
    CHECK(hyst_model_load("/nonexistent/model.toml", tiny, sizeof tiny) == NULL);
    CHECK(tiny[4] == '\0' && strlen(tiny) == 4);
    CHECK(hyst_model_load(NULL, error, sizeof error) == NULL && error[0] != '\0');
    CHECK(hyst_model_load(NULL, NULL, 0) == NULL);
    hyst_model_free(NULL);
    EXPECT(hyst_model_reset(NULL), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_model_process(NULL, 0, x, whole, 1), HYST_ERR_NULL_POINTER);
    if (!path)
        return;

    m = hyst_model_load(path, error, sizeof error);
    CHECK(m != NULL);
    if (!m) {
        fprintf(stderr, "smoke: %s\n", error);
        return;
    }
    /* the inverse over a record, whole, then in blocks of 77 after a reset */
    {
        double lo = 1e300, hi = -1e300;
        /* desired outputs: the direct model's own outputs over an input sweep */
        for (k = 0; k < N_SAMPLES; k++)
            x[k] = 1.8 + 1.5 * signal(k);
        EXPECT(hyst_model_process(m, 0, x, whole, N_SAMPLES), HYST_OK);
        for (k = 0; k < N_SAMPLES; k++) {
            lo = whole[k] < lo ? whole[k] : lo;
            hi = whole[k] > hi ? whole[k] : hi;
        }
        CHECK(lo < hi);
    }
    memcpy(x, whole, sizeof x);
    EXPECT(hyst_model_process(m, 1, x, whole, N_SAMPLES), HYST_OK);
    EXPECT(hyst_model_reset(m), HYST_OK);
    for (k = 0; k < N_SAMPLES; k += 77) {
        size_t n = N_SAMPLES - k < 77 ? (size_t)(N_SAMPLES - k) : 77;
        ok &= hyst_model_process(m, 1, x + k, blocks + k, n) == HYST_OK;
    }
    CHECK(ok);
    CHECK(memcmp(whole, blocks, sizeof whole) == 0);
    /* in place */
    EXPECT(hyst_model_reset(m), HYST_OK);
    memcpy(blocks, x, sizeof blocks);
    EXPECT(hyst_model_process(m, 1, blocks, blocks, N_SAMPLES), HYST_OK);
    CHECK(memcmp(whole, blocks, sizeof whole) == 0);
    /* NULL arrays only with n = 0; a refused sample gives its status */
    EXPECT(hyst_model_process(m, 1, NULL, NULL, 0), HYST_OK);
    EXPECT(hyst_model_process(m, 1, NULL, blocks, 1), HYST_ERR_NULL_POINTER);
    EXPECT(hyst_model_process(m, 1, x, NULL, 1), HYST_ERR_NULL_POINTER);
    {
        double bad[3] = {x[0], NAN, x[0]}, out[3];
        EXPECT(hyst_model_process(m, 0, bad, out, 3), HYST_ERR_NON_FINITE);
    }
    hyst_model_free(m);
}

int main(int argc, char **argv)
{
    if (argc > 2) {
        fprintf(stderr, "usage: smoke [MODEL.toml]\n");
        return 2;
    }
    status_messages();
    operator_f64();
    operator_f32();
    shaped_model();
    compensator();
    bad_arguments();
    host_model(argc > 1 ? argv[1] : NULL);
    printf("smoke: %d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
