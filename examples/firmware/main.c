/*
 * main.c: the firmware test run on a Cortex-M4F (QEMU mps2-an386): the shared driver (driver.c)
 * runs the test signal through the f32 C API of libhyst.a built for thumbv7em-none-eabihf, and
 * its lines go to the host through semihosting. scripts/test-firmware compares them with
 * host_reference.c's, the same driver on the host.
 */
#include "driver.h"
#include "semihost.h"

int main(void) {
    return drv_run(semihost_write0) == 0 ? 0 : 1; /* the startup exits through semihosting */
}
