/*
 * export_host.c: the exported models' run (exported.c) on the host, printed to standard output;
 * exit status 0 when it had no errors.
 */
#include <stdio.h>

#include "exported.h"

static void print_line(const char *line) {
    fputs(line, stdout);
}

int main(void) {
    return exp_run(print_line) == 0 ? 0 : 1;
}
