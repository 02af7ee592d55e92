/*
 * exported.h: the run of the exported models (hyst export c), shared by the firmware
 * (export_main.c under QEMU) and the host (export_host.c), as driver.h is for the API test.
 */
#ifndef HYST_FIRMWARE_EXPORTED_H
#define HYST_FIRMWARE_EXPORTED_H

#include "driver.h"

/*
 * Runs each exported model over its test signal (export_signals.h), direct and inverse, in
 * double and in float, and writes one line per output:
 *
 *   e <model>.<dir|inv|cmp>[32] <index> <IEEE-754 bits in hex>
 *
 * (cmp: the piezo model's Lemma 5.1 compensator of a second-order plant; for piezo_dyn, a model
 * with dynamics: dir is the model with its plant, inv its compensator, from the desired output
 * and its derivatives), "# <model>.inv clamped <count>" after each inverse, "# friction.inv status <status>" and "# friction.cmp
 * status <status>" (the stop form has no inverse and no compensator), and "# done: <values>
 * values, <errors> errors". Returns the number
 * of errors (a status other than HYST_OK where one is expected): 0 on success.
 */
int exp_run(drv_write_fn write);

#endif /* HYST_FIRMWARE_EXPORTED_H */
