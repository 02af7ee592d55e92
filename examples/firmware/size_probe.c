/*
 * size_probe.c: the smallest useful firmware with the operator pair and the n = 2 compensator in
 * float (what the code-size goal is about): H^-1 in front of an actuator, H to monitor
 * it, and the Lemma 5.1 compensator of a second-order plant, one step each per tick. The inputs
 * come from volatile variables (an ADC, a trajectory) and the outputs go to volatile ones (a
 * DAC), so the compiler keeps every call. scripts/test-firmware reports this image's size (and
 * runs it, so it is known to work).
 */
#include "hyst.h"

volatile float adc_desired = 0.5f, adc_u_new = 0.25f;
volatile float dac_command, dac_monitor, dac_force;

int main(void) {
    static hyst_operator_f32 inverse, direct;
    static hyst_compensator_f32 comp;
    const float a[2] = {0.9f, 1.0f};
    int32_t status = HYST_OK;
    int tick;

    status |= hyst_operator_init_inverse_f32(&inverse, 0.2f, 8.0f);
    status |= hyst_operator_init_direct_f32(&direct, 0.2f, 8.0f);
    status |= hyst_compensator_init_f32(&comp, 0.2f, 8.0f, 1.0f, a, 0, 2);
    for (tick = 0; tick < 1000; tick++) {
        float command, monitor, force;
        status |= hyst_operator_step_f32(&inverse, adc_desired, &command);
        status |= hyst_operator_step_f32(&direct, command, &monitor);
        status |= hyst_compensator_step_f32(&comp, adc_u_new, 1e-4f, &force);
        dac_command = command;
        dac_monitor = monitor;
        dac_force = force;
        adc_desired = -adc_desired * 0.999f;
    }
    return status == HYST_OK ? 0 : 1;
}
