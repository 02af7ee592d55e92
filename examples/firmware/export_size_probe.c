/*
 * export_size_probe.c: the smallest useful firmware with one exported model (piezo.h, written by
 * `hyst export c`) as a shaped compensator of order 2 in float: the model's exact inverse in
 * front of the actuator, and the Lemma 5.1 compensator of the same shaped model for a
 * second-order plant, one step each per tick. Inputs come from volatile variables (an ADC, a
 * trajectory) and outputs go to volatile ones (a DAC), so the compiler keeps every call.
 * scripts/test-firmware reports this image's size (and runs it, so it is known to work).
 */
#include "piezo.h"

volatile float adc_desired = -100.0f, adc_u_new = 0.25f;
volatile float dac_command, dac_force;

int main(void) {
    static piezo_state_f32 inverse;
    static hyst_shaped_compensator_f32 comp;
    hyst_shaped_model_params_f32 params;
    const float a[2] = {0.9f, 1.0f};
    int32_t status = HYST_OK;
    int tick;

    status |= piezo_init_inverse_f32(&inverse);
    piezo_params_f32(&params);
    params.initial_state = HYST_INITIAL_STATE_LINE; /* the integrators' state sets the history */
    status |= hyst_shaped_compensator_init_f32(&comp, &params, 1.0f, a, 0, 2);
    for (tick = 0; tick < 1000; tick++) {
        float command, force;
        status |= piezo_step_f32(&inverse, adc_desired, &command);
        status |= hyst_shaped_compensator_step_f32(&comp, adc_u_new, 1e-4f, &force);
        dac_command = command;
        dac_force = force;
        adc_desired = -100.0f + 10.0f * (float)(tick % 7);
    }
    return status == HYST_OK ? 0 : 1;
}
