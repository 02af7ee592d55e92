/*
 * export_size_probe.c: the smallest useful firmware with one exported shaped compensator
 * (piezo.h, written by `hyst export c`) of order 2 in float: the Lemma 5.1 compensator of the
 * fitted piezo model for a second-order plant, one step per tick. The input comes from a
 * volatile variable (the reference's second derivative) and the output goes to a volatile one
 * (a DAC), so the compiler keeps every call. scripts/test-firmware reports this image's size
 * (and runs it, so it is known to work).
 */
#include "piezo.h"

volatile float adc_u_new = 0.25f;
volatile float dac_command;

int main(void) {
    static piezo_compensator_f32 comp;
    const float a[2] = {0.9f, 1.0f}; /* a_1 = 0.9 s, a_2 = 1 s^2, b = 1 */
    int32_t status = piezo_compensator_init_f32(&comp, 1.0f, a, 0, 2);
    int tick;

    for (tick = 0; tick < 1000; tick++) {
        float command;
        status |= piezo_compensator_step_f32(&comp, adc_u_new, 1e-4f, &command);
        dac_command = command;
        adc_u_new = (tick % 200 < 100) ? 0.25f : -0.25f;
    }
    return status == HYST_OK ? 0 : 1;
}
