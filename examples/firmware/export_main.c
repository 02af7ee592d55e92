/*
 * export_main.c: the exported models' run (exported.c) on a Cortex-M4F under QEMU, its lines to
 * the host through semihosting. scripts/test-firmware compares them with export_host.c's.
 */
#include "exported.h"
#include "semihost.h"

int main(void) {
    return exp_run(semihost_write0) == 0 ? 0 : 1; /* the startup exits through semihosting */
}
