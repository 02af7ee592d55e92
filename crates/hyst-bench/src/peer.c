/*
 * The plain-C peer of hyst's inverse operator: eq. (4) with Definition 2.1's
 * memory, written as a careful C programmer would, with no checks (no finiteness test, no
 * band test, no overflow repair). `hyst-bench` (crates/hyst-bench) times it on the same signal
 * as hyst's inverse (`inverse_over_c_peer`, goal <= 1.0); a unit test checks that it is a real
 * inverse (its outputs equal hyst's).
 *
 * The same arithmetic as InverseHysteresis in crates/hyst-core/src/parametric.rs, in the same
 * order, with the same exponential, the platform's exp (so the outputs agree when no band
 * clamp fires):
 *   a change of direction makes the previous sample the reversal point (alpha0, beta0);
 *   s = +1 rising, -1 falling; M = s (beta0 - alpha0); M* = k1 - M;
 *   ud = s (u_d - alpha0); v = (ud s + beta0) + (1 - exp(-(k2 ud))) (M* s).
 * Built by build.rs with the `cc` crate at -O2 with -ffp-contract=off (no fused
 * multiply-adds, as Rust), calling the platform's libm `exp`, as a plain C program does.
 */
#include <math.h>
#include <stddef.h>

/* The memory of Definition 2.1 plus the last sample. */
struct peer_memory {
    double reversal_input;  /* alpha0 */
    double reversal_output; /* beta0 */
    double last_input;
    double last_output;
    double sign;            /* s: +1 rising, -1 falling */
};

static inline double peer_step(struct peer_memory *m, double k1, double k2, double x) {
    double s = m->sign;
    if (x > m->last_input) {
        s = 1.0;
    } else if (x < m->last_input) {
        s = -1.0;
    }
    if (s != m->sign) {
        m->reversal_input = m->last_input;
        m->reversal_output = m->last_output;
        m->sign = s;
    }
    double m_star = k1 - (m->reversal_output - m->reversal_input) * s;
    double ud = (x - m->reversal_input) * s;
    double along = ud * s + m->reversal_output;
    double v = along + (1.0 - exp(-(k2 * ud))) * (m_star * s);
    m->last_input = x;
    m->last_output = v;
    return v;
}

/* The first sample: a reversal point on the line v = u_d, rising. */
static inline struct peer_memory peer_start(double x) {
    struct peer_memory m = {x, x, x, x, 1.0};
    return m;
}

/* H^-1(k1, k2) from no history over x[0..n), outputs into y[0..n). */
void hyst_peer_inverse(double k1, double k2, const double *x, double *y, size_t n) {
    if (n == 0) {
        return;
    }
    struct peer_memory m = peer_start(x[0]);
    for (size_t i = 0; i < n; i++) {
        y[i] = peer_step(&m, k1, k2, x[i]);
    }
}

/* The same, returning the sum of the outputs (the benchmark's checksum, as hyst's workload). */
double hyst_peer_inverse_sum(double k1, double k2, const double *x, size_t n) {
    if (n == 0) {
        return 0.0;
    }
    struct peer_memory m = peer_start(x[0]);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        sum += peer_step(&m, k1, k2, x[i]);
    }
    return sum;
}
