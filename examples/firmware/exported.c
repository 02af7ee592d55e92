/*
 * exported.c: the exported models (piezo.h, steel.h, friction.h, piezo_dyn.h, written by
 * `hyst export c` from models/) over their test signals; see exported.h. Plain C99 without libc.
 */
#include "exported.h"

#include "export_signals.h"
#include "friction.h"
#include "piezo.h"
#include "piezo_dyn.h"
#include "steel.h"

#define LINE_MAX 64

struct line {
    char text[LINE_MAX];
    int len;
};

static void put_str(struct line *l, const char *s) {
    while (*s != '\0' && l->len < LINE_MAX - 2) {
        l->text[l->len++] = *s++;
    }
}

static void put_uint(struct line *l, uint32_t v) {
    char digits[10];
    int n = 0;
    do {
        digits[n++] = (char)('0' + v % 10u);
        v /= 10u;
    } while (v != 0u);
    while (n > 0 && l->len < LINE_MAX - 2) {
        l->text[l->len++] = digits[--n];
    }
}

static void put_hex(struct line *l, uint64_t v, int digits) {
    static const char hex[] = "0123456789abcdef";
    int shift;
    for (shift = 4 * (digits - 1); shift >= 0 && l->len < LINE_MAX - 2; shift -= 4) {
        l->text[l->len++] = hex[(v >> shift) & 0xfu];
    }
}

static void emit(drv_write_fn write, struct line *l) {
    l->text[l->len++] = '\n';
    l->text[l->len] = '\0';
    write(l->text);
    l->len = 0;
}

static uint64_t bits64(double x) {
    union {
        double d;
        uint64_t u;
    } v;
    v.d = x;
    return v.u;
}

static uint64_t bits32(float x) {
    union {
        float f;
        uint32_t u;
    } v;
    v.f = x;
    return v.u;
}

static void value(drv_write_fn write, const char *series, int i, uint64_t bits, int digits) {
    struct line l = {{0}, 0};
    put_str(&l, "e ");
    put_str(&l, series);
    put_str(&l, " ");
    put_uint(&l, (uint32_t)i);
    put_str(&l, " ");
    put_hex(&l, bits, digits);
    emit(write, &l);
}

static void note(drv_write_fn write, const char *what, const char *label, uint32_t n) {
    struct line l = {{0}, 0};
    put_str(&l, "# ");
    put_str(&l, what);
    put_str(&l, " ");
    put_str(&l, label);
    put_str(&l, " ");
    put_uint(&l, n);
    emit(write, &l);
}

/* One model (NAME) started by INIT over the signal X, in double and in float: SERIES.
 * Counts values and errors. */
#define EXP_SERIES(NAME, INIT, X, SERIES)                                                        \
    do {                                                                                         \
        NAME##_state s;                                                                          \
        NAME##_state_f32 s32;                                                                    \
        int i;                                                                                   \
        errors += INIT(&s) != HYST_OK;                                                           \
        errors += INIT##_f32(&s32) != HYST_OK;                                                   \
        for (i = 0; i < EXP_SAMPLES; i++) {                                                      \
            double y = 0.0;                                                                      \
            float y32 = 0.0f;                                                                    \
            errors += NAME##_step(&s, X[i], &y) != HYST_OK;                                      \
            errors += NAME##_step_f32(&s32, (float)X[i], &y32) != HYST_OK;                       \
            value(write, SERIES, i, bits64(y), 16);                                              \
            value(write, SERIES "32", i, bits32(y32), 8);                                \
            values += 2;                                                                         \
        }                                                                                        \
        if (s.inverse) {                                                                         \
            note(write, SERIES, "clamped", s.clamped);                                           \
        }                                                                                        \
    } while (0)

int exp_run(drv_write_fn write) {
    int errors = 0;
    uint32_t values = 0;
    struct line l = {{0}, 0};
    friction_state stop;

    EXP_SERIES(piezo, piezo_init, piezo_x, "piezo.dir");
    EXP_SERIES(piezo, piezo_init_inverse, piezo_y, "piezo.inv");
    EXP_SERIES(steel, steel_init, steel_x, "steel.dir");
    EXP_SERIES(steel, steel_init_inverse, steel_y, "steel.inv");
    EXP_SERIES(friction, friction_init, friction_x, "friction.dir");
    /* The piezo model's Lemma 5.1 compensator for a second-order plant (a_1 = 0.05 s,
     * a_2 = 0.001 s^2, b = 1), its integrators' input a square wave: double and float. */
    {
        piezo_compensator c;
        piezo_compensator_f32 c32;
        const double a[2] = {0.05, 0.001};
        const float a32[2] = {0.05f, 0.001f};
        int i;
        errors += piezo_compensator_init(&c, 1.0, a, 0, 2) != HYST_OK;
        errors += piezo_compensator_init_f32(&c32, 1.0f, a32, 0, 2) != HYST_OK;
        for (i = 0; i < EXP_SAMPLES; i++) {
            double u_new = (i / 50) % 2 ? -2000.0 : 2000.0, u = 0.0;
            float u32 = 0.0f;
            errors += piezo_compensator_step(&c, u_new, 1e-3, &u) != HYST_OK;
            errors += piezo_compensator_step_f32(&c32, (float)u_new, 1e-3f, &u32) != HYST_OK;
            value(write, "piezo.cmp", i, bits64(u), 16);
            value(write, "piezo.cmp32", i, bits32(u32), 8);
            values += 2;
        }
    }
    /* A model with dynamics (piezo_dyn: piezo with a second-order plant): the model with its
     * plant over the commands piezo_dyn_x, and Lemma 5.1's compensator of its fitted plant over
     * the desired output and its derivatives piezo_dyn_desired, in double and float. */
    {
        piezo_dyn_timed_state s;
        piezo_dyn_timed_state_f32 s32;
        piezo_dyn_timed_compensator c;
        piezo_dyn_timed_compensator_f32 c32;
        int i, k;
        errors += piezo_dyn_timed_init(&s) != HYST_OK;
        errors += piezo_dyn_timed_init_f32(&s32) != HYST_OK;
        errors += piezo_dyn_timed_compensator_init(&c) != HYST_OK;
        errors += piezo_dyn_timed_compensator_init_f32(&c32) != HYST_OK;
        for (i = 0; i < EXP_SAMPLES; i++) {
            double y = 0.0, u = 0.0;
            float y32 = 0.0f, u32 = 0.0f, desired32[PIEZO_DYN_ORDER + 1];
            errors += piezo_dyn_timed_step(&s, piezo_dyn_x[i], &y) != HYST_OK;
            errors += piezo_dyn_timed_step_f32(&s32, (float)piezo_dyn_x[i], &y32) != HYST_OK;
            value(write, "piezo_dyn.dir", i, bits64(y), 16);
            value(write, "piezo_dyn.dir32", i, bits32(y32), 8);
            for (k = 0; k <= PIEZO_DYN_ORDER; k++) {
                desired32[k] = (float)piezo_dyn_desired[i][k];
            }
            errors += piezo_dyn_timed_compensator_step(&c, piezo_dyn_desired[i], &u) != HYST_OK;
            errors += piezo_dyn_timed_compensator_step_f32(&c32, desired32, &u32) != HYST_OK;
            value(write, "piezo_dyn.inv", i, bits64(u), 16);
            value(write, "piezo_dyn.inv32", i, bits32(u32), 8);
            values += 4;
        }
    }
    /* The stop form has no compensator either. */
    {
        friction_compensator c;
        const double a[1] = {0.01};
        int32_t status = friction_compensator_init(&c, 1.0, a, 0, 1);
        note(write, "friction.cmp", "status", (uint32_t)status);
        errors += status != HYST_ERR_INVALID_PARAMETER;
    }
    /* The stop form has no inverse: the init refuses it and leaves the state untouched. */
    {
        int32_t status = friction_init_inverse(&stop);
        note(write, "friction.inv", "status", (uint32_t)status);
        errors += status != HYST_ERR_INVALID_PARAMETER;
    }
    put_str(&l, "# done: ");
    put_uint(&l, values);
    put_str(&l, " values, ");
    put_uint(&l, (uint32_t)errors);
    put_str(&l, " errors");
    emit(write, &l);
    return errors;
}
