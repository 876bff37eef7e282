/* SPDX-License-Identifier: MIT */
/* Small helpers of libsh2000-sim (it sees only libsh2000's public API). */
#ifndef SH2000_SIMUTIL_H
#define SH2000_SIMUTIL_H

#include <stddef.h>
#include <stdint.h>

/* Format a message into msg (if any) and return code. */
int sim_msg(char *msg, size_t len, int code, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
/* CLOCK_MONOTONIC in ns. */
uint64_t sim_mono_ns(void);

#endif /* SH2000_SIMUTIL_H */
