/*
 * adaptive_size_probe.c: the smallest useful firmware with the adaptive compensator in float
 * (online adaptation): each tick the command for a desired output, then the update
 * from the output measured for it, and now and then a look at a parameter and the counts. The
 * inputs come from volatile variables (a trajectory, an ADC) and the outputs go to volatile ones
 * (a DAC), so the compiler keeps every call. It links only hyst_affine_adaptive_*_f32 (affine
 * shapings, up to four parameters: the firmware variant) and hyst_adaptive_config_default_f32:
 * scripts/test-firmware reports this image's size (goal <= 24 KiB) and runs it, so it is known to work.
 */
#include "hyst.h"

volatile float trajectory = 0.5f, adc_measured = 0.0f;
volatile float dac_command, monitor_gain;
volatile uint64_t monitor_updated;

int main(void) {
    static hyst_affine_adaptive_f32 adaptive;
    hyst_shaped_model_params_f32 params = {0};
    hyst_adaptive_config_f32 cfg;
    hyst_adaptive_sample_counts counts;
    int32_t status = HYST_OK;
    int tick;

    params.k1 = 0.2f;
    params.k2.kind = HYST_K2_CONSTANT;
    params.k2.value = 8.0f;
    params.input.kind = HYST_SHAPING_IDENTITY;
    params.input.pre_gain = 1.0f;
    params.input.post_gain = 1.0f;
    params.output.kind = HYST_SHAPING_AFFINE;
    params.output.p[0] = 1.0f;
    params.output.pre_gain = 1.0f;
    params.output.post_gain = 2.0f;
    status |= hyst_adaptive_config_default_f32(&cfg, 1e-3f);
    status |= hyst_affine_adaptive_init_f32(&adaptive, &params, &cfg);
    for (tick = 0; tick < 1000; tick++) {
        float command, prediction, gain;
        int32_t what;
        status |= hyst_affine_adaptive_step_f32(&adaptive, trajectory, &command);
        dac_command = command;
        adc_measured = 2.1f * command; /* the actuator, here a wire with some gain */
        status |= hyst_affine_adaptive_measure_f32(&adaptive, adc_measured, &prediction, &what);
        if (tick % 100 == 0) {
            status |= hyst_affine_adaptive_parameter_f32(&adaptive, 2, &gain);
            status |= hyst_affine_adaptive_counts_f32(&adaptive, &counts);
            monitor_gain = gain;
            monitor_updated = counts.updated;
        }
        trajectory = -trajectory * 0.999f;
    }
    return status == HYST_OK ? 0 : 1;
}
