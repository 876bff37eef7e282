/* SPDX-License-Identifier: MIT */
/*
 * What the libFuzzer harnesses share (tests/fuzz, DEVELOPERS.md "Fuzzing").
 * A harness that finds a broken promise aborts with a message, so libFuzzer
 * keeps the input as a crash like any sanitizer report.
 */
#ifndef SH2000_FUZZ_H
#define SH2000_FUZZ_H

#include <stddef.h>
#include <stdint.h>

#include <sh2000/program.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Print "fuzz: <message>" and abort. */
void fz_fail(const char *fmt, ...)
	__attribute__((format(printf, 1, 2), noreturn));

/* The promises of program.h about a read program: r is what
 * sh2000_program_read() returned for text of len bytes. */
void fz_check_program(int r, const struct sh2000_program *p,
		      const struct sh2000_prog_diags *d, const char *text,
		      size_t len);

#endif /* SH2000_FUZZ_H */
