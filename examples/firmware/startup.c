/*
 * startup.c: a minimal Cortex-M4F startup for QEMU's mps2-an386 (no libc, no CMSIS): the vector
 * table, a reset handler that enables the FPU, copies .data, zeroes .bss and calls main, a
 * handler for every other exception (it reports and fails instead of hanging), and semihosting.
 */
#include <stdint.h>

#include "semihost.h"

int main(void);

/* From the linker script (mps2-an386.ld). */
extern uint32_t _sidata[], _sdata[], _edata[], _sbss[], _ebss[], _estack[];

#define SYS_WRITE0 0x04
#define SYS_EXIT 0x18
#define ADP_STOPPED_RUNTIME_ERROR_UNKNOWN 0x20023
#define ADP_STOPPED_APPLICATION_EXIT 0x20026

static int semihost_call(int op, const void *arg) {
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_write0(const char *text) {
    (void)semihost_call(SYS_WRITE0, text);
}

void semihost_exit(int success) {
    /* On AArch32 the argument of SYS_EXIT is the reason itself, not a parameter block. */
    uintptr_t reason = success ? ADP_STOPPED_APPLICATION_EXIT : ADP_STOPPED_RUNTIME_ERROR_UNKNOWN;
    for (;;) {
        (void)semihost_call(SYS_EXIT, (const void *)reason);
    }
}

/* After the FPU is on: .data from its load address in the code memory, .bss zeroed, main. */
void reset_c(void) __attribute__((noreturn, used));
void reset_c(void) {
    volatile uint32_t *dst = _sdata; /* volatile: keeps these loops from becoming memcpy/memset */
    const uint32_t *src = _sidata;
    while (dst < _edata) {
        *dst++ = *src++;
    }
    for (dst = _sbss; dst < _ebss;) {
        *dst++ = 0u;
    }
    semihost_exit(main() == 0);
}

/* The reset handler in assembly, so that no compiler-generated code can touch a floating-point
 * register before CPACR grants CP10 and CP11 full access (bits 20-23); DSB and ISB make the
 * change visible before the next instruction. Then on to C. */
void Reset_Handler(void) __attribute__((naked, noreturn));
void Reset_Handler(void) {
    __asm__ volatile(
        "movw r0, #0xed88\n"
        "movt r0, #0xe000\n" /* CPACR = 0xE000ED88 */
        "ldr r1, [r0]\n"
        "orr r1, r1, #(0xf << 20)\n"
        "str r1, [r0]\n"
        "dsb\n"
        "isb\n"
        "b reset_c\n");
}

/* Any other exception: a fault (or an unexpected interrupt) ends the run as a failure. */
void Default_Handler(void) __attribute__((noreturn));
void Default_Handler(void) {
    uint32_t ipsr;
    char text[] = "\n*** exception 00: firmware stopped\n";
    __asm__ volatile("mrs %0, ipsr" : "=r"(ipsr));
    text[15] = (char)('0' + (ipsr / 10u) % 10u);
    text[16] = (char)('0' + ipsr % 10u);
    semihost_write0(text);
    semihost_exit(0);
}

typedef void (*vector_t)(void);

/* The Cortex-M4 core's 16 vectors (the first is the initial stack pointer); the board's
 * interrupts are never enabled here. */
__attribute__((section(".isr_vector"), used)) const vector_t vector_table[16] = {
    (vector_t)_estack,
    Reset_Handler,
    Default_Handler, /* NMI */
    Default_Handler, /* HardFault */
    Default_Handler, /* MemManage */
    Default_Handler, /* BusFault */
    Default_Handler, /* UsageFault */
    0,
    0,
    0,
    0,
    Default_Handler, /* SVCall */
    Default_Handler, /* DebugMonitor */
    0,
    Default_Handler, /* PendSV */
    Default_Handler, /* SysTick */
};
