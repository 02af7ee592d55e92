/*
 * export_timed_size_probe.c: the smallest useful firmware with the exported compensator of a
 * model with dynamics (piezo_dyn.h, written by `hyst export c`), in float: Lemma 5.1's
 * compensator of the fitted plant (order 2) in track mode, one step per tick from the desired
 * output and its two derivatives. The desired values come from volatile variables (a trajectory
 * generator) and the command goes to a volatile one (a DAC), so the compiler keeps every call.
 * scripts/test-firmware reports this image's size (and runs it, so it is known to work).
 */
#include "piezo_dyn.h"

volatile float trajectory[PIEZO_DYN_ORDER + 1] = {-100.0f, 0.0f, 0.0f};
volatile float dac_command;

int main(void) {
    static piezo_dyn_timed_compensator_f32 comp;
    int32_t status = piezo_dyn_timed_compensator_init_f32(&comp);
    int tick, k;

    for (tick = 0; tick < 1000; tick++) {
        float desired[PIEZO_DYN_ORDER + 1], command;
        for (k = 0; k <= PIEZO_DYN_ORDER; k++) {
            desired[k] = trajectory[k];
        }
        status |= piezo_dyn_timed_compensator_step_f32(&comp, desired, &command);
        dac_command = command;
        trajectory[0] = (tick % 200 < 100) ? -100.0f + 0.01f * (float)(tick % 100) : -99.0f;
        trajectory[1] = (tick % 200 < 100) ? 10.0f : 0.0f;
    }
    return status == HYST_OK ? 0 : 1;
}
