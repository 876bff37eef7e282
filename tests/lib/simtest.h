/* SPDX-License-Identifier: MIT */
/* Helpers for the tests that drive the card model through the library. */
#ifndef SH2000_TEST_SIMTEST_H
#define SH2000_TEST_SIMTEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <cmocka.h>

#include "sh2000/sh2000.h"
#include "sh2000/sh2000_protocol.h"
#include "sh2000/sim.h"

#define CHECK(call) do { \
	int r_ = (call); \
	if (r_ < 0) \
		fail_msg("%s = %d (%s): %s", #call, r_, sh2000_strerror(r_), \
			 sh2000_last_error(h)); \
} while (0)

static inline struct sh2000 *simtest_open(void)
{
	struct sh2000 *h = NULL;
	char msg[256];
	int r = sh2000_open(&h, "sim", msg, sizeof(msg));

	if (r < 0)
		fail_msg("open sim: %d %s", r, msg);
	return h;
}

/* Set-points of all axes now (counts). */
static inline void simtest_cmd(struct sh2000 *h, int32_t p[SH2000_AXES])
{
	struct sh2000_status st;
	unsigned int a;

	CHECK(sh2000_poll(h, &st));
	for (a = 0; a < SH2000_AXES; a++)
		p[a] = st.axis[a].cmd_counts;
}

/*
 * Push n points moving `axis` by `step` counts per coarse period from p
 * (p is updated), in batches of `batch`, waiting for room. Returns the
 * last push result.
 */
static inline int simtest_line(struct sh2000 *h, int32_t p[SH2000_AXES],
			       unsigned int axis, int32_t step, size_t n,
			       size_t batch, unsigned int flags)
{
	int32_t pts[SH2000_RING_RECORDS][SH2000_AXES];
	size_t done = 0, i, k;
	int r = 0;

	while (done < n) {
		k = n - done < batch ? n - done : batch;
		r = sh2000_wait_space(h, (unsigned int)k, 10000);
		if (r < 0)
			return r;
		for (i = 0; i < k; i++) {
			p[axis] += step;
			memcpy(pts[i], p, sizeof(pts[i]));
		}
		r = sh2000_push_counts(h, (const int32_t (*)[SH2000_AXES])pts,
				       k, done + k == n ? flags : 0);
		if (r < 0)
			return r;
		done += k;
	}
	return r;
}

#endif
