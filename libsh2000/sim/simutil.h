/* SPDX-License-Identifier: MIT */
/* Small helpers of libsh2000-sim (it sees only libsh2000's public API). */
#ifndef SH2000_SIMUTIL_H
#define SH2000_SIMUTIL_H

#include <stddef.h>
#include <stdint.h>

#include <stdio.h>

/* Format a message into msg (if any) and give code. */
#define sim_msg(msg, len, code, ...)					\
	((msg) && (len) ? (void)snprintf((msg), (len), __VA_ARGS__) :	\
			  (void)0, (code))
/* CLOCK_MONOTONIC in ns. */
uint64_t sim_mono_ns(void);

#endif /* SH2000_SIMUTIL_H */
