/*
 * semihost.h: Arm semihosting (bkpt 0xab) for output and exit, and the startup's symbols.
 * QEMU implements it with -semihosting-config enable=on,target=native.
 */
#ifndef HYST_FIRMWARE_SEMIHOST_H
#define HYST_FIRMWARE_SEMIHOST_H

/* Writes a NUL-terminated string to the host's console (SYS_WRITE0). */
void semihost_write0(const char *text);

/* Ends the program (SYS_EXIT): ADP_Stopped_ApplicationExit when `success` (QEMU exits with 0),
 * ADP_Stopped_RunTimeErrorUnknown otherwise (QEMU exits with 1). */
void semihost_exit(int success) __attribute__((noreturn));

#endif /* HYST_FIRMWARE_SEMIHOST_H */
